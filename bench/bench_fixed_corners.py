"""In-plane corner functions at fixed-free corners (``docs/method.md`` section 10.5): how the
in-plane field of the generated cases converges with and without them, and what they cost.

For ``cases/stiffened_panel.toml`` (184.8, 257, 1000 and 2500 Hz; resolutions 1.25, 1.875,
2.8) and ``cases/box_with_wall.toml`` with its folds held (189.2 and 600 Hz; resolutions 1.5,
2.25, 3.375; the folds are then the fixed ends its welds meet; they move since 2026-11-27): the
largest relative L2 change over the in-plane plates between successive resolutions, of
``(u, v)`` and of ``w``, on an 80 x 64 grid of each plate, and the processor time of each solve;
"without" replaces ``solver.in_plane.fixed_free_corners`` by a function that adds none.

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_fixed_corners.py [--quick]`` (about six
minutes; ``--quick``: the stiffened panel at 184.8 Hz only).
"""

from __future__ import annotations

import argparse
import copy
import sys
import time
import tomllib
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT)]

import solver.in_plane  # noqa: E402
from assembly import parse_case  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402

CASES = {"stiffened_panel": ([184.8, 257.0, 1000.0, 2500.0], (1.25, 1.875, 2.8)),
         "box_with_wall": ([189.2, 600.0], (1.5, 2.25, 3.375))}
HELD_FOLDS = {"box_with_wall"}


def fields(description: dict, frequency: float, resolution: float
           ) -> tuple[dict[str, tuple[np.ndarray, np.ndarray]], float]:
    """Per in-plane plate ``((u, v), w)`` on an 80 x 64 inner grid, and the solve's
    processor time."""
    description = copy.deepcopy(description)
    description["discretisation"]["resolution"] = resolution
    case = parse_case(description)
    start = time.process_time()
    solution = solve_assembly(case, frequency, residuals=False)
    seconds = time.process_time() - start
    out = {}
    for name in solution.system.membranes:
        lx, ly = case.plates[name].size
        gx, gy = np.meshgrid(np.linspace(0, lx, 82)[1:-1], np.linspace(0, ly, 66)[1:-1])
        points = np.column_stack([gx.ravel(), gy.ravel()])
        out[name] = (solution.in_plane(name, points), solution.plates[name].field(points)["w"])
    return out, seconds


def worst_change(coarse: dict, fine: dict, index: int) -> float:
    return max(np.linalg.norm(coarse[p][index] - fine[p][index]) / np.linalg.norm(fine[p][index])
               for p in fine)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    with_corners = solver.in_plane.fixed_free_corners
    print("largest change over the plates between resolutions (r1 -> r2, r2 -> r3) of (u, v) "
          "and of w; processor time of each solve")
    for name, (frequencies, resolutions) in CASES.items():
        if args.quick and name != "stiffened_panel":
            continue
        description = tomllib.loads((ROOT / "cases" / f"{name}.toml").read_text())
        for joint in description["joints"].values():
            if name in HELD_FOLDS and joint["kind"] == "hinge":
                joint["held"] = True
        for frequency in frequencies[:1] if args.quick else frequencies:
            for label, corners in (("without", lambda *a, **k: ()), ("with", with_corners)):
                solver.in_plane.fixed_free_corners = corners
                solved = [fields(description, frequency, r) for r in resolutions]
                u = [worst_change(a[0], b[0], 0) for a, b in zip(solved, solved[1:])]
                w = [worst_change(a[0], b[0], 1) for a, b in zip(solved, solved[1:])]
                times = " / ".join(f"{s:.2f}" for _, s in solved)
                print(f"  {name} {frequency:7.1f} Hz {label:7s}: (u, v) {u[0]:.1e}, {u[1]:.1e}; "
                      f"w {w[0]:.1e}, {w[1]:.1e}; {times} s", flush=True)
    solver.in_plane.fixed_free_corners = with_corners


if __name__ == "__main__":
    main()
