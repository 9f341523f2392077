r"""Substructured VTCR of jointed plates: admissibility, joint residuals, reduced problem.

Formulation: ``docs/method.md`` sections 6.2, 6.3, 6.4 and 7 (the consistent,
"Neumann-substructured" reading of the paper's eqs. 5–16 and 25–30).

**Reliable equations (admissibility).** Each plate :math:`i` is a complete VTCR problem whose
joined edges carry unknown line loads (:math:`K_n = F`, :math:`M_n = C`, as static data of the
variational form) — a Neumann-type subproblem, square and invertible for :math:`\eta > 0`:

.. math:: K_i U_i = F_i + B_i S ,\qquad U_i = U_i^0 + T_i S,\quad
          U_i^0 = K_i^{-1}F_i,\; T_i = K_i^{-1}B_i .

:math:`S` gathers the interface unknowns, discretised along each joint by Legendre polynomials
:math:`\psi_m(\sigma)` (:math:`\sigma` the arc length along the joint from the start of its
first edge; the second edge runs the other way, as edges do when the assembly is unfolded
flat). Per joint:

* ``coplanar``: the common bending moment :math:`C` (:math:`M_n^A = M_n^B = C`) and the shear
  loads — one function :math:`F` with :math:`K_n^A = F = -K_n^B` when the joint is massless
  (exact force balance built in), or :math:`F_A, F_B` when it has a line mass. Rigid
  translation is a reliable constraint, imposed weakly:
  :math:`\int_\Gamma (w_A - w_B)\psi_m\,d\sigma = 0`.
* ``hinge``: the joint line is a kinematic support of both plates (:math:`w = 0`), and only
  :math:`C` is unknown.
* **Junction points.** Where plate corners meet at a joint end (the centre of a 2 x 2
  arrangement, the ends of a joint between free edges), each *static* corner (no kinematic
  edge next to it) receives an unknown corner force :math:`P_c` (static corner term
  :math:`(R_c - P_c)\delta w_c^*`); the displacements of the corners meeting there are made
  equal (or zero if one of them is supported), and, with no support, :math:`\sum_c P_c = 0`.
  Without them a free corner would be forced to :math:`R_c = 0`, which the continuous plate
  does not satisfy where a joint cuts it.

None of :math:`K_i, F_i, B_i, T_i`, nor the constraints, depends on the joint parameters.

**Unreliable equations (the joint laws) and their residual.** With
:math:`\theta = \partial_n w` (outward normals) and :math:`k^* = k(1 + j\zeta)`:

.. math::
    r_{rot} = C - k^*(\theta_A + \theta_B),\qquad
    r_{mass} = F_A + F_B - \omega^2\mu\,\tfrac12(w_A + w_B),

    e_\Gamma^2 = \frac{\|\Pi_\psi r_{rot}\|_\Gamma^2}{2k}
               + \frac{\|\Pi_\psi r_{mass}\|_\Gamma^2}{2\omega^2\mu} ,\qquad
    E_\Gamma^2 = e_\Gamma^2 / E_{ref},\qquad E_{int}^2 = \sum_\Gamma \alpha_\Gamma E_\Gamma^2 ,

(the constitutive-relation error in the energy norm; :math:`e^2` in J), where
:math:`\Pi_\psi` is the :math:`L^2(\Gamma)` projection on the joint's Legendre functions,
those that carry its loads (:func:`load_function_projection`): the law is imposed as far as the
discretised loads can carry it, and the part of the plates' traces beyond them, which no load
of the discretisation balances, is left to the error estimate. :math:`E_{ref}` is a
fixed energy, twice the time-averaged kinetic energy of the r = 0 solution at the initial
parameters, :math:`\tfrac12\omega^2\sum_i\rho_ih_i\int_{\Omega_i}|w_i|^2dA`, so every
:math:`E_\Gamma^2` is dimensionless and unchanged by the unit system or the load level.

Every residual sample is affine in :math:`S` and in the parameter :math:`c` (:math:`k^*` or
:math:`\omega^2\mu`): :math:`r = (L S + l) - c\,(R S + \rho)`, and its samples involve only the
interface unknowns that the joint's two plates see (their transfer operators :math:`T_i` span
the unknowns of their own joints and corners). The samples (the Gauss samples times the
square roots of the Gauss weights, taken on an orthonormal basis of the load functions: one
per function) are stored per channel, so that memory grows linearly with the assembly; a cost
for new parameters is a weighted sum of them (:meth:`Channel.block`).

**Direct problem (r = 0).** Minimise :math:`E_{int}^2` subject to the constraints
:math:`GS = g`, a sparse constrained least-squares problem (:mod:`solver.interface`). The
projected laws can be met exactly (as many as the loads they constrain), so the minimum is
zero to round-off and the minimiser is the assembly's forced response; the discretisation
floor of the updating comes from the enriched solve (:mod:`updating.inverse.cost`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
import scipy.sparse

from solver.errors import plate_condition_warnings
from solver.interface import Block, factorise_interface, residual_weight, squared_norm
from solver.joint_rules import (
    interface_function_count,
    joint_gauss,
    joint_parameters,
    legendre_values,
    load_function_projection,
)
from solver.plate import (
    PlateSolution,
    assemble_plate,
    boundary_traces,
    edge_projection,
    edge_values,
    factorise_dense,
)
from solver.power import kinetic_energies
from solver.problems import plate_basis, plate_problems, plate_ray_counts, plate_resolution
from solver.rays import EDGES
from solver.solution import CaseSolution

__all__ = [
    "Channel",
    "AssemblySystem",
    "PlateAdmissibility",
    "AssemblySolution",
    "InterfaceLayout",
    "PlateBlock",
    "interface_layout",
    "plate_block",
    "build_assembly_system",
    "plate_bases",
    "channel_blocks",
    "solve_interface",
    "solve_assembly",
]

KINEMATIC_DEFLECTION = frozenset({"clamped", "simply_supported"})

RIGID_CROSSOVER = 1e3
r"""Crossover of the joint residuals to compliance form, in units of the plates' own
stiffness: :math:`10^3D\kappa_0` for rotation (N), :math:`10^3D\kappa_0^3` for a line mass
(:math:`\omega^2\mu`, N/m^2). A rotational spring :math:`10^3` times stiffer than the plate's
bending stiffness over a wavelength (log10 k = 5.8 for 1 mm steel at 250 Hz) makes a joint
rigid to 1e-3 of the plates' rotations; above it the residual is measured in compliance form
(:func:`solver.interface.residual_weight`), whose weight no longer grows with k."""


def _projected(block, projection):
    """A Block's rows replaced by ``projection`` of them (:func:`load_function_projection`)."""
    return Block(block.index, projection @ block.matrix, projection @ block.offset)


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

    def samples(self, s, c):
        """Residual samples :math:`Q^HW^{1/2}r` at interface unknowns ``s``."""
        return self.load.residual(s) - c * self.kinematic.residual(s)

    def energy(self, s, c):
        r""":math:`e^2 = g(c)\|\Pi_\psi r\|_\Gamma^2` (J), :math:`g = 1/(2\,\mathrm{Re}\,c)`
        below the crossover (:func:`solver.interface.residual_weight`); one per column of a
        matrix ``s`` (:meth:`solver.interface.Block.residual`)."""
        return squared_norm(self.samples(s, c)) * residual_weight(c, self.crossover)

    def dissipated_power(self, s, c, omega):
        r"""Power dissipated in the channel, :math:`\tfrac12\omega\,\mathrm{Im}\,c\,
        \|\Pi_\psi[q]\|^2`: the power its loads do on the jump (kinematic samples) on the
        joint's load functions."""
        return 0.5 * omega * c.imag * squared_norm(self.kinematic.residual(s))

    def block(self, c, kappa):
        r"""The rows :math:`\sqrt{\kappa g(c)}\,Q^HW^{1/2}r` as one Block over
        :attr:`kinematic` ``.index`` (the load unknowns are a subset of it)."""
        scale = math.sqrt(kappa * residual_weight(c, self.crossover))
        matrix = -c * self.kinematic.matrix
        matrix[:, np.searchsorted(self.kinematic.index, self.load.index)] += self.load.matrix
        return Block(self.kinematic.index, scale * matrix,
                     scale * (self.load.offset - c * self.kinematic.offset), self.group)


@dataclass
class PlateAdmissibility:
    """The plates of an assembly at one frequency, each admissible for any interface unknowns:
    what the joints' channels and constraints are built on (:class:`AssemblySystem` adds them).

    Attributes
    ----------
    frequency : float
        Hz.
    problems, bases : dict of str to PlateProblem / RayBasis
    unknowns : dict of str to ndarray of int
        Per plate, the (sorted) interface unknowns it sees.
    u0 : dict of str to ndarray, shape (n_i,)
        Plate amplitudes for ``S = 0``.
    transfer : dict of str to ndarray, shape (n_i, len(unknowns[plate]))
        :math:`T_i`: plate amplitudes per unit interface unknown of the plate.
    n_s : int
        Number of interface unknowns.
    layout : dict of str to dict of str to slice
        Position of each joint's unknown functions (``"C"``, ``"F"``, ``"FA"``, ``"FB"``) in S.
    rcond : dict of str to float
        Reciprocal condition estimate of each plate's VTCR matrix.
    """

    frequency: float
    problems: dict
    bases: dict
    unknowns: dict
    u0: dict
    transfer: dict
    n_s: int
    layout: dict
    rcond: dict

    @property
    def omega(self) -> float:
        return 2.0 * math.pi * self.frequency

    def plate_amplitudes(self, s):
        """Ray amplitudes of every plate for interface unknowns ``s``."""
        return {pid: self.u0[pid] + self.transfer[pid] @ s[self.unknowns[pid]]
                for pid in self.problems}

    def affine_plate_operator(self, plate_id, values, particular):
        r"""A plate quantity :math:`XU_i + x_p` as a :class:`Block` over the plate's unknowns:
        ``(X T_i, X U_i^0 + x_p)``."""
        return Block(self.unknowns[plate_id], values @ self.transfer[plate_id],
                     values @ self.u0[plate_id] + particular)


@dataclass
class AssemblySystem(PlateAdmissibility):
    """Everything about an assembly at one frequency that does not depend on the joint laws:
    its plates (:class:`PlateAdmissibility`), and the joints' constraints and channels, built
    complete by :func:`build_assembly_system`.

    Data live where the physics lives: a plate's transfer operator spans the interface
    unknowns of its own joints and corners, a channel's samples the unknowns its two plates
    see; the size of each piece does not grow with the assembly.

    Attributes
    ----------
    constraints : (scipy.sparse.csr_matrix, ndarray)
        :math:`G` (n_g, n_s) and :math:`g` (n_g,).
    channels : list of Channel
    timings : dict of str to float
    unknown_groups, constraint_groups : ndarray of int, shape (n_s,) and (n_g,)
        Group of each interface unknown and constraint row: the joint's index in the
        description for its load unknowns, its residual and constraint rows; one group per
        junction corner after them. Each group holds as many rows as unknowns, which lets the
        interface problem be factorised group by group (:mod:`solver.multifrontal`).
    e_ref : float or None
        Reference energy (J), fixed by the first direct solve (:func:`solve_assembly`).
    plate_energies : dict of str to float or None
        Each plate's part of ``e_ref`` (J), from the same solve: the energy around a joint,
        by which the scale-free weights of the updating normalise its residual.
    """

    constraints: tuple = ()
    channels: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    unknown_groups: np.ndarray | None = None
    constraint_groups: np.ndarray | None = None
    e_ref: float | None = None
    plate_energies: dict | None = None


# ----------------------------------------------------------------------------------------------
# building the parameter-independent system
# ----------------------------------------------------------------------------------------------


def _has_mass_channel(joint, identify):
    return joint.kind == "coplanar" and (joint.mass > 0.0 or "mass" in identify)


def _layout(case, counts):
    """Slices of S: per joint ``C`` and ``F`` (or ``FA``, ``FB``), per junction ``C.PLATE``
    for each member and, without a rigid member, ``T`` (the line's rotation, on the joint's
    Legendre functions); then the corner forces."""
    layout, start = {}, 0
    identify = case.updating.identify
    for jid, joint in case.joints.items():
        sizes = {"C": counts[jid]}
        if joint.kind == "coplanar":
            sizes.update(dict.fromkeys(["FA", "FB"] if _has_mass_channel(joint, identify)
                                       else ["F"], counts[jid]))
        elif joint.kind == "junction":
            sizes = {f"C.{plate}": counts[jid] for plate in joint.plates}
            if not _rigid_members(joint):
                sizes["T"] = counts[jid]
        layout[jid] = {}
        for name, size in sizes.items():
            layout[jid][name] = slice(start, start + size)
            start += size
    return layout, start


def _rigid_members(joint):
    """The rigid members of a junction (the first one carries the line's rotation)."""
    finite = joint.finite_members()
    return [plate for plate in joint.plates if plate not in finite]


def _corner_of(edge_name, end):
    """Plate corner index at the start (end=0) or end (end=1) of an edge."""
    return (EDGES.index(edge_name) + end) % 4


def _junctions(case, problems):
    """Groups of plate corners that coincide at joint ends, with their kinematic flags."""
    parent = {}

    def find(a):
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
            kinds = [problems[pid].condition(EDGES[c]).kind,
                     problems[pid].condition(EDGES[c - 1]).kind]
            flags.append(((pid, c), any(k in KINEMATIC_DEFLECTION for k in kinds)))
        if any(not kinematic for _, kinematic in flags):
            junctions.append(flags)
    return junctions


def _plate_unknowns(case, layout, corner_columns):
    """Per plate, the sorted interface unknowns of its joints and of its junction corners."""
    seen = {pid: [] for pid in case.plates}
    for jid, joint in case.joints.items():
        columns = np.concatenate([np.arange(sl.start, sl.stop) for sl in layout[jid].values()])
        for side in joint.sides:
            seen[side.plate].append(columns)
    for (pid, _), column in corner_columns.items():
        seen[pid].append(np.array([column]))
    return {pid: np.unique(np.concatenate(cols)) if cols else np.zeros(0, dtype=int)
            for pid, cols in seen.items()}


def _local(index, columns):
    """Positions of the global unknowns ``columns`` within the sorted ``index``."""
    return np.searchsorted(index, columns)


def _union(*blocks):
    """Sum of Blocks as one Block over the union of their unknowns."""
    index = np.unique(np.concatenate([b.index for b in blocks]))
    matrix = np.zeros((blocks[0].matrix.shape[0], len(index)), dtype=complex)
    for b in blocks:
        matrix[:, _local(index, b.index)] += b.matrix
    return Block(index, matrix, sum(b.offset for b in blocks))


def _scaled(block, factor):
    """A Block with its rows multiplied by ``factor`` (a scalar or one value per row)."""
    factor = np.asarray(factor)
    return Block(block.index, (factor.T * block.matrix.T).T, factor * block.offset)


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
        Per plate, the interface unknowns it sees.
    """

    counts: dict
    slots: dict
    junctions: list
    corner_columns: dict
    n_s: int
    unknowns: dict


@dataclass(frozen=True)
class PlateBlock:
    """One plate's VTCR block, factorised (:func:`plate_block`): its boundary traces, its
    right-hand side :math:`F_i`, a solve with :math:`K_i` and the reciprocal condition
    estimate of :math:`K_i`."""

    boundary: object
    force: np.ndarray
    solve: object
    rcond: float


def interface_layout(case, problems, resolution=None) -> InterfaceLayout:
    """The interface unknowns of an assembly, counted from its description.

    ``resolution`` is None (the description's), one factor, or a mapping by plate; a joint's
    interface functions follow the finest of its plates.
    """
    counts = {}
    for jid, joint in case.joints.items():
        length = case.edge_length(joint.sides[0])
        kappa0 = max(problems[plate].kappa.real for plate in joint.plates)
        joint_scale = max(plate_resolution(case, side.plate, resolution) for side in joint.sides)
        counts[jid] = (case.discretisation.interface_functions
                       or interface_function_count(kappa0, length, joint_scale))
    layout, n_s = _layout(case, counts)
    junctions = _junctions(case, problems)
    corner_columns = {}
    for flags in junctions:
        for corner, kinematic in flags:
            if not kinematic:
                corner_columns[corner] = n_s
                n_s += 1
    return InterfaceLayout(counts, layout, junctions, corner_columns, n_s,
                           _plate_unknowns(case, layout, corner_columns))


def _plate_sides(case, corner_columns):
    """Per plate, its joint sides ``(joint, side index, side)`` and its static junction
    corners ``(corner, column)``: what its load operator needs, found once for all plates."""
    sides = {pid: [] for pid in case.plates}
    corners = {pid: [] for pid in case.plates}
    for jid, joint in case.joints.items():
        for side_index, side in enumerate(joint.sides):
            sides[side.plate].append((jid, side_index, side))
    for (pid, c), column in corner_columns.items():
        corners[pid].append((c, column))
    return sides, corners


def plate_loads(case, boundary, sides, corners, counts, layout, unknowns):
    r""":math:`B_i`: the plate's VTCR right-hand sides per unit interface unknown, over the
    interface unknowns ``unknowns`` it sees: the Legendre loads of its joint ``sides`` and the
    forces of its junction ``corners`` (:func:`_plate_sides`), with the signs of
    ``docs/method.md`` section 6.2."""
    loads = np.zeros((boundary.corner_w.shape[1], len(unknowns)), dtype=complex)

    def add(columns, values):
        loads[:, _local(unknowns, columns)] += values

    for jid, side_index, side in sides:
        length = case.edge_length(side)
        slots = {name: np.arange(sl.start, sl.stop) for name, sl in layout[jid].items()}
        traces = boundary.edges[side.edge]
        direction = case.member_directions(jid)[side_index]
        sigma = traces.s if direction > 0 else length - traces.s
        psi = legendre_values(sigma, length, counts[jid])
        if f"C.{side.plate}" in slots:  # a junction member: M_n = s_i C_i
            add(slots[f"C.{side.plate}"], direction * edge_projection(traces, "moment", psi))
            continue
        add(slots["C"], edge_projection(traces, "moment", psi))
        if "F" in slots:
            sign = 1.0 if side_index == 0 else -1.0
            add(slots["F"], sign * edge_projection(traces, "shear", psi))
        elif "FA" in slots:
            key = "FA" if side_index == 0 else "FB"
            add(slots[key], edge_projection(traces, "shear", psi))
    for c, column in corners:
        add([column], boundary.corner_w[c].conj()[:, None])
    return loads


def plate_block(problem, basis) -> PlateBlock:
    r"""One plate's VTCR block, factorised. The plate's admissibility is then
    :math:`U_i^0 = K_i^{-1}F_i` and :math:`T_i = K_i^{-1}B_i`, with its loads :math:`B_i`
    (:func:`plate_loads`)."""
    boundary = boundary_traces(problem, basis)
    matrix, force = assemble_plate(problem, boundary)
    solve, rcond = factorise_dense(matrix)
    return PlateBlock(boundary, force, solve, rcond)


def build_assembly_system(case, frequency, resolution=None) -> AssemblySystem:
    """Plate admissibility blocks, interface layout, constraints and residual channels.

    Everything here is independent of the joint parameters and is computed once per
    frequency; every piece spans one plate's or one joint's unknowns only.
    """
    t0 = time.perf_counter()
    problems = plate_problems(case, frequency)
    bases = plate_bases(case, problems, resolution)
    k_max = {pid: float(np.max(np.abs(b.k))) for pid, b in bases.items()}

    arrangement = interface_layout(case, problems, resolution)
    counts, layout, n_s = arrangement.counts, arrangement.slots, arrangement.n_s
    corner_columns, unknowns = arrangement.corner_columns, arrangement.unknowns

    sides, corners = _plate_sides(case, corner_columns)
    u0, transfer, rcond, corner_w = {}, {}, {}, {}
    plate_blocks = {}  # identical unforced plates share their traces and factorised block
    for pid in case.plates:
        problem = problems[pid]
        key = None if problem.point_forces else _plate_signature(problem, bases[pid])
        # a plate's boundary traces are the largest data of the build: kept only for plates
        # that share them, else used and dropped here, all but the corner deflections the
        # junction corners need
        block = plate_blocks.get(key) or plate_block(problem, bases[pid])
        if key is not None:
            plate_blocks[key] = block
        loads = plate_loads(case, block.boundary, sides[pid], corners[pid], counts, layout,
                            unknowns[pid])
        solution = block.solve(np.column_stack([block.force, loads]))
        u0[pid], transfer[pid], rcond[pid] = solution[:, 0], solution[:, 1:], block.rcond
        corner_w[pid] = block.boundary.corner_w, block.boundary.corner_w_p
    del plate_blocks
    t1 = time.perf_counter()

    plates = PlateAdmissibility(frequency, problems, bases, unknowns, u0, transfer, n_s, layout,
                                rcond)
    group_of = {jid: i for i, jid in enumerate(case.joints)}
    traces_cache = {}  # the rays' joint traces, shared by plates with one basis
    rows, channels = [], []  # constraint rows as Blocks of one or more rows
    for jid, joint in case.joints.items():
        group = group_of[jid]
        if joint.kind == "junction":
            junction_rows, junction_channels = _junction_line(case, plates, jid, k_max, counts,
                                                              group, traces_cache)
            rows += junction_rows
            channels += junction_channels
            continue
        a, b = joint.sides
        length = case.edge_length(a)
        sigma, wq = joint_gauss(length, max(k_max[a.plate], k_max[b.plate]))
        root_w = np.sqrt(wq)
        psi = legendre_values(sigma, length, counts[jid])
        slots = layout[jid]
        # Each trace is taken on the joint's functions (Q^H W^(1/2), a channel's samples;
        # psi^T W, the moments of the translation constraint) before the plate's transfer
        # operator multiplies it: n_f rows instead of the Gauss points', a third of the
        # products of the build.
        on_functions = load_function_projection(root_w, psi)
        moments = psi.T * wq
        projections = {"slope": ("slope", on_functions)}
        if "FA" in slots:
            projections["w"] = ("w", on_functions)
        if joint.kind == "coplanar":
            projections["w moments"] = ("w", moments)
        traces = {}
        for side, s in ((a, sigma), (b, length - sigma)):
            rays, part = edge_values(problems[side.plate], bases[side.plate], side.edge, s,
                                     traces_cache)
            traces[side.plate, side.edge] = {
                name: plates.affine_plate_operator(side.plate, weights @ rays[key],
                                                   weights @ part[key])
                for name, (key, weights) in projections.items()}
        ta, tb = traces[a.plate, a.edge], traces[b.plate, b.edge]

        def unknown(*names):
            columns = np.concatenate([np.arange(slots[n].start, slots[n].stop) for n in names])
            return Block(columns, on_functions @ np.hstack([psi] * len(names)),
                         np.zeros(len(on_functions), dtype=complex))

        stiffness, kappa0 = max((problems[p].bending_stiffness.real, problems[p].kappa.real)
                                for p in (a.plate, b.plate))
        channels.append(Channel(jid, "rotation", unknown("C"), _union(ta["slope"], tb["slope"]),
                                RIGID_CROSSOVER * stiffness * kappa0, group=group))
        if "FA" in slots:
            channels.append(Channel(jid, "mass", unknown("FA", "FB"),
                                    _scaled(_union(ta["w"], tb["w"]), 0.5),
                                    RIGID_CROSSOVER * stiffness * kappa0**3, group=group))
        if joint.kind == "coplanar":
            gap = _union(ta["w moments"], _scaled(tb["w moments"], -1.0))
            rows.append(Block(gap.index, gap.matrix, -gap.offset, group))

    unknown_groups = np.empty(n_s, dtype=int)
    for jid, slots in layout.items():
        for part in slots.values():
            unknown_groups[part] = group_of[jid]
    for group, flags in enumerate(arrangement.junctions, start=len(case.joints)):
        values = {(pid, c): plates.affine_plate_operator(pid, corner_w[pid][0][c][None, :],
                                                          corner_w[pid][1][c:c + 1])
                  for (pid, c), _ in flags}
        static = [corner for corner, kinematic in flags if not kinematic]
        kinematic = [corner for corner, kin in flags if kin]
        if kinematic:
            for corner in static:
                rows.append(Block(values[corner].index, values[corner].matrix,
                                  -values[corner].offset, group))
        else:
            reference = values[static[0]]
            for corner in static[1:]:
                gap = _union(values[corner], _scaled(reference, -1.0))
                rows.append(Block(gap.index, gap.matrix, -gap.offset, group))
            columns = np.array(sorted(corner_columns[corner] for corner in static))
            rows.append(Block(columns, np.ones((1, len(columns)), dtype=complex),
                              np.zeros(1, dtype=complex), group))
        unknown_groups[[corner_columns[corner] for corner in static]] = group
    constraint_groups = np.repeat([b.group for b in rows],
                                  [len(b.offset) for b in rows]).astype(int)
    return AssemblySystem(**vars(plates), constraints=_constraint_matrix(rows, n_s),
                          channels=channels,
                          timings={"plates": t1 - t0, "interface": time.perf_counter() - t1},
                          unknown_groups=unknown_groups, constraint_groups=constraint_groups)


def _plate_signature(problem, basis):
    """What a plate's VTCR block depends on besides its point forces: its basis object
    (:func:`plate_bases`), material, frequency and edge conditions with their data."""
    return (id(basis), problem.size, problem.bending_stiffness, problem.poisson_ratio,
            problem.mass_per_area, problem.omega, tuple(sorted(problem.edges.items())))


def plate_bases(case, problems, resolution):
    """Each plate's ray basis; plates of the same size, wavenumber and ray counts share one
    object (a grid's or a panel's identical plates), so that their joint traces are computed
    once (:func:`solver.plate.edge_values`' cache)."""
    bases, shared = {}, {}
    for pid, problem in problems.items():
        key = (problem.size, problem.kappa, plate_ray_counts(case, pid, problem, resolution))
        if key not in shared:
            shared[key] = plate_basis(case, pid, problem, resolution)
        bases[pid] = shared[key]
    return bases


def _junction_line(case, plates, jid, k_max, counts, group, traces_cache):
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
    hinge of :math:`k`, with the same residual at every stiffness.
    """
    joint = case.joints[jid]
    sides, directions = joint.sides, case.member_directions(jid)
    length = case.edge_length(sides[0])
    sigma, wq = joint_gauss(length, max(k_max[p] for p in joint.plates))
    root_w = np.sqrt(wq)
    psi = legendre_values(sigma, length, counts[jid])
    slots = plates.layout[jid]
    rotation = {}  # Theta_i of every member, unweighted, over its plate's unknowns
    for side, direction in zip(sides, directions):
        arc = sigma if direction > 0 else length - sigma
        rays, part = edge_values(plates.problems[side.plate], plates.bases[side.plate],
                                 side.edge, arc, traces_cache)
        slope = plates.affine_plate_operator(side.plate, rays["slope"], part["slope"])
        rotation[side.plate] = _scaled(slope, -float(direction))
    rigid = _rigid_members(joint)
    if rigid:
        line = rotation[rigid[0]]
    else:
        line = Block(np.arange(slots["T"].start, slots["T"].stop), psi.astype(complex),
                     np.zeros(len(sigma), dtype=complex))
    weighted = psi.T * wq
    rows = []
    for plate in rigid[1:]:
        gap = _union(rotation[plate], _scaled(line, -1.0))
        rows.append(Block(gap.index, weighted @ gap.matrix, -(weighted @ gap.offset), group))
    moments = np.concatenate([np.arange(slots[f"C.{p}"].start, slots[f"C.{p}"].stop)
                              for p in joint.plates])
    order = np.argsort(moments)
    balance = np.hstack([np.eye(counts[jid], dtype=complex)] * len(joint.plates))
    rows.append(Block(moments[order], balance[:, order], np.zeros(counts[jid], dtype=complex),
                      group))
    stiffness, kappa0 = max((plates.problems[p].bending_stiffness.real,
                             plates.problems[p].kappa.real) for p in joint.plates)
    channels = []
    on_functions = load_function_projection(root_w, psi)
    for plate in joint.finite_members():
        moment = slots[f"C.{plate}"]
        load = Block(np.arange(moment.start, moment.stop), on_functions @ psi,
                     np.zeros(len(on_functions), dtype=complex))
        kinematic = _projected(_union(line, _scaled(rotation[plate], -1.0)), on_functions)
        channels.append(Channel(jid, "rotation", load, kinematic,
                                2.0 * RIGID_CROSSOVER * stiffness * kappa0, member=plate,
                                group=group))
    return rows, channels


def _constraint_matrix(rows, n_s):
    """Stack constraint Blocks (``matrix S_I = offset``) into a sparse :math:`G` and :math:`g`."""
    if not rows:
        return scipy.sparse.csr_matrix((0, n_s), dtype=complex), np.zeros(0, dtype=complex)
    r, c, v, start = [], [], [], 0
    for block in rows:
        n_rows, m = block.matrix.shape
        r.append(np.repeat(np.arange(start, start + n_rows), m))
        c.append(np.tile(block.index, n_rows))
        v.append(block.matrix.ravel())
        start += n_rows
    g_mat = scipy.sparse.csr_matrix((np.concatenate(v), (np.concatenate(r), np.concatenate(c))),
                                    shape=(start, n_s))
    return g_mat, np.concatenate([b.offset for b in rows])


# ----------------------------------------------------------------------------------------------
# parameters, reduced solve
# ----------------------------------------------------------------------------------------------


def channel_blocks(system, params, weights):
    r"""Least-squares Blocks of the joint term :math:`\sum_\Gamma w_\Gamma e_\Gamma^2`.

    Parameters
    ----------
    params : dict
        ``{(joint, kind): c}`` (:func:`joint_parameters`).
    weights : dict of str to float
        Per channel name (joint, or junction member ``JOINT.PLATE``), the weight
        :math:`w_\Gamma` of its energy (J^-1 for a dimensionless cost).
    """
    blocks = []
    for channel in system.channels:
        c = params[channel.name, channel.kind]
        if channel.kind == "mass" and c.real <= 0.0:
            raise ValueError(f"joint {channel.joint}: the mass channel needs a line mass > 0")
        if weights[channel.name] > 0.0:
            blocks.append(channel.block(c, weights[channel.name]))
    return blocks


def solve_interface(system, blocks, keep=True):
    """Minimise the sum of the Blocks' squares under the constraints; an InterfaceFactor
    (without ``keep``, one that holds the minimiser only:
    :func:`solver.interface.factorise_interface`)."""
    return factorise_interface(system.n_s, blocks, system.constraints,
                               (system.unknown_groups, system.constraint_groups), keep)


def reference_energies(system, amplitudes):
    r"""Per plate, :math:`\tfrac12\omega^2\rho_ih_i\int_{\Omega_i}|w_i|^2dA` (J), twice its
    time-averaged kinetic energy (:func:`solver.power.kinetic_energies`); their sum is
    :math:`E_{ref}`."""
    energies = kinetic_energies({pid: (problem, system.bases[pid], amplitudes[pid])
                                 for pid, problem in system.problems.items()})
    return {pid: 2.0 * energy for pid, energy in energies.items()}


def joint_residuals(system, params, s):
    """``{channel name: E_Gamma^2}`` (dimensionless) at interface unknowns ``s``: per joint,
    and per finite member ``JOINT.PLATE`` of a junction (arrays, one value per column, for a
    matrix ``s``)."""
    out = {}
    for channel in system.channels:
        energy = channel.energy(s, params[channel.name, channel.kind])
        out[channel.name] = out.get(channel.name, 0.0) + energy / system.e_ref
    return out


@dataclass(frozen=True)
class AssemblySolution(CaseSolution):
    """Forced response of a jointed assembly (r = 0) and its joint residuals: a
    :class:`solver.solution.CaseSolution` with ``residuals`` (:math:`E_\\Gamma^2` per joint),
    ``interface`` (S) and ``system``."""

    residuals: dict = field(default_factory=dict)
    interface: np.ndarray | None = None
    system: AssemblySystem | None = None

    @property
    def n_unknowns(self) -> int:
        """Ray unknowns of all plates and the interface unknowns."""
        return super().n_unknowns + self.system.n_s


def solve_assembly(case, frequency, resolution=None, system=None,
                   residuals=True) -> AssemblySolution:
    """Direct problem of a jointed assembly: minimise :math:`E_{int}^2` under admissibility.

    The reference energy is fixed by this solve if the system has none yet. With
    ``residuals=False`` only the field is wanted (a simulated experiment): neither the
    reference energy (a field quadrature over every plate) nor the residuals are computed,
    and ``residuals`` is empty.
    """
    system = system or build_assembly_system(case, frequency, resolution)
    t0 = time.perf_counter()
    params = joint_parameters(case, system.omega)
    s = solve_interface(system, channel_blocks(system, params, case.updatable_alpha()),
                        keep=False).s
    amplitudes = system.plate_amplitudes(s)
    if system.e_ref is None and residuals:
        system.plate_energies = reference_energies(system, amplitudes)
        system.e_ref = sum(system.plate_energies.values())
    plates = {pid: PlateSolution(system.problems[pid], system.bases[pid], amplitudes[pid],
                                 system.rcond[pid]) for pid in system.problems}
    timings = dict(system.timings, reduced=time.perf_counter() - t0)
    return AssemblySolution(frequency, plates, timings, plate_condition_warnings(plates),
                            joint_residuals(system, params, s) if residuals else {}, s, system)
