#!/usr/bin/env python3
"""The bad-input and fault probe: each case does what a careless user or an unlucky machine does
(an odd config, an edited or copied run, a second writer, a full disk, a bad Python argument)
and gets a verdict from what cmbrl did:

  clear error   exit 1 (or cmbrl.Error), a message naming what the case expects, no stack trace
  ok            a case whose input is fine (or only looks odd) did the right thing
  unclear error exit 1, but the message does not name it
  accepted      exit 0 where an error was due (or an error where the input was fine: "refused")
  crash         a signal, "terminate called", a LibTorch frame or a Python traceback
  hang          no answer within the case's time
  slow          a refusal that took more than a second beyond the program's start
  skipped       the case needs what this machine lacks (root for a tmpfs)

Usage: tests/fault_probe.py [--cmbrl build/bin/cmbrl] [--work /tmp/cmbrl-probe] [--python-path build/python]
Prints one line per case and the counts per verdict; exits 1 when any case is not clear (or
accepted where it should be).
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time
from collections import Counter

CRASH = re.compile(r"terminate called|frame #\d|Traceback \(most recent call last\)|"
                   r"Segmentation fault|core dumped|Aborted|c10::Error|std::bad_alloc")

# The tests' run of seconds (RCE with tiny networks), the command-line tests' own file.
TINY = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "cli", "tiny-rce.yaml"),
            encoding="utf-8").read()


class Probe:
    def __init__(self, cmbrl, work, python_path):
        self.cmbrl, self.work, self.python_path = cmbrl, work, python_path
        self.results = []

    def path(self, *parts):
        return os.path.join(self.work, *parts)

    def write(self, name, text):
        path = self.path(name)
        with open(path, "w") as out:
            out.write(text)
        return path

    def run(self, args, timeout=600, env=None):
        start = time.time()
        try:
            done = subprocess.run(args, capture_output=True, text=True, timeout=timeout, env=env)
            return done.returncode, done.stdout + done.stderr, time.time() - start
        except subprocess.TimeoutExpired:
            return None, "", timeout

    def verdict(self, code, output, must_name, want_error=True):
        if code is None:
            return "hang"
        if code < 0 or code >= 128 or CRASH.search(output):
            return "crash"
        if not want_error:
            return "ok" if code == 0 else "refused"
        if code == 0:
            return "accepted"
        return "clear error" if re.search(must_name, output) else "unclear error"

    def startup_seconds(self):
        """The program's start alone (`cmbrl --version`, median of 3), measured once."""
        if not hasattr(self, "_startup"):
            self._startup = sorted(self.run([self.cmbrl, "--version"], 60)[2]
                                   for _ in range(3))[1]
        return self._startup

    def case(self, cls, name, args, must_name, want_error=True, timeout=600, check=None,
             env=None, within_a_second=False):
        code, output, seconds = self.run(args, timeout, env)
        verdict = self.verdict(code, output, must_name, want_error)
        if verdict == "clear error" and within_a_second and seconds > self.startup_seconds() + 1:
            verdict = "slow"
        if verdict in ("clear error", "ok") and check is not None and not check():
            verdict = "accepted"  # ran without error but did the wrong thing
        # The line that says what is wrong (CLI11 adds "Run with --help" after it).
        lines = [line for line in output.strip().splitlines() if "Run with --help" not in line]
        last = lines[-1] if lines else ""
        self.results.append((cls, name, verdict, last[:160]))
        print(f"{verdict:13s} {cls:8s} {name}: {last[:140]}", flush=True)

    def python_case(self, cls, name, code_text, must_name, want_error=True):
        env = dict(os.environ, PYTHONPATH=self.python_path)
        script = "import numpy as np, cmbrl\n" + code_text
        code, output, _ = self.run([sys.executable, "-c", script], 600, env)
        if code == 1 and "cmbrl._cmbrl.Error" in output and re.search(must_name, output):
            verdict = "clear error"  # the expected cmbrl.Error, its traceback is Python's own
        elif code == 0:
            verdict = "accepted" if want_error else "ok"
        elif code is None:
            verdict = "hang"
        elif code < 0 or "Segmentation" in output or "terminate called" in output:
            verdict = "crash"
        else:
            verdict = "unclear error"
        last = output.strip().splitlines()[-1] if output.strip() else ""
        self.results.append((cls, name, verdict, last[:160]))
        print(f"{verdict:13s} {cls:8s} {name}: {last[:140]}", flush=True)

    def skip(self, cls, name, why):
        self.results.append((cls, name, "skipped", why))
        print(f"{'skipped':13s} {cls:8s} {name}: {why}", flush=True)


def config_cases(p):
    c = p.cmbrl
    out = lambda name: p.path("runs", name)  # noqa: E731
    cases = {
        "empty file": ("", r"empty"),
        "comment only": ("# nothing\n", r"empty"),
        "two documents": (TINY + "---\n" + TINY, r"document"),
        "not a mapping": ("- task\n- PointGoal1\n", r"mapping"),
        "repeated top key": (TINY + "seed: 3\n", r"seed.*(twice|again|repeated)"),
        "repeated nested key": (TINY.replace("max_epochs: 5}", "max_epochs: 5, max_epochs: 6}"),
                                r"max_epochs"),
        "unknown key": (TINY + "colour: blue\n", r"colour"),
        "bad type": (TINY.replace("population: 24", "population: many"), r"population"),
        "NaN value": (TINY + "objective: {gamma: .nan}\n", r"gamma"),
        "negative population": (TINY.replace("population: 24", "population: -4"), r"population"),
        "elites above population": (TINY.replace("elites: 6", "elites: 60"), r"elites"),
        "empty hidden layers": (TINY.replace("hidden_sizes: [16]", "hidden_sizes: []"),
                                r"hidden_sizes"),
        "no task": (TINY.replace("task: PointGoal1\n", ""), r"task"),
        "unknown task": (TINY.replace("PointGoal1", "PointGoal9"), r"PointGoal9"),
        "huge networks": (TINY.replace("hidden_sizes: [16]", "hidden_sizes: [65536, 65536]"),
                          r"GiB"),
        "huge model-free networks": (
            "task: PointGoal1\nalgorithm: cpo\nvariant: paper-lidar\n"
            "policy_optimisation: {policy_hidden: [65536, 65536]}\n", r"policy_hidden"),
    }
    # Values no one meant: a type changed by a tag, an absurd finite value.
    cases.update({
        "a tag that makes a number a string": (TINY.replace("population: 24",
                                                            "population: !!str 24"), r"tag"),
        "a quoted number": (TINY.replace("population: 24", "population: '24'"), r"population"),
        "min_std 1e300": (TINY.replace("max_epochs: 5}", "max_epochs: 5, min_std: 1.0e+300}"),
                          r"min_std"),
        "penalty 1e300": (TINY.replace("random_samples: 50}", "random_samples: 50, "
                                       "penalty: 1.0e+300}"), r"penalty"),
    })
    for i, (name, (text, must)) in enumerate(cases.items()):
        path = p.write(f"config-{i}.yaml", text)
        p.case("config", name, [c, "train", "--config", path, "--out", out(f"c{i}")], must)
    base = p.write("tiny.yaml", TINY)
    # A bare section in a later file is an error, not a reset of the section to the defaults.
    bare = p.write("bare-planning.yaml", "planning:\n")
    p.case("config", "a bare section in a later file", [c, "train", "--config", base, bare,
                                                         "--out", out("bare")], r"planning")
    # Inputs that never end: each refused within seconds (a hang is a verdict), naming the file.
    bomb = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{chr(98 + i)}: &{chr(98 + i)} [*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}, "
        f"*{chr(97 + i)}, *{chr(97 + i)}, *{chr(97 + i)}]\n" for i in range(9))
    big = TINY + "".join(f"# {'x' * 100}\n" for _ in range(20000))  # 2 MB of comments
    deep = TINY + "extra: " + "{a: " * 200 + "1" + "}" * 200 + "\n"
    fifo = p.path("config.fifo")
    os.mkfifo(fifo)
    loop = p.path("loop-a.yaml")
    os.symlink(p.path("loop-b.yaml"), loop)
    os.symlink(loop, p.path("loop-b.yaml"))
    endless = {
        "a YAML alias bomb under an unused key": (p.write("bomb.yaml", TINY + bomb),
                                                  r"bomb\.yaml.*(alias|anchor)"),
        "a 2 MB config": (p.write("big.yaml", big), r"big\.yaml.*MiB"),
        "nesting 200 deep": (p.write("deep.yaml", deep), r"deep\.yaml.*nest"),
        "/dev/zero as the config": ("/dev/zero", r"/dev/zero.*regular file"),
        "a FIFO as the config": (fifo, r"config\.fifo.*regular file"),
        "a symlink loop as the config": (loop, r"loop-a\.yaml.*symbolic links"),
        "a folder as the config": (p.path("runs"), r"runs' is a folder"),
    }
    for name, (path, must) in endless.items():
        p.case("input", name, [c, "train", "--config", path, "--out", out("endless")], must,
               timeout=20, within_a_second=True)
    p.case("config", "--set malformed", [c, "train", "--config", base, "--set", "planning",
                                         "--out", out("s1")], r"section\.key=value")
    p.case("config", "--set unknown key", [c, "train", "--config", base, "--set",
                                           "planning.colour=3", "--out", out("s2")], r"colour")
    merged = out("s3")
    p.case("config", "--set mapping merges", [c, "train", "--config", base, "--set",
                                              "planning={population: 30}", "--steps", "100",
                                              "--out", merged], "", want_error=False,
           check=lambda: "population: 30" in open(os.path.join(merged, "config.yaml")).read()
           and "horizon: 3" in open(os.path.join(merged, "config.yaml")).read())
    p.case("cli", "missing config file", [c, "train", "--config", p.path("nope.yaml"),
                                          "--out", out("m")], r"nope\.yaml")
    p.case("cli", "steps 0", [c, "train", "--config", base, "--steps", "0", "--out", out("z")],
           r"steps")
    p.case("cli", "unknown command", [c, "trian"], r"trian")
    p.case("cli", "unknown bench command", [c, "bench", "foo"], r"'bench foo'.*env, plan")
    for seconds in ("nan", "-1", "1e12", "soon"):
        p.case("cli", f"checkpoint seconds {seconds}",
               [c, "train", "--config", base, "--checkpoint-seconds", seconds,
                "--out", out("cs-" + seconds)],
               rf"--checkpoint-seconds.*'{seconds}': expected a number from 0",
               check=lambda name=seconds: not os.path.exists(out("cs-" + name)))
    # The sweep's engines: options of the other engine, an unknown one, an sbatch option that
    # would change the sweep's own array, and no sbatch on PATH.
    configs = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "configs")
    sweep = [c, "sweep", "--tasks", "PointGoal1", "--planners", "random", "--seeds", "0",
             "--steps", "100", "--config-dir", configs]
    p.case("cli", "sweep: --wait with the local engine", sweep + ["--out", out("w1"), "--wait"],
           r"--wait is for --engine slurm")
    p.case("cli", "sweep: unknown engine", sweep + ["--out", out("w2"), "--engine", "pbs"],
           r"pbs")
    p.case("cli", "sweep: --sbatch=--array", sweep + ["--out", out("w3"), "--engine", "slurm",
                                                      "--sbatch=--array=0-9"],
           r"'--array=0-9' is the sweep's own")
    p.case("cli", "sweep: no sbatch on PATH", sweep + ["--out", out("w4"), "--engine", "slurm"],
           r"'sbatch' is not on PATH", env=dict(os.environ, PATH="/nonexistent"))


def run_cases(p):
    c = p.cmbrl
    base = p.write("tiny.yaml", TINY)
    whole = p.path("whole")
    code, output, _ = p.run([c, "train", "--config", base, "--out", whole])
    if code != 0:
        raise SystemExit(f"the probe's base run failed: {output}")

    def copy(name, edit):
        sweep = p.path(f"sweep-{name}")
        dest = os.path.join(sweep, "runs", "run")
        shutil.copytree(whole, dest)
        os.remove(os.path.join(dest, "lock"))
        edit(dest)
        return sweep, dest

    def append(path, text):
        with open(path, "a") as out:
            out.write(text)

    def replace(path, old, new):
        text = open(path).read()
        with open(path, "w") as out:
            out.write(text.replace(old, new, 1))

    edits = {
        "config.yaml edited (task)": (lambda d: replace(os.path.join(d, "config.yaml"),
                                                        "PointGoal1", "PointGoal2"),
                                      r"config\.yaml' differs"),
        "config.yaml edited (population)": (lambda d: replace(os.path.join(d, "config.yaml"),
                                                              "population: 24", "population: 30"),
                                            r"config\.yaml' differs"),
        "progress row edited": (lambda d: replace(os.path.join(d, "progress.csv"), "\n1,",
                                                  "\n7,"), r"progress\.csv' differs"),
        "progress shortened": (lambda d: open(os.path.join(d, "progress.csv"), "w").write(
            open(os.path.join(d, "progress.csv")).read().split("\n")[0] + "\n"),
            r"progress\.csv' has 0 rows"),
        "manifest deleted": (lambda d: os.remove(os.path.join(d, "checkpoint", "manifest.json")),
                             r"manifest\.json' is missing"),
        "manifest edited": (lambda d: replace(os.path.join(d, "checkpoint", "manifest.json"),
                                              '"rows": ', '"rows": 1'),
                            r"manifest\.json' is damaged"),
        "sessions deleted": (lambda d: os.remove(os.path.join(d, "sessions.jsonl")),
                             r"sessions\.jsonl' is missing"),
        "sessions edited": (lambda d: replace(os.path.join(d, "sessions.jsonl"), '"cpu":"',
                                              '"cpu":"X'), r"sessions\.jsonl' differs"),
        "model file damaged": (lambda d: open(os.path.join(d, "checkpoint", "ensemble.pt"),
                                              "w").write("x"), r"ensemble\.pt' differs"),
    }
    for name, (edit, must) in edits.items():
        sweep, run = copy(name.replace(" ", "-").replace("(", "").replace(")", ""), edit)
        p.case("run", f"resume: {name}", [c, "train", "--resume", run, "--steps", "400"], must)
        p.case("run", f"eval: {name}", [c, "eval", "--run", run], must)
        # A report reads no model file (its figures are progress.csv's, which is checked): a
        # damaged model leaves them true, so the report goes ahead.
        model_only = name == "model file damaged"
        p.case("run", f"report: {name}", [c, "report", sweep, "--out",
                                          os.path.join(sweep, "report"), "--window", "100"], must,
               want_error=not model_only)

    # Rows and values a checkpoint does not cover, or that lie outside their domain.
    def added_row(d):
        append(os.path.join(d, "progress.csv"), "9,9,1.0,999,100,400,1.0,0,0,0,0,0,0,0,0,0\n")
    sweep, run = copy("added-row", added_row)
    report = os.path.join(sweep, "report")
    p.case("run", "report: a row added after the last checkpoint is not counted",
           [c, "report", sweep, "--out", report, "--window", "100"], "", want_error=False,
           check=lambda: "999" not in open(os.path.join(report, "table-1.csv")).read())

    # A run without its config.yaml is refused by name, not counted silently.
    sweep, run = copy("no-config", lambda d: os.remove(os.path.join(d, "config.yaml")))
    p.case("run", "report: config.yaml deleted", [c, "report", sweep, "--out",
                                                  os.path.join(sweep, "report"), "--window",
                                                  "100"], r"config\.yaml")
    # The original's logs asked for where there are none: an error, not a report without them.
    sweep, run = copy("no-reference", lambda d: None)
    p.case("run", "report: CMBRL_REFERENCE_DIR pointing nowhere",
           [c, "report", sweep, "--out", os.path.join(sweep, "report"), "--window", "100"],
           r"CMBRL_REFERENCE_DIR", env=dict(os.environ, CMBRL_REFERENCE_DIR=p.path("nowhere")))

    # A copied run counts once.
    sweep, run = copy("copied", lambda d: None)
    shutil.copytree(run, os.path.join(sweep, "runs", "run-copy"))
    p.case("run", "report: a copied run folder", [c, "report", sweep, "--out",
                                                  os.path.join(sweep, "report"), "--window", "100"],
           r"hold one run \(run id")

    # checkpoint.old alone (a stop between the two renames).
    sweep, run = copy("old-only", lambda d: os.rename(os.path.join(d, "checkpoint"),
                                                      os.path.join(d, "checkpoint.old")))
    p.case("run", "eval: checkpoint.old alone", [c, "eval", "--run", run], "", want_error=False)
    p.case("run", "resume: checkpoint.old alone", [c, "train", "--resume", run, "--steps", "400"],
           "", want_error=False)

    # A second writer: the lock file deleted under a live run.
    live = p.path("live")
    # A run far longer than the probe, so that it is live whatever the machine's load.
    proc = subprocess.Popen([c, "train", "--config", base, "--steps", "1000000", "--out", live],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    for _ in range(1200):  # up to 2 minutes for LibTorch to load on a busy machine
        if os.path.exists(os.path.join(live, "config.yaml")) or proc.poll() is not None:
            break
        time.sleep(0.1)
    if proc.poll() is not None or not os.path.exists(os.path.join(live, "lock")):
        proc.kill()
        proc.wait()
        for name in ("resume beside a live run whose lock file was deleted",
                     "a second start of a live run"):
            p.skip("writer", name, "the live run did not start")
        return
    os.remove(os.path.join(live, "lock"))
    p.case("writer", "resume beside a live run whose lock file was deleted",
           [c, "train", "--resume", live], r"in use by another cmbrl process")
    p.case("writer", "a second start of a live run", [c, "train", "--config", base, "--out", live],
           r"already holds a run|in use")
    proc.kill()
    proc.wait()


def disk_cases(p):
    c = p.cmbrl
    if os.geteuid() != 0:
        for name in ("checkpoint", "report", "trace"):
            p.skip("disk", name, "mounting a tmpfs needs root")
        return
    disk = p.path("disk")
    os.makedirs(disk)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=300k", "tmpfs", disk]).returncode:
        for name in ("checkpoint", "report", "trace"):
            p.skip("disk", name, "cannot mount a tmpfs here")
        return
    try:
        base = p.write("tiny.yaml", TINY)
        p.case("disk", "a checkpoint that does not fit",
               [c, "train", "--config", base, "--steps", "600", "--out",
                os.path.join(disk, "run")], r"No space left on device")
        shutil.rmtree(os.path.join(disk, "run"), ignore_errors=True)
        sweep = p.path("disk-sweep")
        shutil.copytree(p.path("whole"), os.path.join(sweep, "runs", "run"))
        os.remove(os.path.join(sweep, "runs", "run", "lock"))
        with open(os.path.join(disk, "filler"), "wb") as out:
            try:
                out.write(b"\0" * 280 * 1024)
            except OSError:
                pass
        p.case("disk", "a report that does not fit", [c, "report", sweep, "--out",
                                                      os.path.join(disk, "report"), "--window",
                                                      "100"], r"No space left on device")
        p.case("disk", "a trace that does not fit", [c, "rollout", "--episodes", "3", "--trace",
                                                     os.path.join(disk, "trace.jsonl")],
               r"No space left on device")
    finally:
        subprocess.run(["umount", disk])


def python_cases(p):
    cases = [
        ("Ensemble too large", "cmbrl.Ensemble(4, 2, hidden_sizes=[65536] * 3)", r"GiB"),
        ("make_vec of 10^8 envs", "cmbrl.make_vec('PointGoal1', 100_000_000)", r"num_envs"),
        ("make_vec num_envs=2.5", "cmbrl.make_vec('PointGoal1', 2.5)", r"num_envs is 2\.5"),
        ("reset(seed=1.7)", "cmbrl.make('PointGoal1').reset(seed=1.7)", r"seed is 1\.7"),
        ("reset(seed=-1)", "cmbrl.make('PointGoal1').reset(seed=-1)", r"seed is -1"),
        ("unknown task", "cmbrl.make('PointGoal7')", r"PointGoal7"),
        ("step with NaN", "e = cmbrl.make('PointGoal1'); e.reset(seed=0); e.step([np.nan, 0])",
         r"NaN|finite"),
        ("step with a wrong shape", "e = cmbrl.make('PointGoal1'); e.reset(seed=0); "
                                    "e.step([0, 0, 0])", r"shape|2"),
        ("step before reset", "cmbrl.make('PointGoal1').step([0, 0])", r"reset"),
        ("render before reset", "cmbrl.make('PointGoal1').render()", r"before reset"),
        ("classifier predict before fit", "cmbrl.CostClassifier(3).predict(np.zeros((1, 3)))",
         r"before fit"),
        ("ensemble predict before fit",
         "cmbrl.Ensemble(3, 2, hidden_sizes=[8]).predict(np.zeros((1, 3)), np.zeros((1, 2)))",
         r"before fit"),
        ("render_mode human without a display",
         "import os; os.environ.pop('DISPLAY', None); os.environ.pop('WAYLAND_DISPLAY', None); "
         "cmbrl.make('PointGoal1', render_mode='human')", r"needs a display"),
        ("train a config dict without task", "cmbrl.train(config={}, out='/tmp/probe-x')",
         r"no task"),
        ("classifier fit of 10^9 rows",
         "cmbrl.CostClassifier(8).fit(np.broadcast_to(np.zeros(8), (10**9, 8)), "
         "np.broadcast_to(np.zeros(1), (10**9,)))", r"GiB"),
        ("Ensemble hidden size 3.5", "cmbrl.Ensemble(4, 2, hidden_sizes=[3.5])",
         r"hidden_sizes\[0\] is 3\.5"),
        ("Ensemble hidden sizes '64'", "cmbrl.Ensemble(4, 2, hidden_sizes='64')",
         r"hidden_sizes is '64'"),
        # Wrong argument types are refused by name, not with pybind11's signature.
        ("train(config=123)", "cmbrl.train(config=123)", r"config is 123"),
        ("train(device=0)", "cmbrl.train(config='quickstart', device=0)", r"device is 0"),
        ("train(progress=5)", "cmbrl.train(config='quickstart', progress=5)", r"progress is 5"),
        ("make(spawn=3)", "cmbrl.make('PointGoal1', spawn=3)", r"spawn is 3"),
        ("load_run(overrides=5)", "cmbrl.load_run('x', overrides=5)", r"overrides is 5"),
        # A dict config gets YAML's type rules: no quoted numbers, no bare sections.
        ("a dict config with population '24'",
         "cmbrl.train(config={'task': 'PointGoal1', 'planning': {'population': '24'}}, "
         "out='/tmp/cmbrl-probe-dict')",
         r"planning\.population"),
        ("a dict config with a section None",
         "cmbrl.train(config={'task': 'PointGoal1', 'planning': None}, "
         "out='/tmp/cmbrl-probe-dict')", r"planning"),
    ]
    for name, code_text, must in cases:
        p.python_case("python", name, code_text, must)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cmbrl", default="build/bin/cmbrl")
    parser.add_argument("--work", default="/tmp/cmbrl-probe")
    parser.add_argument("--python-path", default="build/python")
    args = parser.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(os.path.join(args.work, "runs"))
    p = Probe(os.path.abspath(args.cmbrl), args.work, os.path.abspath(args.python_path))
    config_cases(p)
    run_cases(p)
    disk_cases(p)
    python_cases(p)
    counts = Counter(verdict for _, _, verdict, _ in p.results)
    print(json.dumps({"cases": len(p.results), "verdicts": dict(sorted(counts.items()))}))
    return 0 if set(counts) <= {"clear error", "ok", "skipped"} else 1


if __name__ == "__main__":
    sys.exit(main())
