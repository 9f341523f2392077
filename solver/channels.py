r"""The joints of an assembly: their residual channels and their constraint rows.

Formulation: ``docs/method.md`` sections 6.2 (coplanar joints and hinges), 6.2b (junction
lines), 6.3 (residuals) and 6.4 (junction points). Each joint gives

* *channels*, the samples of its unreliable laws (a spring, a line mass), affine in the
  interface unknowns :math:`S` and in the law's parameter :math:`c`:
  :math:`r = (LS + l) - c\,(RS + \rho)` (:class:`Channel`);
* *constraint rows*, its reliable equations (rigid translation of a coplanar joint, rigid
  members and moment balance of a junction line, the corners of a junction point), as
  :class:`solver.interface.Block` rows of :math:`GS = g`.

Everything here is built once per frequency and is independent of the joint parameters.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from assembly import Case
from solver.admissibility import CornerDeflections, PlateAdmissibility
from solver.interface import Block, residual_weight, squared_norm
from solver.interface_loads import (
    FORCE_COMPONENTS,
    LoadTerms,
    member_axes,
    member_load,
    rigid_members,
)
from solver.joint_rules import (
    joint_gauss,
    load_function_projection,
    load_function_values,
    translational_stiffness,
)
from solver.layout import PARALLEL_TOLERANCE, InterfaceLayout
from solver.plate import edge_values

__all__ = ["Channel", "JointBuild", "RIGID_CROSSOVER", "two_plate_joint", "junction_line",
           "junction_corner_rows", "channel_blocks", "joint_residuals"]

RIGID_CROSSOVER = 1e3
r"""Crossover of the joint residuals to compliance form, in units of the plates' own
stiffness: :math:`10^3D\kappa_0` for rotation (N), :math:`10^3D\kappa_0^3` for a line mass
(:math:`\omega^2\mu`, N/m^2). A rotational spring :math:`10^3` times stiffer than the plate's
bending stiffness over a wavelength (log10 k = 5.8 for 1 mm steel at 250 Hz) makes a joint
rigid to 1e-3 of the plates' rotations; above it the residual is measured in compliance form
(:func:`solver.interface.residual_weight`), whose weight no longer grows with k."""


@dataclass(frozen=True)
class Channel:
    r"""One residual channel of one joint, on the joint's load functions.

    The residual is :math:`r = (LS + l) - c\,(RS + \rho)`; both parts are
    :class:`solver.interface.Block` samples: the Gauss samples multiplied by
    :math:`\sqrt{\omega_q}` (the Gauss weights) and taken on an orthonormal basis :math:`Q`
    of the weighted load functions (:func:`load_function_projection`), so that the channel's energy
    is :math:`\|r\|^2 / (2\,\mathrm{Re}\,c)` of the projected law.

    Attributes
    ----------
    joint : str
        The description's joint.
    kind : {"rotation", "mass"}
    load : Block
        :math:`Q^HW^{1/2}(LS + l)`, over the joint's own load unknowns.
    kinematic : Block
        :math:`Q^HW^{1/2}(RS + \rho)`, over the interface unknowns its two plates see.
    member : str or None
        The member plate of a junction's spring channel (:attr:`name` ``JOINT.PLATE``).
    group : int
        The joint's group of interface unknowns (:attr:`AssemblySystem.unknown_groups`).
    """

    joint: str
    kind: str
    load: Block
    kinematic: Block
    crossover: float = math.inf
    member: str | None = None
    group: int = -1

    @property
    def name(self) -> str:
        """The channel's name: the joint's id, or ``JOINT.PLATE`` for a junction member."""
        return self.joint if self.member is None else f"{self.joint}.{self.member}"

    def samples(self, s: np.ndarray, c: complex) -> np.ndarray:
        """Residual samples :math:`Q^HW^{1/2}r` at interface unknowns ``s``."""
        return self.load.residual(s) - c * self.kinematic.residual(s)

    def energy(self, s: np.ndarray, c: complex) -> float | np.ndarray:
        r""":math:`e^2 = g(c)\|\Pi_\psi r\|_\Gamma^2` (J), :math:`g = 1/(2\,\mathrm{Re}\,c)`
        below the crossover (:func:`solver.interface.residual_weight`); one per column of a
        matrix ``s`` (:meth:`solver.interface.Block.residual`)."""
        return squared_norm(self.samples(s, c)) * residual_weight(c, self.crossover)

    def dissipated_power(self, s: np.ndarray, c: complex, omega: float) -> float:
        r"""Power dissipated in the channel, :math:`\tfrac12\omega\,\mathrm{Im}\,c\,
        \|\Pi_\psi[q]\|^2`: the power its loads do on the jump (kinematic samples) on the
        joint's load functions."""
        return 0.5 * omega * c.imag * squared_norm(self.kinematic.residual(s))

    def block(self, c: complex, kappa: float) -> Block:
        r"""The rows :math:`\sqrt{\kappa g(c)}\,Q^HW^{1/2}r` as one Block over
        :attr:`kinematic` ``.index`` (the load unknowns are a subset of it)."""
        scale = math.sqrt(kappa * residual_weight(c, self.crossover))
        matrix = -c * self.kinematic.matrix
        matrix[:, np.searchsorted(self.kinematic.index, self.load.index)] += self.load.matrix
        return Block(self.kinematic.index, scale * matrix,
                     scale * (self.load.offset - c * self.kinematic.offset), self.group)


@dataclass(frozen=True)
class JointBuild:
    """What every joint's channels and rows are built from at one frequency.

    Attributes
    ----------
    case : Case
    plates : PlateAdmissibility
    counts : mapping of str to int
        Load functions per unknown function of each joint (:func:`load_function_values`).
    k_max : mapping of str to float
        Per plate, the largest ray wavenumber (what a joint's quadrature must resolve).
    traces_cache : dict
        The rays' joint traces, shared by plates with one basis
        (:func:`solver.plate.edge_values`).
    moving : frozenset of str
        The moving lines (:meth:`assembly.Case.moving_lines`).
    """

    case: Case
    plates: PlateAdmissibility
    counts: Mapping[str, int]
    k_max: Mapping[str, float]
    traces_cache: dict
    moving: frozenset[str]


def _plate_stiffness(plates: PlateAdmissibility, members: Sequence[str]) -> tuple[float, float]:
    r"""The largest :math:`(D, \kappa_0)` of a joint's plates (real parts): the scale of its
    crossover to compliance form (:data:`RIGID_CROSSOVER`)."""
    return max((plates.problems[p].bending_stiffness.real, plates.problems[p].kappa.real)
               for p in members)


def two_plate_joint(build: JointBuild, jid: str, group: int
                    ) -> tuple[list[Block], list[Channel]]:
    r"""Constraint rows and channels of a coplanar joint or a hinge (``docs/method.md``
    section 6.2): the rotation channel :math:`r = C - k^*(\theta_A + \theta_B)`, with a line
    mass the mass channel :math:`r = F_A + F_B - \omega^2\mu\tfrac12(w_A + w_B)`, and for a
    coplanar joint the rigid translation :math:`\int(w_A - w_B)\psi_m = 0`.

    Each trace is taken on the joint's functions (:math:`Q^HW^{1/2}`, a channel's samples;
    :math:`\psi^TW`, the moments of the translation constraint) before the plate's transfer
    operator multiplies it: n_f rows instead of the Gauss points', a third of the products of
    the build.
    """
    case, plates = build.case, build.plates
    joint = case.joints[jid]
    a, b = joint.sides
    length = case.edge_length(a)
    ends = plates.load_ends[jid]  # a hinge's moment is singular where it ends on a free edge
    sigma, wq = joint_gauss(length, max(build.k_max[a.plate], build.k_max[b.plate]), ends)
    psi = load_function_values(sigma, length, build.counts[jid], ends)
    slots = plates.layout[jid]
    on_functions = load_function_projection(np.sqrt(wq), psi)
    projections = {"slope": ("slope", on_functions)}
    if "FA" in slots:
        projections["w"] = ("w", on_functions)
    if joint.kind == "coplanar":
        projections["w moments"] = ("w", psi.T * wq)
    traces = {}
    for side, s in ((a, sigma), (b, length - sigma)):
        rays, part = edge_values(plates.problems[side.plate], plates.bases[side.plate],
                                 side.edge, s, build.traces_cache)
        traces[side.plate, side.edge] = {
            name: plates.affine_plate_operator(side.plate, weights @ rays[key],
                                               weights @ part[key])
            for name, (key, weights) in projections.items()}
    ta, tb = traces[a.plate, a.edge], traces[b.plate, b.edge]

    def unknown(*names: str) -> Block:
        columns = np.concatenate([np.arange(slots[n].start, slots[n].stop) for n in names])
        return Block(columns, on_functions @ np.hstack([psi] * len(names)),
                     np.zeros(len(on_functions), dtype=complex))

    stiffness, kappa0 = _plate_stiffness(plates, (a.plate, b.plate))
    channels = [Channel(jid, "rotation", unknown("C"), Block.union(ta["slope"], tb["slope"]),
                        RIGID_CROSSOVER * stiffness * kappa0, group=group)]
    if "FA" in slots:
        channels.append(Channel(jid, "mass", unknown("FA", "FB"),
                                Block.union(ta["w"], tb["w"]).scaled(0.5),
                                RIGID_CROSSOVER * stiffness * kappa0**3, group=group))
    rows = []
    if joint.kind == "coplanar":
        rows.append(Block.union(ta["w moments"], tb["w moments"].scaled(-1.0)).constraint(group))
    if "Nn" in slots:
        rows += _in_plane_continuity(build.plates, jid, a.plate, b.plate, group)
    return rows, channels


def _in_plane_continuity(plates: PlateAdmissibility, jid: str, plate_a: str, plate_b: str,
                         group: int) -> list[Block]:
    r"""The in-plane continuity of a coplanar joint between plates with in-plane waves
    (``docs/method.md`` section 10.4): its edges' normals and tangents are opposite, so the
    same displacement reads :math:`u_n^A = -u_n^B`, :math:`u_t^A = -u_t^B`;
    :math:`\int(u_\alpha^A + u_\alpha^B)\psi_m = 0` for :math:`\alpha\in\{n, t\}`, the
    traction unknowns ``Nn``, ``Nt`` acting on both edges. The moments of each plate's
    ``u_n``, ``u_t`` are those its tractions were loaded with
    (:attr:`solver.admissibility.MembraneBlock.moments`), as on a moving line."""
    moments = [plates.membranes[plate].moments[jid] for plate in (plate_a, plate_b)]
    return [Block.union(plates.affine_membrane_operator(plate_a, on_a),
                        plates.affine_membrane_operator(plate_b, on_b)).constraint(group)
            for on_a, on_b in zip(*moments)]


def junction_line(build: JointBuild, jid: str, group: int) -> tuple[list[Block], list[Channel]]:
    r"""Constraint rows and spring channels of a junction line
    (``docs/method.md`` section 6.2b).

    Member :math:`i` (direction :math:`s_i`, :meth:`assembly.Case.member_directions`)
    rotates by :math:`\Theta_i = -s_i\theta_i` about the line. The line's rotation
    :math:`\Theta_J` is that of the first rigid member, or, without one, its own unknown
    ``T`` on the joint's Legendre functions. Reliable: :math:`\sum_iC_i = 0` (per Legendre
    coefficient) and :math:`\int(\Theta_i - \Theta_J)\psi_m = 0` for the other rigid
    members; each finite member's spring :math:`C_i = k_i^*(\Theta_J - \Theta_i)` is a
    channel ``JOINT.PLATE``, load :math:`C_i`, kinematic :math:`\Theta_J + s_i\theta_i`.
    Its crossover is twice a two-plate joint's: two members of :math:`2k` in series are a
    hinge of :math:`k`, with the same residual at every stiffness. A moving hinge is such a
    line of two members, the first rigid: its one channel is the joint's, with a two-plate
    joint's crossover. A moving line adds its translation and force balance
    (:func:`_moving_line_rows`).
    """
    case, plates, counts = build.case, build.plates, build.counts
    joint = case.joints[jid]
    sides, directions = joint.sides, case.member_directions(jid)
    length = case.edge_length(sides[0])
    ends = plates.load_ends[jid]
    sigma, wq = joint_gauss(length, max(build.k_max[p] for p in joint.plates), ends)
    root_w = np.sqrt(wq)
    psi = load_function_values(sigma, length, counts[jid], ends)
    slots = plates.layout[jid]
    # Theta_i of every member, unweighted, over its plate's unknowns
    rotation: dict[str, Block] = {}
    for side, direction in zip(sides, directions):
        arc = sigma if direction > 0 else length - sigma
        rays, part = edge_values(plates.problems[side.plate], plates.bases[side.plate],
                                 side.edge, arc, build.traces_cache)
        slope = plates.affine_plate_operator(side.plate, rays["slope"], part["slope"])
        rotation[side.plate] = slope.scaled(-float(direction))
    rigid = rigid_members(joint)
    if rigid:
        line = rotation[rigid[0]]
    else:
        line = Block(np.arange(slots["T"].start, slots["T"].stop), psi.astype(complex),
                     np.zeros(len(sigma), dtype=complex))
    weighted = psi.T * wq
    rows = []
    for plate in rigid[1:]:
        gap = Block.union(rotation[plate], line.scaled(-1.0)).projected(weighted)
        rows.append(gap.constraint(group))
    if jid in build.moving:  # its balances hold by construction (interface_loads.member_load)
        rows += _moving_line_rows(build, jid, group, sigma, psi, weighted)
    else:
        rows.append(_balance(slots, {(f"C.{p}"): 1.0 for p in joint.plates}, group))
    stiffness, kappa0 = _plate_stiffness(plates, joint.plates)
    channels = []
    on_functions = load_function_projection(root_w, psi)
    # a moving hinge's one spring is its channel, named and weighted as the held hinge's
    hinge = joint.kind == "hinge"
    for plate in joint.finite_members():
        load = _load_block(member_load(case, jid, slots, plate, "C"), on_functions @ psi)
        kinematic = Block.union(line, rotation[plate].scaled(-1.0)).projected(on_functions)
        channels.append(Channel(jid, "rotation", load, kinematic,
                                (1.0 if hinge else 2.0) * RIGID_CROSSOVER * stiffness * kappa0,
                                member=None if hinge else plate, group=group))
    return rows, channels


def _load_block(terms: LoadTerms, samples: np.ndarray) -> Block:
    r"""A load function :math:`\sum c\,S_{slot}` (``terms``,
    :func:`solver.interface_loads.member_load`) sampled by ``samples`` (the samples of each
    Legendre function, by columns), as a Block."""
    columns = np.concatenate([np.arange(part.start, part.stop) for part, _ in terms])
    matrix = np.hstack([coefficient * samples for _, coefficient in terms])
    order = np.argsort(columns)
    return Block(columns[order], matrix[:, order].astype(complex),
                 np.zeros(len(samples), dtype=complex))


def _balance(slots: Mapping[str, slice], coefficients: Mapping[str, float],
             group: int) -> Block:
    r"""The rows :math:`\sum_f c_f\,f_m = 0`, one per Legendre coefficient :math:`m`, of the
    load functions ``f`` named in ``coefficients``: a balance of the loads on a line."""
    first = slots[next(iter(coefficients))]
    terms = [(slots[name], c) for name, c in coefficients.items()]
    return _load_block(terms, np.eye(first.stop - first.start)).constraint(group)


def _moving_line_rows(build: JointBuild, jid: str, group: int, sigma: np.ndarray,
                      psi: np.ndarray, weighted: np.ndarray) -> list[Block]:
    r"""The reliable equations of a moving line (``docs/method.md`` section 10.4): its
    translation :math:`\mathbf X_J` is that of its first member rigid in translation, and
    every other member :math:`i` follows it,
    :math:`\int(\mathbf X_i - \mathbf X_J + \mathbf f_i/k_{t,i}^*)\psi_m\,d\sigma = 0`,
    three rows per function and member, with :math:`\mathbf X_i = u_n\mathbf n_i +
    u_t\mathbf t_i + w\,\mathbf e_{z,i}` the member edge's displacement
    (:func:`solver.interface_loads.member_axes`), :math:`\mathbf f_i = N_{nn}\mathbf n_i +
    N_{nt}\mathbf t_i + K_n\mathbf e_{z,i}` the line's force on it and
    :math:`k_{t,i}^* = k_{t,i}(1 + j\zeta_{t,i})` its translational spring (no term for a
    rigid member). The balances of the massless line, :math:`\sum_iC_i = 0` and
    :math:`\sum_i\mathbf f_i = 0` per Legendre coefficient, need no rows: the balancing
    member's loads are the others' (:func:`solver.interface_loads.member_load`). The deflection's
    traces are taken on the moments :math:`\psi^TW` (``weighted``) before the transfer
    operators multiply them, as in :func:`solver.channels.two_plate_joint`; the in-plane
    displacements' moments are those the member's tractions were loaded with
    (:attr:`solver.admissibility.MembraneBlock.moments`: the same sums on the plate's own edge
    rule, not evaluated again); the loads on the Gram matrix :math:`\int\psi_m\psi_n` of
    their functions ``psi`` (at the Gauss points)."""
    case, plates = build.case, build.plates
    joint = case.joints[jid]
    length = case.edge_length(joint.sides[0])
    displacements, axes = {}, {}
    for side, direction in zip(joint.sides, case.member_directions(jid)):
        arc = sigma if direction > 0 else length - sigma
        normal, tangent, plate_normal = axes[side.plate] = member_axes(case, side)
        rays, part = edge_values(plates.problems[side.plate], plates.bases[side.plate],
                                 side.edge, arc, build.traces_cache)
        w = plates.affine_plate_operator(side.plate, weighted @ rays["w"], weighted @ part["w"])
        u_n, u_t = (plates.affine_membrane_operator(side.plate, moments)
                    for moments in plates.membranes[side.plate].moments[jid])
        # a member along the axes has zero components: those terms would be explicit zeros,
        # as many entries again in the constraint matrix, and fill in its factorisation
        displacements[side.plate] = [
            Block.union(*(part.scaled(axis[c]) for part, axis in
                          ((u_n, normal), (u_t, tangent), (w, plate_normal)) if axis[c] != 0.0))
            for c in range(3)]
    springs = joint.translational_springs()
    line = displacements[next(p for p in joint.plates if p not in springs)]
    gram = weighted @ psi
    rows = []
    for plate in joint.plates:
        member = displacements[plate]
        if member is line:
            continue
        # on a spring, f_i / k_t*: its load functions, each along its member axis
        loads = []
        if plate in springs:
            compliance = 1.0 / translational_stiffness(joint, plate)
            loads = [(_load_block(terms, gram).scaled(compliance), axis)
                     for name, axis in zip(FORCE_COMPONENTS, axes[plate])
                     if (terms := member_load(case, jid, plates.layout[jid], plate, name))]
        for c in range(3):  # X_i - X_J (+ f_i / k_t* on a spring), component c
            gap = Block.union(member[c], line[c].scaled(-1.0),
                              *(load.scaled(axis[c]) for load, axis in loads if axis[c] != 0.0))
            rows.append(gap.constraint(group))
    return rows


def junction_corner_rows(plates: PlateAdmissibility,
                         corner_deflections: Mapping[str, CornerDeflections],
                         arrangement: InterfaceLayout, first_group: int
                         ) -> tuple[list[Block], dict[int, list[int]]]:
    r"""Constraint rows of the junction points (``docs/method.md`` section 6.4), one group
    each from ``first_group`` on, and the corner-force columns of each group.

    Coplanar plates (:attr:`InterfaceLayout.junction_axes` None): with a kinematic corner
    among them, every static corner's deflection vanishes; without one, the static corners
    share one deflection and their forces balance, :math:`\sum_cP_c = 0`. Plates that are not
    coplanar: :func:`_point_rows`.
    """
    rows, columns_of = [], {}
    for group, (flags, axes) in enumerate(zip(arrangement.junctions, arrangement.junction_axes),
                                          start=first_group):
        values = {(pid, c): plates.affine_plate_operator(
                      pid, corner_deflections[pid][0][c][None, :],
                      corner_deflections[pid][1][c:c + 1])
                  for (pid, c), _ in flags}
        static = [corner for corner, kinematic in flags if not kinematic]
        forces = [arrangement.corner_columns[corner] for corner in static]
        if axes is not None:
            rows += _point_rows([values[corner] for corner in static], forces, axes, group)
        elif any(kinematic for _, kinematic in flags):
            rows += [values[corner].constraint(group) for corner in static]
        else:
            reference = values[static[0]]
            rows += [Block.union(values[corner], reference.scaled(-1.0)).constraint(group)
                     for corner in static[1:]]
            columns = np.array(sorted(forces))
            rows.append(Block(columns, np.ones((1, len(columns)), dtype=complex),
                              np.zeros(1, dtype=complex), group))
        columns_of[group] = forces
    return rows, columns_of


def _point_rows(deflections: Sequence[Block], forces: Sequence[int], axes: np.ndarray,
                group: int) -> list[Block]:
    r"""The rows of a junction point between plates that are not coplanar
    (``docs/method.md`` section 6.4): its static corners' deflections :math:`w_s` (one-row
    Blocks) are those of one translation :math:`\mathbf X_P = V\xi` of the point,
    :math:`w_s = A\xi`, and their forces :math:`P` (columns ``forces``) balance along the
    directions it is free to move in, :math:`A^TP = 0` (``axes``: :math:`A`,
    :func:`solver.layout.junction_point_axes`). With :math:`A = U\Sigma W^T` of rank
    :math:`\rho`, eliminating :math:`\xi` leaves :math:`U_0^Tw_s = 0` (the columns of
    :math:`U` beyond :math:`\rho`) and :math:`U_1^TP = 0` (the first :math:`\rho`): as many
    rows as static corners."""
    u, singular, _ = np.linalg.svd(axes, full_matrices=True)
    rank = int(np.sum(singular > PARALLEL_TOLERANCE))
    rows = []
    if rank < len(deflections):
        kinematic = u[:, rank:]
        rows.append(Block.union(*(w.projected(kinematic[j:j + 1].T.astype(complex))
                                  for j, w in enumerate(deflections))).constraint(group))
    if rank:
        order = np.argsort(forces)
        rows.append(Block(np.asarray(forces)[order], u[order, :rank].T.astype(complex),
                          np.zeros(rank, dtype=complex), group))
    return rows


def channel_blocks(channels: Sequence[Channel], params: Mapping[tuple[str, str], complex],
                   weights: Mapping[str, float]) -> list[Block]:
    r"""Least-squares Blocks of the joint term :math:`\sum_\Gamma w_\Gamma e_\Gamma^2`.

    Parameters
    ----------
    params : dict
        ``{(joint, kind): c}`` (:func:`solver.joint_rules.joint_parameters`).
    weights : dict of str to float
        Per channel name (joint, or junction member ``JOINT.PLATE``), the weight
        :math:`w_\Gamma` of its energy (J^-1 for a dimensionless cost).
    """
    blocks = []
    for channel in channels:
        c = params[channel.name, channel.kind]
        if channel.kind == "mass" and c.real <= 0.0:
            raise ValueError(f"joint {channel.joint}: the mass channel needs a line mass > 0")
        if weights[channel.name] > 0.0:
            blocks.append(channel.block(c, weights[channel.name]))
    return blocks


def joint_residuals(channels: Sequence[Channel], params: Mapping[tuple[str, str], complex],
                    s: np.ndarray, e_ref: float) -> dict[str, float | np.ndarray]:
    """``{channel name: E_Gamma^2}`` (dimensionless) at interface unknowns ``s``: per joint,
    and per finite member ``JOINT.PLATE`` of a junction (arrays, one value per column, for a
    matrix ``s``)."""
    out = {}
    for channel in channels:
        energy = channel.energy(s, params[channel.name, channel.kind])
        out[channel.name] = out.get(channel.name, 0.0) + energy / e_ref
    return out
