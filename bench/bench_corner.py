"""Three moving lines meeting at a box's corner against independent finite elements: the
trihedral corner of ``tests/test_meeting_corner.py`` (three 2 mm plates, rigid folds along the
three axes meeting at the origin, far edges simply supported, 1 N on A) and its reference
``tests/data/fem_corner.npz`` (``bench/fem_corner.py``).

By resolution, the worst plate's error of ``w`` and of ``(u, v)``, each with the error
estimate over the error on every plate (smallest to largest), and the seconds of the solve
with its estimate, for the rule and its history:

* **rule**: the members' edge waves reach three times the usual, growing with the resolution
  from 1.5 (``solver.line_ends.MEETING_END_REACH``, ``REACH_GROWTH_FROM``), and the lines,
  whose ends meet, have at least ``solver.joint_rules.end_layer_count`` functions from 1.5;
* **no floor**: the same reach, the count without that floor (until 2026-11-28);
* **fixed**: three times the reach, not growing (2026-11-27, before 0052e57), no floor;
* **usual**: the members reach as elsewhere, no floor.

With ``--floating``, the corner with every supported edge free in plane against
``tests/data/fem_corner_floating.npz``, at 300 Hz, to resolution 7.5: with the rule (its lines'
far ends slide, so their count has a floor, ``solver.joint_rules.end_layer_count``) and
without that floor (until 2026-11-28).

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_corner.py [--floating]`` (about six minutes;
one with ``--floating``).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from support import inner_grid  # noqa: E402
from test_meeting_corner import (  # noqa: E402
    FINITE_ELEMENTS,
    FLOATING_FINITE_ELEMENTS,
    PLATES,
    corner,
)

import solver.joint_rules  # noqa: E402
import solver.line_ends  # noqa: E402
from assembly import parse_case  # noqa: E402
from solver.estimate import estimate_error  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402

REACHES = {"rule": (solver.line_ends.MEETING_END_REACH, solver.line_ends.REACH_GROWTH_FROM),
           "fixed": (solver.line_ends.MEETING_END_REACH, math.inf),
           "usual": (1.0, math.inf)}
RUNS = {300.0: (1.0, 1.5, 2.25, 3.375, 5.0), 1000.0: (1.0, 1.5, 2.25, 3.375)}
FLOATING_RUNS = {300.0: (1.0, 1.5, 2.25, 3.375, 5.0, 7.5)}


def errors(frequency: float, resolution: float, reference, floating: bool = False) -> tuple:
    """``((w error, lowest and highest estimate ratio), (the same of (u, v)), seconds)``."""
    case = parse_case(corner(frequency, resolution, floating=floating))
    start = time.perf_counter()
    solution = solve_assembly(case, frequency)
    estimate = estimate_error(case, solution)
    seconds = time.perf_counter() - start
    rows = {"w": [], "uv": []}
    for name, (size, *_) in PLATES.items():
        points = inner_grid(*size)
        fields = {"w": solution.plates[name].field(points)["w"],
                  "uv": solution.in_plane(name, points)}
        estimates = {"w": estimate.plates, "uv": estimate.in_plane}
        for key, field in fields.items():
            exact = reference[f"{key}_{name}_{frequency:g}"]
            error = float(np.linalg.norm(field - exact) / np.linalg.norm(exact))
            rows[key].append((error, estimates[key][name] / error))
    summary = tuple((max(e for e, _ in rows[key]), min(r for _, r in rows[key]),
                     max(r for _, r in rows[key])) for key in ("w", "uv"))
    return (*summary, seconds)


def main() -> None:
    floating = sys.argv[1:] == ["--floating"]
    reference = np.load(FLOATING_FINITE_ELEMENTS if floating else FINITE_ELEMENTS)
    print(f"{'floating ' if floating else ''}trihedral corner against finite elements: worst "
          "plate's error of w, then of (u, v), (estimate / error over the plates); seconds of "
          "the solve and its estimate")
    floor = solver.joint_rules.END_LAYER_FROM
    reaches = {"rule": (*REACHES["rule"], floor), "no floor": (*REACHES["rule"], math.inf)}
    if not floating:
        reaches |= {label: (*REACHES[label], math.inf) for label in ("fixed", "usual")}
    for frequency, resolutions in (FLOATING_RUNS if floating else RUNS).items():
        for label, (reach, growth, floor_from) in reaches.items():
            solver.line_ends.MEETING_END_REACH, solver.line_ends.REACH_GROWTH_FROM = reach, growth
            solver.joint_rules.END_LAYER_FROM = floor_from
            for resolution in resolutions:
                (w, w_low, w_high), (uv, uv_low, uv_high), seconds = errors(
                    frequency, resolution, reference, floating)
                print(f"  {frequency:6.0f} Hz  {label:8s} {resolution:5.3g}: w {w:.1e} "
                      f"({w_low:.2f} to {w_high:.2f}); (u, v) {uv:.1e} ({uv_low:.2f} to "
                      f"{uv_high:.2f}); {seconds:.1f} s", flush=True)
    solver.line_ends.MEETING_END_REACH, solver.line_ends.REACH_GROWTH_FROM = REACHES["rule"]
    solver.joint_rules.END_LAYER_FROM = floor


if __name__ == "__main__":
    main()
