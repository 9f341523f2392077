"""VTCR versus Argyris finite elements on the reference plate, 100 Hz to 1.6 kHz.

For each frequency: the smallest VTCR discretisation (resolution factor on the ray-count
rule) and the coarsest Argyris mesh whose relative L2 error of w on a 10 x 10 interior grid
is below 1 % against the Navier series; their unknowns, assembly and solve times (best of
``REPEATS`` runs, both measured here in the same process), and the end-to-end time ratio.

Plate: steel, h = 1 mm, eta = 0.01, 0.5 x 0.4 m, simply supported, 1 N at (0.12, 0.31).

Run: ``pip install -e '.[bench]' && OPENBLAS_NUM_THREADS=1 python bench/bench_plate.py``
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from fem_argyris import fem_until_accurate, navier_reference, solve_fem  # noqa: E402

from solver.kirchhoff import complex_bending_stiffness  # noqa: E402
from solver.plate import (  # noqa: E402
    EdgeCondition,
    PlateProblem,
    PointForce,
    assemble_plate,
    boundary_traces,
    evaluate_field,
    solve_dense,
)
from solver.rays import EDGES, automatic_ray_counts, build_ray_basis  # noqa: E402

E, NU, RHO, H, ETA = 210e9, 0.3, 7800.0, 1e-3, 0.01
LX, LY = 0.5, 0.4
FORCE_AT = (0.12, 0.31)
TARGET = 0.01
REPEATS = 5
FREQUENCIES = (100.0, 155.0, 200.0, 400.0, 800.0, 1600.0)
GRID = np.array([(x, y) for x in np.linspace(0, LX, 12)[1:-1] for y in np.linspace(0, LY, 12)[1:-1]])


def vtcr_solve(frequency, resolution):
    """One VTCR solve; returns (w on the grid, unknowns, assembly time, solve time)."""
    t0 = time.perf_counter()
    problem = PlateProblem((LX, LY), complex_bending_stiffness(E, H, NU, ETA), NU, RHO * H,
                           2 * np.pi * frequency,
                           {e: EdgeCondition("simply_supported") for e in EDGES},
                           (PointForce(FORCE_AT, 1.0),))
    counts = automatic_ray_counts(problem.kappa.real, problem.size, resolution)
    basis = build_ray_basis(problem.size, problem.kappa, counts)
    K, F = assemble_plate(problem, boundary_traces(problem, basis))
    t1 = time.perf_counter()
    x, _ = solve_dense(K, F)
    t2 = time.perf_counter()
    w = evaluate_field(problem, basis, x, GRID)["w"]
    return w, basis.n_dof, t1 - t0, t2 - t1


def best_of(run):
    results = [run() for _ in range(REPEATS)]
    return min(results, key=lambda r: r[-2] + r[-1])


def main():
    print(__doc__.split("\n\n")[0])
    print(f"target {TARGET:.0%}; times: best of {REPEATS}\n")
    header = (f"{'f [Hz]':>7} | {'VTCR dof':>8} {'err':>8} {'asm ms':>7} {'solve ms':>8} | "
              f"{'FEM dof':>7} {'err':>8} {'asm ms':>7} {'solve ms':>8} | {'ratio':>6}")
    print(header)
    print("-" * len(header))
    for frequency in FREQUENCIES:
        reference = navier_reference(LX, LY, E, NU, RHO, H, ETA, frequency, FORCE_AT, 1.0, GRID)
        for resolution in np.arange(0.5, 3.0, 0.05):
            w, n, *_ = vtcr_solve(frequency, resolution)
            error = np.linalg.norm(w - reference) / np.linalg.norm(reference)
            if error < TARGET:
                break
        _, n, t_asm, t_solve = best_of(lambda: vtcr_solve(frequency, resolution))
        fem, _ = fem_until_accurate(reference, GRID, LX, LY, E, NU, RHO, H, ETA, frequency,
                                    FORCE_AT, 1.0, target=TARGET)
        fem_best = best_of(lambda: (lambda r: (r, r.t_assembly, r.t_solve))(
            solve_fem(LX, LY, E, NU, RHO, H, ETA, frequency, FORCE_AT, 1.0, GRID,
                      fem.n_x, fem.n_y)))[0]
        fem_error = np.linalg.norm(fem_best.w - reference) / np.linalg.norm(reference)
        ratio = (fem_best.t_assembly + fem_best.t_solve) / (t_asm + t_solve)
        print(f"{frequency:7.0f} | {n:8d} {error:8.1e} {t_asm * 1e3:7.1f} {t_solve * 1e3:8.2f} | "
              f"{fem_best.n_dofs:7d} {fem_error:8.1e} {fem_best.t_assembly * 1e3:7.1f} "
              f"{fem_best.t_solve * 1e3:8.2f} | {ratio:6.1f}")


if __name__ == "__main__":
    main()
