"""The in-plane problems of an assembly: which plates carry in-plane waves, their membrane
problems and bases (``docs/method.md`` section 10).

A plate carries in-plane waves when it is a member of a moving junction line
(:meth:`assembly.Case.moving_lines`); a flat assembly under normal loads, and every held line,
leave them out, so that their fields are those of the held-line model to the bit.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping

from assembly.case import Case
from assembly.geometry import EDGE_NAMES
from solver.line_ends import edge_reach, held_end_corners, reach_growth, singular_end_corners
from solver.membrane import MembraneEdge, MembraneProblem, membrane_stiffness
from solver.membrane_basis import MembraneBasis, build_membrane_basis, membrane_ray_counts
from solver.membrane_corners import (
    fixed_free_corners,
    fixed_free_layout,
    loaded_corners,
    logarithmic_corners,
)
from solver.plate import PlateProblem
from solver.resolution import plate_resolution

__all__ = ["MIRROR_CONDITIONS", "membrane_edge_reach", "in_plane_plates", "coplanar_closure",
           "in_plane_edge_conditions", "membrane_problems", "membrane_bases"]


def in_plane_plates(case: Case) -> list[str]:
    """The plates that carry in-plane waves: the members of the moving lines and, through
    their coplanar joints (which carry in-plane continuity), every plate joined to one by a
    coplanar joint, and so on."""
    members = coplanar_closure(case, {plate for jid in case.moving_lines()
                                      for plate in case.joints[jid].plates})
    return [pid for pid in case.plates if pid in members]


def coplanar_closure(case: Case, plates: set[str]) -> set[str]:
    """``plates`` and every plate joined to one of them by coplanar joints, transitively."""
    coplanar = [joint.plates for joint in case.joints.values() if joint.kind == "coplanar"]
    members = set(plates)
    while joined := {p for pair in coplanar if members.intersection(pair) for p in pair} - members:
        members |= joined
    return members


def in_plane_edge_conditions(case: Case) -> dict[str, dict[str, str]]:
    """Per in-plane plate (:func:`in_plane_plates`), each edge's in-plane condition: ``free``
    (with the interface loads as data) on a moving line or a coplanar joint, the boundary's
    ``in_plane`` on a supported edge, ``fixed`` on a hinge or a held line (they hold their line
    in translation), ``free`` elsewhere."""
    conditions = {pid: dict.fromkeys(EDGE_NAMES, "free") for pid in in_plane_plates(case)}
    moving = set(case.moving_lines())
    for jid, joint in case.joints.items():
        for side in joint.sides:
            if side.plate not in conditions:
                continue
            free = jid in moving or joint.kind == "coplanar"
            conditions[side.plate][side.edge] = "free" if free else "fixed"
    for boundary in case.boundaries:
        side = case.edge(boundary.edge)
        if side.plate in conditions:
            conditions[side.plate][side.edge] = boundary.in_plane_condition
    return conditions


def membrane_problems(case: Case, frequency: float) -> dict[str, MembraneProblem]:
    """``{plate: MembraneProblem}`` of the in-plane plates (:func:`in_plane_plates`); their
    moving-line edges carry no data here (their loads are interface unknowns)."""
    problems = {}
    for pid, conditions in in_plane_edge_conditions(case).items():
        plate = case.plates[pid]
        material = case.materials[plate.material]
        problems[pid] = MembraneProblem(
            tuple(plate.size),
            membrane_stiffness(material.young_modulus, plate.thickness,
                               material.poisson_ratio, material.loss_factor),
            material.poisson_ratio, material.density * plate.thickness,
            2.0 * math.pi * frequency,
            {edge: MembraneEdge(condition) for edge, condition in conditions.items()})
    return problems


MIRROR_CONDITIONS = ("diaphragm", "roller")
r"""In-plane edge conditions that the edge waves of the perpendicular edges meet by themselves
when they are homogeneous (as every boundary of an assembly is): a wave
:math:`U(x)\sin\beta y,\ V(x)\cos\beta y` of an edge along :math:`y` (the sum of its
:math:`\pm\beta` nodes) has :math:`u_x = 0` and :math:`N_{yy} = 0` on :math:`y = 0` (a
diaphragm), its :math:`\cos`/:math:`\sin` partner :math:`u_y = 0` and :math:`N_{xy} = 0` (a
roller) (``docs/method.md`` section 10.3)."""


def membrane_edge_reach(conditions: Mapping[str, str], line_reach: float,
                        own_reach: float) -> tuple[float, ...]:
    r""":math:`\beta_{max}` of each edge, in the order of :data:`EDGE_NAMES`: ``own_reach``
    (:math:`\tau\max(k_S, 5/R_{max})`) on an edge whose ``conditions`` entry is one of
    :data:`MIRROR_CONDITIONS`, which needs none of the wavenumbers a line drives along the
    edges it meets, else ``line_reach`` (:math:`\tau\max(\kappa_0, k_S, 5/R_{max})`)."""
    return tuple(own_reach if conditions[edge] in MIRROR_CONDITIONS else line_reach
                 for edge in EDGE_NAMES)


def membrane_bases(case: Case, problems: Mapping[str, MembraneProblem],
                   bending: Mapping[str, PlateProblem],
                   resolution: float | Mapping[str, float] | None = None
                   ) -> dict[str, MembraneBasis]:
    r"""Each in-plane plate's basis (``docs/method.md`` section 10.3): edge waves up to
    :math:`\beta_{max} = \tau\max(\kappa_0, k_S, 5/R_{max})`, with the plate's bending
    wavenumber :math:`\kappa_0` (the bending waves of the members load the line) and the
    description's ``edge_wavenumber_ratio`` :math:`\tau` (further on a member of a line with a
    ``roller`` end or meeting other moving lines: :func:`solver.line_ends.edge_reach`), except on
    a diaphragm or roller edge (:func:`membrane_edge_reach`); counts by the resolution rule."""
    settings = case.discretisation
    bases, shared = {}, {}  # identical plates share one basis, and through it their traces
    for pid, problem in problems.items():
        k_long, k_shear = problem.wavenumbers
        radius = 0.5 * math.hypot(*problem.size)
        reach = edge_reach(case, pid, resolution, in_plane=True)
        beta_max = membrane_edge_reach(
            {edge: condition.condition for edge, condition in problem.edges.items()},
            reach * max(bending[pid].kappa.real, k_shear.real, 5.0 / radius),
            reach * max(k_shear.real, 5.0 / radius))
        scale = plate_resolution(case, pid, resolution)
        counts = membrane_ray_counts(problem.size, k_shear.real, beta_max, scale,
                                     scale / reach_growth(case, pid, resolution))
        # the corner functions depend on the corners' layout only: plates whose conditions
        # differ elsewhere (a panel's mirrored end bays) still share one basis and its traces
        layout = fixed_free_layout(problem.conditions)
        logarithmic = singular_end_corners(case, pid)
        loaded = held_end_corners(case, pid, resolution)
        key = (problem.size, k_long, k_shear, counts, beta_max, layout,
               problem.poisson_ratio if layout or loaded else None, logarithmic, loaded)
        if key not in shared:
            rays = build_membrane_basis(problem.size, k_long, k_shear, counts, beta_max,
                                        settings.quadrature_per_sector)
            shared[key] = dataclasses.replace(rays, corners=fixed_free_corners(
                problem.size, problem.conditions, problem.poisson_ratio, k_long, k_shear)
                + logarithmic_corners(problem.size, logarithmic, k_long, k_shear)
                + loaded_corners(problem.size, loaded, problem.poisson_ratio, k_long, k_shear))
        bases[pid] = shared[key]
    return bases
