"""The type stubs (cmbrl/*.pyi, with py.typed) agree with the runtime, and a type checker uses
them: mypy's stubtest compares every stub with the module it describes, the examples pass
mypy --strict, and a wrong use of the API is caught. Each runs without gymnasium and, where it is
importable, again with it, under which cmbrl's classes are Gymnasium's."""
import os
import subprocess
import sys
import textwrap

import pytest

import cmbrl

pytest.importorskip("mypy", reason="mypy (Debian's python3-mypy, installed by "
                                   "scripts/install-deps.sh) checks the stubs")
SOURCE_DIR = os.environ.get("CMBRL_SOURCE_DIR",
                            os.path.join(os.path.dirname(__file__), "..", ".."))


def _gymnasium_folder():
    """The folder gymnasium is imported from, or None where it is not importable."""
    try:
        import gymnasium
    except ImportError:
        return None
    return os.path.dirname(os.path.dirname(gymnasium.__file__))


WITH_AND_WITHOUT_GYMNASIUM = pytest.mark.parametrize("with_gymnasium", [False, True],
                                                     ids=["without-gymnasium", "with-gymnasium"])


def _mypy(args, cwd, with_gymnasium=False):
    """mypy on cmbrl, with gymnasium on its path or not (a test with it is skipped where gymnasium
    is not importable; one without it assumes it is not installed beside numpy)."""
    folders = [os.path.dirname(os.path.dirname(cmbrl.__file__))]
    if with_gymnasium:
        if _gymnasium_folder() is None:
            pytest.skip("gymnasium is not importable")
        folders.append(_gymnasium_folder())
        stub = os.path.join(_gymnasium_folder(), "farama_notifications")
        if not os.path.exists(stub) and os.environ.get("PYTHONPATH"):
            folders.extend(os.environ["PYTHONPATH"].split(os.pathsep))  # its stand-ins, say
    environment = dict(os.environ)
    environment["PYTHONPATH"] = os.pathsep.join(folders)
    environment["MYPY_CACHE_DIR"] = os.path.join(cwd, ".mypy_cache")
    return subprocess.run([sys.executable, "-m", *args], cwd=cwd, env=environment,
                          capture_output=True, text=True, timeout=600)


def test_the_package_ships_its_stubs():
    package = os.path.dirname(cmbrl.__file__)
    modules = [name[:-3] for name in os.listdir(package) if name.endswith(".py")]
    assert {"__init__", "envs", "models", "agents", "results"} <= set(modules)
    assert os.path.isfile(os.path.join(package, "py.typed"))
    for module in modules:  # every module has its stub beside it, in the same layout
        assert os.path.isfile(os.path.join(package, module + ".pyi")), module


def test_the_package_init_only_reexports():
    import ast
    with open(cmbrl.__file__) as source:
        tree = ast.parse(source.read())
    allowed = (ast.Import, ast.ImportFrom, ast.Assign)
    for statement in tree.body[1:]:  # after the docstring
        assert isinstance(statement, allowed), ast.dump(statement)[:80]
        if isinstance(statement, ast.Assign):  # only the version and the list of names
            names = [target.id for target in statement.targets]
            assert names in (["__version__"], ["__commit__"], ["__all__"]), names
    for name in cmbrl.__all__:  # cmbrl's own, or (EnvSpec, where importable) Gymnasium's
        module = getattr(cmbrl, name).__module__
        assert module.startswith("cmbrl") or (name, module.split(".")[0]) == (
            "EnvSpec", "gymnasium"), name


@WITH_AND_WITHOUT_GYMNASIUM
def test_the_stubs_agree_with_the_runtime(tmp_path, with_gymnasium):
    result = _mypy(["mypy.stubtest", "cmbrl"], str(tmp_path), with_gymnasium)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Success: no issues found" in result.stdout


@WITH_AND_WITHOUT_GYMNASIUM
def test_the_example_passes_strict_type_checking(tmp_path, with_gymnasium):
    example = os.path.join(SOURCE_DIR, "examples", "gymnasium_loop.py")
    result = _mypy(["mypy", "--strict", example], str(tmp_path), with_gymnasium)
    assert result.returncode == 0, result.stdout + result.stderr


@WITH_AND_WITHOUT_GYMNASIUM
def test_a_wrong_use_is_caught(tmp_path, with_gymnasium):
    (tmp_path / "wrong.py").write_text(textwrap.dedent("""
        import cmbrl
        env = cmbrl.make("PointGoal1")
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        env.reset(seed="0")
        agent: cmbrl.Agent = cmbrl.make_vec("PointGoal1", 2)
    """))
    result = _mypy(["mypy", "--strict", "wrong.py"], str(tmp_path), with_gymnasium)
    assert result.returncode == 1
    assert "wrong.py:4: error: Too many values to unpack (5 expected, 6 provided)" in result.stdout
    assert 'wrong.py:5: error: Argument "seed" to "reset" of "Env" has incompatible type "str"; ' \
           'expected "Optional[int]"' in result.stdout
    if with_gymnasium:
        # Without gymnasium, the classes derive from Any for a type checker (_gymnasium.pyi),
        # which any variable accepts; with it, from Gymnasium's classes, which an Agent is not.
        assert 'wrong.py:6: error: Incompatible types in assignment (expression has type ' \
               '"VectorEnv", variable has type "Agent")' in result.stdout


def test_gymnasium_code_types_cmbrl_as_gymnasiums_classes(tmp_path):
    """The typed example passes mypy --strict with gymnasium, and runs; a vector is still not
    taken for a single environment. (An Env's six-value step is an override Gymnasium's types
    cannot express, as Safety-Gymnasium's: a type checker takes it for a five-value Env.)"""
    example = os.path.join(SOURCE_DIR, "examples", "gymnasium_typed.py")
    result = _mypy(["mypy", "--strict", example], str(tmp_path), with_gymnasium=True)
    assert result.returncode == 0, result.stdout + result.stderr
    (tmp_path / "wrong.py").write_text(textwrap.dedent("""
        import gymnasium
        import numpy as np
        import numpy.typing as npt
        import cmbrl
        env: gymnasium.Env[npt.NDArray[np.float64], npt.NDArray[np.float64]] = cmbrl.make_vec(
            "PointGoal1", 2)
        spec: cmbrl.EnvSpec = cmbrl.make("PointGoal1").spec
    """))
    result = _mypy(["mypy", "--strict", "wrong.py"], str(tmp_path), with_gymnasium=True)
    assert result.returncode == 1
    assert 'wrong.py:6: error: Incompatible types in assignment (expression has type ' \
           '"VectorEnv", variable has type "Env[' in result.stdout
    assert "wrong.py:8: error" not in result.stdout, result.stdout  # its spec is Gymnasium's
    environment = dict(os.environ)
    environment["PYTHONPATH"] = os.pathsep.join(
        [os.path.dirname(os.path.dirname(cmbrl.__file__)), _gymnasium_folder()]
        + os.environ.get("PYTHONPATH", "").split(os.pathsep))
    run = subprocess.run([sys.executable, example], cwd=tmp_path, env=environment,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "episodes ended in 1000 steps" in run.stdout
