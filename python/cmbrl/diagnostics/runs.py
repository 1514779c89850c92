"""Loading a trained run for a diagnostic: its MPC agent, and the same run under named settings."""
import cmbrl


def load_mpc_run(run, lacks, seed=0, overrides=None):
    """The agent of a trained MPC run (cmbrl.load_run); when the run is model-free, exits naming
    it and what it lacks for the diagnostic (`lacks`, e.g. "classifier")."""
    agent = cmbrl.load_run(run, seed=seed, overrides=overrides)
    if not agent.is_mpc:
        raise SystemExit(f"{run} is not an MPC run: it has no {lacks}")
    return agent


def load_settings(run, settings, seed=0):
    """The same run's agent once per named setting, [(NAME, overrides)] -> {NAME: agent}, in
    order (overrides as `cmbrl eval --set`: planner, planning.*, objective.*)."""
    return {name: cmbrl.load_run(run, seed=seed, overrides=overrides)
            for name, overrides in settings}
