r"""The loads the interface unknowns put on each plate (``docs/method.md`` sections 6.2, 6.2b,
7.1 and 10.4).

A joint's load functions act on its members' edges: a two-plate joint's moment and force, a
junction member's moment :math:`C_i` and, on a moving line, its Kirchhoff shear and in-plane
tractions, which for the line's balancing member are the others' with the opposite sign
(:func:`member_load`: the balances hold by construction). :func:`plate_loads` and
:func:`membrane_loads` are a plate's VTCR right-hand sides per unit interface unknown,
:math:`B_i` and :math:`B_i^m`; :mod:`solver.layout` places the unknowns they multiply.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from assembly import Case, EdgeId
from assembly.geometry import edge_geometry
from assembly.joints import Joint
from solver.joint_rules import LoadEnds, load_function_values
from solver.membrane import MembraneProblem, membrane_edge_rule
from solver.membrane_basis import MembraneBasis, membrane_edge_traces
from solver.plate import PlateBoundary, edge_projection

__all__ = ["FORCE_COMPONENTS", "MOVING_MEMBER_LOADS", "JointSide", "LoadTerms", "PlateLoads",
           "balancing_member", "load_values", "member_axes", "member_load", "membrane_loads",
           "plate_loads", "plate_sides", "rigid_members", "traction_loads"]


MOVING_MEMBER_LOADS = ("C", "K", "Nn", "Nt")
"""The load functions of a member of a moving line: the moment :math:`C_i` (``M_n = s_iC_i``),
the Kirchhoff shear :math:`K_n`, and the in-plane tractions :math:`N_{nn}`, :math:`N_{nt}` that
the line exerts on the member (``docs/method.md`` section 10.4)."""

LoadTerms = list[tuple[slice, float]]
r"""A load function on a plate's edge as a combination of interface unknown functions:
``[(slot, coefficient), ...]``, the load :math:`\sum c\,S_{slot}` per Legendre coefficient."""

FORCE_COMPONENTS = ("Nn", "Nt", "K")
r"""The load functions of a moving line's force on a member, along the member's axes
:math:`(\mathbf n_i, \mathbf t_i, \mathbf e_{z,i})` (:func:`member_axes`)."""


def rigid_members(joint: Joint) -> list[str]:
    """The rigid members of a junction (the first one carries the line's rotation)."""
    finite = joint.finite_members()
    return [plate for plate in joint.plates if plate not in finite]



def balancing_member(joint: Joint) -> str:
    """The member of a moving line whose loads the line's balances give (:func:`member_load`):
    its last rigid member, whose moment enters no spring channel, else its last member."""
    rigid = rigid_members(joint)
    return rigid[-1] if rigid else joint.plates[-1]


def member_axes(case: Case, side: EdgeId) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""In 3D, a member edge's outward in-plane normal :math:`\mathbf n_i`, its tangent
    :math:`\mathbf t_i` and its plate's normal :math:`\mathbf e_{z,i}` (the frame of
    :math:`(u_n, u_t, w)` and of :math:`(N_{nn}, N_{nt}, K_n)`)."""
    plate = case.plates[side.plate]
    _, tangent, normal, _ = plate.edge_frame(side.edge)
    frame = plate.frame
    return frame.to_space_vector(normal), frame.to_space_vector(tangent), frame.normal


def member_load(case: Case, jid: str, slots: Mapping[str, slice], plate: str,
                name: str) -> LoadTerms:
    r"""The load function ``name`` (``C``, ``K``, ``Nn``, ``Nt``) of junction ``jid`` on its
    member ``plate``: its own slot ``NAME.PLATE``, or, for a moving line's balancing member
    :math:`b` (:func:`balancing_member`), the loads its balances give (``docs/method.md``
    section 10.4): :math:`C_b = -\sum_{i\ne b}C_i` and, component by component on the
    member's axes :math:`\mathbf a_b` (:data:`FORCE_COMPONENTS`),
    :math:`\mathbf f_b\cdot\mathbf a_b = -\sum_{i\ne b}\mathbf f_i\cdot\mathbf a_b`, with
    :math:`\mathbf f_i = N_{nn}\mathbf n_i + N_{nt}\mathbf t_i + K_n\mathbf e_{z,i}`.
    Empty for a load the joint does not have (``K`` on a held line)."""
    own = f"{name}.{plate}"
    if own in slots:
        return [(slots[own], 1.0)]
    joint = case.joints[jid]
    others = [side for side in joint.sides if side.plate != plate]
    if not any(f"K.{side.plate}" in slots for side in others):  # not a moving line
        return []
    if name == "C":
        return [(slots[f"C.{side.plate}"], -1.0) for side in others]
    side = next(side for side in joint.sides if side.plate == plate)
    axis = member_axes(case, side)[FORCE_COMPONENTS.index(name)]
    terms = []
    for other in others:
        for component, direction in zip(FORCE_COMPONENTS, member_axes(case, other)):
            coefficient = -float(direction @ axis)
            if abs(coefficient) > 1e-12:  # perpendicular frames, to their rounding
                terms.append((slots[f"{component}.{other.plate}"], coefficient))
    return terms


def traction_loads(case: Case, jid: str, slots: Mapping[str, slice],
                   plate: str) -> tuple[LoadTerms, LoadTerms] | None:
    r"""The in-plane tractions :math:`N_{nn}`, :math:`N_{nt}` on ``plate``'s edge of joint
    ``jid`` (``slots``: the joint's): a moving line's on its member (:func:`member_load`), or a
    coplanar joint's, the same on both its edges (their normals and tangents are opposite:
    :math:`\mathbf N\mathbf n_A = -\mathbf N\mathbf n_B`); None without in-plane
    tractions."""
    if "Nn" in slots:
        return [(slots["Nn"], 1.0)], [(slots["Nt"], 1.0)]
    if not case.is_line(jid):
        return None
    normal, tangent = (member_load(case, jid, slots, plate, name) for name in ("Nn", "Nt"))
    return (normal, tangent) if normal or tangent else None


def load_values(terms: LoadTerms, s: np.ndarray) -> np.ndarray:
    """The Legendre coefficients of a load function (``terms``, :func:`member_load`) at the
    interface unknowns ``s``."""
    values = [coefficient * s[part] for part, coefficient in terms]
    return sum(values[1:], values[0])


@dataclass(frozen=True)
class PlateLoads:
    r"""A plate's loads per unit interface unknown, :math:`B = \Phi E`: its distinct load
    functions :math:`\Phi` (rows, functions), a joint side's projected Legendre loads or a
    corner's deflection, and the unknowns each one loads, :math:`E` (functions, unknowns), as
    ``targets``: ``(function columns, unknown positions, coefficient)``.

    A function usually loads one unknown, and :math:`B` is :math:`\Phi` with its columns in
    place. A moving line's balancing member takes each of its functions into the slot of every
    other member with the coefficient its balance gives (:func:`member_load`), so that
    :math:`B` has two to three times the columns of :math:`\Phi` there; the plate's transfer
    operator is then solved on :math:`\Phi` and spread, :math:`K^{-1}B = (K^{-1}\Phi)E`
    (``docs/method.md`` section 10.4), a linear solve being linear."""

    functions: np.ndarray
    targets: tuple[tuple[slice, np.ndarray, float], ...]
    n_unknowns: int

    @classmethod
    def stacked(cls, blocks: Sequence[tuple[np.ndarray, Sequence[tuple[np.ndarray, float]]]],
                n_rows: int, n_unknowns: int) -> PlateLoads:
        """The loads of ``blocks``, ``(values (rows, m), [(unknown positions (m,),
        coefficient), ...])``: each block's ``m`` functions, loading those unknowns."""
        targets, start = [], 0
        for values, destinations in blocks:
            functions = slice(start, start + values.shape[1])
            targets += [(functions, positions, coefficient)
                        for positions, coefficient in destinations]
            start = functions.stop
        functions = (np.hstack([values for values, _ in blocks]) if blocks
                     else np.zeros((n_rows, 0), dtype=complex))
        return cls(functions.astype(complex, copy=False), tuple(targets), n_unknowns)

    @property
    def compressed(self) -> bool:
        r"""Whether :math:`\Phi` has fewer columns than :math:`B`: then solving on it pays."""
        return self.functions.shape[1] < self.n_unknowns

    def spread(self, values: np.ndarray) -> np.ndarray:
        """:math:`YE` for :math:`Y` (n, functions): the functions' columns summed into their
        unknowns' with their coefficients."""
        out = np.zeros((values.shape[0], self.n_unknowns), dtype=complex)
        for functions, positions, coefficient in self.targets:
            out[:, positions] += coefficient * values[:, functions]
        return out

    def right_hand_sides(self) -> np.ndarray:
        r"""What a plate's solve takes: :math:`\Phi` where it is compressed, else :math:`B`."""
        return self.functions if self.compressed else self.spread(self.functions)

    def transfer(self, solutions: np.ndarray) -> np.ndarray:
        """The transfer operator from the solutions of :meth:`right_hand_sides`."""
        return self.spread(solutions) if self.compressed else solutions

    def pattern(self) -> bytes:
        """``targets`` as bytes: plates whose functions and patterns agree share one spread."""
        return b"".join(np.asarray([f.start, f.stop, coefficient]).tobytes() + positions.tobytes()
                        for f, positions, coefficient in self.targets)


JointSide = tuple[str, int, EdgeId]
"""A plate's edge on a joint: the joint, the side's index in it and the edge."""


def plate_sides(case: Case, corner_columns: Mapping[tuple[str, int], int]
                ) -> tuple[dict[str, list[JointSide]], dict[str, list[tuple[int, int]]]]:
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


def plate_loads(case: Case, boundary: PlateBoundary, sides: Sequence[JointSide],
                corners: Sequence[tuple[int, int]], counts: Mapping[str, int],
                load_ends: Mapping[str, LoadEnds], layout: Mapping[str, Mapping[str, slice]],
                unknowns: np.ndarray) -> PlateLoads:
    r""":math:`B_i`: the plate's VTCR right-hand sides per unit interface unknown, over the
    interface unknowns ``unknowns`` it sees: the Legendre loads of its joint ``sides`` and the
    forces of its junction ``corners`` (:func:`plate_sides`), with the signs of
    ``docs/method.md`` section 6.2, as distinct functions and the unknowns they load
    (:class:`PlateLoads`)."""
    blocks = []

    def add(columns: Sequence[int] | np.ndarray, values: np.ndarray) -> None:
        blocks.append((values, [(np.searchsorted(unknowns, columns), 1.0)]))

    def add_terms(terms: LoadTerms, values: np.ndarray) -> None:
        if terms:
            blocks.append((values, [(np.searchsorted(unknowns, np.arange(part.start, part.stop)),
                                     coefficient) for part, coefficient in terms]))

    for jid, side_index, side in sides:
        length = case.edge_length(side)
        slots = {name: np.arange(sl.start, sl.stop) for name, sl in layout[jid].items()}
        traces = boundary.edges[side.edge]
        direction = case.member_directions(jid)[side_index]
        sigma = traces.s if direction > 0 else length - traces.s
        psi = load_function_values(sigma, length, counts[jid], load_ends[jid])
        if case.is_line(jid):  # M_n = s_i C_i and, moving, K_n = K_i
            add_terms(member_load(case, jid, layout[jid], side.plate, "C"),
                      direction * edge_projection(traces, "moment", psi))
            add_terms(member_load(case, jid, layout[jid], side.plate, "K"),
                      edge_projection(traces, "shear", psi))
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
    return PlateLoads.stacked(blocks, boundary.corner_w.shape[1], len(unknowns))


def membrane_loads(case: Case, problem: MembraneProblem, basis: MembraneBasis,
                   sides: Sequence[JointSide], counts: Mapping[str, int],
                   load_ends: Mapping[str, LoadEnds],
                   layout: Mapping[str, Mapping[str, slice]], unknowns: np.ndarray,
                   cache: dict | None = None
                   ) -> tuple[PlateLoads, dict[str, tuple[np.ndarray, np.ndarray]]]:
    r""":math:`B_i^m`: the membrane VTCR right-hand sides of an in-plane plate per unit
    interface unknown, over the interface unknowns ``unknowns`` it sees: on each of its
    moving-line edges the static data :math:`N_{nn} = \sum_m(N_n)_m\psi_m` and
    :math:`N_{nt} = \sum_m(N_t)_m\psi_m`, whose columns are
    :math:`\int\overline{u_\alpha(\Phi_k)}\,\psi_m\,ds` (``docs/method.md`` section 10.2).

    Also, per joint, the moments :math:`\int\psi_m\,u_n(\Phi_k)\,ds` and
    :math:`\int\psi_m\,u_t(\Phi_k)\,ds`, (functions, n_dof): the conjugates of the same
    sums, which a moving line's translation rows and a coplanar joint's in-plane continuity
    test (``solver.channels``), so that the rows and the loads pair the plate's functions
    with the joint's on one quadrature rule."""
    blocks = []
    moments = {}
    for jid, side_index, side in sides:
        tractions = traction_loads(case, jid, layout[jid], side.plate)
        if tractions is None:
            continue
        edge = edge_geometry(problem.size, side.edge)
        s, weights = membrane_edge_rule(edge, basis)
        traces = membrane_edge_traces(basis, edge, s, problem.stiffness, problem.poisson_ratio,
                                      cache)
        direction = case.member_directions(jid)[side_index]
        sigma = s if direction > 0 else edge.length - s
        psi = load_function_values(sigma, edge.length, counts[jid], load_ends[jid])
        works = [traces[displacement].conj().T @ (weights[:, None] * psi)
                 for displacement in ("u_n", "u_t")]
        moments[jid] = (works[0].conj().T, works[1].conj().T)
        blocks += [(work, [(np.searchsorted(unknowns, np.arange(part.start, part.stop)),
                            coefficient) for part, coefficient in terms])
                   for terms, work in zip(tractions, works) if terms]
    return PlateLoads.stacked(blocks, basis.n_dof, len(unknowns)), moments
