"""Corner functions at clamped-free corners (``solver.plate_corners``): what they change, what
they cost, and how the result compares with finite elements.

* **A plate clamped on one edge**: 0.3 x 0.4 m, 2 mm steel (loss factor 0.01), clamped on
  x = 0, free elsewhere, 1 N/m of Kirchhoff shear on x = 0.3 (two clamped-free corners). At
  300 Hz, 1 kHz and 3 kHz and resolutions 1, 1.5, 2.25, 3.4: the change of ``w`` on a 15 x 19
  grid between resolutions, with and without the corner functions; processor time of a solve
  and unknowns. With scikit-fem installed, at 300 Hz and 1 kHz ``w`` is also compared on the
  same grid with an Argyris finite-element reference written apart from the solver
  (``bench/fem_clamped.py``, corner-refined meshes, about 4e4 unknowns: 1e-8 or better).
* **A stiffener with clamped ends**: the T junction of ``tests/test_moving_lines.py`` with its
  ends clamped (its stiffener T1 has four clamped-free corners) at 300 Hz and 1 kHz: the change
  of T1's ``w`` between resolutions 1, 1.5, 2.25, 3.4 and the time of a solve, with and
  without the functions (``solver.problems.plate_wedges`` switched off for the comparison).

Run: ``OPENBLAS_NUM_THREADS=1 python bench/bench_clamped_corners.py`` (about two minutes, and
two more for the finite elements; ``--no-fem`` skips them).
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "bench")]

from support import folded_w  # noqa: E402
from test_moving_lines import LY, SHAPES, clamped_t_junction  # noqa: E402

import solver.problems  # noqa: E402
from assembly import parse_case  # noqa: E402
from assembly.geometry import EDGE_NAMES  # noqa: E402
from solver.plate import EdgeCondition, EdgeLoad, PlateProblem, solve_plate  # noqa: E402
from solver.plate_corners import clamped_free_wedges  # noqa: E402
from solver.rays import WedgeBasis, automatic_ray_counts, build_ray_basis  # noqa: E402
from solver.substructure import solve_assembly  # noqa: E402

E, RHO, H, NU, ETA = 210e9, 7800.0, 0.002, 0.3, 0.01
SIZE = (0.3, 0.4)
GRID = np.array([(a, b) for a in np.linspace(0.01, 0.29, 15) for b in np.linspace(0.01, 0.39, 19)])
RESOLUTIONS = (1.0, 1.5, 2.25, 3.4)


def clamped_plate(frequency: float) -> PlateProblem:
    d = E * H**3 / (12 * (1 - NU**2)) * (1 + 1j * ETA)
    edges = {"left": EdgeCondition("clamped"), "right": EdgeCondition("free", shear=EdgeLoad(1.0)),
             "top": EdgeCondition("free"), "bottom": EdgeCondition("free")}
    return PlateProblem(SIZE, d, NU, RHO * H, 2 * math.pi * frequency, edges)


def plate_solve(problem: PlateProblem, resolution: float, wedges: bool):
    """``(w on GRID, seconds, unknowns)``; the time is the best of three."""
    times = []
    for _ in range(3):
        start = time.process_time()
        rays = build_ray_basis(SIZE, problem.kappa,
                               automatic_ray_counts(problem.kappa.real, SIZE, resolution))
        basis = rays
        if wedges:
            families = clamped_free_wedges(SIZE, [problem.condition(n).kind for n in EDGE_NAMES],
                                           NU)
            basis = WedgeBasis.extending(rays, problem.kappa, families)
        solution = solve_plate(problem, basis)
        times.append(time.process_time() - start)
    return solution.field(GRID)["w"], min(times), basis.n_dof


def change(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def plate_study(frequencies: list[float], fem: bool) -> None:
    print("A plate clamped on one edge (0.3 x 0.4 m, 2 mm): change of w between resolutions "
          f"{' -> '.join(map(str, RESOLUTIONS))}; time of one solve at 2.25 (unknowns)")
    for frequency in frequencies:
        problem = clamped_plate(frequency)
        finest = {}
        for wedges in (False, True):
            fields, seconds = [], {}
            for resolution in RESOLUTIONS:
                w, t, n = plate_solve(problem, resolution, wedges)
                fields.append(w)
                seconds[resolution] = (t, n)
            changes = ", ".join(f"{change(b, a):.1e}" for a, b in zip(fields[1:], fields[:-1]))
            t, n = seconds[2.25]
            label = "with corner functions" if wedges else "rays alone"
            print(f"  {frequency:6.0f} Hz, {label:21s}: {changes}; {t:.3f} s ({n})")
            finest[wedges] = fields
        if fem and frequency <= 1000.0:
            from fem_clamped import clamped_plate_reference

            reference, run = clamped_plate_reference(frequency, GRID)
            for wedges in (False, True):
                errors = ", ".join(f"{change(w, reference):.1e}" for w in finest[wedges])
                label = "with corner functions" if wedges else "rays alone"
                print(f"  {frequency:6.0f} Hz, {label:21s} against Argyris FE ({run}): "
                      f"{errors}")


def stiffener_study(frequencies: list[float]) -> None:
    print("A stiffener with clamped ends (the T junction of tests/test_moving_lines.py): "
          "change of T1's w between resolutions; time of one solve at 1.5")
    plates = SHAPES["T"][0]
    wedges = solver.problems.plate_wedges
    for frequency in frequencies:
        for on in (False, True):
            solver.problems.plate_wedges = wedges if on else (lambda *args: ())
            fields, seconds = [], 0.0
            for resolution in RESOLUTIONS:
                case = parse_case(clamped_t_junction(frequency, resolution))
                times = []
                for _ in range(3 if resolution == 1.5 else 1):
                    start = time.process_time()
                    solution = solve_assembly(case, frequency, residuals=False)
                    times.append(time.process_time() - start)
                if resolution == 1.5:
                    seconds = min(times)
                fields.append(folded_w(solution, plates, LY)["T1"])
            changes = ", ".join(f"{change(b, a):.1e}" for a, b in zip(fields[1:], fields[:-1]))
            label = "with corner functions" if on else "without"
            print(f"  {frequency:6.0f} Hz, {label:21s}: {changes}; {seconds:.2f} s")
    solver.problems.plate_wedges = wedges


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--no-fem", action="store_true", help="skip the finite elements")
    args = parser.parse_args()
    fem = not args.no_fem and importlib.util.find_spec("skfem") is not None
    if not args.no_fem and not fem:
        print("scikit-fem is not installed: no finite-element reference")
    plate_study([300.0, 1000.0, 3000.0], fem)
    stiffener_study([300.0, 1000.0])


if __name__ == "__main__":
    main()
