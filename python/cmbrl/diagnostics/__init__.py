"""Diagnostics of trained runs and models, for the questions the experiments leave open.

- planner_study: a trained run's frozen models planned under other settings, on the same layouts
  (how much of a cell's violations or return the planner explains, apart from training).
- planner_compare: several planners plan from the same states with one run's frozen models, and
  the run's own objective scores every chosen plan (predicted reward cost and feasibility).
- violation_anatomy: each violating step of a trained run sorted by what its models knew
  (classifier holes, dynamics errors, RCE's fallback plans).
- open_loop: where a trained run's ensemble members put the robot 1, 4 and 8 steps ahead under
  the executed actions of its own episodes, against where it went (by robot, inside or outside
  hazards, speed, turning).
- hazard_escape: whether a hazard is a trap for a trained RCE run: at each state inside a
  hazard, the feasible share of the action sequences that leave it and of those that stay, how
  the reward ranks them against the executed plan (with a control outside hazards), and what
  other planner settings would plan there.
- hidden_state: whether a robot's observation holds its motion state: how much of one step's
  motion an ensemble explains from the observed motion and the action, with the previous action
  or an unrelated one added.
- model_size: the offline one-step error of dynamics ensembles of several sizes and targets on
  the same random-action data (a criterion for a protocol's network size that looks at no
  return or violation count).

runs: loading a trained run's MPC agent, and the same run under named settings, for them.

Each is a module with a main(argv): `python3 -m cmbrl.diagnostics.<name> --help`.
"""
