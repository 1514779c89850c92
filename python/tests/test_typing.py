"""The type stubs (cmbrl/*.pyi, with py.typed) agree with the runtime, and a type checker uses
them: mypy's stubtest compares every stub with the module it describes, the example passes
mypy --strict, and a wrong use of the API is caught."""
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


def _mypy(args, cwd):
    environment = dict(os.environ)
    environment["PYTHONPATH"] = os.path.dirname(os.path.dirname(cmbrl.__file__))
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
    for name in cmbrl.__all__:
        assert getattr(cmbrl, name).__module__.startswith("cmbrl"), name


def test_the_stubs_agree_with_the_runtime(tmp_path):
    result = _mypy(["mypy.stubtest", "cmbrl"], str(tmp_path))
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Success: no issues found" in result.stdout


def test_the_example_passes_strict_type_checking(tmp_path):
    example = os.path.join(SOURCE_DIR, "examples", "gymnasium_loop.py")
    result = _mypy(["mypy", "--strict", example], str(tmp_path))
    assert result.returncode == 0, result.stdout + result.stderr


def test_a_wrong_use_is_caught(tmp_path):
    (tmp_path / "wrong.py").write_text(textwrap.dedent("""
        import cmbrl
        env = cmbrl.make("PointGoal1")
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        agent: cmbrl.Agent = cmbrl.make_vec("PointGoal1", 2)
    """))
    result = _mypy(["mypy", "--strict", "wrong.py"], str(tmp_path))
    assert result.returncode == 1
    assert "wrong.py:4: error: Too many values to unpack (5 expected, 6 provided)" in result.stdout
    assert 'wrong.py:5: error: Incompatible types in assignment (expression has type ' \
           '"VectorEnv", variable has type "Agent")' in result.stdout
