"""Whether a trained RCE run's models make a hazard a trap: at each state where the robot is inside
a hazard, which action sequences do its models call feasible, those that leave the hazard or those
that stay in it?

RCE keeps only feasible sequences (no member's classifier calls any predicted state a violation).
If the classifier misses the inside of the hazard the robot is in (a hole) but not the ring around
it, every way out crosses predicted violations and only staying is feasible: the robot stays. This
measures it. The run's own agent drives episodes (reset with seed + k); at every state inside a
hazard, SAMPLES action sequences drawn uniformly from the action box over the planner's horizon
are scored by the run's own objective (Agent.score: feasible or not) and rolled out by every
member under those actions; a sequence "leaves" when the members' mean predicted position at the
horizon's end lies outside the hazard the robot is in (its centre farther than the hazard's
radius), else it "stays". Pose from the hazards' ego coordinates, as open_loop.

Per state: the feasible share of the leaving sequences and of the staying ones; the state is
"trapped" when no leaving sequence is feasible and some staying one is; and the plan the agent
executed there (RCE's mean of its elites), judged alike: feasible or not, leaving or not. Pooled
over the states of episodes with 20 or more violations ("dwelling") and of the others.

And how the objective's reward part (its reward cost, lower is better: RCE picks the feasible
sequence that scores lowest) ranks them: the chance that a feasible leaving sequence scores
better than a feasible staying one (ties half; where both exist), and, at the states where the
executed plan was feasible and stayed, whether some feasible uniform way out scored better than
it ("outscored": the planner's search missed a better way out) or none did (the reward, as far as
the samples reach, prefers the staying plan).

The search's quality outside hazards, the control: at every state outside all hazards, as many
uniform sequences again (from a generator of their own, so the columns inside hazards do not
move) score the executed plan alike. "Beaten": the share of the feasible uniform sequences that
score better than a feasible executed plan (a rank, which does not grow with how many are
feasible, as "some sequence outscores it" does); pooled over the staying plans inside hazards
and over the feasible plans outside them.

With --search NAME=OVERRIDE[,...] (repeatable; overrides as `cmbrl eval --set`, e.g.
big=planning.population=500): at each state inside a hazard each setting's planner, on the same
models, plans from that state alone (cold: begun afresh, as the paper's planner plans every step,
with planning.warm_start off; a warm-starting run's executed plans were not) and its plan is
judged alike: feasible, leaving, its reward cost.

Usage:
  PYTHONPATH=build/python python3 -m cmbrl.diagnostics.hazard_escape RUN_DIR [RUN_DIR ...] \\
      [--episodes 20] [--seed 100] [--samples 500] [--search NAME=OVERRIDES ...] [--out DIR]
Prints (and with --out writes DIR/table.md and DIR/summary.json) Markdown tables with a row a run
and episode kind: the ways out, the control and, with --search, the settings' plans.
"""
import argparse
import os

import numpy as np

from cmbrl.diagnostics.open_loop import collect, hazard_slots, pose_from_ego, roll_out
from cmbrl.diagnostics.planner_study import parse_setting
from cmbrl.diagnostics.runs import load_mpc_run, load_settings
from cmbrl.diagnostics.tables import write_table

DWELLING = 20  # violations: an episode with this many or more is "dwelling"
FLAGS = {"trapped", "plan_feasible", "plan_leaves", "plan_outscored", "dwelling"}  # per state


def escape_at(agent, obs, hazard, radius, slots, world, sequences):
    """One state: (feasible (N) bool, leaves (N) bool, reward cost (N)) of the sequences
    (N, H, A)."""
    scores = agent.score(obs, sequences)
    feasible = np.asarray(scores["feasible"], dtype=bool)
    reward_cost = np.asarray(scores["reward_cost"], dtype=float)
    n = sequences.shape[0]
    predicted = roll_out(agent, np.tile(obs, (n, 1)), sequences)  # (E, N, H, S)
    position, _, _ = pose_from_ego(predicted[:, :, -1][..., slots], world)  # (E, N, 2)
    end = position.mean(axis=0)  # (N, 2)
    leaves = np.hypot(*(end - hazard).T) > radius
    return feasible, leaves, reward_cost


def chance_lower(a, b):
    """The chance that a draw from a scores lower than one from b, ties half (the Mann-Whitney
    statistic over len(a) x len(b)); NaN when either is empty."""
    if len(a) == 0 or len(b) == 0:
        return float("nan")
    a, b = np.asarray(a, dtype=float)[:, None], np.asarray(b, dtype=float)[None, :]
    return float(((a < b) + 0.5 * (a == b)).mean())


def beaten(feasible, reward_cost, plan_cost):
    """The share of the feasible sequences (N bool, their reward cost N) that score better than a
    plan's reward cost; NaN when none is feasible."""
    better = np.asarray(reward_cost)[feasible] < plan_cost
    return float(better.mean()) if better.size else float("nan")


def judge_state(feasible, leaves, reward_cost):
    """One state's sequences, feasible (N) and leaves (N) bool and their reward cost (N): the
    feasible share of the leaving and of the staying ones (NaN where none), the leaving share,
    whether it is trapped (no leaving sequence feasible, some staying one), the chance that a
    feasible leaving sequence scores better than a feasible staying one (NaN unless both exist)
    and the best reward cost of the feasible leaving ones (inf when none)."""
    share = lambda mask: float(feasible[mask].mean()) if mask.any() else float("nan")
    out, stay = feasible & leaves, feasible & ~leaves
    return {"leave_feasible": share(leaves), "stay_feasible": share(~leaves),
            "leaving": float(leaves.mean()),
            "trapped": bool(not out.any() and stay.any()),
            "leave_scores_better": chance_lower(reward_cost[out], reward_cost[stay]),
            "best_way_out": float(reward_cost[out].min()) if out.any() else float("inf")}


def cold_plan(agent, obs):
    """The plan an agent makes from one observation alone (its warm start forgotten), (H, A)."""
    agent.begin_episode()
    agent.act(obs)
    return np.asarray(agent.last_plan()["actions"])


def study_run(run, episodes, seed, samples, searches=()):
    """Per state inside a hazard: a dict of arrays (leave_feasible, stay_feasible: shares, NaN
    where no sequence fell in the group; leaving: share of sequences leaving; trapped;
    leave_scores_better: judge_state's chance, NaN where undefined; plan_feasible, plan_leaves:
    the executed plan's verdicts; plan_outscored: a feasible uniform way out scored better than
    the executed plan; plan_beaten: beaten()'s share for the executed plan; dwelling); per state
    outside every hazard, the control's (plan_feasible, plan_beaten, dwelling); per search
    setting (NAME, overrides) and state inside a hazard, its cold plan's feasible, leaves and
    reward_cost; and the episodes' violations."""
    agent = load_mpc_run(run, "planner's models to judge", seed=seed)
    planners = load_settings(run, searches, seed=seed)
    env = agent.make_env()
    slots = hazard_slots(env.observation_names)
    low, high = np.asarray(agent.action_space.low), np.asarray(agent.action_space.high)
    rng, control_rng = np.random.default_rng(seed), np.random.default_rng([seed, 1])
    rows = {"leave_feasible": [], "stay_feasible": [], "leaving": [], "trapped": [],
            "leave_scores_better": [], "plan_feasible": [], "plan_leaves": [],
            "plan_outscored": [], "plan_beaten": [], "dwelling": []}
    outside = {"plan_feasible": [], "plan_beaten": [], "dwelling": []}
    searched = {name: {"feasible": [], "leaves": [], "reward_cost": []} for name in planners}
    violations = []
    for k in range(episodes):
        episode = collect(agent, env, seed + k, plans=True)
        violations.append(episode["violations"])
        horizon = episode["plans"].shape[1]
        world, radius = episode["hazards"], episode["hazard_radius"]
        real, _, _ = pose_from_ego(episode["observations"][:, slots], world)
        dwelling = episode["violations"] >= DWELLING
        for t in np.flatnonzero(~episode["inside"][:-1]):
            sequences = control_rng.uniform(low, high, size=(samples, horizon, len(low)))
            scores = agent.score(episode["observations"][t],
                                 np.concatenate([episode["plans"][t][None], sequences]))
            feasible = np.asarray(scores["feasible"], dtype=bool)
            reward_cost = np.asarray(scores["reward_cost"], dtype=float)
            outside["plan_feasible"].append(bool(feasible[0]))
            outside["plan_beaten"].append(beaten(feasible[1:], reward_cost[1:], reward_cost[0]))
            outside["dwelling"].append(dwelling)
        for t in np.flatnonzero(episode["inside"][:-1]):
            hazard = world[np.argmin(np.hypot(*(world - real[t]).T))]
            sequences = rng.uniform(low, high, size=(samples, horizon, len(low)))
            # The executed plan first, judged alike, then the search settings' cold plans, then
            # the uniform ones.
            obs = episode["observations"][t]
            plans = [episode["plans"][t]] + [cold_plan(p, obs) for p in planners.values()]
            sequences = np.concatenate([np.stack(plans), sequences])
            feasible, leaves, reward_cost = escape_at(agent, obs, hazard, radius, slots, world,
                                                      sequences)
            for i, name in enumerate(planners, start=1):
                searched[name]["feasible"].append(bool(feasible[i]))
                searched[name]["leaves"].append(bool(leaves[i]))
                searched[name]["reward_cost"].append(float(reward_cost[i]))
            n = len(plans)
            feasible, leaves, reward_cost = (np.concatenate([a[:1], a[n:]])
                                             for a in (feasible, leaves, reward_cost))
            judged = judge_state(feasible[1:], leaves[1:], reward_cost[1:])
            rows["plan_outscored"].append(bool(judged.pop("best_way_out") < reward_cost[0]))
            for key, value in judged.items():
                rows[key].append(value)
            rows["plan_beaten"].append(beaten(feasible[1:], reward_cost[1:], reward_cost[0]))
            rows["plan_feasible"].append(bool(feasible[0]))
            rows["plan_leaves"].append(bool(leaves[0]))
            rows["dwelling"].append(dwelling)
    env.close()
    # Typed, so that a run that never entered a hazard gives empty arrays that still mask.
    arrays = lambda d: {key: np.array(value, dtype=bool if key in FLAGS else float)
                        for key, value in d.items()}
    searched = {name: {key: np.array(value, dtype=float if key == "reward_cost" else bool)
                       for key, value in record.items()} for name, record in searched.items()}
    return arrays(rows), arrays(outside), searched, violations


def summarise(rows, mask):
    """The states of mask pooled: means of the shares (over the states where defined); the
    executed plan's verdicts; and, over the states where it was feasible and stayed
    (staying_plans of them), the share where a feasible uniform way out outscored it."""
    n = int(mask.sum())
    if n == 0:
        return {"states": 0}
    mean = lambda key: float(np.nanmean(rows[key][mask])) if np.isfinite(
        rows[key][mask]).any() else None
    staying = mask & rows["plan_feasible"] & ~rows["plan_leaves"]
    return {"states": n, "leaving": mean("leaving"), "leave_feasible": mean("leave_feasible"),
            "stay_feasible": mean("stay_feasible"),
            "trapped": float(rows["trapped"][mask].mean()),
            "leave_scores_better": mean("leave_scores_better"),
            "plan_feasible": float(rows["plan_feasible"][mask].mean()),
            "plan_leaves": float(rows["plan_leaves"][mask].mean()),
            "staying_plans": int(staying.sum()),
            "plan_outscored": float(rows["plan_outscored"][staying].mean())
            if staying.any() else None,
            "staying_plan_beaten": pooled(rows["plan_beaten"][staying])}


def pooled(shares):
    """The mean of the shares that are defined (not NaN); None when none is."""
    shares = shares[np.isfinite(shares)]
    return float(shares.mean()) if shares.size else None


def summarise_outside(outside, mask):
    """The control's states of mask: their count, the executed plan's feasible share, and over the
    feasible plans (feasible_plans of them) the mean beaten share."""
    n = int(mask.sum())
    if n == 0:
        return {"states": 0}
    feasible = mask & outside["plan_feasible"]
    return {"states": n, "plan_feasible": float(outside["plan_feasible"][mask].mean()),
            "feasible_plans": int(feasible.sum()),
            "plan_beaten": pooled(outside["plan_beaten"][feasible])}


def summarise_search(record, mask):
    """A search setting's cold plans at the states of mask: their count, the shares feasible,
    leaving, and both, and the median reward cost."""
    n = int(mask.sum())
    if n == 0:
        return {"states": 0}
    feasible, leaves = record["feasible"][mask], record["leaves"][mask]
    return {"states": n, "feasible": float(feasible.mean()), "leaves": float(leaves.mean()),
            "feasible_and_leaves": float((feasible & leaves).mean()),
            "reward_cost": float(np.median(record["reward_cost"][mask]))}


def study(runs, episodes, seed, samples, searches=()):
    result = {}
    for run in runs:
        rows, outside, searched, violations = study_run(run, episodes, seed, samples, searches)
        dwelling, away = rows["dwelling"], outside["dwelling"]
        result[os.path.basename(os.path.normpath(run))] = {
            "violations": violations,
            "dwelling": summarise(rows, dwelling),
            "other": summarise(rows, ~dwelling),
            "outside": {"dwelling": summarise_outside(outside, away),
                        "other": summarise_outside(outside, ~away)},
            "searches": {name: {"dwelling": summarise_search(record, dwelling),
                                "other": summarise_search(record, ~dwelling)}
                         for name, record in searched.items()}}
    return result


def row(lead, states, cells, width):
    """A Markdown table row: the leading cells and the state count, then `cells()` or, when there
    are no states, `width` blank cells."""
    rest = cells() if states else [""] * width
    return "| " + " | ".join([*lead, str(states), *rest]) + " |"


def table(result, episodes, seed, samples):
    fmt = lambda v, spec: "-" if v is None else format(v, spec)
    lines = [f"Each run's agent, {episodes} episodes (reset with seed {seed} + k); at every state "
             f"inside a hazard, {samples} uniform action sequences scored by the run's objective. "
             f"Dwelling: episodes with {DWELLING} or more violations.", "",
             "Leaving scores better: the chance that a feasible leaving sequence's reward cost is "
             "lower than a feasible staying one's. Outscored: of the states where the executed "
             "plan was feasible and stayed (their count), the share where a feasible uniform "
             "way out scored better than it.", "",
             "| run | episodes | states in a hazard | sequences leaving | feasible, leaving | "
             "feasible, staying | trapped states | executed plan feasible | executed plan leaves "
             "| leaving scores better | staying plan outscored |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for run, entry in result.items():
        heavy = sum(v >= DWELLING for v in entry["violations"])
        for kind, count in (("dwelling", heavy), ("other", len(entry["violations"]) - heavy)):
            s = entry[kind]
            lines.append(row([run, f"{kind} ({count})"], s["states"], lambda: [
                fmt(s["leaving"], ".2f"), fmt(s["leave_feasible"], ".3f"),
                fmt(s["stay_feasible"], ".3f"), f"{s['trapped']:.2f}",
                f"{s['plan_feasible']:.2f}", f"{s['plan_leaves']:.2f}",
                fmt(s["leave_scores_better"], ".2f"),
                f"{fmt(s['plan_outscored'], '.2f')} ({s['staying_plans']})"], 8))
    lines += ["", "The search's quality, inside hazards against outside them (the control): the "
              "mean share of the feasible uniform sequences that score better than the executed "
              "plan, over the staying plans inside hazards and over the feasible plans outside "
              "all hazards (their counts).", "",
              "| run | episodes | inside: staying plans beaten by | outside: states | "
              "outside: executed plan feasible | outside: feasible plans beaten by |",
              "|---|---|---|---|---|---|"]
    for run, entry in result.items():
        for kind in ("dwelling", "other"):
            s, o = entry[kind], entry["outside"][kind]
            inside = f"{fmt(s.get('staying_plan_beaten'), '.3f')} ({s.get('staying_plans', 0)})"
            lines.append(row([run, kind, inside], o["states"], lambda: [
                f"{o['plan_feasible']:.2f}",
                f"{fmt(o['plan_beaten'], '.3f')} ({o['feasible_plans']})"], 2))
    if any(entry["searches"] for entry in result.values()):
        lines += ["", "Each search setting's planner at each state inside a hazard, planning from "
                  "it alone (cold), its plan judged by the run's objective.", "",
                  "| run | episodes | setting | states | plan feasible | plan leaves | feasible "
                  "and leaves | median reward cost |", "|---|---|---|---|---|---|---|---|"]
        for run, entry in result.items():
            for name, kinds in entry["searches"].items():
                for kind, s in kinds.items():
                    lines.append(row([run, kind, name], s["states"], lambda: [
                        f"{s['feasible']:.2f}", f"{s['leaves']:.2f}",
                        f"{s['feasible_and_leaves']:.2f}", f"{s['reward_cost']:.3f}"], 4))
    return "\n".join(lines) + "\n"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument("--seed", type=int, default=100)
    parser.add_argument("--samples", type=int, default=500)
    parser.add_argument("--search", action="append", default=[], type=parse_setting,
                        help="NAME=OVERRIDE[,OVERRIDE...]: a planner setting that plans cold at "
                             "each state inside a hazard (repeatable)")
    parser.add_argument("--out")
    args = parser.parse_args(argv)
    if args.episodes < 1 or args.samples < 1:
        parser.error(f"--episodes {args.episodes}, --samples {args.samples}: expected 1 or more")
    names = [name for name, _ in args.search]
    if len(set(names)) != len(names):
        parser.error(f"--search names repeat: {names}")
    result = study(args.runs, args.episodes, args.seed, args.samples, args.search)
    text = table(result, args.episodes, args.seed, args.samples)
    print(text, end="")
    if args.out:
        write_table(args.out, text, result)


if __name__ == "__main__":
    main()
