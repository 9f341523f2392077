"""VTCR versus Argyris finite elements on the reference plate, 100 Hz to 1.6 kHz.

For each frequency: the smallest VTCR discretisation and the smallest Argyris mesh whose
relative L2 error of w on a 10 x 10 interior grid is below 1 % against the Navier series;
their unknowns, assembly and solve times (best of ``REPEATS`` runs, both measured here in the
same process), and the ratio of the end-to-end times (FEM / VTCR).

Both searches try every candidate in increasing number of unknowns and keep the first that
reaches 1 %: for the VTCR every distinct set of ray counts the resolution rule gives as its
factor grows; for the FEM every ``n_x x n_y`` tensor mesh with elements of aspect ratio at
most ``MAX_ASPECT``.

Timed for both, and nothing else: assembly (VTCR: ray basis, boundary traces, matrix and
right-hand side; FEM: mesh, basis, matrices, load vector, constraints) and solve (dense LU
with a condition estimate; sparse LU). Evaluating w on the grid is timed for neither.

Plate: steel, h = 1 mm, eta = 0.01, 0.5 x 0.4 m, simply supported, 1 N at (0.12, 0.31).

Run: ``pip install -e '.[bench]' && OPENBLAS_NUM_THREADS=1 python bench/bench_plate.py``
"""

from __future__ import annotations

import functools
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "bench")]

from fem_argyris import navier_reference, relative_error, solve_fem  # noqa: E402

from assembly.geometry import EDGE_NAMES  # noqa: E402
from solver.dense import solve_dense  # noqa: E402
from solver.kirchhoff import complex_bending_stiffness  # noqa: E402
from solver.plate import (  # noqa: E402
    EdgeCondition,
    PlateProblem,
    PointForce,
    assemble_plate,
    boundary_traces,
    evaluate_field,
)
from solver.rays import automatic_ray_counts, build_ray_basis  # noqa: E402

E, NU, RHO, H, ETA = 210e9, 0.3, 7800.0, 1e-3, 0.01
LX, LY = 0.5, 0.4
FORCE_AT = (0.12, 0.31)
TARGET = 0.01
REPEATS = 10
MAX_ASPECT = 3.0
FREQUENCIES = (100.0, 155.0, 200.0, 400.0, 800.0, 1600.0)
GRID = np.array([(x, y) for x in np.linspace(0, LX, 12)[1:-1] for y in np.linspace(0, LY, 12)[1:-1]])


def plate_problem(frequency):
    return PlateProblem((LX, LY), complex_bending_stiffness(E, H, NU, ETA), NU, RHO * H,
                        2 * np.pi * frequency,
                        {e: EdgeCondition("simply_supported") for e in EDGE_NAMES},
                        (PointForce(FORCE_AT, 1.0),))


def vtcr_solve(frequency, counts):
    """One VTCR solve; returns (w on the grid, unknowns, assembly time, solve time)."""
    t0 = time.perf_counter()
    problem = plate_problem(frequency)
    basis = build_ray_basis(problem.size, problem.kappa, counts)
    K, F = assemble_plate(problem, boundary_traces(problem, basis))
    t1 = time.perf_counter()
    x, _ = solve_dense(K, F)
    t2 = time.perf_counter()
    w = evaluate_field(problem, basis, x, GRID)["w"]
    return w, basis.n_dof, t1 - t0, t2 - t1


def fem_solve(frequency, mesh):
    """One FEM solve on an ``(n_x, n_y)`` mesh; same returns as :func:`vtcr_solve`."""
    r = solve_fem(LX, LY, E, NU, RHO, H, ETA, frequency, FORCE_AT, 1.0, GRID, *mesh)
    return r.w, r.n_dofs, r.t_assembly, r.t_solve


def ray_count_candidates(frequency):
    """Every distinct output of the ray-count rule, by increasing resolution factor.

    Each count is a rounded-up multiple of the factor, so the counts (and the unknowns) never
    decrease as it grows; steps of 1e-3 resolve every change.
    """
    kappa0 = plate_problem(frequency).kappa.real
    candidates = []
    for resolution in np.arange(0.1, 3.0, 1e-3):
        counts = automatic_ray_counts(kappa0, (LX, LY), resolution)
        if not candidates or counts != candidates[-1]:
            candidates.append(counts)
    return candidates


def argyris_unknowns(n_x, n_y):
    """Free unknowns of the simply supported Argyris mesh (checked against the solver).

    Six per vertex and one per edge (``3 n_x n_y + n_x + n_y`` edges with the diagonals),
    minus three per boundary vertex and edge direction, plus the four corners counted twice.
    """
    vertices = (n_x + 1) * (n_y + 1)
    edges = 3 * n_x * n_y + n_x + n_y
    return 6 * vertices + edges - 6 * (n_x + 1) - 6 * (n_y + 1) + 4


def mesh_candidates(max_intervals=60):
    """Tensor meshes with elements of aspect ratio at most ``MAX_ASPECT``, by unknowns."""
    meshes = [(n_x, n_y) for n_x in range(1, max_intervals + 1)
              for n_y in range(1, max_intervals + 1)
              if 1.0 / MAX_ASPECT <= (LX / n_x) / (LY / n_y) <= MAX_ASPECT]
    return sorted(meshes, key=lambda m: (argyris_unknowns(*m), m))


def smallest_accurate(solve, candidates, reference):
    """First candidate whose relative error against ``reference`` is below ``TARGET``."""
    for candidate in candidates:
        w, *_ = solve(candidate)
        error = relative_error(w, reference)
        if error < TARGET:
            return candidate, error
    raise RuntimeError(f"no candidate reaches {TARGET}")


def best_of(run):
    results = [run() for _ in range(REPEATS)]
    return min(results, key=lambda r: r[-2] + r[-1])


def main():
    print(__doc__.split("\n\n")[0])
    print(f"target {TARGET:.0%}; times: best of {REPEATS}; assembly + solve, no evaluation\n")
    header = (f"{'f [Hz]':>7} | {'VTCR dof':>8} {'err':>8} {'asm ms':>7} {'solve ms':>8} | "
              f"{'FEM dof':>7} {'err':>8} {'asm ms':>7} {'solve ms':>8} | {'ratio':>6}")
    print(header)
    print("-" * len(header))
    for frequency in FREQUENCIES:
        reference = navier_reference(LX, LY, E, NU, RHO, H, ETA, frequency, FORCE_AT, 1.0, GRID)
        counts, error = smallest_accurate(functools.partial(vtcr_solve, frequency),
                                          ray_count_candidates(frequency), reference)
        mesh, fem_error = smallest_accurate(functools.partial(fem_solve, frequency),
                                            mesh_candidates(), reference)
        _, n, t_asm, t_solve = best_of(functools.partial(vtcr_solve, frequency, counts))
        _, fem_n, fem_asm, fem_solve_time = best_of(functools.partial(fem_solve, frequency, mesh))
        assert fem_n == argyris_unknowns(*mesh)
        ratio = (fem_asm + fem_solve_time) / (t_asm + t_solve)
        print(f"{frequency:7.0f} | {n:8d} {error:8.1e} {t_asm * 1e3:7.1f} {t_solve * 1e3:8.2f} | "
              f"{fem_n:7d} {fem_error:8.1e} {fem_asm * 1e3:7.1f} {fem_solve_time * 1e3:8.2f} | "
              f"{ratio:6.1f}", flush=True)


if __name__ == "__main__":
    main()
