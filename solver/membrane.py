r"""In-plane (membrane) VTCR of one plate: plane-stress waves, their edge traces and the
variational form (``docs/method.md`` section 10).

A plate of thickness :math:`h` carries, besides its bending field, an in-plane displacement
:math:`\mathbf u = (u_x, u_y)` in its own frame, with the resultants

.. math::
    \mathbf N = A^*\big[\nu\,(\nabla\cdot\mathbf u)\,\mathbf I
        + (1-\nu)\,\tfrac12(\nabla\mathbf u + \nabla\mathbf u^T)\big],\qquad
    A^* = \frac{E h (1 + j\eta)}{1 - \nu^2},

and the equation :math:`\nabla\cdot\mathbf N + \rho h\omega^2\mathbf u = 0`. An exponential
:math:`\mathbf d\,e^{\mathbf k\cdot\mathbf x}` solves it exactly as a longitudinal wave
(:math:`\mathbf d\parallel\mathbf k`, :math:`\mathbf k\cdot\mathbf k = -k_L^2`) or a shear
wave (:math:`\mathbf d\cdot\mathbf k = 0`, :math:`\mathbf k\cdot\mathbf k = -k_S^2`), with

.. math:: k_L^2 = \rho h\omega^2 / A^*,\qquad k_S^2 = 2k_L^2 / (1 - \nu).

On an edge of outward normal :math:`\mathbf n` and tangent :math:`\mathbf t = \mathbf e_z
\times\mathbf n` the work-conjugate pairs are :math:`(u_n, N_{nn})` and :math:`(u_t, N_{nt})`;
an edge condition makes each pair static (the resultant given) or kinematic (the displacement
given): ``fixed`` (:math:`u_n, u_t`), ``free`` (:math:`N_{nn}, N_{nt}`), ``diaphragm``
(:math:`u_t, N_{nn}`), ``roller`` (:math:`u_n, N_{nt}`). The VTCR form is the bending one
(section 4) with these pairs and no corner terms (the membrane operator is of second order).

The basis and its traces are in :mod:`solver.membrane_basis` (section 10.3).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from assembly.geometry import EDGE_NAMES, EdgeGeometry, plate_edges
from solver.dense import MEMBRANE_RANK_TOLERANCE, factorise_dense
from solver.membrane_basis import MembraneBasis, membrane_edge_traces, membrane_field
from solver.rays import edge_rule

__all__ = [
    "IN_PLANE_CONDITIONS",
    "membrane_stiffness",
    "membrane_wavenumbers",
    "MembraneEdge",
    "MembraneProblem",
    "MembraneSolution",
    "membrane_edge_rule",
    "membrane_dissipated_power",
    "assemble_membrane",
    "solve_membrane",
]

IN_PLANE_CONDITIONS: Mapping[str, tuple[str, str]] = {
    "fixed": ("kinematic", "kinematic"),
    "free": ("static", "static"),
    "diaphragm": ("static", "kinematic"),
    "roller": ("kinematic", "static"),
}
"""Per in-plane edge condition, the kind of the normal pair :math:`(u_n, N_{nn})` and of the
tangential pair :math:`(u_t, N_{nt})`."""

COMPONENTS = ("n", "t")
"""The edge components of a membrane trace: normal and tangential."""


def membrane_stiffness(young_modulus: float, thickness: float, poisson_ratio: float,
                       loss_factor: float) -> complex:
    r"""Hysteretic membrane stiffness :math:`A^* = Eh(1 + j\eta)/(1 - \nu^2)`, N/m."""
    return young_modulus * thickness * (1.0 + 1j * loss_factor) / (1.0 - poisson_ratio**2)


def membrane_wavenumbers(mass_per_area: float, omega: float, stiffness: complex,
                         poisson_ratio: float) -> tuple[complex, complex]:
    r"""Longitudinal and shear wavenumbers :math:`(k_L, k_S)`, 1/m:
    :math:`k_L^2 = \rho h\omega^2/A^*`, :math:`k_S^2 = 2k_L^2/(1-\nu)` (principal roots,
    :math:`\mathrm{Re} > 0`, :math:`\mathrm{Im} < 0` for :math:`\eta > 0`)."""
    k_long = complex(np.sqrt(mass_per_area * omega**2 / complex(stiffness)))
    return k_long, k_long * math.sqrt(2.0 / (1.0 - poisson_ratio))


EdgeData = Callable[[np.ndarray], np.ndarray]
"""Data along an edge as a function of the arc length from the edge's start."""


@dataclass(frozen=True)
class MembraneEdge:
    """The in-plane condition of one edge and its data.

    Attributes
    ----------
    condition : {"fixed", "free", "diaphragm", "roller"}
    data : mapping of str to callable
        Given values along the edge (functions of the arc length ``s``), by the component
        they prescribe: ``"u_n"``, ``"u_t"`` (kinematic) or ``"N_nn"``, ``"N_nt"`` (static);
        a component not given is zero.
    """

    condition: str = "free"
    data: Mapping[str, EdgeData] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.condition not in IN_PLANE_CONDITIONS:
            raise ValueError(f"in-plane condition must be one of {sorted(IN_PLANE_CONDITIONS)}, "
                             f"not {self.condition!r}")


@dataclass(frozen=True)
class MembraneProblem:
    """The in-plane problem of one rectangular plate at one circular frequency."""

    size: tuple[float, float]
    stiffness: complex
    poisson_ratio: float
    mass_per_area: float
    omega: float
    edges: Mapping[str, MembraneEdge] = field(default_factory=dict)

    @property
    def wavenumbers(self) -> tuple[complex, complex]:
        return membrane_wavenumbers(self.mass_per_area, self.omega, self.stiffness,
                                    self.poisson_ratio)

    def condition(self, edge: str) -> MembraneEdge:
        return self.edges.get(edge, MembraneEdge())

    @property
    def conditions(self) -> tuple[str, ...]:
        """Every edge's in-plane condition, in the order of :data:`assembly.geometry.
        EDGE_NAMES`."""
        return tuple(self.condition(edge).condition for edge in EDGE_NAMES)


def membrane_edge_rule(edge: EdgeGeometry, basis: MembraneBasis) -> tuple[np.ndarray, np.ndarray]:
    r"""Gauss points (arc lengths) and weights integrating the products of two traces on an
    edge: :math:`\lceil 0.75\max|\mathbf k|L\rceil + 10` points (``docs/method.md``
    section 5.3). Towards an end where the plate has corner functions
    (:mod:`solver.membrane_corners`), whose tractions grow as :math:`r^{\lambda - 1}`, the
    quarter of the edge next to it and the other end's quarter are cut into geometric panels
    (:func:`solver.rays.edge_rule`)."""
    n = math.ceil(0.75 * float(np.max(np.abs(basis.k))) * edge.length) + 10
    return edge_rule([edge], n, [family.point for family in basis.corners])


def assemble_membrane(problem: MembraneProblem, basis: MembraneBasis,
                      cache: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    r""":math:`K` and :math:`F` of the membrane VTCR form (``docs/method.md`` section 10.2):

    .. math::
        \sum_{\alpha\ \mathrm{static}}\int\overline{u_\alpha(\delta\mathbf u)}
            (N_\alpha(\mathbf u) - N_{\alpha,d})\,ds
        - \sum_{\alpha\ \mathrm{kin.}}\int\overline{N_\alpha(\delta\mathbf u)}
            (u_\alpha(\mathbf u) - u_{\alpha,d})\,ds = 0,

    :math:`\alpha\in\{n, t\}` on each edge, :math:`K` edge by edge. ``cache`` keeps
    :func:`membrane_edge_traces`' traces and each edge's part of :math:`K` by basis object,
    material, edge and condition: plates that share a basis and differ in some edges' conditions
    (a panel's end and inner bays) compute the others' once."""
    matrix = np.zeros((basis.n_dof, basis.n_dof), dtype=complex)
    force = np.zeros(basis.n_dof, dtype=complex)
    for edge in plate_edges(problem.size):
        s, w = membrane_edge_rule(edge, basis)
        traces = membrane_edge_traces(basis, edge, s, problem.stiffness, problem.poisson_ratio,
                                      cache)
        condition = problem.condition(edge.name)
        kinds = IN_PLANE_CONDITIONS[condition.condition]
        tests, trials, given = [], [], []
        for component, kind in zip(COMPONENTS, kinds):
            displacement, resultant = f"u_{component}", f"N_n{component}"
            if kind == "static":
                test, trial, datum, sign = displacement, resultant, resultant, 1.0
            else:
                test, trial, datum, sign = resultant, displacement, displacement, -1.0
            data = condition.data.get(datum)
            given.append(np.zeros(len(s), complex) if data is None
                         else np.asarray(data(s), complex))
            tests.append(traces[test].conj().T * (sign * w))
            trials.append(traces[trial])
        test = np.hstack(tests)
        key = ("membrane edge", id(basis), problem.stiffness, problem.poisson_ratio, edge.name,
               s.tobytes(), kinds)
        part = None if cache is None else cache.get(key)
        if part is None:
            part = test @ np.vstack(trials)
            if cache is not None:
                cache[key] = part
        matrix += part
        force += test @ np.concatenate(given)
    return matrix, force


@dataclass(frozen=True)
class MembraneSolution:
    """In-plane field of one plate: its problem, basis, dof amplitudes and the reciprocal
    condition estimate of its VTCR matrix."""

    problem: MembraneProblem
    basis: MembraneBasis
    amplitudes: np.ndarray
    rcond: float

    def u(self, points: ArrayLike) -> np.ndarray:
        """In-plane displacement (points, 2) in the plate's frame."""
        return membrane_field(self.basis, self.amplitudes, points)["u"]

    def resultants(self, points: ArrayLike) -> np.ndarray:
        """:math:`\\mathbf N` (points, 2, 2), N/m."""
        return membrane_field(self.basis, self.amplitudes, points, self.problem.stiffness,
                              self.problem.poisson_ratio)["N"]


def solve_membrane(problem: MembraneProblem, basis: MembraneBasis) -> MembraneSolution:
    """Assemble and solve one plate's membrane VTCR problem."""
    matrix, force = assemble_membrane(problem, basis)
    solve, rcond = factorise_dense(matrix, MEMBRANE_RANK_TOLERANCE)
    return MembraneSolution(problem, basis, solve(force), rcond)


def membrane_dissipated_power(problem: MembraneProblem, basis: MembraneBasis,
                              amplitudes: np.ndarray) -> float:
    r"""Time-averaged power dissipated in a plate's in-plane field (W):
    :math:`\tfrac12\omega\,\mathrm{Im}\oint(\mathbf N\mathbf n)\cdot\bar{\mathbf u}\,ds
    = \tfrac12\omega\,\mathrm{Im}(A^*)\,a(\mathbf u)` (``docs/method.md`` section 10.2), on
    the edge rules that integrate the traces' products to round-off."""
    total = 0.0
    for edge in plate_edges(problem.size):
        s, weights = membrane_edge_rule(edge, basis)
        traces = membrane_edge_traces(basis, edge, s, problem.stiffness, problem.poisson_ratio)
        u_n, u_t, n_nn, n_nt = (traces[k] @ amplitudes for k in ("u_n", "u_t", "N_nn", "N_nt"))
        total += weights @ (n_nn * np.conj(u_n) + n_nt * np.conj(u_t))
    return 0.5 * problem.omega * float(np.imag(total))
