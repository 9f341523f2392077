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

The basis (section 10.3): for each wave type, sector means of interior plane waves and of edge
waves :math:`\mathbf k = -j\beta\,\mathbf t + \sqrt{\beta^2 - k^2}\,\mathbf n` for
:math:`|\beta|\le\beta_{max}`. Below the first in-plane resonance (the regime of most
structures: in-plane wavelengths of 10-40 plate sizes) the field is quasi-static and is carried
by the edge waves of large :math:`\beta`, the Saint-Venant boundary layers of the static
problem; :math:`\beta_{max}` is therefore set by what loads the edges (the bending waves of the
plates meeting at a fold), not by :math:`k_S`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from assembly.geometry import EdgeGeometry, plate_edges
from solver.dense import factorise_dense
from solver.rays import RayBasis, gauss_legendre, line_exponentials, node_exponentials

__all__ = [
    "IN_PLANE_CONDITIONS",
    "membrane_stiffness",
    "membrane_wavenumbers",
    "MembraneCounts",
    "membrane_ray_counts",
    "MembraneBasis",
    "build_membrane_basis",
    "MembraneEdge",
    "MembraneProblem",
    "MembraneSolution",
    "membrane_edge_traces",
    "membrane_edge_rule",
    "membrane_field",
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


# ----------------------------------------------------------------------------------------------
# basis
# ----------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class MembraneCounts:
    """Sector counts of a membrane basis: interior plane waves and edge waves (per edge), the
    same for the longitudinal and the shear family."""

    interior: int
    edge: tuple[int, int, int, int]


def membrane_ray_counts(size: tuple[float, float], k_shear: float, edge_wavenumber: float,
                        resolution: float = 1.0) -> MembraneCounts:
    r"""Sector counts by the resolution rule of ``docs/method.md`` section 5.2, for each wave
    type: :math:`N_{int} = \max(8, \lceil 2.6\,s k R_{max}\rceil_4)` with the shear wavenumber
    :math:`k_S` (the shorter in-plane wave), and per edge
    :math:`N_e = \max(4, \lceil s\,2\beta_{max}L_e/2\pi\rceil)` sectors of
    :math:`\beta\in[-\beta_{max}, \beta_{max}]`: a sector of width at most :math:`2\pi/L_e`
    carries its edge wave over the whole edge."""
    lx, ly = size
    radius = 0.5 * math.hypot(lx, ly)
    interior = max(8, 4 * math.ceil(2.6 * resolution * k_shear * radius / 4))
    edge = tuple(max(4, math.ceil(resolution * edge_wavenumber * length / math.pi))
                 for length in (lx, ly, lx, ly))
    return MembraneCounts(interior, edge)


@dataclass(frozen=True)
class MembraneBasis(RayBasis):
    """Sector-averaged in-plane waves of one plate, stored node by node: a
    :class:`solver.rays.RayBasis` (wave vectors, reference points, sector weights; families
    ``"interior:L"``, ``"edge:S:<edge>"``, ...) whose nodes also carry their displacement
    direction.

    Attributes
    ----------
    polarisation : ndarray of complex, shape (n_nodes, 2)
        Displacement direction :math:`\\mathbf d` of each node: :math:`\\mathbf k/|\\mathbf k|`
        (longitudinal) or :math:`\\mathbf e_z\\times\\mathbf k/|\\mathbf k|` (shear), of unit
        Euclidean norm, so that every node is of order 1 on the plate.
    """

    polarisation: np.ndarray


def _sector_nodes(lower: float, upper: float, n_sectors: int,
                  n_q: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and normalised weights on ``n_sectors`` equal sectors."""
    x, w = gauss_legendre(n_q)
    edges = np.linspace(lower, upper, n_sectors + 1)
    half, mid = 0.5 * np.diff(edges), 0.5 * (edges[1:] + edges[:-1])
    return ((mid[:, None] + half[:, None] * x).ravel(),
            np.broadcast_to(0.5 * w, (n_sectors, n_q)).ravel())


def _root_positive_real(z: np.ndarray) -> np.ndarray:
    s = np.sqrt(z + 0j)
    return np.where(s.real < 0, -s, s)


def _polarisation(k: np.ndarray, wave: str) -> np.ndarray:
    """Unit displacement directions of longitudinal (``"L"``) or shear (``"S"``) nodes."""
    d = k if wave == "L" else np.stack([-k[:, 1], k[:, 0]], axis=1)
    return d / np.linalg.norm(k, axis=1)[:, None]


def build_membrane_basis(size: tuple[float, float], k_long: complex, k_shear: complex,
                         counts: MembraneCounts, edge_wavenumber: float,
                         n_q: int = 8) -> MembraneBasis:
    r"""The in-plane waves of one plate: for each wave type :math:`X\in\{L, S\}`, interior
    plane waves :math:`\mathbf k = -jk_X(\cos\theta, \sin\theta)` about the centre and, per
    edge, edge waves :math:`\mathbf k = -j\beta\,\mathbf t + \sqrt{\beta^2 - k_X^2}\,\mathbf n`
    (:math:`|\beta|\le` ``edge_wavenumber``) from the edge's start, decaying into the plate
    where :math:`|\beta| > \mathrm{Re}\,k_X`."""
    ks, origins, weights, families = [], [], [], []
    pols = []
    centre = 0.5 * np.asarray(size, float)
    for wave, k_wave in (("L", k_long), ("S", k_shear)):
        theta, w = _sector_nodes(0.0, 2.0 * np.pi, counts.interior, n_q)
        k = -1j * k_wave * np.stack([np.cos(theta), np.sin(theta)], axis=1)
        ks.append(k), pols.append(_polarisation(k, wave)), weights.append(w)
        origins.append(np.broadcast_to(centre, (len(theta), 2)))
        families += [f"interior:{wave}"] * counts.interior
        for edge, n_sectors in zip(plate_edges(size), counts.edge):
            beta, w = _sector_nodes(-edge_wavenumber, edge_wavenumber, n_sectors, n_q)
            across = _root_positive_real(beta**2 - k_wave**2)
            k = (-1j * beta)[:, None] * edge.tangent + across[:, None] * edge.normal
            ks.append(k), pols.append(_polarisation(k, wave)), weights.append(w)
            origins.append(np.broadcast_to(edge.start, (len(beta), 2)))
            families += [f"edge:{wave}:{edge.name}"] * n_sectors
    return MembraneBasis(np.concatenate(ks), np.concatenate(origins), np.concatenate(weights),
                         n_q, tuple(families), np.concatenate(pols))


def _edge_node_values(basis: MembraneBasis, edge: EdgeGeometry, s: np.ndarray) -> np.ndarray:
    r"""Node exponentials :math:`e^{\mathbf k\cdot(\mathbf x - \mathbf x_r)}` at the arc
    lengths ``s`` of an edge, (len(s), nodes).

    Where the points lie symmetrically on the edge (its Gauss rules, a joint's), the
    exponentials factor through :func:`solver.rays.line_exponentials`: about a seventh of the
    exponentials of the direct evaluation on a 50-point rule (a quarter of the nodes share
    their wavenumber along the edge, and half of the points mirror the others)."""
    axis = int(np.argmax(np.abs(edge.tangent)))
    along = edge.start[axis] + s * edge.tangent[axis]  # the coordinate along the edge
    order = np.argsort(along)
    u = np.concatenate([[0.0], along[order], [edge.length]])
    if not np.allclose(u + u[::-1], edge.length, rtol=0.0, atol=1e-12 * edge.length):
        return node_exponentials(basis, edge.start + s[:, None] * edge.tangent)
    shared, constants = line_exponentials(basis, axis, u, [edge.start[1 - axis]])
    values = np.empty((len(s), shared.shape[1]), dtype=complex)
    values[order] = shared[1:-1] * constants[0]
    return values


def membrane_field(basis: MembraneBasis, amplitudes: np.ndarray, points: ArrayLike,
                   stiffness: complex | None = None, poisson_ratio: float = 0.0
                   ) -> dict[str, np.ndarray]:
    r"""``u`` (points, 2) at ``points`` (n, 2) for the dof ``amplitudes`` and, given the
    ``stiffness`` :math:`A^*`, the resultants ``N`` (points, 2, 2)."""
    points = np.atleast_2d(np.asarray(points, float))
    d, k = basis.polarisation, basis.k
    factors = [d[:, 0], d[:, 1]]
    if stiffness is not None:
        div = np.sum(d * k, axis=1)
        for i in range(2):
            for j in range(2):
                shear = 0.5 * (1.0 - poisson_ratio) * (d[:, i] * k[:, j] + d[:, j] * k[:, i])
                factors.append(stiffness * (shear + poisson_ratio * div * (i == j)))
    means = basis.sector_means(node_exponentials(basis, points), np.stack(factors)) @ amplitudes
    out = {"u": np.stack(means[:2], axis=-1)}
    if stiffness is not None:
        out["N"] = np.stack(means[2:], axis=-1).reshape(-1, 2, 2)
    return out


# ----------------------------------------------------------------------------------------------
# one plate's problem
# ----------------------------------------------------------------------------------------------

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


def membrane_edge_traces(basis: MembraneBasis, edge: EdgeGeometry, s: np.ndarray,
                         stiffness: complex, poisson_ratio: float,
                         cache: dict | None = None) -> dict[str, np.ndarray]:
    r"""Traces of the shape functions at the arc lengths ``s`` of ``edge``: ``u_n``, ``u_t``,
    ``N_nn``, ``N_nt``, each (len(s), n_dof). ``cache`` (a dict, optional) keeps them by basis
    object, material, edge and points: identical plates sharing one basis compute them once.

    For a node :math:`\mathbf d\,e^{\mathbf k\cdot\mathbf x}`, with :math:`d_n, d_t, k_n, k_t`
    the components on :math:`\mathbf n, \mathbf t`:

    .. math::
        u_n = d_n,\quad u_t = d_t,\quad
        N_{nn} = A^*\big[(1-\nu)d_nk_n + \nu\,\mathbf d\cdot\mathbf k\big],\quad
        N_{nt} = A^*\tfrac{1-\nu}{2}(d_tk_n + d_nk_t).
    """
    key = ("membrane", id(basis), stiffness, poisson_ratio, edge.name, np.asarray(s).tobytes())
    if cache is not None and key in cache:
        return cache[key]
    nodal = _edge_node_values(basis, edge, np.asarray(s, dtype=float))
    d, k = basis.polarisation, basis.k
    d_n, d_t, k_n, k_t = d @ edge.normal, d @ edge.tangent, k @ edge.normal, k @ edge.tangent
    nu = poisson_ratio
    factors = np.stack([d_n, d_t,
                        stiffness * ((1.0 - nu) * d_n * k_n + nu * np.sum(d * k, axis=1)),
                        0.5 * stiffness * (1.0 - nu) * (d_t * k_n + d_n * k_t)])
    traces = dict(zip(("u_n", "u_t", "N_nn", "N_nt"), basis.sector_means(nodal, factors)))
    if cache is not None:
        cache[key] = traces
    return traces


def membrane_edge_rule(edge: EdgeGeometry, basis: MembraneBasis) -> tuple[np.ndarray, np.ndarray]:
    """Gauss points (arc lengths) and weights integrating the products of two traces on an
    edge: :math:`\\lceil 0.75\\max|\\mathbf k|L\\rceil + 10` points (``docs/method.md``
    section 5.3)."""
    n = math.ceil(0.75 * float(np.max(np.abs(basis.k))) * edge.length) + 10
    x, w = gauss_legendre(n)
    return 0.5 * edge.length * (x + 1.0), 0.5 * edge.length * w


def assemble_membrane(problem: MembraneProblem, basis: MembraneBasis,
                      cache: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    r""":math:`K` and :math:`F` of the membrane VTCR form (``docs/method.md`` section 10.2):

    .. math::
        \sum_{\alpha\ \mathrm{static}}\int\overline{u_\alpha(\delta\mathbf u)}
            (N_\alpha(\mathbf u) - N_{\alpha,d})\,ds
        - \sum_{\alpha\ \mathrm{kin.}}\int\overline{N_\alpha(\delta\mathbf u)}
            (u_\alpha(\mathbf u) - u_{\alpha,d})\,ds = 0,

    :math:`\alpha\in\{n, t\}` on each edge (``cache``: :func:`membrane_edge_traces`').
    """
    rows_test, rows_trial, rows_data = [], [], []
    for edge in plate_edges(problem.size):
        s, w = membrane_edge_rule(edge, basis)
        traces = membrane_edge_traces(basis, edge, s, problem.stiffness, problem.poisson_ratio,
                                      cache)
        condition = problem.condition(edge.name)
        for component, kind in zip(COMPONENTS, IN_PLANE_CONDITIONS[condition.condition]):
            displacement, resultant = f"u_{component}", f"N_n{component}"
            if kind == "static":
                test, trial, given, sign = displacement, resultant, resultant, 1.0
            else:
                test, trial, given, sign = resultant, displacement, displacement, -1.0
            data = condition.data.get(given)
            values = np.zeros(len(s), complex) if data is None else np.asarray(data(s), complex)
            weights = sign * w
            rows_test.append(traces[test].conj().T * weights)
            rows_trial.append(traces[trial])
            rows_data.append(values)
    test = np.hstack(rows_test)
    return test @ np.vstack(rows_trial), test @ np.concatenate(rows_data)


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
    solve, rcond = factorise_dense(matrix)
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
