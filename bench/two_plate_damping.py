"""Two-plate study, paper Figs. 8–9: how far a wrong assumed joint damping moves the optimum.

Simulated experiment (finer discretisation, ±20 % noise) with true log10 k = 1.5 and true
joint loss factor zeta_true; the model assumes zeta_assumed; the script prints the log10 k
that minimises E_mod^2 and the share of the power the true joint dissipates.

Run: ``OPENBLAS_NUM_THREADS=1 python bench/two_plate_damping.py``
"""

import sys
from pathlib import Path

import numpy as np
from scipy import optimize

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from support import chain_description  # noqa: E402

from assembly import parse_case  # noqa: E402
from updating.data.measurements import simulate_measurements  # noqa: E402
from updating.inverse.cost import ModifiedProblem  # noqa: E402


def optimum(zeta_true, zeta_assumed, noise=0.2, seed=1):
    joint = {"kind": "coplanar", "log10_stiffness": 1.5, "loss_factor": zeta_assumed}
    shear = {"kind": "edge_shear", "edge": "P1.left", "amplitude": 1.0}
    description = chain_description([joint], 1.0, left="free", right="clamped", force=None,
                                    edge_loads=[shear], frequency=155.0, lengths=(0.5, 0.5),
                                    ly=0.4)
    description["truth"] = {"joints": {"G1": {"loss_factor": zeta_true}}}
    description["measurement"] = {"spacing": 0.05, "noise": noise, "seed": seed}
    case = parse_case(description)
    problem = ModifiedProblem(case, simulate_measurements(case))
    base = problem.initial_parameters()["G1"]

    def cost(value):
        return problem.cost({"G1": dict(base, log10_stiffness=float(value))})

    grid = np.linspace(-1.0, 5.0, 61)
    costs = [cost(v) for v in grid]
    i = int(np.argmin(costs))
    return optimize.minimize_scalar(cost, bounds=(grid[max(i - 1, 0)], grid[min(i + 1, 60)]),
                                    method="bounded", options={"xatol": 1e-4}).x


def main():
    print(f"{'zeta true':>9} {'zeta assumed':>12} {'argmin log10 k':>15} {'shift':>7}")
    for zeta_true, assumed in ((0.1, (0.0, 0.01, 0.1, 1.0, 10.0)), (10.0, (0.1, 1.0, 5.0, 10.0, 20.0))):
        for zeta in assumed:
            best = optimum(zeta_true, zeta)
            print(f"{zeta_true:9.2f} {zeta:12.2f} {best:15.3f} {best - 1.5:+7.3f}")


if __name__ == "__main__":
    main()
