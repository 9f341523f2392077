"""Refinement to a tolerance: solve, estimate the error (:mod:`solver.estimate`), and raise the
resolution of the plates that need it until every plate's estimate is below the tolerance, or
say why it cannot be reached (``docs/accuracy.md`` sections 1 and 2).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import networkx as nx

from assembly.case import Case
from solver.errors import ToleranceError, check_finite
from solver.estimate import (
    ENRICHMENT,
    ErrorEstimate,
    enriched_solution,
    estimate_error,
    slow_lines,
    unseen_texts,
)
from solver.in_plane import in_plane_plates
from solver.near_forces import forces_near_joints, near_force_remedy
from solver.rays import QUASI_STATIC_KAPPA_R
from solver.resolution import plate_resolution
from solver.solution import CaseSolution
from solver.substructure import solve_assembly
from solver.vtcr import solve_case

__all__ = ["refined_together", "solve_to_tolerance"]


def solve_to_tolerance(
    case: Case, frequency: float, tolerance: float, max_refinements: int = 4,
    resolution: float | Mapping[str, float] | None = None,
) -> tuple[CaseSolution, ErrorEstimate]:
    r"""Solve, estimate, and raise the resolution until every plate's estimate is below
    ``tolerance``.

    A plate's estimate is :meth:`solver.estimate.ErrorEstimate.plate_errors` (its relative L2
    error of ``w``, or of the displacement :math:`(u, v, w)` where that is larger). Each
    refinement multiplies the ray counts of the plates that need it by
    :data:`solver.estimate.ENRICHMENT` (and the interface counts of their joints), starting
    from ``resolution`` (default the description's): :func:`_to_refine`, with the plates
    :func:`refined_together` ties to them.
    The total over the assembly is then below ``tolerance`` too (it is a weighted mean of the
    plates' squared errors of ``w``). Where every plate is refined, the next solve is the
    estimate's enriched solve, already made: only its interface problem is solved again, for
    the joint residuals (:func:`_with_residuals`).

    Returns
    -------
    (solution, ErrorEstimate)
        The first solution whose estimate is below ``tolerance`` on every plate.

    Raises
    ------
    ToleranceError
        After ``max_refinements`` refinements, or as soon as a refinement no longer lowers the
        worst plate's estimate by half (the ray basis has met its round-off floor, the plate
        is outside what the basis converges for, or its moving line's loads converge slowly:
        :func:`solver.estimate.slow_lines`): the message names the plate with the
        largest estimated error, its estimates at each resolution and its condition estimate.
        Or when the estimate meets ``tolerance`` but cannot see the error of some lines
        (:func:`solver.estimate.unrefined_lines`) or of a point force next to a joint
        (:func:`solver.estimate.unresolved_near_forces`): the message names them.
    """
    resolution = {pid: plate_resolution(case, pid, resolution) for pid in case.plates}
    together = refined_together(case)
    solution = solve_case(case, frequency, resolution=resolution, check=False)
    history = []
    for refinement in range(max_refinements + 1):
        enriched, finer = enriched_solution(case, frequency, resolution)
        estimate = estimate_error(case, solution, resolution, enriched)
        if estimate.total is None:
            raise ToleranceError(f"{frequency:g} Hz: the tolerance cannot be checked: "
                                 f"{estimate.reason}; solve without a tolerance")
        history.append(estimate)
        worst = max(estimate.plate_errors().values())
        if worst <= tolerance:
            unseen = unseen_texts(estimate, worst)
            if unseen:
                raise ToleranceError(f"{frequency:g} Hz: the tolerance cannot be checked: "
                                     f"{'; '.join(unseen.values())}, or solve without a "
                                     "tolerance")
            return solution, estimate
        stalled = len(history) > 1 and worst > 0.5 * max(history[-2].plate_errors().values())
        if stalled or refinement == max_refinements:
            raise ToleranceError(_tolerance_message(case, frequency, tolerance, history,
                                                    solution, stalled))
        refine = set().union(*(together[pid] for pid in _to_refine(case, estimate, tolerance)))
        resolution = {pid: r * (ENRICHMENT if pid in refine else 1.0)
                      for pid, r in resolution.items()}
        # where every plate is refined the next solve is the enriched one, already made (it
        # was: an estimate without it has no total, and stopped above)
        if refine == set(case.plates):
            solution = _with_residuals(case, finer)
        else:
            solution = finer = enriched = None  # freed before the next solve
            solution = solve_case(case, frequency, resolution=resolution, check=False)
    raise AssertionError("unreachable")


def refined_together(case: Case) -> dict[str, frozenset[str]]:
    """Per plate, the plates a refinement of it refines too: itself, and for a plate with an
    in-plane field every in-plane plate it reaches through moving lines and coplanar joints.

    Why: a moving line's interface functions follow its finest member, which a coarser
    member's rays do not answer; refining one member alone made the field worse (the U
    channel at 3 kHz, resolution 1 with its leg C at 1.5: the error of ``w`` on C 1.4e-3 ->
    2.0e-3, of ``(u, v)`` 9.8e-4 -> 8.2e-3, true and estimated alike), where refining the
    three together gives estimates of 2e-6 to 4e-6 on ``w`` (true errors 5e-7 to 8e-7)."""
    in_plane = set(in_plane_plates(case))
    links = nx.Graph()
    links.add_nodes_from(case.plates)
    for plates in ([case.joints[jid].plates for jid in case.moving_lines()]
                   + [joint.plates for joint in case.joints.values()
                      if joint.kind == "coplanar" and set(joint.plates) <= in_plane]):
        nx.add_path(links, plates)
    return {pid: frozenset(group) for group in nx.connected_components(links) for pid in group}


def _to_refine(case: Case, estimate: ErrorEstimate, tolerance: float) -> set[str]:
    r"""The plates a refinement refines: those whose own estimate exceeds ``tolerance``
    (:meth:`solver.estimate.ErrorEstimate.plate_errors`), and each plate joined to one of them
    whose error of ``w`` is larger than that plate may have, :math:`\int_{\Omega_a}|e|^2 >
    \mathrm{tolerance}^2\int_{\Omega_b}|w|^2`: an error small beside its own plate's field may
    still spoil a weakly excited neighbour through their joint. The rule reads a plate, its
    joints and its neighbours only, so that a plate gets the same decision in an assembly of
    any size (the share of the squared total above :math:`\mathrm{tolerance}^2/P`, P plates,
    refined ever more plates as P grew). Plates far from the load or already converged keep
    their counts."""
    errors = estimate.plate_errors()
    failing = {pid for pid, error in errors.items() if error > tolerance}
    refine = set(failing)
    for joint in case.joints.values():
        for weak in failing.intersection(joint.plates):
            if estimate.plates[weak] > 0.0:  # its part of the squared norm: shares / error**2
                allowed = tolerance**2 * estimate.shares[weak] / estimate.plates[weak] ** 2
                refine.update(pid for pid in joint.plates if estimate.shares[pid] > allowed)
    return refine


def _tolerance_message(case: Case, frequency: float, tolerance: float,
                       history: Sequence[ErrorEstimate], solution: CaseSolution,
                       stalled: bool) -> str:
    plate = history[-1].worst_plate()
    steps = ", ".join(f"{e.plate_errors()[plate]:.1e} at resolution {e.resolution_of(plate):.3g}"
                      for e in history)
    last = history[-1]
    field_name = ("the displacement (u, v, w)"
                  if last.displacement.get(plate, 0.0) > last.plates[plate] else "w")
    problem = solution.plates[plate].problem
    condition = solution.plates[plate].condition_estimate
    spans = 0.5 * math.hypot(*problem.size) * problem.kappa.real
    slow = [jid for jid in slow_lines(case, frequency) if plate in case.joints[jid].plates]
    near = forces_near_joints(case, {pid: p.problem for pid, p in solution.plates.items()})
    if not stalled:
        cause = ("it still decreases; start from a higher [discretisation] resolution than "
                 f"{history[0].resolution_of(plate):g}")
    elif spans < QUASI_STATIC_KAPPA_R:
        cause = (f"the plate is far below its first resonances (its half-diagonal is "
                 f"{spans / (2 * math.pi):.2g} bending wavelength), where the ray basis converges "
                 "slowly; raise the frequency or accept the estimated error")
    elif near:
        closest = min(near, key=lambda force: force.kappa_d)
        cause = (f"refinement no longer lowers it: the point force on plate {closest.plate} is "
                 f"{closest.distance:.2g} m from its joint {closest.joint} (kappa0 d = "
                 f"{closest.kappa_d:.2g}), whose near field the joint's functions and the rays' "
                 "edge waves follow slowly (docs/accuracy.md section 8); "
                 f"{near_force_remedy([closest])}, or accept a tolerance above the estimate")
    elif slow:
        cause = (f"refinement no longer lowers it: the loads of {', '.join(slow)} converge "
                 "slowly in their Legendre functions at their ends free or meeting other "
                 "moving lines (docs/accuracy.md section 8); accept a tolerance above the "
                 "estimate")
    else:
        cause = (f"refinement no longer lowers it (condition estimate {condition:.1e}): the ray "
                 "basis has reached its round-off floor; accept a tolerance above the "
                 "estimate, or check for a load very close to an edge or extreme properties")
    return (f"{frequency:g} Hz: the estimated error {last.plate_errors()[plate]:.1e} of "
            f"{field_name} stays above the tolerance {tolerance:g}; plate {plate}: {steps}; "
            f"{cause}")


def _with_residuals(case: Case, solution: CaseSolution) -> CaseSolution:
    """A solve made without joint residuals as :func:`solver.vtcr.solve_case` returns it: an
    assembly's interface problem solved again on the solve's system (its plates' blocks, the
    cost of a solve, are not rebuilt) with the residuals and their reference energy."""
    if not case.joints:
        return solution
    return check_finite(solve_assembly(case, solution.frequency, system=solution.system))
