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

import dataclasses
import time
from collections.abc import Mapping

import numpy as np

from assembly.case import Case
from solver.dense import solve_dense
from solver.errors import check_finite, plate_condition_warnings
from solver.guards import check_description
from solver.plate import PlateSolution, assemble_plate, boundary_traces
from solver.problems import plate_basis, plate_problem
from solver.solution import CaseSolution
from solver.substructure import solve_assembly

__all__ = ["solve_case", "field_grid"]


def solve_case(case: Case, frequency: float | None = None,
               resolution: float | Mapping[str, float] | None = None, residuals: bool = True,
               check: bool = True) -> CaseSolution:
    """Solve the forced response of ``case`` at one frequency.

    Parameters
    ----------
    case : assembly.Case
        A validated description.
    frequency : float, optional
        Hz; default the description's first frequency.
    resolution : float or mapping of str to float, optional
        Overrides ``[discretisation] resolution`` (multiplier on the ray-count rule), for
        every plate or per plate (a joint follows the finer of its plates).
    residuals : bool, optional
        For an assembly, compute the joint residuals (and the reference energy that
        normalises them); False when only the field is wanted.
    check : bool, optional
        Run the description's guard rails at this frequency first
        (:func:`solver.guards.check_description`: errors raise, warnings join the solution's);
        False where they ran already, or at a resolution chosen by the caller (default True).

    Returns
    -------
    CaseSolution
        For an assembly with joints, a :class:`solver.substructure.AssemblySolution` (the
        same interface plus the joint residuals). ``warnings`` lists the plates whose
        condition estimate exceeds :data:`solver.errors.CONDITION_WARNING`.

    Raises
    ------
    assembly.DescriptionError
        With ``check``, if the description fails a guard rail (ray counts, magnitudes,
        memory; ``docs/accuracy.md``).
    solver.errors.NumericalError
        If a ray amplitude or joint residual is not finite (names the frequency and plate).
    ValueError
        If the frequency is not finite and > 0, or an assembly with joints has no loads.
    """
    frequency = case.frequencies[0] if frequency is None else float(frequency)
    if not (np.isfinite(frequency) and frequency > 0):
        raise ValueError(f"the frequency must be finite and > 0 Hz, got {frequency}")
    # at a frequency of the description its own field is named, else the frequency asked for
    asked = None if frequency in case.frequencies else [frequency]
    warnings = tuple(check_description(case, case.name, asked)) if check else ()
    solution = _solve(case, frequency, resolution, residuals)
    return dataclasses.replace(solution, warnings=warnings + solution.warnings) if warnings \
        else solution


def _solve(case: Case, frequency: float, resolution: float | Mapping[str, float] | None,
           residuals: bool) -> CaseSolution:
    """:func:`solve_case` after its checks."""
    if case.joints:
        if not case.loads:
            raise ValueError(
                "the assembly has no loads: its response is zero and the joint residuals, "
                "relative to its energy, are undefined; add a [[loads]] table")
        return check_finite(solve_assembly(case, frequency, resolution, residuals=residuals))
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
    return check_finite(
        CaseSolution(frequency, solutions, timings, plate_condition_warnings(solutions)))


def field_grid(case: Case, plate_id: str, spacing: float) -> np.ndarray:
    """Interior grid of a plate with about ``spacing`` between points (plate-local, m)."""
    lx, ly = case.plates[plate_id].size
    nx, ny = max(1, round(lx / spacing)), max(1, round(ly / spacing))
    xs = (np.arange(nx) + 0.5) * lx / nx
    ys = (np.arange(ny) + 0.5) * ly / ny
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    return np.c_[X.ravel(), Y.ravel()]
