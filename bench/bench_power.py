"""Detection power of ``vtcr update`` across structure sizes: the scale-free weights against the
paper's (``r = 0.8``, ``alpha = 1/N_joints``), on the same scenarios and data.

Per size (plate grids n x n, and ``cases/stiffened_panel.toml`` measured on its skin only),
``--scenarios`` random scenarios; every fifth is a right model, the others have 1-3 wrong
joints (one on the panel) at random places, wrong by 0.5-1.5 decade either way; one or two unit
point forces at random places; 1-3 frequencies; ±10 % uniform noise. The experiment is
simulated with the true joints at the description's finer measurement resolution. Both weight
rules run on the same measured data, as ``vtcr update`` runs them (localisation, corrections,
re-corrections, then the 90 % intervals). Printed per size and rule:

* ``recall``: of the wrong joints that ``vtcr plan`` calls identifiable (the truth outside the
  interval it expects at the model value, with the default weights, as a user runs it), the
  fraction found: corrected towards the truth, to within half of the error
  (``|final - truth| < |model - truth| / 2``) or with an interval that holds the truth;
* ``right moved``: right joints moved by more than 0.2 decade, per run;
* ``coverage``: the fraction of the corrected joints' 90 % intervals that hold the truth (right
  joints that were corrected included), with the binomial 95 % range of a calibrated interval;
* ``converged``: the fraction of runs ending with status 0;
* ``median s``: the median wall time of one update (set-up included, plan excluded).

Usage::

    OPENBLAS_NUM_THREADS=1 python bench/bench_power.py                       # every size
    OPENBLAS_NUM_THREADS=1 python bench/bench_power.py --sizes 2 4 --scenarios 10 --workers 2

Scenarios run on ``--workers`` local processes (``updating.executor``); the numbers do not
depend on it.
"""

from __future__ import annotations

import argparse
import copy
import math
import sys
import time
import tomllib
from pathlib import Path

import numpy as np
from scipy import stats

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from assembly import parse_case  # noqa: E402
from assembly.generate import grid_joint_ids, plate_grid  # noqa: E402
from updating.data.measurements import simulate_measurements  # noqa: E402
from updating.executor import Executor  # noqa: E402
from updating.inverse.cost import ModifiedProblem  # noqa: E402
from updating.inverse.plan import identifiability_plan  # noqa: E402
from updating.inverse.strategy import excess_ratios, update_joints  # noqa: E402

NOISE = 0.1
FREQUENCIES = (180.0, 210.0, 250.0, 290.0, 330.0)  # Hz, the grids' band (0.5 x 0.4 m, 1 mm steel)
PANEL_FREQUENCIES = (184.8, 230.0, 257.0)
RULES = {"scale-free": {"r": "auto"}, "paper r = 0.8": {"r": 0.8}}
MOVED = 0.2  # decade: a right joint moved by more is a false correction


def grid_scenario(n, index, seed):
    """Description of scenario ``index`` of the n x n grid (a plain dict), and its truths."""
    rng = np.random.default_rng([seed, n, index])
    ids = grid_joint_ids(n, n)
    wrong = 0 if index % 5 == 4 else int(rng.integers(1, min(3, len(ids) - 1) + 1))
    truth = {str(j): round(2.0 + float(rng.choice([-1, 1]) * rng.uniform(0.5, 1.5)), 2)
             for j in rng.choice(ids, wrong, replace=False)}
    frequencies = sorted(float(f) for f in rng.choice(FREQUENCIES, int(rng.integers(1, 4)),
                                                      replace=False))
    description = plate_grid(n, n, truth=truth, noise=NOISE, seed=int(rng.integers(1, 10**6)),
                             frequency=frequencies if len(frequencies) > 1 else frequencies[0])
    description["loads"] = [
        {"kind": "point_force", "plate": f"P{rng.integers(1, n + 1)}_{rng.integers(1, n + 1)}",
         "at": [round(float(rng.uniform(0.05, 0.45)), 3), round(float(rng.uniform(0.05, 0.35)), 3)],
         "amplitude": 1.0} for _ in range(int(rng.integers(1, 3)))]
    return description, truth


def panel_scenario(index, seed):
    """Scenario ``index`` of the stiffened panel: one weld member wrong (or none), a random
    force on the skin, 1-3 of its frequencies; measured on the skin only, as the case is."""
    rng = np.random.default_rng([seed, 99, index])
    description = tomllib.loads((ROOT / "cases" / "stiffened_panel.toml").read_text())
    members = [("W1", "T1"), ("W2", "T2"), ("W3", "T3")]
    truth, truths = {}, {}
    if index % 5 != 4:
        weld, member = members[int(rng.integers(len(members)))]
        value = round(3.5 + float(rng.choice([-1, 1]) * rng.uniform(0.5, 1.5)), 2)
        truth[weld] = {"log10_stiffness": {member: value}}
        truths[f"{weld}.{member}"] = value
    description["truth"] = {"joints": truth}
    frequencies = sorted(float(f) for f in rng.choice(PANEL_FREQUENCIES, int(rng.integers(1, 4)),
                                                      replace=False))
    description["frequencies"] = frequencies
    description["loads"] = [{"kind": "point_force", "plate": f"B{rng.integers(1, 5)}",
                             "at": [round(float(rng.uniform(0.05, 0.45)), 3),
                                    round(float(rng.uniform(0.05, 0.35)), 3)],
                             "amplitude": 1.0}]
    description["measurement"]["seed"] = int(rng.integers(1, 10**6))
    return description, truths


def _found(start, final, truth, interval):
    """A wrong joint is found when it was corrected towards its truth, to within half of its
    error or with an interval that holds the truth (a near-hinge corrected to 0.1 with
    ``<= 1.1``, truth 0.85, is found: below about 1 its value hardly moves the field)."""
    towards = (final - start) * (truth - start) > 0.0
    return interval is not None and towards and (
        abs(final - truth) < 0.5 * abs(start - truth) or interval.holds(truth))


def run_scenario(task):
    """One scenario under the ``rules`` (names of :data:`RULES`): per rule, a dict of what
    the table counts; ``balance`` overrides the scale-free rule's ``[updating] balance``."""
    size, index, seed, rules, balance = task
    description, truths = (panel_scenario(index, seed) if size == "panel"
                           else grid_scenario(size, index, seed))
    cases = {}
    for name in rules:
        rule = copy.deepcopy(description)
        rule.setdefault("updating", {}).update(RULES[name])
        if balance is not None and RULES[name]["r"] == "auto":
            rule["updating"]["balance"] = balance
        cases[name] = parse_case(rule)
    planned = parse_case(description)  # the default weights, as a user's vtcr plan
    measurements = simulate_measurements(planned)  # the same data for every rule
    identifiable, plans = set(), {}
    if truths:  # the plan reads the measured points, not their values
        plans, _, _ = identifiability_plan(planned, measurements, joints=list(truths))
        identifiable = {j for j, plan in plans.items() if not plan.interval.holds(truths[j])}
    out = {}
    for name, case in cases.items():
        t0 = time.perf_counter()
        problem = ModifiedProblem(case, measurements)
        result = update_joints(problem, case.updating, noise=case.measurement.noise)
        seconds = time.perf_counter() - t0
        start = problem.initial_parameters()
        final = result.parameters
        found = [j for j in identifiable if _found(start[j]["log10_stiffness"],
                                                   final[j]["log10_stiffness"], truths[j],
                                                   result.intervals.get(j))]
        first = excess_ratios(result.steps[0], case.updating.stop_ratio)
        missed = [(j, truths[j], final[j]["log10_stiffness"], plans[j].interval.text,
                   first[j], max(first, key=first.get)) for j in identifiable if j not in found]
        moved = [j for j in final if j not in truths and abs(
            final[j]["log10_stiffness"] - start[j]["log10_stiffness"]) > MOVED]
        held = [interval.holds(truths.get(j, start[j]["log10_stiffness"]))
                for j, interval in result.intervals.items()]
        out[name] = {"identifiable": len(identifiable), "found": len(found),
                     "moved": len(moved), "held": held, "status": result.status,
                     "seconds": seconds, "wrong": len(truths), "missed": missed,
                     "status_message": result.message}
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", nargs="+", default=["2", "4", "6", "10", "panel"],
                        help="grid sizes n (n x n plates) and/or 'panel'")
    parser.add_argument("--scenarios", type=int, default=20)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--rules", nargs="+", default=list(RULES), choices=list(RULES))
    parser.add_argument("--balance", type=float, default=None,
                        help="the scale-free rule's [updating] balance (default the default)")
    parser.add_argument("--details", action="store_true",
                        help="print each missed identifiable joint: truth, final value, the "
                             "plan's expected interval, its first excess and the largest one")
    args = parser.parse_args()
    sizes = [s if s == "panel" else int(s) for s in args.sizes]
    print(f"{'size':>6} {'rule':>15} {'recall':>12} {'right moved':>12} {'coverage':>22} "
          f"{'converged':>10} {'median s':>9}", flush=True)
    with Executor(args.workers) as executor:
        for size in sizes:
            tasks = [(size, i, args.seed, args.rules, args.balance)
                     for i in range(args.scenarios)]
            results = executor.map(run_scenario, tasks)
            label = "panel" if size == "panel" else f"{size}x{size}"
            for name in args.rules:
                rows = [r[name] for r in results]
                identifiable = sum(r["identifiable"] for r in rows)
                found = sum(r["found"] for r in rows)
                held = [h for r in rows for h in r["held"]]
                n = len(held)
                low, high = ((stats.binom.ppf(0.025, n, 0.9) / n,
                              stats.binom.ppf(0.975, n, 0.9) / n) if n else (math.nan, math.nan))
                print(f"{label:>6} {name:>15} {f'{found}/{identifiable}':>7} "
                      f"{found / max(identifiable, 1):>4.2f} "
                      f"{np.mean([r['moved'] for r in rows]):>12.2f} "
                      f"{f'{sum(held)}/{n}':>8} {sum(held) / max(n, 1):.2f} "
                      f"[{low:.2f}, {high:.2f}] "
                      f"{np.mean([r['status'] == 0 for r in rows]):>10.2f} "
                      f"{np.median([r['seconds'] for r in rows]):>9.1f}", flush=True)
                if args.details:
                    for index, r in enumerate(rows):
                        for joint, truth, final, planned, excess, most in r["missed"]:
                            print(f"    scenario {index}: {joint} true {truth:.2f} -> "
                                  f"{final:.2f}; plan at the model: {planned}; first excess "
                                  f"{excess:.2f} (largest: {most}); status {r['status']}",
                                  flush=True)


if __name__ == "__main__":
    main()
