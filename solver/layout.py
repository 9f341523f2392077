r"""Where the interface unknowns of an assembly sit, and how many each joint has.

The interface unknowns :math:`S` (``docs/method.md`` sections 6.2, 6.2b, 6.4 and 7.1) are,
per joint, its load functions on the joint's Legendre functions (``C``, ``F`` or ``FA``,
``FB``; per junction member ``C.PLATE`` and, without a rigid member, the line's rotation
``T``), then one force per static corner at a junction point. :func:`interface_layout`
counts and places them from the description alone (all that :mod:`solver.sizing` needs);
the loads they put on each plate, :math:`B_i`, are :mod:`solver.interface_loads`'.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from assembly import Case, EdgeId
from assembly.geometry import EDGE_NAMES
from assembly.joints import Joint
from solver.in_plane import in_plane_edge_conditions, in_plane_plates
from solver.interface_loads import (
    MOVING_MEMBER_LOADS,
    balancing_member,
    member_axes,
    member_load,
    rigid_members,
    traction_loads,
)
from solver.joint_rules import (
    LOAD_WAVENUMBER_COUNT,
    end_layer_count,
    extra_load_functions,
    interface_function_count,
    legendre_count_floor,
    pinned_line_count,
    singular_load_ends,
)
from solver.line_ends import (
    HELD_END_FROM,
    edge_reach,
    end_layer_lines,
    held_free_ends,
    pinned_lines,
)
from solver.plate import KINEMATIC_DEFLECTION, PlateProblem
from solver.resolution import joint_resolution

__all__ = ["InterfaceLayout", "interface_layout", "answered_wavenumber", "members_wavenumber",
           "junction_point_axes"]

Corner = tuple[str, int]
"""A plate corner: the plate and the corner's index (:data:`assembly.geometry.EDGE_NAMES` order)."""

def _has_mass_channel(joint: Joint, identify: Collection[str]) -> bool:
    return joint.kind == "coplanar" and (joint.mass > 0.0 or "mass" in identify)


def _layout(case: Case, counts: Mapping[str, int],
            moving: Collection[str]) -> tuple[dict[str, dict[str, slice]], int]:
    """Slices of S: per joint ``C`` and ``F`` (or ``FA``, ``FB``), per junction ``C.PLATE``
    for each member (and, on a moving line, its edge forces ``K.PLATE``, ``Nn.PLATE``,
    ``Nt.PLATE``: :math:`K_n`, :math:`N_{nn}`, :math:`N_{nt}`; not for its balancing member,
    whose loads its balances give: :func:`member_load`) and, without a rigid member,
    ``T`` (the line's rotation, on the joint's Legendre functions); a coplanar joint between
    plates with in-plane waves also ``Nn``, ``Nt``, the in-plane tractions on both its edges;
    then the corner forces."""
    layout, start = {}, 0
    identify = case.updating.identify
    in_plane = set(in_plane_plates(case))
    for jid, joint in case.joints.items():
        sizes = {"C": counts[jid]}
        if joint.kind == "coplanar":
            sizes.update(dict.fromkeys(["FA", "FB"] if _has_mass_channel(joint, identify)
                                       else ["F"], counts[jid]))
            if in_plane.issuperset(joint.plates):
                sizes.update(dict.fromkeys(["Nn", "Nt"], counts[jid]))
        elif case.is_line(jid):
            names = MOVING_MEMBER_LOADS if jid in moving else ("C",)
            # a moving line's balances fix one member's loads (member_load)
            kept = [p for p in joint.plates if jid not in moving or p != balancing_member(joint)]
            sizes = {f"{name}.{plate}": counts[jid] for plate in kept for name in names}
            if not rigid_members(joint):
                sizes["T"] = counts[jid]
        layout[jid] = {}
        for name, size in sizes.items():
            layout[jid][name] = slice(start, start + size)
            start += size
    return layout, start


def _corner_of(edge_name: str, end: int) -> int:
    """Plate corner index at the start (end=0) or end (end=1) of an edge."""
    return (EDGE_NAMES.index(edge_name) + end) % 4


def _junctions(case: Case, problems: Mapping[str, PlateProblem]) -> list[list[tuple[Corner, bool]]]:
    """Groups of plate corners that coincide at joint ends, with their kinematic flags."""
    parent = {}

    def find(a: Corner) -> Corner:
        while parent.setdefault(a, a) != a:
            a = parent[a]
        return a

    for jid, joint in case.joints.items():
        sides, directions = joint.sides, case.member_directions(jid)
        for end in (0, 1):  # the corners of every member at each end of the line
            corners = [find((side.plate, _corner_of(side.edge, end if d > 0 else 1 - end)))
                       for side, d in zip(sides, directions)]
            for other in corners[1:]:
                root, other = find(corners[0]), find(other)
                if root != other:
                    parent[other] = root
    groups = {}
    for corner in list(parent):
        groups.setdefault(find(corner), []).append(corner)
    junctions = []
    for members in groups.values():
        flags = []
        for pid, c in sorted(members):
            kinds = [problems[pid].condition(EDGE_NAMES[c]).kind,
                     problems[pid].condition(EDGE_NAMES[c - 1]).kind]
            flags.append(((pid, c), any(k in KINEMATIC_DEFLECTION for k in kinds)))
        if any(not kinematic for _, kinematic in flags):
            junctions.append(flags)
    return junctions


def _loading_slots(case: Case, jid: str, slots: Mapping[str, slice],
                   plate: str) -> tuple[list[slice], list[slice]]:
    """The slots of a joint that load ``plate``'s edge: those of its bending field (a junction
    member's moment and Kirchhoff shear, :func:`member_load`; every load of a two-plate joint
    but its in-plane tractions) and those of its in-plane field (:func:`traction_loads`)."""
    tractions = [part for terms in traction_loads(case, jid, slots, plate) or ()
                 for part, _ in terms]
    if case.is_line(jid):
        bending = [part for name in ("C", "K")
                   for part, _ in member_load(case, jid, slots, plate, name)]
    else:
        bending = [part for part in slots.values() if part not in tractions]
    return bending, tractions


HELD_IN_PLANE = {"fixed": ("normal", "tangent"), "diaphragm": ("tangent",),
                 "roller": ("normal",), "free": ()}
"""The in-plane displacement components an edge's in-plane condition gives (section 10.1):
``fixed`` holds :math:`u_n` and :math:`u_t`, ``diaphragm`` :math:`u_t`, ``roller`` :math:`u_n`."""

PARALLEL_TOLERANCE = 1e-9
"""Below this, a cross product of unit normals is parallel and a singular value of the
junction point's geometry (unit vectors' dot products, of order 1) is zero."""


def _held_directions(case: Case, corner: Corner, kinematic: bool,
                     in_plane: Mapping[str, Mapping[str, str]]) -> list[np.ndarray]:
    r"""The 3D directions in which a plate corner holds its junction point: the plate's normal
    :math:`\mathbf e_z` if its deflection is held there (``kinematic``), and the in-plane
    components its two edges at the corner hold (:data:`HELD_IN_PLANE`; ``in_plane``: the
    in-plane plates' edge conditions). A plate without in-plane waves is rigid in its plane
    (the held-line model of section 6.2b), so it holds both in-plane directions."""
    pid, c = corner
    held = [case.plates[pid].frame.normal] if kinematic else []
    for edge in (EDGE_NAMES[c], EDGE_NAMES[c - 1]):  # the edges that start and end at c
        normal, tangent, _ = member_axes(case, EdgeId(pid, edge))
        axes = {"normal": normal, "tangent": tangent}
        condition = in_plane[pid][edge] if pid in in_plane else "fixed"
        held += [axes[name] for name in HELD_IN_PLANE[condition]]
    return held


def junction_point_axes(case: Case, flags: Sequence[tuple[Corner, bool]],
                        in_plane: Mapping[str, Mapping[str, str]]) -> np.ndarray | None:
    r"""The geometry of a junction point whose plates are not coplanar
    (``docs/method.md`` section 6.4): :math:`A = E_s^TV`, shape (static corners, r), with
    :math:`E_s` the static corners' plate normals :math:`\mathbf e_{z,c}` (columns, in the
    order of ``flags``) and :math:`V` an orthonormal basis of the directions in which the point
    may move (orthogonal to every held direction, :func:`_held_directions`).

    The point translates by :math:`\mathbf X_P = V\xi`; a static corner's deflection is
    :math:`w_c = \mathbf e_{z,c}\cdot\mathbf X_P`, so :math:`w_s = A\xi`; the corner forces
    :math:`P_c` balance along every free direction, :math:`A^TP = 0` (the held directions'
    reactions take the rest). None where section 6.4's coplanar rule applies: frameless or
    parallel normals, or a point held in every direction by a kinematic corner (then every
    static corner has :math:`w_c = 0`, the same rows)."""
    frames = [case.plates[pid].frame for (pid, _), _ in flags]
    if any(frame is None for frame in frames):
        return None
    normals = [frame.normal for frame in frames]
    if all(np.linalg.norm(np.cross(normals[0], n)) < PARALLEL_TOLERANCE for n in normals[1:]):
        return None
    held = [d for corner, kinematic in flags
            for d in _held_directions(case, corner, kinematic, in_plane)]
    free = np.eye(3)
    if held:
        _, singular, vh = np.linalg.svd(np.array(held))
        free = vh[int(np.sum(singular > PARALLEL_TOLERANCE)):].T
    if free.shape[1] == 0 and any(kinematic for _, kinematic in flags):
        return None
    static = [n for n, (_, kinematic) in zip(normals, flags) if not kinematic]
    return np.array(static) @ free


def _plate_unknowns(case: Case, layout: Mapping[str, Mapping[str, slice]],
                    corner_columns: Mapping[Corner, int]
                    ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """Per plate, the sorted interface unknowns that load its bending field (its joints' loads
    on its edges and its junction corners' forces), and those that load its in-plane field.

    A plate's transfer operators have one column per unknown it sees, and every product
    with them (each channel's and constraint's rows) as many: a member of a three-plate
    moving line sees 4 of the line's 12 load functions, two in bending and two in plane."""
    bending = {pid: [] for pid in case.plates}
    in_plane = {pid: [] for pid in case.plates}
    for jid, joint in case.joints.items():
        for side in joint.sides:
            for seen, parts in zip((bending, in_plane),
                                   _loading_slots(case, jid, layout[jid], side.plate)):
                seen[side.plate] += [np.arange(part.start, part.stop) for part in parts]
    for (pid, _), column in corner_columns.items():
        bending[pid].append(np.array([column]))

    def sorted_unique(columns: list[np.ndarray]) -> np.ndarray:
        return np.unique(np.concatenate(columns)) if columns else np.zeros(0, dtype=int)

    return ({pid: sorted_unique(cols) for pid, cols in bending.items()},
            {pid: sorted_unique(cols) for pid, cols in in_plane.items() if cols})


@dataclass(frozen=True)
class InterfaceLayout:
    """Where the interface unknowns of an assembly sit in S (:func:`interface_layout`).

    Attributes
    ----------
    counts : dict of str to int
        Legendre functions per unknown function of each joint.
    slots : dict
        Slices of each joint's unknown functions in S (:func:`_layout`).
    junctions : list
        Corner groups at joint ends (:func:`_junctions`).
    corner_columns : dict of (str, int) to int
        Position in S of the unknown corner force of each static junction corner.
    n_s : int
    unknowns : dict of str to ndarray of int
        Per plate, the interface unknowns that load its bending field.
    membrane_unknowns : dict of str to ndarray of int
        Per plate with in-plane tractions on its edges, the unknowns that load its in-plane
        field.
    junction_axes : list
        Per junction, :func:`junction_point_axes` (None: the coplanar rule of section 6.4).
    load_ends : dict of str to tuple
        Per joint, how its loads are singular at its ends
        (:func:`solver.joint_rules.singular_load_ends` at the joint's resolution).
    """

    counts: dict
    slots: dict
    junctions: list
    corner_columns: dict
    n_s: int
    unknowns: dict
    membrane_unknowns: dict
    junction_axes: list
    load_ends: dict


def interface_layout(case: Case, problems: Mapping[str, PlateProblem],
                     resolution: float | Mapping[str, float] | None = None) -> InterfaceLayout:
    """The interface unknowns of an assembly, counted from its description.

    ``resolution`` is None (the description's), one factor, or a mapping by plate; a joint's
    interface functions follow the finest of its plates, and stop, on a moving line, at the
    largest wavenumber every member's rays answer (:func:`interface_function_count`, with the
    members' own edge reach: :func:`answered_wavenumber`); a moving line with a mixed end has
    at least :func:`legendre_count_floor` of them, one with an end that translates along it (an
    end that slides, or a junction point: :func:`solver.line_ends.end_layer_lines`) at least
    :func:`solver.joint_rules.end_layer_count`, one with a pinned end
    (:func:`solver.line_ends.pinned_lines`) :func:`solver.joint_rules.pinned_line_count` from
    the resolution where that applies.
    """
    counts, load_ends = {}, {}
    moving = set(case.moving_lines())
    layered, pinned = end_layer_lines(case), pinned_lines(case)
    tau = case.discretisation.edge_wavenumber_ratio
    for jid, joint in case.joints.items():
        length = case.edge_length(joint.sides[0])
        kappas = [problems[plate].kappa.real for plate in joint.plates]
        joint_scale = joint_resolution(case, jid, resolution)
        ends = load_ends[jid] = singular_load_ends(case, jid, resolution)
        answered = (answered_wavenumber(case, jid, problems, resolution) if jid in moving
                    else _own_reach(case, jid, max(kappas), resolution))
        counts[jid] = (case.discretisation.interface_functions
                       or (jid in pinned and pinned_line_count(answered, length, joint_scale,
                                                            pinned[jid]))
                       or max(interface_function_count(max(kappas), length, joint_scale, tau,
                                                       answered),
                              legendre_count_floor(ends),
                              end_layer_count(answered, length, joint_scale, tau)
                              if jid in layered else 0)
                       ) + extra_load_functions(ends)
    layout, n_s = _layout(case, counts, moving)
    junctions = _junctions(case, problems)
    corner_columns = {}
    for flags in junctions:
        for corner, kinematic in flags:
            if not kinematic:
                corner_columns[corner] = n_s
                n_s += 1
    in_plane = in_plane_edge_conditions(case)
    axes = [junction_point_axes(case, flags, in_plane) for flags in junctions]
    return InterfaceLayout(counts, layout, junctions, corner_columns, n_s,
                           *_plate_unknowns(case, layout, corner_columns), axes, load_ends)


def _own_reach(case: Case, joint_id: str, kappa0: float,
               resolution: float | Mapping[str, float] | None) -> float | None:
    r""":math:`\kappa_a` of a joint that is not a moving line: None (its :math:`\kappa_0`, the
    usual) unless one of its plates reaches further than the description's
    ``edge_wavenumber_ratio`` :math:`\tau`; then :math:`\kappa_0\min_m\tau_m/\tau`, so that
    the count's cap :math:`\tfrac\tau2\kappa_a`
    (:func:`solver.joint_rules.interface_function_count`) follows the plates' shortest reach,
    as a moving line's does (:func:`answered_wavenumber`). :math:`\tau_m` is the plate's own
    ratio (``[discretisation.plates.ID]``), and on a held line with an end on a free edge its
    reach, which grows with the resolution (:func:`solver.line_ends.edge_reach`,
    :func:`solver.line_ends.held_free_ends`): the moment there is singular, and with the count
    stopped at :math:`\tfrac\tau2\kappa_0` the paper's folded plate with its model's
    :math:`k = 10^5` N at 1234.5 Hz stopped 1.6e-5 and 1.3e-5 off independent finite elements
    at resolutions 1.875 and 2.8, where the estimate read 0.37 and 0.41 of that (1.0e-5 and
    3.1e-6, estimated 0.75 and 1.37 times, with the count following; ``docs/method.md``
    section 5.5)."""
    settings = case.discretisation
    plates = case.joints[joint_id].plates
    if any(held_free_ends(case, joint_id)):
        ratios = [edge_reach(case, plate, resolution) for plate in plates]
    else:
        ratios = [settings.edge_ratio(plate) for plate in plates]
    if all(ratio == settings.edge_wavenumber_ratio for ratio in ratios):
        return None
    return kappa0 * (min(ratios) / settings.edge_wavenumber_ratio)


def answered_wavenumber(case: Case, joint_id: str, problems: Mapping[str, PlateProblem],
                        resolution: float | Mapping[str, float] | None = None) -> float:
    r""":math:`\kappa_a = \min_m \kappa_{0,m}\,\tau_m/\tau` (1/m) of a moving line, so that the
    cap :math:`\tfrac\tau2\kappa_a` of :func:`solver.joint_rules.interface_function_count`
    (:math:`\tau` the description's ``edge_wavenumber_ratio``) is half the largest edge
    wavenumber every member's rays reach: :math:`\tau_m` is the member's own reach at its
    resolution (:func:`solver.line_ends.edge_reach`, ``resolution`` as there: three times
    :math:`\tau` where the line meets other lines or ends on a free edge, growing with the
    resolution above :data:`solver.line_ends.REACH_GROWTH_FROM`).

    There the line's loads converge slowly in their Legendre functions (its ends are corners
    of the assembled field), and stopping the count at :math:`\tau\kappa_0/2` hid it: from
    resolution 5/3 on, the count no longer grew, nor in the error estimate's enriched solve.
    An L fold with free ends at 300 Hz (``tests/test_free_ends.py``) stalled 1.7e-3 off
    independent finite elements while resolutions 2.25 and 3.375 agreed to 1e-6 and the
    estimate said 5e-6; with the members' reach it is 5.0e-4 and 3.4e-4 off there, and with
    the reach growing with the resolution 5.3e-4 and 4.4e-5
    (:data:`solver.line_ends.REACH_GROWTH_FROM`). A line with a mixed end keeps
    :math:`\min_m\kappa_{0,m}`: its logarithmic loads and
    :func:`solver.joint_rules.legendre_count_floor` carry its ends, and more functions cost it
    reciprocity and convergence (the hanging L fold of ``tests/test_moving_lines.py`` at 1 kHz
    and resolution 2.25: reciprocity 3.7e-6 to 4.1e-5, the change of ``w`` to 3.4 from 2.9e-5
    to 3.2e-4).

    A line held in its plane at an end whose loads carry their singular terms there
    (:func:`solver.line_ends.held_end_exponents`) keeps the usual cap: those terms carry the
    ends' layer, and following the doubled reach then spoils the solve (the T junction of
    ``tests/test_held_ends.py`` at 300 Hz, resolutions 2.25 and 3.4: 5.6e-4 and 3.0e-4 off its
    finite elements, against 1.8e-5 and 1.4e-5). Another line held in its plane at an end
    (:func:`solver.line_ends.held_end_lines`), whose members reach twice as far from resolution
    :data:`solver.line_ends.HELD_END_FROM` on, has its count follow that reach only where the
    usual one would cap it below the wavenumbers' count at
    that resolution, :math:`\tfrac\tau2\kappa_a < 0.75\,s_h\max_m\kappa_{0,m}`
    (:func:`_held_count_follows`): members of different wavenumbers, the slowest capping the
    count (a stiffened skin). Elsewhere the count stays at the usual reach
    (``docs/method.md`` section 10.4, *Ends held in their plane*)."""
    ends = singular_load_ends(case, joint_id, resolution)
    if any(end is True for end in ends):
        return members_wavenumber(case, joint_id, problems)
    plates = case.joints[joint_id].plates
    tau = case.discretisation.edge_wavenumber_ratio

    def answered(held_ends: bool) -> float:
        # the reach in units of tau first: exactly 1 where a member reaches as the description
        # says, so that such a line's kappa_a is its members' kappa_0 to the bit, which
        # solver.estimate.slow_lines compares it with (kappa_0 tau / tau rounded above kappa_0
        # at 5 to 9 % of the frequencies and made such lines "slow")
        return min(problems[plate].kappa.real
                   * (edge_reach(case, plate, resolution, held_ends) / tau) for plate in plates)

    usual, wider = answered(False), answered(True)
    if any(ends):  # its loads' functions t^(lambda - 1) carry the held ends' layer
        return usual
    if wider == usual or _held_count_follows(max(problems[plate].kappa.real for plate in plates),
                                             usual, tau):
        return wider
    return usual


def _held_count_follows(kappa0: float, kappa_usual: float, tau: float) -> bool:
    r"""Whether the Legendre count of a line held at an end follows its members' doubled reach:
    :math:`\tfrac\tau2\kappa_a < 0.75\,s_h\kappa_0` (0.75:
    :data:`solver.joint_rules.LOAD_WAVENUMBER_COUNT`), :math:`\kappa_a` what the usual reach
    answers, :math:`\kappa_0` the members' largest bending wavenumber and :math:`s_h`
    :data:`solver.line_ends.HELD_END_FROM`: the usual cap of
    :func:`solver.joint_rules.interface_function_count` would stop the count below the
    wavenumbers' at :math:`s_h`.

    Why: the loads of a held end converge slowly (``docs/method.md`` section 10.4). On a skin
    of 1 mm stiffened by plates of 1.5 to 2 mm (:math:`\kappa_0/\kappa_a` = 1.2 to 1.4) the
    usual cap binds from resolution 1.2 and the line's count must grow past it: with the
    doubled reach alone and that cap, ``cases/stiffened_panel.toml`` stalls 4.3e-4, 3.4e-4 and
    6.2e-4 off its finite elements in ``(u, v)`` at 184.8, 230 and 257 Hz from resolution 1.5
    to 3.4, and the error estimate says 0.00 to 0.04 of it; with the count following, 6.4e-5
    to 3.4e-4 at 3.4, the estimate 0.5 to 2.5 times the error. Between members alike (the L
    fold of two 2 mm plates) the count reaches the wavenumbers' before the cap binds, and
    following the doubled reach past it spoils the solve at high resolution: at 3.4 the fold
    is 7.7e-4 and 5.2e-4 off in ``(u, v)`` at 300 Hz and 1 kHz, against 3.0e-6 and 7.4e-5 at
    the usual cap, where its count stays. Those figures are from before the lines' loads
    carried their singular terms (0.3.8): the panel's and the T junction's lines carry them
    now and keep the usual cap (:func:`answered_wavenumber`), so the rule decides only for
    held lines whose ends have no exponent loading them, between unlike members (an L fold of
    a 1 mm and a 2 mm plate), which no reference has measured."""
    return 0.5 * tau * kappa_usual < LOAD_WAVENUMBER_COUNT * HELD_END_FROM * kappa0


def members_wavenumber(case: Case, joint_id: str, problems: Mapping[str, PlateProblem]
                       ) -> float:
    r"""The smallest bending wavenumber :math:`\kappa_0` of a joint's members (1/m): the
    :math:`\kappa_a` of a line whose members reach as far as the description says."""
    return min(problems[plate].kappa.real for plate in case.joints[joint_id].plates)
