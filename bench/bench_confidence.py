"""Coverage of the confidence intervals of ``vtcr update`` (``updating.inverse.confidence``).

For each case, the noise-free measured field is computed once (``cases/four_plates.toml``: its
simulated experiment, the true structure at the finer measurement resolution; the Levy chains:
the exact series), then ``--realisations`` independent ±10 % uniform noise draws are added and
the whole updating run is repeated on each, as ``vtcr update`` runs it (localisation,
corrections, re-corrections, then the intervals at ``--level``). Per joint whose model is wrong,
printed: its field sensitivity (relative change of the measured values per 0.1 decade of
log10 k at the truth), how often it was corrected, the fraction of its intervals holding the
truth, with the binomial 95 % range of that fraction for a calibrated interval, how many were
one-sided, the median width of the two-sided ones, and the fraction of runs that end
converged (status 0)::

    OPENBLAS_NUM_THREADS=1 python bench/bench_confidence.py                  # 100 each, ~15 min
    OPENBLAS_NUM_THREADS=1 python bench/bench_confidence.py --realisations 20 --workers 2

Realisations run on ``--workers`` local processes (``updating.executor``); the numbers do not
depend on it.
"""

from __future__ import annotations

import argparse
import functools
import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy import stats

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from support import (  # noqa: E402
    chain_description,
    exact_measurements,
    levy_chain_experiment,
)

from assembly import load_case, parse_case  # noqa: E402
from updating.data.measurements import add_noise, simulate_measurements  # noqa: E402
from updating.executor import Executor  # noqa: E402
from updating.inverse.cost import ModifiedProblem, direct_interface  # noqa: E402
from updating.inverse.strategy import update_joints  # noqa: E402

NOISE = 0.1


def levy_chain_case(truths, lengths):
    """A chain of plates, every model joint at log10 k = 2.5, measured by its exact Levy field
    with the ``truths`` (``test_assemblies.levy_chain_experiment``)."""
    case, exact = levy_chain_experiment(truths, lengths, noise=NOISE)
    return case, exact_measurements(case, exact)


def simulated_chain_case(model, truth, identify):
    """Two plates whose joint is ``model`` in the description and ``truth`` in the simulated
    experiment (the finer measurement resolution, ±10 % noise), the parameters ``identify``
    names identified."""
    description = chain_description([{"kind": "coplanar", **model}], 1.0,
                                    force=(0, 0.12, 0.31))
    description["truth"] = {"joints": {"G1": truth}}
    description["measurement"] = {"spacing": 0.08, "noise": NOISE}
    description["updating"] = {"identify": ["stiffness", identify], "bounds": [-1.0, 6.0]}
    case = parse_case(description)
    return case, simulate_measurements(case, noise=0.0)


# stiffness and loss factor both wrong (log10 k 2.0 and 0.02 against 3.0 and 0.3)
damped_chain_case = functools.partial(
    simulated_chain_case, {"log10_stiffness": 2.0, "loss_factor": 0.02},
    {"log10_stiffness": 3.0, "loss_factor": 0.3}, "damping")
# stiffness and line mass both wrong (2.0 and 0.02 kg/m against 3.0 and 0.1 kg/m)
massive_chain_case = functools.partial(
    simulated_chain_case, {"log10_stiffness": 2.0, "loss_factor": 0.05, "mass": 0.02},
    {"log10_stiffness": 3.0, "mass": 0.1}, "mass")


def four_plates_case():
    case = load_case(ROOT / "cases" / "four_plates.toml")
    return case, simulate_measurements(case, noise=0.0)


CASES = {
    "four_plates": four_plates_case,
    "two-plate Levy chain": functools.partial(levy_chain_case, (2.0,), (0.5, 0.45)),
    "three-plate Levy chain": functools.partial(levy_chain_case, (2.0, 3.0), (0.5, 0.45, 0.55)),
    "damped two-plate chain": damped_chain_case,
    "massive two-plate chain": massive_chain_case,
}


def sensitivity(problem, truth_parameters, joint):
    """Relative change of the model's measured values per +0.1 decade of ``joint`` at the
    truth (all frequencies together)."""
    def values(parameters):
        out = []
        for freq in problem.frequencies.values():
            s = direct_interface(freq.system, parameters, problem.alpha)
            out += [op.residual(s) for op in freq.operators]
        return np.concatenate(out)

    moved = {j: dict(p) for j, p in truth_parameters.items()}
    moved[joint]["log10_stiffness"] += 0.1
    base = values(truth_parameters)
    return float(np.linalg.norm(values(moved) - base) / np.linalg.norm(base))


@functools.lru_cache(maxsize=None)
def _problem(name, r=None):
    """Case ``name``, its noise-free data and its modified problem; ``r`` a number for the
    paper's weights (default: the description's, scale-free unless it gives r)."""
    case, clean = CASES[name]()
    if r is not None:
        case = case.model_copy(update={"updating": case.updating.model_copy(update={"r": r})})
    return case, clean, ModifiedProblem(case, clean)


def realisation(name, level, r, seed):
    """One noisy data set of case ``name``: the updating run and its intervals (a task)."""
    case, clean, problem = _problem(name, r)
    rng = np.random.default_rng(seed)
    data = {f: [add_noise(w, NOISE, rng) for _, w in clean.data[f].values()]
            for f in clean.frequencies}
    settings = case.updating.model_copy(update={"confidence": level})
    t0 = time.perf_counter()
    result = update_joints(problem.with_data(data), settings, noise=NOISE)
    intervals = {(j, "log10_stiffness"): i for j, i in result.intervals.items()}
    intervals.update(result.parameter_intervals)
    return ({key: (i.low, i.high, i.kind) for key, i in intervals.items()},
            time.perf_counter() - t0, result.status)


def binomial_range(n, level):
    """The central 95 % range of the covered fraction of ``n`` calibrated intervals."""
    return (stats.binom.ppf(0.025, n, level) / n, stats.binom.ppf(0.975, n, level) / n)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--realisations", type=int, default=100)
    parser.add_argument("--level", type=float, default=0.9)
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--first-seed", type=int, default=1000)
    parser.add_argument("--r", type=float, default=None,
                        help="the paper's weights with this r (default: each case's own)")
    args = parser.parse_args()
    print(f"{args.realisations} realisations of ±{100 * NOISE:g} % uniform noise per case, "
          f"intervals at {args.level:g}")
    header = (f"{'case':<24} {'joint':<8} {'truth':>5} {'sens. %/0.1':>11} {'corrected':>9} "
              f"{'coverage':>8} {'calibrated 95 % range':>21} {'one-sided':>9} "
              f"{'median width':>12} {'s/run':>6} {'converged':>9}")
    print(header, flush=True)
    with Executor(args.workers) as executor:
        for name_of_case in args.cases:
            case, _, problem = _problem(name_of_case, args.r)
            names = (["log10_stiffness"]
                     + (["loss_factor"] if "damping" in case.updating.identify else [])
                     + (["mass"] if "mass" in case.updating.identify else []))
            truth = {(j, n): getattr(case.truth.joints[j], n) for j in case.truth.joints
                     for n in names if getattr(case.truth.joints[j], n) is not None}
            truth_parameters = problem.initial_parameters()
            for (j, n), value in truth.items():
                truth_parameters[j][n] = value
            seeds = range(args.first_seed, args.first_seed + args.realisations)
            results = executor.map(functools.partial(realisation, name_of_case, args.level,
                                                     args.r),
                                   seeds)
            seconds = np.median([t for _, t, _ in results])
            converged = np.mean([status == 0 for *_, status in results])
            for (joint, name), value in truth.items():
                if value == getattr(case.joints[joint], name):
                    continue  # a right parameter: its intervals are not the question
                intervals = [r[joint, name] for r, *_ in results if (joint, name) in r]
                held = [(lo is None or lo <= value) and (hi is None or value <= hi)
                        for lo, hi, _ in intervals]
                widths = [hi - lo for lo, hi, kind in intervals if kind == "two-sided"]
                n = len(intervals)
                lo_range, hi_range = binomial_range(n, args.level) if n else (math.nan,) * 2
                label = {"log10_stiffness": joint, "loss_factor": f"{joint} eta",
                         "mass": f"{joint} mu"}[name]
                sens = (f"{100 * sensitivity(problem, truth_parameters, joint):>11.2f}"
                        if name == "log10_stiffness" else f"{'-':>11}")
                print(
                    f"{name_of_case:<24} {label:<8} {value:>5.2f} {sens} "
                    f"{n:>9} {np.mean(held) if n else math.nan:>8.2f} "
                    f"{f'[{lo_range:.2f}, {hi_range:.2f}]':>21} "
                    f"{sum(k != 'two-sided' for *_, k in intervals):>9} "
                    f"{np.median(widths) if widths else math.nan:>12.3f} {seconds:>6.1f} "
                    f"{converged:>9.2f}",
                    flush=True)


if __name__ == "__main__":
    main()
