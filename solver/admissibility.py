r"""The plates of an assembly, each admissible for any interface unknowns.

Each plate :math:`i` is a complete VTCR problem whose joined edges carry the interface loads as
static data (``docs/method.md`` section 7.1): :math:`K_iU_i = F_i + B_iS`, so that
:math:`U_i = U_i^0 + T_iS` with :math:`U_i^0 = K_i^{-1}F_i` and :math:`T_i = K_i^{-1}B_i`.
:func:`plate_admissibility` factorises every plate once and keeps :math:`U_i^0` and
:math:`T_i`; identical unforced plates (a grid's, a panel's) share one factorisation,
identical plates one factorisation of their in-plane matrix, and those whose loads are the
same their :math:`U_i^0` and :math:`T_i` (:class:`_SharedSolves`).
"""

from __future__ import annotations

import functools
import hashlib
import math
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field

import numpy as np

from assembly import Case
from assembly.geometry import edge_geometry
from solver.dense import MEMBRANE_RANK_TOLERANCE, factorise_dense
from solver.interface import Block
from solver.interface_loads import PlateLoads, membrane_loads, plate_loads, plate_sides
from solver.layout import InterfaceLayout
from solver.membrane import MembraneProblem, assemble_membrane
from solver.membrane_basis import MembraneBasis, membrane_edge_traces
from solver.plate import (
    PlateBoundary,
    PlateProblem,
    assemble_plate,
    boundary_traces,
)
from solver.rays import RayBasis

__all__ = ["PlateAdmissibility", "PlateBlock", "MembraneBlock", "plate_block",
           "plate_admissibility", "membrane_blocks", "factorised_sizes"]

CornerDeflections = tuple[np.ndarray, np.ndarray]
"""A plate's corner deflections: per corner, the rays' ``w`` (4, n_i) and the particular
solution's (4,)."""


@dataclass(frozen=True)
class MembraneBlock:
    """One plate's in-plane field: its problem, basis, transfer operator :math:`T_i^m` (membrane
    amplitudes per unit interface unknown of ``unknowns``, those that load it), the
    reciprocal condition estimate of its VTCR matrix and, per joint whose tractions load it,
    the moments of its shape functions' ``u_n``, ``u_t`` on the joint's load functions
    (:func:`solver.interface_loads.membrane_loads`)."""

    problem: MembraneProblem
    basis: MembraneBasis
    transfer: np.ndarray
    rcond: float
    unknowns: np.ndarray
    moments: Mapping[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)

    def edge_traces(self, edge: str, arc: np.ndarray) -> dict[str, np.ndarray]:
        """The traces ``u_n``, ``u_t``, ``N_nn``, ``N_nt`` of the plate's in-plane shape
        functions at the arc lengths ``arc`` of its edge ``edge``
        (:func:`solver.membrane_basis.membrane_edge_traces`)."""
        return membrane_edge_traces(self.basis, edge_geometry(self.problem.size, edge), arc,
                                    self.problem.stiffness, self.problem.poisson_ratio)


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
        Per plate, the (sorted) interface unknowns that load its bending field.
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
    membranes : dict of str to MembraneBlock
        The in-plane plates' membrane fields (``docs/method.md`` section 10), affine in the
        interface unknowns like the bending ones; empty without moving lines.
    corner_columns : dict of (str, int) to int
        Position in S of the force of each static junction corner, by plate and corner
        (:class:`solver.layout.InterfaceLayout`).
    """

    frequency: float
    problems: dict[str, PlateProblem]
    bases: dict[str, RayBasis]
    unknowns: dict[str, np.ndarray]
    u0: dict[str, np.ndarray]
    transfer: dict[str, np.ndarray]
    n_s: int
    layout: dict[str, dict[str, slice]]
    rcond: dict[str, float]
    membranes: dict[str, MembraneBlock] = field(default_factory=dict)
    corner_columns: dict[tuple[str, int], int] = field(default_factory=dict)
    load_ends: dict[str, tuple] = field(default_factory=dict)

    @property
    def omega(self) -> float:
        return 2.0 * math.pi * self.frequency

    @property
    def ray_unknowns(self) -> int:
        """Ray unknowns of all plates, bending and in-plane (what ``vtcr check`` foresees)."""
        return (sum(basis.n_dof for basis in self.bases.values())
                + sum(block.basis.n_dof for block in self.membranes.values()))

    def plate_amplitudes(self, s: np.ndarray,
                         plates: Iterable[str] | None = None) -> dict[str, np.ndarray]:
        """Ray amplitudes of every plate (or of ``plates``) for interface unknowns ``s``."""
        return {pid: self.u0[pid] + self.transfer[pid] @ s[self.unknowns[pid]]
                for pid in (self.problems if plates is None else plates)}

    def membrane_amplitudes(self, s: np.ndarray) -> dict[str, np.ndarray]:
        """Membrane amplitudes of every in-plane plate for interface unknowns ``s``."""
        return {pid: block.transfer @ s[block.unknowns] for pid, block in self.membranes.items()}

    def affine_membrane_operator(self, plate_id: str, values: np.ndarray) -> Block:
        r"""A membrane quantity :math:`XU_i^m` as a :class:`Block` over the unknowns that load
        the plate's in-plane field (no in-plane load acts inside a plate, so
        :math:`U_i^m = T_i^mS`)."""
        block = self.membranes[plate_id]
        return Block(block.unknowns, values @ block.transfer,
                     np.zeros(len(values), dtype=complex))

    def affine_plate_operator(self, plate_id: str, values: np.ndarray,
                              particular: np.ndarray) -> Block:
        r"""A plate quantity :math:`XU_i + x_p` as a :class:`Block` over the plate's unknowns:
        ``(X T_i, X U_i^0 + x_p)``."""
        return Block(self.unknowns[plate_id], values @ self.transfer[plate_id],
                     values @ self.u0[plate_id] + particular)


@dataclass(frozen=True)
class PlateBlock:
    """One plate's VTCR block, factorised (:func:`plate_block`): its boundary traces, its
    right-hand side :math:`F_i`, a solve with :math:`K_i` and the reciprocal condition
    estimate of :math:`K_i`."""

    boundary: PlateBoundary
    force: np.ndarray
    solve: Callable[[np.ndarray], np.ndarray]
    rcond: float


def plate_block(problem: PlateProblem, basis: RayBasis) -> PlateBlock:
    r"""One plate's VTCR block, factorised. The plate's admissibility is then
    :math:`U_i^0 = K_i^{-1}F_i` and :math:`T_i = K_i^{-1}B_i`, with its loads :math:`B_i`
    (:func:`solver.interface_loads.plate_loads`)."""
    boundary = boundary_traces(problem, basis)
    matrix, force = assemble_plate(problem, boundary)
    solve, rcond = factorise_dense(matrix)
    return PlateBlock(boundary, force, solve, rcond)


class _SharedSolves:
    """Solutions shared by identical plates whose loads are the same, to the bit (the inner
    bays of a panel, a grid's inner plates: their load functions are the same functions of
    the same traces, only the interface unknowns they load differ): one solve of
    :math:`K_i^{-1}B_i` serves them all, and one array holds it (read-only); so does one
    transfer operator spread from it (:meth:`transfer`)."""

    def __init__(self) -> None:
        self._solutions: dict[tuple, list[tuple[np.ndarray, np.ndarray]]] = {}
        self._spread: dict[tuple[int, int, bytes], tuple[np.ndarray, np.ndarray]] = {}

    def transfer(self, loads: PlateLoads, solution: np.ndarray, first: int = 0) -> np.ndarray:
        """The transfer operator ``loads.transfer(solution[:, first:])``
        (:class:`solver.interface_loads.PlateLoads`) of a ``solution`` that :meth:`get`
        returned: one array for the plates that share it and spread it alike."""
        if not loads.compressed:
            return solution[:, first:]
        key = (id(solution), first, loads.pattern())
        if key not in self._spread:  # the solution is kept with it, so its id stays its own
            spread = loads.transfer(solution[:, first:])
            spread.setflags(write=False)
            self._spread[key] = solution, spread
        return self._spread[key][1]

    def get(self, signature: tuple | None, loads: np.ndarray,
            solve: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
        """The solution for a plate of ``signature`` (None: a plate that shares nothing, a
        forced one) with ``loads``: a shared one, or ``solve(loads)``."""
        if signature is None:
            return solve(loads)
        # a digest of every 61st entry sorts the loads; equal ones are then compared whole
        sample = np.ascontiguousarray(loads.reshape(-1)[::61]).tobytes()
        candidates = self._solutions.setdefault(
            (signature, loads.shape, hashlib.blake2b(sample, digest_size=16).digest()), [])
        for seen, solution in candidates:
            if np.array_equal(seen, loads):
                return solution
        solution = solve(loads)
        solution.setflags(write=False)
        candidates.append((loads, solution))
        return solution


def _with_force(block: PlateBlock, loads: np.ndarray) -> np.ndarray:
    r""":math:`K_i^{-1}[F_i\ B_i]`: the plate's :math:`U_i^0` and :math:`T_i` side by side."""
    return block.solve(np.column_stack([block.force, loads]))


def _plate_signature(problem: PlateProblem, basis: RayBasis) -> tuple | None:
    """What a plate's VTCR block depends on besides its point forces: its basis object
    (:func:`solver.problems.plate_bases`), material, frequency and edge conditions with their
    data; None for a forced plate, whose block is its own."""
    if problem.point_forces:
        return None
    return (id(basis), problem.size, problem.bending_stiffness, problem.poisson_ratio,
            problem.mass_per_area, problem.omega, tuple(sorted(problem.edges.items())))


def factorised_sizes(problems: Mapping[str, PlateProblem], bases: Mapping[str, RayBasis],
                     membranes: Mapping[str, MembraneProblem],
                     membrane_bases: Mapping[str, MembraneBasis]
                     ) -> tuple[list[int], list[int]]:
    """The orders of the dense matrices a build factorises, bending and in-plane: one per
    group of identical plates (:func:`plate_admissibility`, :func:`membrane_blocks`), one per
    forced plate. What :mod:`solver.sizing` counts the plates' cost from."""
    bending, seen = [], set()
    for pid, problem in problems.items():
        key = _plate_signature(problem, bases[pid])
        if key is None or key not in seen:
            seen.add(key)
            bending.append(bases[pid].n_dof)
    in_plane = {_membrane_signature(problem, membrane_bases[pid]): membrane_bases[pid].n_dof
                for pid, problem in membranes.items()}
    return bending, list(in_plane.values())


def plate_admissibility(case: Case, frequency: float, problems: Mapping[str, PlateProblem],
                        bases: Mapping[str, RayBasis], arrangement: InterfaceLayout
                        ) -> tuple[PlateAdmissibility, dict[str, CornerDeflections]]:
    r"""Every plate's :math:`U_i^0` and :math:`T_i` for the interface unknowns of
    ``arrangement``, and its corner deflections (what the junction corners need).

    A plate's boundary traces are the largest data of the build: they are kept only for the
    identical unforced plates that share them, else used and dropped here.
    """
    sides, corners = plate_sides(case, arrangement.corner_columns)
    u0, transfer, rcond, corner_w = {}, {}, {}, {}
    shared: dict[tuple, PlateBlock] = {}
    solved = _SharedSolves()
    for pid in case.plates:
        problem = problems[pid]
        key = _plate_signature(problem, bases[pid])
        block = shared.get(key) or plate_block(problem, bases[pid])
        if key is not None:
            shared[key] = block
        loads = plate_loads(case, block.boundary, sides[pid], corners[pid], arrangement.counts,
                            arrangement.load_ends,
                            arrangement.slots, arrangement.unknowns[pid])
        solution = solved.get(key, loads.right_hand_sides(),
                              functools.partial(_with_force, block))
        u0[pid], rcond[pid] = solution[:, 0], block.rcond
        transfer[pid] = solved.transfer(loads, solution, 1)
        corner_w[pid] = block.boundary.corner_w, block.boundary.corner_w_p
    plates = PlateAdmissibility(frequency, dict(problems), dict(bases), arrangement.unknowns, u0,
                                transfer, arrangement.n_s, arrangement.slots, rcond,
                                corner_columns=dict(arrangement.corner_columns),
                                load_ends=dict(arrangement.load_ends))
    return plates, corner_w


def _membrane_signature(problem: MembraneProblem, basis: MembraneBasis) -> tuple:
    """What a plate's membrane VTCR matrix depends on: its basis object
    (:func:`solver.in_plane.membrane_bases`), material, frequency and in-plane edge
    conditions. The conditions' data enter only the right-hand side, which an assembly's
    membranes do not use (their loads are interface unknowns)."""
    return (id(basis), problem.size, problem.stiffness, problem.poisson_ratio,
            problem.mass_per_area, problem.omega, problem.conditions)


def membrane_blocks(case: Case, problems: Mapping[str, MembraneProblem],
                    bases: Mapping[str, MembraneBasis], arrangement: InterfaceLayout
                    ) -> dict[str, MembraneBlock]:
    r"""Every in-plane plate's :math:`T_i^m = K_i^{m\,-1}B_i^m`
    (:func:`solver.interface_loads.membrane_loads`); identical plates share one factorisation of
    :math:`K_i^m`."""
    sides, _ = plate_sides(case, arrangement.corner_columns)
    blocks, cache = {}, {}  # the traces, shared by identical plates and by both uses
    factorised, solved = {}, _SharedSolves()  # identical plates (a panel's inner bays, its
    # stiffeners) share one factorisation, and with the same loads one transfer operator
    for pid, problem in problems.items():
        key = _membrane_signature(problem, bases[pid])
        if key not in factorised:
            matrix, _ = assemble_membrane(problem, bases[pid], cache)
            factorised[key] = factorise_dense(matrix, MEMBRANE_RANK_TOLERANCE)
        solve, rcond = factorised[key]
        unknowns = arrangement.membrane_unknowns[pid]
        loads, moments = membrane_loads(case, problem, bases[pid], sides[pid],
                                        arrangement.counts, arrangement.load_ends,
                                        arrangement.slots, unknowns, cache)
        blocks[pid] = MembraneBlock(problem, bases[pid], solved.transfer(
            loads, solved.get(key, loads.right_hand_sides(), solve)), rcond, unknowns, moments)
    return blocks
