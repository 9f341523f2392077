"""Effectivity and cost of the a-posteriori error estimate (``solver.estimate``).

For cases with an exact series (Navier: simply supported plate under a point force; Levy:
chains of plates with coplanar, damped, massive and hinge joints), at several frequencies and
resolutions, prints the true relative L2 error of w (against the series, on the estimate's own
Gauss rule), the estimate, their ratio (the effectivity) and the time of the estimate against
the time of the solve (best of ``--repeats``, one process, one BLAS thread advised)::

    OPENBLAS_NUM_THREADS=1 python bench/bench_estimate.py
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from exact import Section, complex_rigidity, levy_chain, navier_point_force  # noqa: E402
from support import LENGTHS, LY, NU, OMEGA, RHO, D, H, chain_description, exact_joint  # noqa: E402

from assembly import parse_case  # noqa: E402
from solver import solve_case  # noqa: E402
from solver.estimate import estimate_error, plate_l2_rule  # noqa: E402

STEEL = {"young_modulus": 210e9, "poisson_ratio": 0.3, "density": 7800.0, "loss_factor": 0.01}
SIZE, FORCE = (0.5, 0.4), (0.12, 0.31)


def plate_case(resolution):
    return parse_case({
        "name": "ss-plate", "frequency": 155.0, "materials": {"steel": STEEL},
        "plates": {"P1": {"material": "steel", "thickness": 1e-3, "size": list(SIZE)}},
        "boundaries": [{"edge": f"P1.{e}", "condition": "simply_supported"}
                       for e in ("left", "right", "bottom", "top")],
        "loads": [{"kind": "point_force", "plate": "P1", "at": list(FORCE), "amplitude": 1.0}],
        "discretisation": {"resolution": resolution}})


def navier(frequency):
    d = complex_rigidity(STEEL["young_modulus"], 1e-3, STEEL["poisson_ratio"], 0.01)

    def exact(plate, points):
        return navier_point_force(*SIZE, d, STEEL["density"] * 1e-3, 2 * math.pi * frequency,
                                  *FORCE, 1.0, points[:, 0], points[:, 1], n_terms=400)
    return exact


def levy(joints):
    n = len(joints) + 1
    reference = levy_chain([Section(LENGTHS[i], D, NU, RHO * H) for i in range(n)], LY, OMEGA,
                           joints=[exact_joint(j) for j in joints], left="simply_supported",
                           right="clamped", point_forces=[(0, *FORCE, 1.0)])

    def exact(plate, points):
        return reference.w(points[:, 0], points[:, 1], plate=int(plate[1:]) - 1)
    return exact


def best_time(function, repeats):
    times, result = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - t0)
    return min(times), result


def measure(label, case, frequency, exact, repeats):
    t_solve, solution = best_time(lambda: solve_case(case, frequency), repeats)
    t_estimate, estimate = best_time(lambda: estimate_error(case, solution), repeats)
    error = norm = 0.0
    for pid, plate in solution.plates.items():
        points, weights = plate_l2_rule(plate.problem)
        reference = exact(pid, points)
        error += weights @ abs(plate.field(points)["w"] - reference) ** 2
        norm += weights @ abs(reference) ** 2
    error = math.sqrt(error / norm)
    print(f"| {label} | {frequency:g} | {case.discretisation.resolution:g} | "
          f"{solution.n_unknowns} | {error:.2e} | {estimate.total:.2e} | "
          f"{estimate.total / error:.2f} | {1e3 * t_solve:.1f} | {1e3 * t_estimate:.1f} | "
          f"{t_estimate / t_solve:.1f} |", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    print("| case | f [Hz] | resolution | unknowns | true error | estimate | effectivity "
          "| solve ms | estimate ms | estimate / solve |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for frequency in (1.0, 10.0, 60.0, 155.0, 400.0, 1000.0):
        for resolution in (0.6, 0.8, 1.0):
            measure("simply supported plate (Navier)", plate_case(resolution), frequency,
                    navier(frequency), args.repeats)
    chains = {
        "two plates, coplanar log k 1.5, zeta 0.1, mu 0.05 (Levy)":
            [{"kind": "coplanar", "log10_stiffness": 1.5, "loss_factor": 0.1, "mass": 0.05}],
        "two plates, coplanar log k 3.5 (Levy)": [{"kind": "coplanar", "log10_stiffness": 3.5}],
        "two plates, hinge log k 2.5 (Levy)": [{"kind": "hinge", "log10_stiffness": 2.5}],
        "three plates, coplanar + hinge (Levy)":
            [{"kind": "coplanar", "log10_stiffness": 1.5, "loss_factor": 0.1, "mass": 0.05},
             {"kind": "hinge", "log10_stiffness": 3.5}],
    }
    for label, joints in chains.items():
        for resolution in (0.85, 1.0, 1.25):
            case = parse_case(chain_description(joints, resolution))
            measure(label, case, case.frequencies[0], levy(joints), args.repeats)
    grid_sum_against_points(args.repeats)


def grid_sum_against_points(repeats):
    """The fields on the plates' Gauss grids (kinetic energy, the estimate's integrals): the
    tensor-grid sum against evaluating every point, same solution, same run."""
    from solver.plate import evaluate_field
    from solver.power import grid_deflections, plate_gauss_axes

    joints = [{"kind": "coplanar", "log10_stiffness": 1.5, "loss_factor": 0.1, "mass": 0.05},
              {"kind": "hinge", "log10_stiffness": 3.5}]
    case = parse_case(chain_description(joints, 1.0))
    plates = solve_case(case).plates.values()

    def on_grid():
        fields = grid_deflections({i: (p.problem, p.basis, p.amplitudes)
                                   for i, p in enumerate(plates)})
        return [fields[i] for i in range(len(plates))]

    def point_by_point():
        out = []
        for p in plates:
            (x, _), (y, _) = plate_gauss_axes(p.problem)
            points = np.array([(u, v) for u in x for v in y])
            out.append(evaluate_field(p.problem, p.basis, p.amplitudes, points)["w"])
        return out

    t_grid, grid = best_time(on_grid, repeats)
    t_points, points = best_time(point_by_point, repeats)
    difference = max(float(np.max(abs(g.ravel() - q)) / np.max(abs(q)))
                     for g, q in zip(grid, points))
    print(f"\nw on the Gauss grids of the three-plate chain: tensor-grid sum "
          f"{1e3 * t_grid:.1f} ms, point by point {1e3 * t_points:.1f} ms "
          f"(x{t_points / t_grid:.1f}), largest relative difference {difference:.1e}")


if __name__ == "__main__":
    main()
