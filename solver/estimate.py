r"""A-posteriori estimate of the discretisation error of a solve.

**What is estimated.** The relative :math:`L^2` error of the deflection over the assembly, the
norm the accuracy tests use,

.. math:: \varepsilon = \Big(\sum_i\int_{\Omega_i}|w_i - w_{h,i}|^2\,dA\Big)^{1/2}
          \Big/ \Big(\sum_i\int_{\Omega_i}|w_i|^2\,dA\Big)^{1/2},

and per plate the same ratio over that plate alone. On the plates that carry an in-plane field
(the members of moving lines, ``docs/method.md`` section 10.4) the same ratio of the in-plane
displacement :math:`\mathbf u = (u, v)`, per plate and over those plates, and per plate that of
the displacement vector :math:`(u, v, w)`,

.. math:: \varepsilon_{X,i} = \Big(\int_{\Omega_i}|\mathbf u^+ - \mathbf u_h|^2
          + |w^+ - w_h|^2\,dA\Big)^{1/2} \Big/
          \Big(\int_{\Omega_i}|\mathbf u^+|^2 + |w^+|^2\,dA\Big)^{1/2},

which is what a tolerance asks of the plate with that of ``w`` (:meth:`ErrorEstimate.plate_errors`;
``docs/accuracy.md`` sections 1 and 2 say why each norm is used where). The membrane waves
satisfy the plane-stress equation exactly, so the in-plane error is a Trefftz field too and the
argument below holds for it unchanged; the enriched solve refines them with the rays.

**Why it can be estimated.** Every ray and the particular solution satisfy the plate equation
exactly, so the error :math:`e = w - w_h` of a plate is itself a Trefftz field: the response of
the plate to the residuals of the boundary and interface conditions that the VTCR satisfies
only weakly (:math:`q(e) = q_d - q(w_h)` on the kinematic components,
:math:`g(e) = g_d - g(w_h)` on the static ones, and on the joints the residuals of the joint
laws and of the translation and corner constraints). Those residuals vanish when tested with
the rays of the basis — that is the VTCR equation — so the error problem has to be solved in a
richer space. Solving it in the space of the enriched discretisation (every ray count and every
interface function count of the rule multiplied by :data:`ENRICHMENT`) gives
:math:`e^+ = w^+ - w_h`, where :math:`w^+` is the enriched solution: the residual functional
tested with the enriched basis is linear in the residuals, so the enriched error problem and
the enriched solve differ only by :math:`w_h`. The estimate is

.. math:: \hat\varepsilon = \|w^+ - w_h\| / \|w^+\| .

It is reliable when the enriched discretisation is markedly more accurate than the estimated
one (the saturation assumption of hierarchical estimators): the ray bases converge
exponentially with the counts, so one step of 1.5 lowers the error by one to three orders of
magnitude wherever the rule converges (measured on the simply supported plate from 10 Hz to
400 Hz). Where it does not — round-off at the floor of the Trefftz ill-conditioning — the two
solutions differ by about their common floor and the estimate stays of the order of the error.
Near the floor (about 1e-6) the estimate is dominated by round-off and only says "small".

**Large assemblies.** The enriched assembly solve refactorises an interface problem with 1.5
times the unknowns, one and a half to three times the cost of the solve (10 x 10 grid of
``bench/bench_scale.py``: 2.9 s with the integrals against 1.5 s, the factorisations 1.35 s
against 0.62 s). When
:mod:`solver.sizing` estimates it above :data:`ENRICHED_SOLVE_SECONDS`, or beyond half the
available memory, the estimate is not made and says why (:func:`estimate_error` returns an
estimate whose ``total`` is None): a wrong number would be worse than none. A cheaper
per-plate estimate (each plate solved again alone with enriched rays under the interface loads
of the solution) was measured and rejected: effectivity 0.43–1.1 on Levy chains but 14 on a
4 x 4 grid, whose coarse interface loads carry components the coarse rays absorb and the
enriched ones do not.

The :math:`L^2` integrals are tensor Gauss rules on each plate with
:math:`\lceil\kappa_0L\rceil + 12` points per side (the kinetic energy's rule): on the simply
supported plate from 1 Hz to 1 kHz, the estimates agree to 1e-2 of themselves with a rule of
:math:`\lceil 2\kappa_0L\rceil + 16` points, at a third of the cost. The particular solutions
of the point forces are identical in both fields and cancel in the difference.

:mod:`solver.tolerance` raises the resolution until these estimates meet a tolerance.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from assembly.case import Case
from solver.layout import answered_wavenumber, interface_layout, members_wavenumber
from solver.membrane import MembraneSolution
from solver.membrane_basis import membrane_grid_displacement
from solver.near_forces import (
    NearForce,
    forces_near_joints,
    near_force_remedy,
    near_forces_text,
)
from solver.plate import PlateProblem, PlateSolution
from solver.power import grid_deflections, plate_gauss_axes
from solver.problems import plate_problems
from solver.resolution import plate_resolution
from solver.sizing import SizeEstimate, available_memory, estimate_size
from solver.solution import CaseSolution
from solver.vtcr import solve_case

__all__ = ["ENRICHMENT", "EnrichedSolve", "ErrorEstimate", "enriched_size",
           "enriched_solution", "enriched_solve", "estimate_error", "in_plane_l2_errors",
           "plate_l2_rule", "slow_lines", "unrefined_lines", "unresolved_near_forces",
           "unseen_lines_remedy", "unseen_lines_text", "unseen_texts"]

ENRICHMENT = 1.5
ENRICHED_SOLVE_SECONDS = 60.0


@dataclass(frozen=True)
class ErrorEstimate:
    r"""Estimated relative L2 error of ``w`` (and of the in-plane field, where there is one) of
    one solve.

    Attributes
    ----------
    total : float or None
        Of ``w`` over the assembly; None when the estimate was not made (``reason`` says why).
    plates : dict of str to float
        Of ``w`` over each plate (relative to that plate's own norm of ``w``).
    resolution : float or dict of str to float
        Resolution factor of the estimated solve (per plate when they differ).
    enriched_resolution : float or dict of str to float
        Resolution factor of the enriched solve the estimate compares with.
    seconds : float
        Cost of the estimate (the enriched solve and the integrals).
    method : {"enriched", "skipped"}
        ``"enriched"``: the whole problem solved again with every count times
        :data:`ENRICHMENT`; ``"skipped"``: not estimated (see the module docstring).
    reason : str
        Why the estimate was skipped (empty otherwise).
    shares : dict of str to float
        Each plate's part of ``total**2``: :math:`\int_{\Omega_i}|e|^2 / \sum_j\int|w^+|^2`.
    in_plane : dict of str to float
        Of the in-plane displacement :math:`(u, v)` over each plate that carries one
        (relative to that plate's own norm of :math:`(u, v)`); empty without moving lines.
    in_plane_total : float or None
        Of :math:`(u, v)` over the plates that carry it; None without them.
    displacement : dict of str to float
        Of the displacement vector :math:`(u, v, w)` over each plate that carries an in-plane
        field (relative to that plate's norm of it); empty without moving lines.
    unseen_lines : tuple of str
        The moving lines whose loads' error the estimate cannot see (:func:`unrefined_lines`):
        where it names any, the estimate may be far below the error (the free-ended fold of
        ``docs/accuracy.md`` section 8: 0.07 of it).
    unseen_count_fixed : bool
        Whether those lines' count is the description's (``interface_functions``); else it
        stopped with their members' reach (:func:`unseen_lines_text`).
    unseen_near_forces : tuple of :class:`solver.near_forces.NearForce`
        The point forces next to a joint whose error the estimate cannot see
        (:func:`unresolved_near_forces`): there it read 0.03 to 0.67 of the errors, of the
        plates beyond the joint too.
    """

    total: float | None
    plates: dict
    resolution: float | dict
    enriched_resolution: float | dict
    seconds: float
    method: str = "enriched"
    reason: str = ""
    shares: dict = field(default_factory=dict)
    in_plane: dict = field(default_factory=dict)
    in_plane_total: float | None = None
    displacement: dict = field(default_factory=dict)
    unseen_lines: tuple = ()
    unseen_count_fixed: bool = False
    unseen_near_forces: tuple = ()

    def plate_errors(self) -> dict[str, float]:
        """Per plate, what a tolerance asks of it: the larger of its estimates of ``w`` and of
        the displacement :math:`(u, v, w)` (``plates`` without in-plane fields). The in-plane
        part counts in proportion to its size, not relative to its own norm: see
        ``docs/accuracy.md`` section 2."""
        return {pid: max(value, self.displacement.get(pid, 0.0))
                for pid, value in self.plates.items()}

    def worst_plate(self) -> str:
        """The plate of the largest :meth:`plate_errors` (that of ``w`` without in-plane
        fields)."""
        errors = self.plate_errors()
        return max(errors, key=errors.get)

    def resolution_of(self, plate_id: str) -> float:
        if isinstance(self.resolution, dict):
            return self.resolution[plate_id]
        return self.resolution

    def to_json(self) -> dict[str, Any]:
        """The JSON of ``error_estimate``; ``in_plane`` (``total``, ``plates`` and
        ``displacement``) only where some plate carries an in-plane field, so a flat
        assembly's is as before, and ``unseen_lines`` and ``unseen_near_forces`` only where
        there are some."""
        out = {"total": self.total, "plates": dict(self.plates),
               "resolution": self.resolution, "enriched_resolution": self.enriched_resolution,
               "method": self.method, "enrichment": ENRICHMENT, "reason": self.reason}
        if self.in_plane:
            out["in_plane"] = {"total": self.in_plane_total, "plates": dict(self.in_plane),
                               "displacement": dict(self.displacement)}
        if self.unseen_lines:
            out["unseen_lines"] = list(self.unseen_lines)
        if self.unseen_near_forces:
            out["unseen_near_forces"] = [
                {"plate": force.plate, "joint": force.joint, "distance": force.distance,
                 "kappa0_d": force.kappa_d} for force in self.unseen_near_forces]
        return out


@dataclass(frozen=True)
class EnrichedSolve:
    """What the estimate keeps of the enriched solve (:func:`enriched_solve`): every plate's
    :class:`solver.plate.PlateSolution` and every in-plane plate's
    :class:`solver.membrane.MembraneSolution` (not the system, whose transfer operators would
    stay alive beside the solution's own), or None and why the solve was not made, and its
    time (s). :func:`solver.tolerance.solve_to_tolerance` keeps the system while it may take
    the enriched solve as its next one (:func:`enriched_solution`); that solve's build
    overlapped the solution's system anyway."""

    plates: dict[str, PlateSolution] | None
    membranes: dict[str, MembraneSolution]
    reason: str
    seconds: float


def plate_l2_rule(problem: PlateProblem) -> tuple[np.ndarray, np.ndarray]:
    r"""Tensor Gauss rule over a plate: points (n, 2) and weights (n,), with
    :math:`\lceil\kappa_0L\rceil + 12` points per side."""
    (x, wx), (y, wy) = plate_gauss_axes(problem)
    X, Y = np.meshgrid(x, y, indexing="ij")
    return np.c_[X.ravel(), Y.ravel()], np.outer(wx, wy).ravel()


def relative_l2_errors(solution: CaseSolution,
                       enriched: Mapping[str, PlateSolution]) -> dict[str, tuple[float, float]]:
    r"""Per plate :math:`(\int|w^+ - w_h|^2, \int|w^+|^2)` over the plate's Gauss rule;
    ``enriched`` maps each plate to its enriched :class:`solver.plate.PlateSolution`."""
    w_h = grid_deflections({pid: (p.problem, p.basis, p.amplitudes)
                            for pid, p in solution.plates.items()})
    w_plus = grid_deflections({pid: (p.problem, p.basis, p.amplitudes)
                               for pid, p in enriched.items()})
    out = {}
    for pid, plate in solution.plates.items():
        (_, wx), (_, wy) = plate_gauss_axes(plate.problem)
        weights = np.outer(wx, wy)
        out[pid] = (float(np.sum(weights * np.abs(w_plus[pid] - w_h[pid]) ** 2)),
                    float(np.sum(weights * np.abs(w_plus[pid]) ** 2)))
    return out


def in_plane_l2_errors(solution: CaseSolution, enriched: Mapping[str, MembraneSolution]
                       ) -> dict[str, tuple[float, float]]:
    r"""Per in-plane plate :math:`(\int|\mathbf u^+ - \mathbf u_h|^2,
    \int|\mathbf u^+|^2)`, :math:`|\mathbf u|^2 = |u|^2 + |v|^2`, over the plate's Gauss rule
    (:func:`plate_l2_rule`, that of ``w``); ``enriched`` maps each in-plane plate to its
    enriched :class:`solver.membrane.MembraneSolution`."""
    out = {}
    for pid, membrane in solution.membranes.items():
        (x, wx), (y, wy) = plate_gauss_axes(solution.plates[pid].problem)
        weights = np.outer(wx, wy)
        u_h = membrane_grid_displacement(membrane.basis, membrane.amplitudes, x, y)
        u_plus = membrane_grid_displacement(enriched[pid].basis, enriched[pid].amplitudes, x, y)
        out[pid] = (float(np.sum(weights * np.sum(np.abs(u_plus - u_h) ** 2, axis=0))),
                    float(np.sum(weights * np.sum(np.abs(u_plus) ** 2, axis=0))))
    return out


def enriched_solve(case: Case, frequency: float,
                   resolution: float | Mapping[str, float] | None = None) -> EnrichedSolve:
    """The enriched solve (every count of the rule at ``resolution`` times
    :data:`ENRICHMENT`) as an :class:`EnrichedSolve`, or none and why (:mod:`solver.sizing`
    estimates it too long or too large)."""
    return enriched_solution(case, frequency, resolution)[0]


def enriched_solution(case: Case, frequency: float,
                       resolution: float | Mapping[str, float] | None
                       ) -> tuple[EnrichedSolve, CaseSolution | None]:
    """:func:`enriched_solve`, and the whole solution it was taken from (without joint
    residuals; None where the solve was not made)."""
    t0 = time.perf_counter()
    _, enriched_resolution = _resolutions(case, resolution)
    if case.joints:
        reason = _enriched_solve_unaffordable(case, frequency, enriched_resolution)
        if reason:
            return EnrichedSolve(None, {}, reason, time.perf_counter() - t0), None
    solution = solve_case(case, frequency, resolution=enriched_resolution, residuals=False,
                          check=False)
    return (EnrichedSolve(solution.plates, solution.membranes, "", time.perf_counter() - t0),
            solution)


def estimate_error(
    case: Case, solution: CaseSolution, resolution: float | Mapping[str, float] | None = None,
    enriched: EnrichedSolve | None = None,
) -> ErrorEstimate:
    """Estimate the relative L2 error of ``w``, and of ``(u, v)`` where there is an in-plane
    field, of ``solution`` (see the module docstring).

    Parameters
    ----------
    case : assembly.Case
    solution : solver.solution.CaseSolution or solver.substructure.AssemblySolution
        A solve of ``case`` at ``solution.frequency``.
    resolution : float or mapping of str to float, optional
        The resolution factor ``solution`` was solved with, for every plate or per plate
        (default: the description's).
    enriched : EnrichedSolve, optional
        :func:`enriched_solve` of the same solve, if already made.
    """
    t0 = time.perf_counter()
    if enriched is None:
        enriched = enriched_solve(case, solution.frequency, resolution)
    else:
        t0 -= enriched.seconds  # the estimate's cost includes its enriched solve
    resolution, enriched_resolution = _resolutions(case, resolution)
    if enriched.plates is None:
        return ErrorEstimate(None, {}, _compact(resolution), _compact(enriched_resolution),
                             time.perf_counter() - t0, "skipped", enriched.reason)
    integrals = relative_l2_errors(solution, enriched.plates)
    plates, total = _relative(integrals)
    norm2 = sum(n for _, n in integrals.values())
    shares = {pid: e / norm2 if norm2 > 0.0 else 0.0 for pid, (e, _) in integrals.items()}
    in_plane_integrals = in_plane_l2_errors(solution, enriched.membranes)
    in_plane, in_plane_total = _relative(in_plane_integrals)
    displacement, _ = _relative({pid: (e + integrals[pid][0], n + integrals[pid][1])
                                 for pid, (e, n) in in_plane_integrals.items()})
    unseen = unrefined_lines(case, solution.frequency, resolution, enriched_resolution)
    count_fixed = bool(unseen and case.discretisation.interface_functions)
    return ErrorEstimate(total, plates, _compact(resolution), _compact(enriched_resolution),
                         time.perf_counter() - t0, shares=shares, in_plane=in_plane,
                         in_plane_total=in_plane_total, displacement=displacement,
                         unseen_lines=unseen, unseen_count_fixed=count_fixed,
                         unseen_near_forces=unresolved_near_forces(
                             case, {pid: p.problem for pid, p in solution.plates.items()},
                             resolution, enriched_resolution))


def _relative(integrals: Mapping[str, tuple[float, float]]
              ) -> tuple[dict[str, float], float | None]:
    r"""Per plate :math:`\sqrt{\int|e|^2/\int|u^+|^2}` and over them all (None when there
    are none), from ``{plate: (error integral, norm integral)}``; 0 for a zero field."""
    if not integrals:
        return {}, None
    error2 = sum(e for e, _ in integrals.values())
    norm2 = sum(n for _, n in integrals.values())
    return ({pid: math.sqrt(e / n) if n > 0.0 else 0.0 for pid, (e, n) in integrals.items()},
            math.sqrt(error2 / norm2) if norm2 > 0.0 else 0.0)


def _resolutions(
    case: Case, resolution: float | Mapping[str, float] | None,
) -> tuple[dict[str, float], dict[str, float]]:
    """Per plate, the resolution of the solve (``resolution``: one number, a mapping or None
    for the description's) and of its enriched solve (:data:`ENRICHMENT` times it)."""
    per_plate = {pid: plate_resolution(case, pid, resolution) for pid in case.plates}
    return per_plate, {pid: ENRICHMENT * r for pid, r in per_plate.items()}


def _compact(resolution: Mapping[str, float]) -> float | dict[str, float]:
    """One number when every plate has the same resolution, else the mapping."""
    values = set(resolution.values())
    return values.pop() if len(values) == 1 else dict(resolution)


def enriched_size(case: Case, frequency: float | None = None,
                  resolution: float | Mapping[str, float] | None = None) -> SizeEstimate:
    """:func:`solver.sizing.estimate_size` of the estimate's enriched solve (every count of
    the rule at ``resolution``, default the description's, times :data:`ENRICHMENT`)."""
    return estimate_size(case, frequency, _resolutions(case, resolution)[1])


def _enriched_solve_unaffordable(case: Case, frequency: float,
                                 enriched_resolution: Mapping[str, float]) -> str:
    """Why the enriched assembly solve is not made (:mod:`solver.sizing` estimates), or ''."""
    size = estimate_size(case, frequency, enriched_resolution)
    memory = available_memory()
    if size.solve_seconds > ENRICHED_SOLVE_SECONDS:
        return (f"the enriched solve it needs would take about {size.solve_seconds:.2g} s "
                f"(more than {ENRICHED_SOLVE_SECONDS:g} s)")
    if memory is not None and size.solve_bytes > 0.5 * memory:
        return (f"the enriched solve it needs would take about {size.solve_bytes / 1e9:.2g} GB, "
                f"more than half the {memory / 1e9:.2g} GB available")
    return ""


def slow_lines(case: Case, frequency: float) -> tuple[str, ...]:
    """The moving lines whose loads converge slowly, an end free to slide (a free edge, or a
    supported one free in plane) or meeting other moving lines: their members reach further,
    so that their Legendre count stops above the usual
    (:func:`solver.layout.answered_wavenumber`); ``docs/accuracy.md`` section 8."""
    if not case.moving_lines():  # the common case, without the plates' problems
        return ()
    return _slow_lines(case, plate_problems(case, frequency))


def _slow_lines(case: Case, problems: Mapping[str, PlateProblem]) -> tuple[str, ...]:
    """:func:`slow_lines` from the plates' problems."""
    return tuple(jid for jid in case.moving_lines() if answered_wavenumber(case, jid, problems)
                 > members_wavenumber(case, jid, problems))


def unseen_lines_text(lines: Sequence[str], estimate: float, count_fixed: bool) -> str:
    """Why an estimate cannot see the error of ``lines`` (:func:`unrefined_lines`), for a
    message: their count is the description's (``count_fixed``), or it stopped where their
    members' reach stops growing, at a pinned end's cap
    (:data:`solver.line_ends.PINNED_END_REACH`)."""
    why = ("fixed by [discretisation] interface_functions" if count_fixed else
           "stopped where their members' reach stops growing, at a pinned end: "
           "solver.line_ends.PINNED_END_REACH")
    return (f"the Legendre functions of {', '.join(lines)} do not grow with the resolution "
            f"(their count {why}), and their loads converge slowly (an end free, pinned or "
            f"meeting other moving lines), so the estimate {estimate:.1e} cannot see their "
            "error (docs/accuracy.md section 8)")


def unseen_lines_remedy(count_fixed: bool) -> str:
    """What gives an estimate that sees the lines of :func:`unseen_lines_text`."""
    if count_fixed:
        return "let their count grow (leave interface_functions out) for an estimate that sees them"
    return ("an estimate at a lower [discretisation] resolution, where their count still "
            "grows, sees them")


def unseen_texts(estimate: ErrorEstimate, value: float) -> dict[str, str]:
    """What ``estimate`` cannot see, by kind (``"lines"``: :func:`unrefined_lines`, ``"near
    forces"``: :func:`unresolved_near_forces`): why, quoting the estimate ``value``, and what
    would let it see; empty where it sees every error. For the messages of ``--tolerance`` and
    the warnings beside a printed estimate."""
    texts = {}
    if estimate.unseen_lines:
        fixed = estimate.unseen_count_fixed
        texts["lines"] = (f"{unseen_lines_text(estimate.unseen_lines, value, fixed)}; "
                          f"{unseen_lines_remedy(fixed)}")
    if estimate.unseen_near_forces:
        texts["near forces"] = (f"{near_forces_text(estimate.unseen_near_forces, value)}; "
                                f"{near_force_remedy(estimate.unseen_near_forces)}")
    return texts


def unrefined_lines(case: Case, frequency: float, resolution: Mapping[str, float],
                    enriched_resolution: Mapping[str, float]) -> tuple[str, ...]:
    """The moving lines whose loads converge slowly (:func:`slow_lines`) and whose Legendre
    count the enriched solve does not raise: the estimate cannot see their loads' error. With
    the members' reach growing with the resolution
    (:data:`solver.line_ends.REACH_GROWTH_FROM`) that happens where the description fixes the
    count (``interface_functions``), and where the reach stops at its cap, at a pinned end
    (:data:`solver.line_ends.PINNED_END_REACH`: from resolution 3.375 on the T junction whose
    stiffener is free at its ends and the fold with sliding ends, where the in-plane errors
    then fall little and the estimate read 0.18 to 0.56 of them, ``docs/accuracy.md`` section
    8). With the reach fixed, as until 2026-11-27, the free-ended fold of
    ``tests/test_free_ends.py`` met its stop at resolution 5, 8.5e-4 off finite elements while
    the estimate read 0.07 of that."""
    if not case.moving_lines():
        return ()
    problems = plate_problems(case, frequency)
    slow = _slow_lines(case, problems)
    if not slow:
        return ()
    counts = interface_layout(case, problems, resolution).counts
    enriched = interface_layout(case, problems, enriched_resolution).counts
    return tuple(jid for jid in slow if enriched[jid] <= counts[jid])


def unresolved_near_forces(case: Case, problems: Mapping[str, PlateProblem],
                           resolution: Mapping[str, float],
                           enriched_resolution: Mapping[str, float]) -> tuple[NearForce, ...]:
    r"""The point forces next to a joint (:func:`solver.near_forces.forces_near_joints`) whose
    joint the enriched solve does not refine as it refines the rays, its count :math:`M^+`
    short of :data:`ENRICHMENT` times the solve's :math:`M` (past one function of rounding):
    :math:`M^+ - 2 < E\,(M - 2) - E`. Its count then stops where the members' edge waves stop
    (:func:`solver.joint_rules.interface_function_count`), both solves leave the same part of
    the force's near field unresolved, and the estimate cannot see it (``docs/accuracy.md``
    section 8). Measured against exact solutions with the force 1 to 4 cm from the joint: a
    flat two-plate chain at 450 Hz (its Levy series), the estimate 0.48 to 0.60 of the error
    at resolution 1.5 (the count 26, enriched 29) and 0.22 to 0.52 from 2.25 on (29 and 29),
    0.91 to 0.95 at resolution 1 (18 and 26); with a third plate joined beyond, 0.03 to 0.04
    of that plate's error (7.6e-4) from 1.5 on, 0.54 at resolution 1; the U channel at 1 kHz
    (the exact folded plate, the fold moving or held) 0.22 to 0.44 at 3.375. With the force
    10 cm away (:math:`\kappa_0 d` 4.2) the chains' errors are below 1.6e-7 from 1.5 on.
    ``problems``: the plates' problems at the frequency, those of the solve."""
    near = forces_near_joints(case, problems)
    if not near:  # the common case
        return ()
    counts = interface_layout(case, problems, resolution).counts
    enriched = interface_layout(case, problems, enriched_resolution).counts
    return tuple(force for force in near if enriched[force.joint] - 2
                 < ENRICHMENT * (counts[force.joint] - 2) - ENRICHMENT)
