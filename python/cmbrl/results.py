"""Runs as reports read them (read_runs) and reports made from them (report), as `cmbrl report`
does."""
import os

from . import _cmbrl
from ._common import Error, _as_flag, _as_int, _as_path


def _paths(dirs, what):
    if isinstance(dirs, (str, os.PathLike)):
        dirs = [dirs]
    if not isinstance(dirs, (list, tuple)):
        raise Error(f"{what} is {dirs!r}: expected a folder's path or a list of them")
    paths = [_as_path(d, f"{what}[{i}]") for i, d in enumerate(dirs)]
    if not paths:
        raise Error(f"{what} is empty: expected at least one sweep or report folder")
    return paths


def read_runs(dirs):
    """The runs of sweep folders (their runs/) and report folders (their run-logs/), as `cmbrl
    report` reads them: only what each run's last checkpoint covers, each run once.

    dirs: one folder or several. Returns a list of dicts, in name order: name, task, method,
    seed, setting (an experiment's axis values, "" for none), epoch_log (True for a model-free
    run, whose points are epochs), source, and numpy arrays with one entry per episode (or
    epoch): end_step, steps, episode_return, episode_cost, cumulative_violations,
    feasible_fraction, elapsed_seconds (the run's wall seconds over all its sessions) and
    cpu_seconds (the CPU seconds its process used over them, progress.csv's CpuTime), each NaN
    where not logged.
    """
    return _cmbrl.read_runs(_paths(dirs, "dirs"))


def report(dirs, out, window=None, reference=None, complete=False):
    """Writes the report of sweep or report folders into `out`, as `cmbrl report --out` does:
    report.md, Table I as Markdown and CSV, the curves as PNG and SVG, and run-logs/.

    window: agent steps counted (default: the smallest run budget, at most 10,000);
    reference: the original's logs (default: the source tree's data/reference); complete: leave
    out runs that have not reached the window. Returns {"report", "runs", "window", "cells",
    "left_out"}.
    """
    return _cmbrl.report(_paths(dirs, "dirs"), _as_path(out, "out"),
                         None if window is None else _as_int(window, "window", 1, 10**10),
                         None if reference is None else _as_path(reference, "reference"),
                         _as_flag(complete, "complete"))
