"""Diagnostics of trained runs and models, for the questions the experiments leave open.

- planner_study: a trained run's frozen models planned under other settings, on the same layouts
  (how much of a cell's violations or return the planner explains, apart from training).
- violation_anatomy: each violating step of a trained run sorted by what its models knew
  (classifier holes, dynamics errors, RCE's fallback plans).
- model_size: the offline one-step error of dynamics ensembles of several sizes and targets on
  the same random-action data (a criterion for a protocol's network size that looks at no
  return or violation count).

Each is a module with a main(argv): `python3 -m cmbrl.diagnostics.<name> --help`.
"""
