"""From a validated :class:`assembly.Case` to the pure plate problems of :mod:`solver.plate`.

The only place where the solver reads the description: everything downstream works on
arrays and frozen dataclasses.
"""

from __future__ import annotations

import math

from solver.kirchhoff import complex_bending_stiffness
from solver.plate import EdgeCondition, EdgeLoad, PlateProblem, PointForce
from solver.rays import EDGES, RayCounts, automatic_ray_counts, build_ray_basis

__all__ = ["plate_problem", "plate_ray_counts", "plate_basis", "joint_edge_kinds"]


def joint_edge_kinds(case):
    """Edge condition that each joined edge takes in its plate's subproblem.

    A coplanar joint leaves both components static (translation and rotation loads are
    interface unknowns, so the edge behaves as ``free`` with unknown data); a hinge fixes the
    joint line (``simply_supported``, with the moment an interface unknown).
    """
    kinds = {}
    for joint in case.joints.values():
        kind = "free" if joint.kind == "coplanar" else "simply_supported"
        for side in joint.sides:
            kinds[(side.plate, side.edge)] = kind
    return kinds


def plate_problem(case, plate_id, frequency):
    """The plate ``plate_id`` of ``case`` at ``frequency`` (Hz) as a :class:`PlateProblem`.

    Joined edges carry no data here (their loads are interface unknowns, see
    :func:`joint_edge_kinds`).
    """
    plate = case.plates[plate_id]
    material = case.materials[plate.material]
    conditions = {name: "free" for name in EDGES}
    for (pid, edge), kind in joint_edge_kinds(case).items():
        if pid == plate_id:
            conditions[edge] = kind
    for boundary in case.boundaries:
        side = case.edge(boundary.edge)
        if side.plate == plate_id:
            conditions[side.edge] = boundary.condition
    shear, moment, forces = {}, {}, []
    for load in case.loads:
        if load.kind == "point_force":
            if load.plate == plate_id:
                forces.append(PointForce(tuple(load.at), complex(load.amplitude)))
            continue
        side = case.edge(load.edge)
        if side.plate != plate_id:
            continue
        target = shear if load.kind == "edge_shear" else moment
        if side.edge in target:
            raise ValueError(f"two {load.kind} loads on {load.edge}: give their sum")
        target[side.edge] = EdgeLoad(complex(load.amplitude), load.distribution)
    edges = {
        name: EdgeCondition(conditions[name], shear.get(name), moment.get(name)) for name in EDGES
    }
    return PlateProblem(
        size=tuple(plate.size),
        bending_stiffness=complex_bending_stiffness(
            material.young_modulus, plate.thickness, material.poisson_ratio,
            material.loss_factor),
        poisson_ratio=material.poisson_ratio,
        mass_per_area=material.density * plate.thickness,
        omega=2.0 * math.pi * frequency,
        edges=edges,
        point_forces=tuple(forces),
    )


def plate_ray_counts(case, plate_id, problem, resolution=None):
    """Sector counts of one plate: the automatic rule, then the description's overrides."""
    settings = case.discretisation
    scale = settings.resolution if resolution is None else resolution
    counts = automatic_ray_counts(problem.kappa.real, problem.size, scale,
                                  settings.edge_wavenumber_ratio)
    override = settings.for_plate(plate_id)
    return RayCounts(
        interior=override.interior if override.interior is not None else counts.interior,
        edge_propagating=(counts.edge_propagating if override.edge_propagating is None
                          else (2 * (override.edge_propagating // 2),) * 4),
        edge_evanescent=(counts.edge_evanescent if override.edge_evanescent is None
                         else (override.edge_evanescent,) * 4),
        corner=override.corner if override.corner is not None else counts.corner,
    )


def plate_basis(case, plate_id, problem, resolution=None):
    """Ray basis of one plate (counts from :func:`plate_ray_counts`)."""
    counts = plate_ray_counts(case, plate_id, problem, resolution)
    settings = case.discretisation
    return build_ray_basis(problem.size, problem.kappa, counts,
                           n_q=settings.quadrature_per_sector,
                           tau=settings.edge_wavenumber_ratio)
