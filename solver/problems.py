"""From a validated :class:`assembly.Case` to the pure plate problems of :mod:`solver.plate`.

With :mod:`solver.line_ends` (the rules a moving line's ends set) and :mod:`solver.layout`
(the interface unknowns), where the solver reads the description: everything downstream works
on arrays and frozen dataclasses. Here: each plate's problem (its edges' conditions and loads)
and its basis (rays, edge waves as far as :func:`solver.line_ends.edge_reach` says, corner
functions).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable, Mapping

from assembly.case import Case
from assembly.geometry import EDGE_NAMES, plate_edges
from solver.kirchhoff import complex_bending_stiffness
from solver.line_ends import edge_reach, held_end_corners, reach_growth, singular_end_corners
from solver.plate import EdgeCondition, EdgeLoad, PlateProblem, PointForce
from solver.plate_corners import WedgeFamily, clamped_free_wedges, logarithmic_wedges
from solver.rays import RayBasis, RayCounts, WedgeBasis, automatic_ray_counts, build_ray_basis
from solver.resolution import plate_resolution

__all__ = [
    "joint_edge_kinds",
    "plate_bases",
    "plate_basis",
    "plate_problem",
    "plate_problems",
    "plate_ray_counts",
    "plate_wedges",
]


def joint_edge_kinds(case: Case) -> dict[tuple[str, str], str]:
    """Edge condition that each joined edge takes in its plate's subproblem.

    A coplanar joint, or a moving junction line, leaves both components static (translation
    and rotation loads are interface unknowns, so the edge behaves as ``free`` with unknown
    data); a hinge or a held junction line fixes the joint line (``simply_supported``, with the
    moment an interface unknown).
    """
    kinds = {}
    moving_lines = set(case.moving_lines())
    for jid, joint in case.joints.items():
        moving = joint.kind == "coplanar" or jid in moving_lines
        kind = "free" if moving else "simply_supported"
        for side in joint.sides:
            kinds[(side.plate, side.edge)] = kind
    return kinds


def plate_problem(case: Case, plate_id: str, frequency: float) -> PlateProblem:
    """The plate ``plate_id`` of ``case`` at ``frequency`` (Hz) as a :class:`PlateProblem`.

    Joined edges carry no data here (their loads are interface unknowns, see
    :func:`joint_edge_kinds`).
    """
    return plate_problems(case, frequency, [plate_id])[plate_id]


def plate_problems(case: Case, frequency: float,
                   plate_ids: Iterable[str] | None = None) -> dict[str, PlateProblem]:
    """``{plate: PlateProblem}`` (:func:`plate_problem`) of ``plate_ids`` (default every plate),
    from one pass over the joints, boundaries and loads: plate by plate, the passes would cost
    plates x joints."""
    plate_ids = list(case.plates) if plate_ids is None else list(plate_ids)
    conditions = {pid: dict.fromkeys(EDGE_NAMES, "free") for pid in plate_ids}
    for (pid, edge), kind in joint_edge_kinds(case).items():
        if pid in conditions:
            conditions[pid][edge] = kind
    for boundary in case.boundaries:
        side = case.edge(boundary.edge)
        if side.plate in conditions:
            conditions[side.plate][side.edge] = boundary.condition
    shear = {pid: {} for pid in plate_ids}
    moment = {pid: {} for pid in plate_ids}
    forces = {pid: [] for pid in plate_ids}
    for load in case.loads:
        if load.kind == "point_force":
            if load.plate in forces:
                forces[load.plate].append(PointForce(tuple(load.at), complex(load.amplitude)))
            continue
        side = case.edge(load.edge)
        if side.plate not in conditions:
            continue
        target = (shear if load.kind == "edge_shear" else moment)[side.plate]
        if side.edge in target:
            raise ValueError(f"two {load.kind} loads on {load.edge}: give their sum")
        target[side.edge] = EdgeLoad(complex(load.amplitude), load.distribution)
    problems = {}
    for pid in plate_ids:
        plate = case.plates[pid]
        material = case.materials[plate.material]
        edges = {name: EdgeCondition(conditions[pid][name], shear[pid].get(name),
                                     moment[pid].get(name)) for name in EDGE_NAMES}
        problems[pid] = PlateProblem(
            size=tuple(plate.size),
            bending_stiffness=complex_bending_stiffness(
                material.young_modulus, plate.thickness, material.poisson_ratio,
                material.loss_factor),
            poisson_ratio=material.poisson_ratio,
            mass_per_area=material.density * plate.thickness,
            omega=2.0 * math.pi * frequency,
            edges=edges,
            point_forces=tuple(forces[pid]),
        )
    return problems


def plate_ray_counts(case: Case, plate_id: str, problem: PlateProblem,
                     resolution: float | Mapping[str, float] | None = None) -> RayCounts:
    """Sector counts of one plate: the automatic rule, then the description's overrides.

    The overrides are counts at the description's own resolution; a ``resolution`` other than
    the description's scales them by the same ratio as the rule's counts (the enriched solve of
    the error estimate refines every plate, overridden or not).
    """
    settings = case.discretisation
    scale = plate_resolution(case, plate_id, resolution)
    counts = automatic_ray_counts(problem.kappa.real, problem.size, scale,
                                  edge_reach(case, plate_id, resolution),
                                  scale / reach_growth(case, plate_id, resolution))
    override = settings.for_plate(plate_id)
    ratio = scale / settings.resolution

    def scaled(value: int, multiple: int = 1) -> int:
        if ratio == 1.0:
            return value
        return multiple * math.ceil(ratio * value / multiple - 1e-9)

    return RayCounts(
        interior=(scaled(override.interior, 4) if override.interior is not None
                  else counts.interior),
        edge_propagating=(counts.edge_propagating if override.edge_propagating is None
                          else (scaled(2 * (override.edge_propagating // 2), 2),) * 4),
        edge_evanescent=(counts.edge_evanescent if override.edge_evanescent is None
                         else (scaled(override.edge_evanescent),) * 4),
        corner=scaled(override.corner) if override.corner is not None else counts.corner,
    )


def plate_wedges(case: Case, plate_id: str, problem: PlateProblem) -> tuple[WedgeFamily, ...]:
    """The corner functions of the plate's corners where a clamped edge meets a free one
    (:func:`solver.plate_corners.clamped_free_wedges`): a free or loaded edge, or a member edge
    of a moving line. The edge of a held line (a hinge, or a junction line held in translation:
    :math:`w = 0`, its rotation tied by a spring) counts as clamped (``docs/method.md`` section
    5.5, *A held line's end on a free edge*). A coplanar joint's edge does not count: the plate
    continues across it, and the assembled field has no corner there. Then the bending
    logarithmic family (:func:`solver.plate_corners.logarithmic_wedges`) at every corner of
    :func:`solver.line_ends.singular_end_corners`."""
    corners = singular_end_corners(case, plate_id)
    edges = plate_edges(problem.size) if corners else ()
    logarithmic = tuple(logarithmic_wedges(edges[c].start, edges[c].tangent) for c in corners)
    kinds = [problem.condition(name).kind for name in EDGE_NAMES]
    if "clamped" not in kinds and not {"simply_supported", "free"} <= set(kinds):
        return logarithmic  # the common case, without a pass over the joints
    for joint in case.joints.values():
        for side in joint.sides:
            if side.plate == plate_id:
                i = EDGE_NAMES.index(side.edge)
                if joint.kind == "coplanar":
                    kinds[i] = "joined"
                elif kinds[i] == "simply_supported":  # a held line's edge (joint_edge_kinds)
                    kinds[i] = "clamped"
    return clamped_free_wedges(problem.size, kinds, problem.poisson_ratio) + logarithmic


def plate_basis(case: Case, plate_id: str, problem: PlateProblem,
                resolution: float | Mapping[str, float] | None = None) -> RayBasis:
    """Shape functions of one plate: rays (counts from :func:`plate_ray_counts`), and the
    corner functions of :func:`plate_wedges` after them."""
    counts = plate_ray_counts(case, plate_id, problem, resolution)
    settings = case.discretisation
    rays = build_ray_basis(problem.size, problem.kappa, counts,
                           n_q=settings.quadrature_per_sector,
                           tau=edge_reach(case, plate_id, resolution))
    if held_end_corners(case, plate_id, resolution):
        # the loads t^(lambda - 1) at those corners: their work on the rays, and the field they
        # drive near the corners, need the rules graded there (the end edges' too: on the
        # panel's far bay at 257 Hz and resolution 3.4, w 2.4e-5 off with the line edges
        # graded alone, 8.7e-6 with all, 5.8e-5 with none); every edge, so that the members
        # of a panel's lines, whose held corners differ, share one basis and its traces
        rays = dataclasses.replace(rays, graded_edges=EDGE_NAMES)
    wedges = plate_wedges(case, plate_id, problem)
    if not wedges:
        return rays
    return WedgeBasis.extending(rays, problem.kappa, wedges)


def plate_bases(case: Case, problems: Mapping[str, PlateProblem],
                resolution: float | Mapping[str, float] | None) -> dict[str, RayBasis]:
    """Each plate's ray basis; plates of the same size, wavenumber and ray counts share one
    object (a grid's or a panel's identical plates), so that their joint traces are computed
    once (:func:`solver.plate.edge_values`' cache)."""
    bases, shared = {}, {}
    for pid, problem in problems.items():
        key = (problem.size, problem.kappa, plate_ray_counts(case, pid, problem, resolution),
               edge_reach(case, pid, resolution), plate_wedges(case, pid, problem),
               bool(held_end_corners(case, pid, resolution)))
        if key not in shared:
            shared[key] = plate_basis(case, pid, problem, resolution)
        bases[pid] = shared[key]
    return bases
