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
those that carry its loads (:func:`solver.joint_rules.load_function_projection`): the law is imposed as far as the
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
for new parameters is a weighted sum of them (:meth:`solver.channels.Channel.block`).

**Direct problem (r = 0).** Minimise :math:`E_{int}^2` subject to the constraints
:math:`GS = g`, a sparse constrained least-squares problem (:mod:`solver.interface`). The
projected laws can be met exactly (as many as the loads they constrain), so the minimum is
zero to round-off and the minimiser is the assembly's forced response; the discretisation
floor of the updating comes from the enriched solve (:mod:`updating.inverse.cost`).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse
from numpy.typing import ArrayLike

from assembly import Case
from solver.admissibility import PlateAdmissibility, membrane_blocks, plate_admissibility
from solver.channels import (
    Channel,
    JointBuild,
    channel_blocks,
    joint_residuals,
    junction_corner_rows,
    junction_line,
    two_plate_joint,
)
from solver.errors import plate_condition_warnings
from solver.in_plane import membrane_bases, membrane_problems
from solver.interface import Block, InterfaceFactor, factorise_interface, stacked_blocks
from solver.joint_rules import joint_parameters
from solver.layout import interface_layout
from solver.membrane import MembraneSolution
from solver.membrane_basis import membrane_field
from solver.plate import PlateSolution
from solver.power import kinetic_energies
from solver.problems import plate_bases, plate_problems
from solver.solution import CaseSolution

__all__ = [
    "AssemblySystem",
    "AssemblySolution",
    "ReferenceEnergy",
    "build_assembly_system",
    "reference_energy",
    "solve_interface",
    "solve_assembly",
]


@dataclass
class AssemblySystem(PlateAdmissibility):
    """Everything about an assembly at one frequency that does not depend on the joint laws:
    its plates (:class:`solver.admissibility.PlateAdmissibility`), and the joints' constraints
    and channels, built complete by :func:`build_assembly_system`.

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
    """

    constraints: tuple[scipy.sparse.csr_matrix, np.ndarray] = ()
    channels: list[Channel] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    unknown_groups: np.ndarray | None = None
    constraint_groups: np.ndarray | None = None


@dataclass(frozen=True)
class ReferenceEnergy:
    r"""The energy :math:`E_{ref}` that makes every :math:`E_\Gamma^2` dimensionless
    (``docs/method.md`` section 6.3): :math:`\tfrac12\omega^2\sum_i\rho_ih_i
    \int_{\Omega_i}|w_i|^2dA` of the r = 0 solution at the initial parameters (J), twice its
    time-averaged kinetic energy, and each plate's part of it (the energy around a joint, by
    which the scale-free weights of the updating normalise its residual)."""

    total: float
    plates: Mapping[str, float]


def reference_energy(system: PlateAdmissibility,
                     amplitudes: Mapping[str, np.ndarray]) -> ReferenceEnergy:
    """The :class:`ReferenceEnergy` of the plates' ray amplitudes
    (:func:`solver.power.kinetic_energies`)."""
    energies = kinetic_energies({pid: (problem, system.bases[pid], amplitudes[pid])
                                 for pid, problem in system.problems.items()})
    plates = {pid: 2.0 * energy for pid, energy in energies.items()}
    return ReferenceEnergy(sum(plates.values()), plates)


def build_assembly_system(case: Case, frequency: float,
                          resolution: float | Mapping[str, float] | None = None
                          ) -> AssemblySystem:
    """Plate admissibility blocks, interface layout, constraints and residual channels.

    Everything here is independent of the joint parameters and is computed once per
    frequency; every piece spans one plate's or one joint's unknowns only.
    """
    t0 = time.perf_counter()
    problems = plate_problems(case, frequency)
    bases = plate_bases(case, problems, resolution)
    arrangement = interface_layout(case, problems, resolution)
    plates, corner_deflections = plate_admissibility(case, frequency, problems, bases,
                                                     arrangement)
    in_plane = membrane_problems(case, frequency)
    if in_plane:
        plates = dataclasses.replace(plates, membranes=membrane_blocks(
            case, in_plane, membrane_bases(case, in_plane, problems, resolution), arrangement))
    t1 = time.perf_counter()

    build = JointBuild(case, plates, arrangement.counts,
                       {pid: float(np.max(np.abs(b.k))) for pid, b in bases.items()}, {},
                       frozenset(case.moving_lines()))
    rows, channels = [], []  # constraint rows as Blocks of one or more rows
    unknown_groups = np.empty(arrangement.n_s, dtype=int)
    for group, (jid, joint) in enumerate(case.joints.items()):
        builder = junction_line if case.is_line(jid) else two_plate_joint
        joint_rows, joint_channels = builder(build, jid, group)
        rows += joint_rows
        channels += joint_channels
        for part in arrangement.slots[jid].values():
            unknown_groups[part] = group
    corner_rows, corner_columns = junction_corner_rows(plates, corner_deflections, arrangement,
                                                       len(case.joints))
    rows += corner_rows
    for group, columns in corner_columns.items():
        unknown_groups[columns] = group
    constraint_groups = np.repeat([b.group for b in rows],
                                  [len(b.offset) for b in rows]).astype(int)
    return AssemblySystem(**vars(plates), constraints=_constraint_matrix(rows, plates.n_s),
                          channels=channels,
                          timings={"plates": t1 - t0, "interface": time.perf_counter() - t1},
                          unknown_groups=unknown_groups, constraint_groups=constraint_groups)


def _constraint_matrix(rows: list[Block], n_s: int
                       ) -> tuple[scipy.sparse.csr_matrix, np.ndarray]:
    """Stack constraint Blocks (``matrix S_I = offset``) into a sparse :math:`G` and :math:`g`
    (:func:`solver.interface.stacked_blocks`)."""
    g_mat = stacked_blocks(rows, n_s)
    if not rows:
        return g_mat, np.zeros(0, dtype=complex)
    return g_mat, np.concatenate([b.offset for b in rows])


def solve_interface(system: AssemblySystem, blocks: list[Block],
                    keep: bool = True) -> InterfaceFactor:
    """Minimise the sum of the Blocks' squares under the constraints; an InterfaceFactor
    (without ``keep``, one that holds the minimiser only:
    :func:`solver.interface.factorise_interface`)."""
    return factorise_interface(system.n_s, blocks, system.constraints,
                               (system.unknown_groups, system.constraint_groups), keep)


@dataclass(frozen=True)
class AssemblySolution(CaseSolution):
    """Forced response of a jointed assembly (r = 0) and its joint residuals: a
    :class:`solver.solution.CaseSolution` with ``residuals`` (:math:`E_\\Gamma^2` per joint),
    ``interface`` (S), ``system`` and the ``reference`` energy the residuals are relative
    to."""

    residuals: dict[str, float] = field(default_factory=dict)
    interface: np.ndarray | None = None
    system: AssemblySystem | None = None
    reference: ReferenceEnergy | None = None

    def in_plane(self, plate_id: str, points: ArrayLike) -> np.ndarray:
        """Complex in-plane displacement ``(u, v)`` (m) along the plate's local x and y at its
        points, shape (n, 2): the membrane field of a member of a moving line
        (``docs/method.md`` section 10.4), zero for any other plate."""
        block = self.system.membranes.get(plate_id)
        if block is None:
            return super().in_plane(plate_id, points)
        amplitudes = block.transfer @ self.interface[block.unknowns]
        return membrane_field(block.basis, amplitudes, points)["u"]

    @property
    def membranes(self) -> dict[str, MembraneSolution]:
        """The in-plane field of every member of a moving line (and of the plates joined to
        one by a coplanar joint), :math:`U_i^m = T_i^mS` with its basis: what the error
        estimate keeps of an enriched solve without its system. Empty for a flat assembly."""
        amplitudes = self.system.membrane_amplitudes(self.interface)
        return {pid: MembraneSolution(block.problem, block.basis, amplitudes[pid], block.rcond)
                for pid, block in self.system.membranes.items()}

    @property
    def n_unknowns(self) -> int:
        """Ray unknowns of all plates (bending and in-plane) and the interface unknowns."""
        return self.system.ray_unknowns + self.system.n_s


def solve_assembly(case: Case, frequency: float,
                   resolution: float | Mapping[str, float] | None = None,
                   system: AssemblySystem | None = None, residuals: bool = True,
                   reference: ReferenceEnergy | None = None) -> AssemblySolution:
    """Direct problem of a jointed assembly: minimise :math:`E_{int}^2` under admissibility.

    The residuals are relative to ``reference``, by default the :class:`ReferenceEnergy` of
    this solve (at the description's parameters). With ``residuals=False`` only the field is
    wanted (a simulated experiment): neither the reference energy (a field quadrature over
    every plate) nor the residuals are computed, and ``residuals`` is empty.
    """
    system = system or build_assembly_system(case, frequency, resolution)
    t0 = time.perf_counter()
    params = joint_parameters(case, system.omega)
    blocks = channel_blocks(system.channels, params, case.updatable_alpha())
    s = solve_interface(system, blocks, keep=False).s
    amplitudes = system.plate_amplitudes(s)
    if residuals and reference is None:
        reference = reference_energy(system, amplitudes)
    plates = {pid: PlateSolution(system.problems[pid], system.bases[pid], amplitudes[pid],
                                 system.rcond[pid]) for pid in system.problems}
    timings = dict(system.timings, reduced=time.perf_counter() - t0)
    return AssemblySolution(
        frequency, plates, timings, plate_condition_warnings(plates),
        joint_residuals(system.channels, params, s, reference.total) if residuals else {},
        s, system, reference if residuals else None)
