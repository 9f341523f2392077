"""Moving lines with free ends (``docs/method.md`` section 10.4): what the members' longer edge
reach (``solver.problems.FREE_END_REACH``) buys and costs, on the bracket of
``tests/test_free_ends.py`` (2 mm steel legs 0.4 and 0.3 m folded at 90 degrees, a lossy weld,
far edges simply supported, ends free, 1 N on the first leg).

* **refinement**: the worst plate's relative L2 change of ``w`` and of ``(u, v)`` on a 15 x 15
  grid between resolutions 1.5 -> 2.25 -> 3.375, with the rule and with the usual reach
  (``FREE_END_REACH`` = 1), and for the held line;
* **cost**: one solve at resolution 1.5 (processor time of one BLAS thread, best of three) and
  its unknowns, with the rule, with the usual reach and held;
* **finite elements** (``--finite-elements``): the bracket with a rigid line at 300 Hz against
  ``tests/data/fem_fold_free_ends.npz``, worst plate's error of ``w`` and the error estimate
  over it on every plate, by resolution, with the line's Legendre count following its
  members' reach (:func:`solver.layout.answered_wavenumber`) and stopped at the usual one, as
  until 2026-11-27 (about a minute).

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_free_ends.py [--quick | --finite-elements]``
(about two minutes; ``--quick`` stops at 1 kHz).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from support import inner_grid  # noqa: E402
from test_free_ends import LY, PLATES, _bracket, _errors_and_estimates  # noqa: E402

import solver.layout  # noqa: E402
import solver.problems  # noqa: E402
from assembly import parse_case  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402

RULE = solver.problems.FREE_END_REACH
MODELS = {"rule": (RULE, None), "usual reach": (1.0, None), "held": (RULE, True)}


def fields(frequency: float, resolution: float, held: bool | None) -> dict:
    """Per plate ``(w, (u, v))`` on a 15 x 15 grid."""
    solution = solve_assembly(parse_case(_bracket(frequency, resolution, held)), frequency,
                              residuals=False)
    out = {}
    for name, (length, *_) in PLATES.items():
        points = inner_grid(length, LY)
        out[name] = (solution.plates[name].field(points)["w"], solution.in_plane(name, points))
    return out


def change(a: dict, b: dict, component: int) -> float:
    """The worst plate's relative L2 difference of one component (0: w, 1: (u, v))."""
    worst = 0.0
    for name in a:
        norm = np.linalg.norm(b[name][component])
        if norm > 0.0:
            worst = max(worst, np.linalg.norm(a[name][component] - b[name][component]) / norm)
    return worst


def finite_elements() -> None:
    """The rigid bracket against the finite elements, by resolution, the line's count
    following its members' reach and then stopped at the usual reach."""
    print("against finite elements (300 Hz, rigid line): worst plate's error of w; "
          "estimate / error over the plates")
    following = solver.layout.answered_wavenumber
    usual = {"members' reach": following,
             "usual reach": solver.layout.members_wavenumber}
    for label, answered in usual.items():
        solver.layout.answered_wavenumber = answered
        for resolution in (1.0, 1.5, 2.25, 3.375, 5.0):
            pairs = _errors_and_estimates(resolution)
            ratios = [estimate / true for true, estimate in pairs]
            print(f"  {label:15s} {resolution:5.3g}: {max(t for t, _ in pairs):.1e}; "
                  f"{min(ratios):.2f} to {max(ratios):.2f}", flush=True)
    solver.layout.answered_wavenumber = following


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--finite-elements", action="store_true")
    args = parser.parse_args()
    if args.finite_elements:
        return finite_elements()
    frequencies = (300.0, 1000.0) if args.quick else (300.0, 1000.0, 3000.0)
    print("refinement: worst plate's change of w ; (u, v) between resolutions "
          "1.5 -> 2.25 -> 3.375")
    for frequency in frequencies:
        for label, (reach, held) in MODELS.items():
            solver.problems.FREE_END_REACH = reach
            steps = [fields(frequency, r, held) for r in (1.5, 2.25, 3.375)]
            w = ", ".join(f"{change(a, b, 0):.1e}" for a, b in zip(steps, steps[1:]))
            uv = ("" if held else "; " + ", ".join(f"{change(a, b, 1):.1e}"
                                                    for a, b in zip(steps, steps[1:])))
            print(f"  {frequency:6.0f} Hz  {label:12s} {w}{uv}", flush=True)
    print("cost: one solve at resolution 1.5 (processor time, best of three; unknowns)")
    for frequency in frequencies:
        row = []
        for label, (reach, held) in MODELS.items():
            solver.problems.FREE_END_REACH = reach
            case = parse_case(_bracket(frequency, 1.5, held))
            times = []
            for _ in range(3):
                start = time.process_time()
                solution = solve_assembly(case, frequency, residuals=False)
                times.append(time.process_time() - start)
            row.append((label, min(times), solution.n_unknowns))
        ratios = (f"rule / usual {row[0][1] / row[1][1]:.1f}x, "
                  f"rule / held {row[0][1] / row[2][1]:.1f}x")
        print(f"  {frequency:6.0f} Hz  " + "; ".join(f"{label} {t:.2f} s ({n})"
                                                    for label, t, n in row) + f"; {ratios}",
              flush=True)
    solver.problems.FREE_END_REACH = RULE


if __name__ == "__main__":
    main()
