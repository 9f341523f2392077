r"""Forced response of an assembly description with the VTCR.

This module validates once and delegates to the pure kernels:

* :mod:`solver.kirchhoff` — plate operators, wavenumber, point-force Green function;
* :mod:`solver.rays` — complex-ray families, sector means, the resolution rule;
* :mod:`solver.plate` — boundary traces, VTCR matrix of one plate, dense solve;
* :mod:`solver.substructure` — joints: interface unknowns, admissibility, residuals.

Each plate :math:`\Omega_i` is a Kirchhoff plate, :math:`D_i^*\Delta^2 w - \rho_i h_i\omega^2 w = f`,
whose field is :math:`w = w_p + \sum_l x_l\Phi_l` with rays :math:`\Phi_l` solving the
homogeneous equation exactly; its boundary conditions hold weakly through the VTCR
variational form, and the joints couple the plates through interface unknowns (see
:mod:`solver.substructure`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from solver.plate import PlateSolution, assemble_plate, boundary_traces, solve_dense
from solver.problems import plate_basis, plate_problem

__all__ = ["CaseSolution", "solve_case", "field_grid", "CONDITION_WARNING"]

CONDITION_WARNING = 1e20
"""Condition estimate above which a solve is reported as numerically doubtful.

Trefftz matrices reach 1e17–1e19 while the field is accurate to 1e-9 (formulation notes,
pitfall 1); past 1e20 the field itself starts to lose digits in double precision.
"""


@dataclass(frozen=True)
class CaseSolution:
    """Field of every plate of an assembly at one frequency.

    Attributes
    ----------
    frequency : float
        Hz.
    plates : dict of str to PlateSolution
    timings : dict of str to float
        Seconds spent in ``"assembly"`` (basis, boundary traces, matrices) and ``"solve"``.
    warnings : tuple of str
    """

    frequency: float
    plates: dict
    timings: dict
    warnings: tuple = ()

    @property
    def n_unknowns(self) -> int:
        """Ray unknowns of all plates."""
        return sum(p.basis.n_dof for p in self.plates.values())

    @property
    def condition_estimate(self) -> float:
        """Largest condition estimate of the solves."""
        return max(p.condition_estimate for p in self.plates.values())

    def w(self, plate_id, points):
        """Complex displacement (m) at plate-local points of one plate, shape (n,)."""
        return self.plates[plate_id].field(points)["w"]


def _condition_warnings(solutions):
    return tuple(
        f"plate {pid}: condition estimate {s.condition_estimate:.1e} exceeds "
        f"{CONDITION_WARNING:.0e}; lower [discretisation] resolution"
        for pid, s in solutions.items() if s.condition_estimate > CONDITION_WARNING
    )


def solve_case(case, frequency=None, resolution=None) -> CaseSolution:
    """Solve the forced response of ``case`` at one frequency.

    Parameters
    ----------
    case : assembly.Case
        A validated description.
    frequency : float, optional
        Hz; default the description's first frequency.
    resolution : float, optional
        Overrides ``[discretisation] resolution`` (multiplier on the ray-count rule).

    Returns
    -------
    CaseSolution
    """
    frequency = case.frequencies[0] if frequency is None else float(frequency)
    if case.joints:
        from solver.substructure import solve_assembly

        return solve_assembly(case, frequency, resolution)
    solutions, timings = {}, {"assembly": 0.0, "solve": 0.0}
    for plate_id in case.plates:
        t0 = time.perf_counter()
        problem = plate_problem(case, plate_id, frequency)
        basis = plate_basis(case, plate_id, problem, resolution)
        K, F = assemble_plate(problem, boundary_traces(problem, basis))
        t1 = time.perf_counter()
        x, rcond = solve_dense(K, F)
        timings["assembly"] += t1 - t0
        timings["solve"] += time.perf_counter() - t1
        solutions[plate_id] = PlateSolution(problem, basis, x, rcond)
    return CaseSolution(frequency, solutions, timings, _condition_warnings(solutions))


def field_grid(case, plate_id, spacing):
    """Interior grid of a plate with about ``spacing`` between points (plate-local, m)."""
    lx, ly = case.plates[plate_id].size
    nx, ny = max(1, round(lx / spacing)), max(1, round(ly / spacing))
    xs = (np.arange(nx) + 0.5) * lx / nx
    ys = (np.arange(ny) + 0.5) * ly / ny
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    return np.c_[X.ravel(), Y.ravel()]
