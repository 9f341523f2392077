"""A forward solve's square system: factorised by groups of joints against SuperLU or dense LAPACK.

A forward solve (no measurements) solves the square system ``[A; G] S = [-a; g]`` of the
joints' laws and constraints (``docs/method.md`` section 7.4). From
``solver.interface.GROUPED_LU_MIN_SIZE`` unknowns on it is factorised by groups
(``solver.grouped_lu.GroupedLU``); below, and as the fallback, densely when more than
``DENSE_FILL`` of it is filled, else by SuperLU. This bench times both ways on the same
systems, whatever their size:

* N x N grids of plates (``assembly.generate.plate_grid``) at 500 Hz;
* the stiffened panel of ``bench_moving_lines.py`` widened (``wider_panel``), with moving and
  with held lines.

Each line gives the interface unknowns, the time of the square solve by groups and by the
other path (processor time, best of ``--repeats``; the whole solve, equilibration and
refinement included), their ratio, and how far the two solutions' fields are apart: the
largest relative difference over the plates of w (and of the in-plane displacement where
there is one) on a 12 x 12 grid of points. Run::

    OPENBLAS_NUM_THREADS=1 python bench/bench_square_solve.py
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench"), str(ROOT / "tests")]

from bench_moving_lines import LOAD, LY, wider_panel
from support import folded_description

from assembly import parse_case
from assembly.generate import plate_grid
from solver import interface
from solver.substructure import solve_assembly


def cases(grids: list[int], bays: list[tuple[int, float, bool]]):
    """``(label, case, frequency)`` of every system benched."""
    for n in grids:
        yield f"{n} x {n} grid, 500 Hz", parse_case(plate_grid(n, n, frequency=500.0)), 500.0
    for n_bays, frequency, held in bays:
        plates, lines = wider_panel(n_bays)
        case = parse_case(folded_description(plates, lines, LOAD, frequency, held, LY))
        yield (f"{n_bays}-bay {'held' if held else 'moving'}-line panel, {frequency:.0f} Hz",
               case, frequency)


def captured_system(case, frequency):
    """The arguments of the forward solve's square system, as ``solve_assembly`` passes them."""
    captured = []
    square = interface._determined_solution

    def capture(*args):
        captured.append(args)
        return square(*args)

    interface._determined_solution = capture
    try:
        solve_assembly(case, frequency, residuals=False)
    finally:
        interface._determined_solution = square
    return captured[0]


def timed(arguments, repeats: int, grouped: bool) -> tuple[float, str]:
    """Best processor time of the square solve by groups or by the other path, and the path
    that served (seen, not predicted: the grouped solution kept, or a dense LU called)."""
    interface.GROUPED_LU_MIN_SIZE = 0 if grouped else 10**12
    served, dense_calls = [], []
    by_groups, dense_lu = interface._grouped_solution, scipy.linalg.lu_factor

    def spy_groups(*args):
        served.append(by_groups(*args))
        return served[-1]

    def spy_dense(*args, **kwargs):
        dense_calls.append(1)
        return dense_lu(*args, **kwargs)

    interface._grouped_solution, scipy.linalg.lu_factor = spy_groups, spy_dense
    try:
        best = np.inf
        for _ in range(repeats):
            start = time.process_time()
            interface._determined_solution(*arguments)
            best = min(best, time.process_time() - start)
    finally:
        interface._grouped_solution, scipy.linalg.lu_factor = by_groups, dense_lu
    if served and served[-1] is not None:
        return best, "groups"
    return best, "dense" if dense_calls else "SuperLU"


def field_difference(case, frequency) -> float:
    """Largest relative difference between the fields of the two paths, over the plates."""
    solutions = []
    for size in (0, 10**12):
        interface.GROUPED_LU_MIN_SIZE = size
        solutions.append(solve_assembly(case, frequency, residuals=False))
    worst = 0.0
    for pid, plate in case.plates.items():
        lx, ly = plate.size
        points = np.array([[x, y] for x in np.linspace(0.02 * lx, 0.98 * lx, 12)
                           for y in np.linspace(0.02 * ly, 0.98 * ly, 12)])
        for field in ("w", "in_plane"):
            a, b = (getattr(s, field)(pid, points) for s in solutions)
            if np.linalg.norm(b) > 0.0:
                worst = max(worst, float(np.linalg.norm(a - b) / np.linalg.norm(b)))
    return worst


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", type=int, nargs="*", default=[4, 6, 8, 10])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    bays = [(6, 2500.0, False), (12, 2500.0, False), (24, 1000.0, False), (24, 2500.0, True)]
    default = interface.GROUPED_LU_MIN_SIZE
    print("square forward solve (processor time, one BLAS thread, best of "
          f"{args.repeats}): by groups / the other path; vtcr takes groups from {default} "
          "unknowns on")
    try:
        for label, case, frequency in cases(args.grids, bays):
            arguments = captured_system(case, frequency)
            grouped, path = timed(arguments, args.repeats, grouped=True)
            other, other_path = timed(arguments, args.repeats, grouped=False)
            difference = field_difference(case, frequency)
            print(f"  {label:38s} {arguments[0]:6d} unknowns: {path} {grouped:.3f} s, "
                  f"{other_path} {other:.3f} s ({other / grouped:.2f}x); fields apart "
                  f"{difference:.1e}")
    finally:
        interface.GROUPED_LU_MIN_SIZE = default


if __name__ == "__main__":
    main()
