r"""Point forces next to joints: where the joints' loads follow a force's near field slowly
(``docs/accuracy.md`` section 8).

A point force at a distance :math:`d` from a joined edge of its plate loads the joint with its
near field: along the joint, a peak about :math:`d` wide, whose spectrum along the joint decays
as :math:`e^{-\beta d}`. The joint's Legendre functions resolve wavenumbers up to about
:math:`2(M - 2)/L`, and their count :math:`M` stops growing with the resolution where those
reach the members' largest edge wavenumber :math:`\tau\kappa_a`, at
:math:`M = \lceil\tfrac{\tau}{2}\kappa_aL\rceil + 2`
(:func:`solver.joint_rules.interface_function_count`). Where :math:`\kappa_0 d` is small, the
part of the spectrum beyond stays unresolved at every resolution: refinement stalls, and the
error estimate, whose enriched solve's count stops there too, no longer sees that part of the
error.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import NamedTuple

from assembly.case import Case
from solver.plate import PlateProblem

__all__ = ["NEAR_FORCE_KAPPA_D", "NearForce", "forces_near_joints", "near_force_remedy",
           "near_forces_text"]

NEAR_FORCE_KAPPA_D = 2.0
r"""A point force closer to one of its plate's joined edges than this many :math:`1/\kappa_0`
loads the joint with a near field that the joint's functions and the rays' edge waves follow
slowly (``docs/accuracy.md`` section 8). Measured at resolutions 2.25 and 3.375, where the
joints' counts have stopped: on the U channel of ``tests/test_moving_lines.py`` at 1 kHz, a
force at :math:`\kappa_0d` = 0.45 and 0.89 from a fold left ``w`` 7.4e-3 and 1.4e-3 off and
refinement stalled, at 2.2 it met 1e-4 at the default resolution; on a flat two-plate chain at
450 Hz (against its Levy series) forces at :math:`\kappa_0d` = 0.42 to 1.7 left 1.3e-3 to
4.1e-5 (worst plate), at 2.1 1.2e-5 and at 4.2 1.9e-8, the estimate reading 0.22 to 0.72 of
the error."""


class NearForce(NamedTuple):
    """A point force next to a joined edge of its plate (:func:`forces_near_joints`)."""

    plate: str
    joint: str
    distance: float
    kappa_d: float
    members: tuple[str, ...]


def forces_near_joints(case: Case, problems: Mapping[str, PlateProblem]) -> list[NearForce]:
    r"""Each point force closer than :data:`NEAR_FORCE_KAPPA_D` :math:`/\kappa_0` to an edge of
    its plate that a joint joins, with :math:`d` its distance to that edge,
    :math:`\kappa_0 d` (:math:`\kappa_0` the plate's real bending wavenumber; ``problems``: the
    plates' :class:`solver.plate.PlateProblem` at the frequency) and the joint's plates."""
    near = []
    for load in case.loads:
        if load.kind != "point_force" or load.plate not in problems:
            continue
        (lx, ly), (x, y) = case.plates[load.plate].size, load.at
        to_edge = {"left": x, "right": lx - x, "bottom": y, "top": ly - y}
        kappa = problems[load.plate].kappa.real
        near += [NearForce(load.plate, jid, to_edge[side.edge], kappa * to_edge[side.edge],
                           tuple(joint.plates))
                 for jid, joint in case.joints.items() for side in joint.sides
                 if side.plate == load.plate and kappa * to_edge[side.edge] < NEAR_FORCE_KAPPA_D]
    return near


def near_forces_text(near: Sequence[NearForce], estimate: float) -> str:
    """Why an estimate cannot see the error that forces next to joints leave
    (:func:`solver.estimate.unresolved_near_forces`), for a message."""
    forces = "; ".join(f"the point force on plate {force.plate} is {force.distance:.2g} m from "
                       f"its joint {force.joint} (kappa0 d = {force.kappa_d:.2g})"
                       for force in near)
    return (f"{forces}: the enriched solve refines the joint's Legendre functions less than its "
            "rays (their count stops at the members' reach), so neither solve follows that "
            f"force's near field and the estimate {estimate:.1e} cannot see the error it leaves "
            "(docs/accuracy.md section 8)")


def near_force_remedy(near: Sequence[NearForce]) -> str:
    r"""What lets a solve follow the near field of forces next to joints (``near``): the joints'
    plates with their own ``edge_wavenumber_ratio`` above 1.5 times the finest resolution
    asked, or the forces moved away.

    Why that ratio: the joint's count stops growing from resolution :math:`s = 2\tau/3` on
    (:func:`solver.joint_rules.interface_function_count`), and at its cap the functions reach
    the rays' largest edge wavenumber, where a near field loads them. On the three-plate chain
    of ``tests/test_near_forces.py`` at resolution 3.375, a ratio of 5 (56 functions, at the
    cap) left 1.4e-2, 7 and 10 (the same 56, below it) 5.0e-5 and 3.5e-5, 3.5 (40, at the cap)
    8.0e-4 and the default 2.5 (29) 1.0e-3; at 2.25 (38 functions, below the cap from 3.5 on)
    7.9e-4, 4.4e-4, 2.8e-4 and 2.5e-4 for 3.5, 5, 7 and 10. Given to P1 and P2 alone, 10 gives
    the same fields on them as given to every plate (2.5e-4 and 2.0e-4 at 2.25, 3.5e-5 and
    2.8e-5 at 3.375) in 1.1 s, 2.5 s and 6.8 s at resolutions 1.5, 2.25 and 3.375, against
    1.5 s, 3.8 s and 11.0 s on every plate and 0.09 s, 0.16 s and 0.33 s for the default's
    stalled solves (processor time, best of three, alternating in one run)."""
    plates = sorted({plate for force in near for plate in force.members})
    also = f", and the same for {', '.join(plates[1:])}" if len(plates) > 1 else ""
    return ("give the plates next to the force their own edge_wavenumber_ratio, above 1.5 times "
            "the finest resolution asked, so that the joint's count keeps growing "
            f"([discretisation.plates.{plates[0]}] edge_wavenumber_ratio = 10{also}: on a "
            "three-plate chain 10 converged to resolution 3.375 where the default 2.5 stalled, "
            "with an estimate that sees the error, at 12 to 21 times the solve), or move the "
            "force away from the joint")
