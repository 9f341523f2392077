r"""The in-plane (membrane) Trefftz basis of one plate and its evaluations: fields, grids and
edge traces (``docs/method.md`` section 10.3).

Sector means of interior plane waves of each wave type (longitudinal :math:`k_L`, shear
:math:`k_S`) and, per edge and :math:`|\beta|\le\beta_{max}`, of the shear edge wave
:math:`\mathbf k_S = -j\beta\,\mathbf t + \sqrt{\beta^2 - k_S^2}\,\mathbf n` and of a
boundary-layer node, the divided difference of the longitudinal and the shear edge wave of the
same :math:`\beta` (:func:`boundary_layer_node`). Below the first in-plane resonance the field
is quasi-static and carried by the edge waves of large :math:`\beta`, the Saint-Venant
boundary layers of the static problem; there the two edge waves of one :math:`\beta` tend to
one field, and their difference, which the boundary layer needs, is what the divided difference
evaluates without cancellation. The problem these functions solve, its edge conditions and its
variational form are in :mod:`solver.membrane`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from assembly.geometry import EdgeGeometry, plate_edges
from solver.membrane_corners import (
    CornerFamily,
    corner_displacements,
    corner_fields,
    plane_stress_resultants,
)
from solver.rays import RayBasis, edge_exponentials, gauss_legendre, node_exponentials

__all__ = [
    "MembraneCounts",
    "membrane_ray_counts",
    "MembraneBasis",
    "build_membrane_basis",
    "boundary_layer_node",
    "layer_growth",
    "membrane_field",
    "membrane_grid_displacement",
    "membrane_edge_traces",
]


@dataclass(frozen=True)
class MembraneCounts:
    """Sector counts of a membrane basis: interior plane waves and edge waves (per edge), the
    same for the longitudinal and the shear family."""

    interior: int
    edge: tuple[int, int, int, int]


def membrane_ray_counts(size: tuple[float, float], k_shear: float,
                        edge_wavenumber: float | Sequence[float],
                        resolution: float = 1.0,
                        edge_resolution: float | None = None) -> MembraneCounts:
    r"""Sector counts by the resolution rule of ``docs/method.md`` section 5.2, for each wave
    type: :math:`N_{int} = \max(8, \lceil 2.6\,s k R_{max}\rceil_4)` with the shear wavenumber
    :math:`k_S` (the shorter in-plane wave), and per edge
    :math:`N_e = \max(4, \lceil s\,2\beta_{max}L_e/2\pi\rceil)` sectors of
    :math:`\beta\in[-\beta_{max}, \beta_{max}]`: a sector of width at most :math:`2\pi/L_e`
    carries its edge wave over the whole edge. ``edge_wavenumber`` is :math:`\beta_{max}`, one
    for every edge or one per edge in the order of :data:`assembly.geometry.EDGE_NAMES`;
    ``edge_resolution`` the :math:`s` of :math:`N_e` (default ``resolution``: see
    :func:`solver.rays.automatic_ray_counts`)."""
    edge_resolution = resolution if edge_resolution is None else edge_resolution
    lx, ly = size
    radius = 0.5 * math.hypot(lx, ly)
    interior = max(8, 4 * math.ceil(2.6 * resolution * k_shear * radius / 4))
    edge = tuple(max(4, math.ceil(edge_resolution * reach * length / math.pi))
                 for reach, length in zip(_per_edge(edge_wavenumber), (lx, ly, lx, ly)))
    return MembraneCounts(interior, edge)


@dataclass(frozen=True)
class MembraneBasis(RayBasis):
    r"""Sector-averaged in-plane waves of one plate, stored node by node: a
    :class:`solver.rays.RayBasis` (wave vectors, reference points, sector weights; families
    ``"interior:L"``, ``"edge:S:<edge>"``, ``"edge:layer:<edge>"``, ...) whose nodes also carry
    their displacement.

    A node's displacement is

    .. math:: \mathbf u_q(\mathbf x) = e^{\mathbf k_q\cdot(\mathbf x - \mathbf x_{r,q})}
        \big[\mathbf d_q + g(\delta_q, \nu_q(\mathbf x))\,\mathbf b_q\big],\qquad
        \nu_q = (\mathbf x - \mathbf x_{r,q})\cdot\mathbf n_q,\quad
        g(\delta, \nu) = \frac{e^{\delta\nu} - 1}{\delta},

    a plain wave where :math:`\mathbf b_q = 0` (every interior and shear node), and for a
    boundary-layer node the divided difference of a longitudinal and a shear edge wave of the
    same :math:`\beta` (:func:`boundary_layer_node`).

    Attributes
    ----------
    polarisation : ndarray of complex, shape (n_nodes, 2)
        :math:`\mathbf d_q`: :math:`\mathbf k/|\mathbf k|` (longitudinal) or
        :math:`\mathbf e_z\times\mathbf k/|\mathbf k|` (shear), of unit Euclidean norm, so
        that every node is of order 1 on the plate; of order 1 too for a boundary-layer node.
    layer : ndarray of complex, shape (n_nodes, 2)
        :math:`\mathbf b_q`, zero for the plain waves.
    layer_normal : ndarray of float, shape (n_nodes, 2)
        :math:`\mathbf n_q`, the outward normal of a boundary-layer node's edge (zero for the
        plain waves).
    layer_rate : ndarray of complex, shape (n_nodes,)
        :math:`\delta_q = \gamma_L - \gamma_S`, the difference of the two waves' rates
        across the edge (zero for the plain waves).
    corners : tuple of :class:`solver.membrane_corners.CornerFamily`
        The corner functions of the plate's fixed-free corners
        (:func:`solver.in_plane.membrane_bases`), dofs after the rays' (``n_rays`` on).
    """

    polarisation: np.ndarray
    layer: np.ndarray
    layer_normal: np.ndarray
    layer_rate: np.ndarray
    corners: tuple[CornerFamily, ...] = ()

    @property
    def n_dof(self) -> int:
        return self.n_rays + sum(family.n_functions for family in self.corners)

    @functools.cached_property
    def edge_factors(self) -> dict:
        """The trace factors of :func:`_edge_factors` by material and edge, computed once per
        basis (identical plates share their basis)."""
        return {}

    @functools.cached_property
    def layer_nodes(self) -> np.ndarray:
        r"""Indices of the boundary-layer nodes (those with :math:`\mathbf b_q \ne 0`)."""
        return np.flatnonzero(np.any(self.layer != 0, axis=1))

    @functools.cached_property
    def layer_groups(self) -> tuple[tuple[slice, np.ndarray, np.ndarray], ...]:
        r"""The boundary-layer nodes by edge, each a contiguous run of whole sectors sharing
        :math:`\mathbf n_q` and :math:`\mathbf x_{r,q}`: ``(nodes, rates, index)`` with the
        node slice, the distinct :math:`\delta_q` of the run (the nodes of :math:`\pm\beta`
        share one) and each node's position among them."""
        groups, layer = [], self.layer_nodes
        breaks = np.flatnonzero((np.diff(layer) != 1)
                                | np.any(np.diff(self.layer_normal[layer], axis=0) != 0, axis=1))
        for run in np.split(layer, breaks + 1):
            if len(run):
                rates, index = np.unique(self.layer_rate[run], return_inverse=True)
                groups.append((slice(run[0], run[-1] + 1), rates, index.ravel()))
        return tuple(groups)


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


def layer_growth(rate: np.ndarray, distance: np.ndarray) -> np.ndarray:
    r""":math:`g(\delta, \nu) = (e^{\delta\nu} - 1)/\delta`, :math:`\delta \ne 0`: the divided
    difference of two exponentials across an edge, exact to round-off however small
    :math:`\delta\nu` (``expm1``, no subtraction)."""
    return np.expm1(rate * distance) / rate


def boundary_layer_node(beta: np.ndarray, k_long: complex, k_shear: complex,
                        tangent: np.ndarray, normal: np.ndarray
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    r"""The boundary-layer nodes of an edge: for each :math:`\beta`, the divided difference of
    the longitudinal and the shear edge wave of that :math:`\beta`,

    .. math::
        \mathbf u = \frac{\mathbf k_L e^{\mathbf k_L\cdot\mathbf x}
            - c\,\mathbf e_z\times\mathbf k_S\,e^{\mathbf k_S\cdot\mathbf x}}{\delta}
        = e^{\mathbf k_S\cdot\mathbf x}\big[\mathbf d + g(\delta, \nu)\,\mathbf k_L\big],
        \qquad \mathbf d = \frac{\mathbf k_L - c\,\mathbf e_z\times\mathbf k_S}{\delta},

    with :math:`\mathbf k_X = -j\beta\mathbf t + \gamma_X\mathbf n`,
    :math:`\gamma_X = \sqrt{\beta^2 - k_X^2}`, :math:`\delta = \gamma_L - \gamma_S`,
    :math:`\nu = \mathbf x\cdot\mathbf n` and :math:`c = -j\,\mathrm{sgn}\beta`, the factor
    that makes the two waves agree as :math:`k_X/\beta\to0` (there
    :math:`\mathbf e_z\times\mathbf k_S\to j\,\mathrm{sgn}\beta\,\mathbf k_L`). In the
    static limit the shear wave and this node span the static boundary layer
    :math:`(\mathbf A + \nu\mathbf B)e^{-j\beta s + |\beta|\nu}`, this node carrying its
    :math:`\nu\mathbf B` term with a coefficient of order 1. Every difference is written
    without cancellation, in components on :math:`(\mathbf t, \mathbf n)`:

    .. math::
        \delta = \frac{k_S^2 - k_L^2}{\gamma_L + \gamma_S},\qquad
        \delta\,d_t = -j\,\mathrm{sgn}\beta\,(|\beta| - \gamma_S)
            = \frac{-j\,\mathrm{sgn}\beta\;k_S^2}{|\beta| + \gamma_S},\qquad
        \delta\,d_n = \gamma_L - |\beta| = \frac{-k_L^2}{\gamma_L + |\beta|}.

    Returns the wave vectors :math:`\mathbf k_S`, the directions :math:`\mathbf d`, the
    vectors :math:`\mathbf k_L` (the :math:`\mathbf b` of :class:`MembraneBasis`) and the
    rates :math:`\delta`.
    """
    gamma_long = _root_positive_real(beta**2 - k_long**2)
    gamma_shear = _root_positive_real(beta**2 - k_shear**2)
    rate = (k_shear**2 - k_long**2) / (gamma_long + gamma_shear)
    sign, size = np.sign(beta), np.abs(beta)
    along = -1j * sign * k_shear**2 / ((size + gamma_shear) * rate)
    across = -k_long**2 / ((gamma_long + size) * rate)
    k_shear_vector = (-1j * beta)[:, None] * tangent + gamma_shear[:, None] * normal
    k_long_vector = (-1j * beta)[:, None] * tangent + gamma_long[:, None] * normal
    direction = along[:, None] * tangent + across[:, None] * normal
    return k_shear_vector, direction, k_long_vector, rate


def _per_edge(edge_wavenumber: float | Sequence[float]) -> tuple[float, ...]:
    r""":math:`\beta_{max}` of each of the four edges."""
    return tuple(float(b) for b in np.broadcast_to(np.asarray(edge_wavenumber, float), (4,)))


def build_membrane_basis(size: tuple[float, float], k_long: complex, k_shear: complex,
                         counts: MembraneCounts, edge_wavenumber: float | Sequence[float],
                         n_q: int = 8) -> MembraneBasis:
    r"""The in-plane waves of one plate: for each wave type :math:`X\in\{L, S\}`, interior
    plane waves :math:`\mathbf k = -jk_X(\cos\theta, \sin\theta)` about the centre and, per
    edge and :math:`|\beta|\le` ``edge_wavenumber`` (one for all edges or one per edge), from the
    edge's start, the shear edge wave
    :math:`\mathbf k = -j\beta\,\mathbf t + \sqrt{\beta^2 - k_S^2}\,\mathbf n` and the
    boundary-layer node of :func:`boundary_layer_node` (the divided difference of the
    longitudinal and the shear edge waves, which spans with the shear wave what the two edge
    waves span, without their near-dependence as :math:`k_X/\beta\to0`)."""
    ks, origins, weights, families = [], [], [], []
    pols, layers, normals, rates = [], [], [], []

    def add(k: np.ndarray, origin: np.ndarray, weight: np.ndarray, polarisation: np.ndarray,
            family: str, n_sectors: int, layer: np.ndarray | None = None,
            normal: np.ndarray | None = None, rate: np.ndarray | None = None) -> None:
        ks.append(k), weights.append(weight), pols.append(polarisation)
        origins.append(np.broadcast_to(origin, (len(k), 2)))
        layers.append(np.zeros((len(k), 2), complex) if layer is None else layer)
        normals.append(np.zeros((len(k), 2)) if normal is None
                       else np.broadcast_to(normal, (len(k), 2)))
        rates.append(np.zeros(len(k), complex) if rate is None else rate)
        families.extend([family] * n_sectors)

    centre = 0.5 * np.asarray(size, float)
    for wave, k_wave in (("L", k_long), ("S", k_shear)):
        theta, w = _sector_nodes(0.0, 2.0 * np.pi, counts.interior, n_q)
        k = -1j * k_wave * np.stack([np.cos(theta), np.sin(theta)], axis=1)
        add(k, centre, w, _polarisation(k, wave), f"interior:{wave}", counts.interior)
    for edge, n_sectors, reach in zip(plate_edges(size), counts.edge,
                                      _per_edge(edge_wavenumber)):
        beta, w = _sector_nodes(-reach, reach, n_sectors, n_q)
        beta = 0.5 * (beta - beta[::-1])  # exactly odd: +-beta share exponentials and rates
        k, direction, layer, rate = boundary_layer_node(beta, k_long, k_shear, edge.tangent,
                                                        edge.normal)
        add(k, edge.start, w, direction, f"edge:layer:{edge.name}", n_sectors, layer,
            edge.normal, rate)
        add(k, edge.start, w, _polarisation(k, "S"), f"edge:S:{edge.name}", n_sectors)
    return MembraneBasis(np.concatenate(ks), np.concatenate(origins), np.concatenate(weights),
                         n_q, tuple(families), np.concatenate(pols), np.concatenate(layers),
                         np.concatenate(normals), np.concatenate(rates))


def _resultant_factors(direction: np.ndarray, k: np.ndarray, stiffness: complex,
                       poisson_ratio: float) -> np.ndarray:
    r""":math:`\mathbf N` of :math:`\mathbf d\,e^{\mathbf k\cdot\mathbf x}` over its
    exponential, (nodes, 2, 2): :math:`A^*[\nu(\mathbf d\cdot\mathbf k)\mathbf I +
    \tfrac{1-\nu}2(\mathbf d\mathbf k^T + \mathbf k\mathbf d^T)]`, the plane-stress law
    (:func:`solver.membrane_corners.plane_stress_resultants`) of the gradient
    :math:`\mathbf d\otimes\mathbf k`."""
    return plane_stress_resultants(direction[:, :, None] * k[:, None, :], stiffness,
                                   poisson_ratio)


def _node_factors(basis: MembraneBasis, stiffness: complex, poisson_ratio: float
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    r"""Per node, the factors of the displacement and the resultants over the exponential
    :math:`E = e^{\mathbf k\cdot(\mathbf x - \mathbf x_r)}`:
    :math:`\mathbf u = E[\mathbf d + g\mathbf b]` and, since
    :math:`\nabla\mathbf u = E[\mathbf d\otimes\mathbf k + \mathbf b\otimes\mathbf n
    + g\,\mathbf b\otimes(\mathbf k + \delta\mathbf n)]` (:math:`\partial_\nu g = 1 + \delta g
    = e^{\delta\nu}`),
    :math:`\mathbf N = E[\mathbf N(\mathbf d, \mathbf k) + \mathbf N(\mathbf b, \mathbf n)
    + g\,\mathbf N(\mathbf b, \mathbf k + \delta\mathbf n)]`, with :math:`\mathbf N(\cdot,
    \cdot)` of :func:`_resultant_factors`. Returns
    :math:`(\mathbf d, \mathbf b, \mathbf N_0, \mathbf N_1)`, the parts without and with
    :math:`g`."""
    d, b, normal, rate = basis.polarisation, basis.layer, basis.layer_normal, basis.layer_rate
    plain = (_resultant_factors(d, basis.k, stiffness, poisson_ratio)
             + _resultant_factors(b, normal.astype(complex), stiffness, poisson_ratio))
    grown = _resultant_factors(b, basis.k + rate[:, None] * normal, stiffness, poisson_ratio)
    return d, b, plain, grown


def _layer_sector_means(basis: MembraneBasis, nodes: slice | np.ndarray, nodal: np.ndarray,
                        factors: np.ndarray) -> np.ndarray:
    """:meth:`solver.rays.RayBasis.sector_means` over the dofs whose nodes are ``nodes`` (whole
    sectors, in order, as a slice or indices): ``nodal`` (points, nodes), ``factors``
    (n_factors, nodes); returns (n_factors, points, nodes // n_q)."""
    n_points, n_dofs = nodal.shape[0], nodal.shape[1] // basis.n_q
    blocks = nodal.reshape(n_points, n_dofs, basis.n_q).transpose(1, 0, 2)
    weighted = (factors * basis.weight[nodes]).reshape(-1, n_dofs, basis.n_q).transpose(1, 2, 0)
    return np.matmul(blocks, weighted).transpose(2, 1, 0)


def membrane_field(basis: MembraneBasis, amplitudes: np.ndarray, points: ArrayLike,
                   stiffness: complex | None = None, poisson_ratio: float = 0.0
                   ) -> dict[str, np.ndarray]:
    r"""``u`` (points, 2) at ``points`` (n, 2) for the dof ``amplitudes`` and, given the
    ``stiffness`` :math:`A^*`, the resultants ``N`` (points, 2, 2): the sector means of
    :math:`E_q[\mathbf a_q + g_q\mathbf b_q]` (:func:`_node_factors`)."""
    points = np.atleast_2d(np.asarray(points, float))
    d, b, plain, grown = _node_factors(basis, 1.0 if stiffness is None else stiffness,
                                       poisson_ratio)
    factors, layer_factors = [d[:, 0], d[:, 1]], [b[:, 0], b[:, 1]]
    if stiffness is not None:
        factors += [plain[:, i, j] for i in range(2) for j in range(2)]
        layer_factors += [grown[:, i, j] for i in range(2) for j in range(2)]
    nodal = node_exponentials(basis, points)
    means = basis.sector_means(nodal, np.stack(factors))
    layer = basis.layer_nodes
    if len(layer):
        normal, origin = basis.layer_normal[layer], basis.origin[layer]
        distance = points @ normal.T - np.sum(origin * normal, axis=1)
        growth = layer_growth(basis.layer_rate[layer], distance)
        means[:, :, layer[::basis.n_q] // basis.n_q] += _layer_sector_means(
            basis, layer, nodal[:, layer] * growth, np.stack(layer_factors)[:, layer])
    rays, corner = amplitudes[:basis.n_rays], amplitudes[basis.n_rays:]
    means = means @ rays
    out = {"u": np.stack(means[:2], axis=-1)}
    if stiffness is not None:
        out["N"] = np.stack(means[2:], axis=-1).reshape(-1, 2, 2)
    if not basis.corners:
        return out
    if stiffness is None:
        out["u"] = out["u"] + corner_displacements(basis.corners, points) @ corner
    else:
        u, resultants = corner_fields(basis.corners, points, stiffness, poisson_ratio)
        out["u"] = out["u"] + u @ corner
        out["N"] = out["N"] + resultants @ corner
    return out


def membrane_grid_displacement(basis: MembraneBasis, amplitudes: np.ndarray, xs: np.ndarray,
                               ys: np.ndarray) -> np.ndarray:
    r"""In-plane displacement :math:`(u, v)` on the tensor grid ``xs`` x ``ys``, shape
    (2, len(xs), len(ys)):

    .. math:: u_c = \sum_q\omega_qU_{i(q)}e^{k_{q,x}(x - x_{r,q})}e^{k_{q,y}(y - y_{r,q})}
        \big[d_{q,c} + g(\delta_q, \nu_q)\,b_{q,c}\big]

    (:func:`membrane_field` separated as :func:`solver.rays.tensor_grid_field` separates the
    rays: matrix products over :math:`n_q(n_x + n_y)` exponentials instead of
    :math:`n_qn_xn_y`). A boundary-layer node's :math:`\nu_q` is a distance to its edge, a
    function of :math:`x` or of :math:`y` alone (the edges are along the axes), so its
    :math:`g` joins that coordinate's factor. Each factor is bounded on the plate, the edge
    waves decaying away from their edge in each coordinate."""
    xs, ys = np.asarray(xs, float), np.asarray(ys, float)
    amplitudes = np.asarray(amplitudes)
    nodes = basis.weight * np.repeat(amplitudes[:basis.n_rays], basis.n_q)
    ex = np.exp(basis.k[:, 0, None] * (xs[None, :] - basis.origin[:, 0, None]))
    ey = np.exp(basis.k[:, 1, None] * (ys[None, :] - basis.origin[:, 1, None]))
    layer = basis.layer_nodes
    normal, origin, rate = basis.layer_normal[layer], basis.origin[layer], basis.layer_rate[layer]
    across_x = (normal[:, 0] != 0)[:, None]  # an edge x = const: the distance to it is along x
    layer_x = ex[layer] * np.where(across_x, layer_growth(
        rate[:, None], normal[:, 0, None] * (xs[None, :] - origin[:, 0, None])), 1.0)
    layer_y = ey[layer] * np.where(across_x, 1.0, layer_growth(
        rate[:, None], normal[:, 1, None] * (ys[None, :] - origin[:, 1, None])))
    grid = np.stack([ex.T @ ((nodes * basis.polarisation[:, c])[:, None] * ey)
                     + layer_x.T @ ((nodes * basis.layer[:, c])[layer, None] * layer_y)
                     for c in range(2)])
    if basis.corners:  # the corner functions point by point: they do not separate
        x, y = np.meshgrid(xs, ys, indexing="ij")
        u = corner_displacements(basis.corners, np.column_stack([x.ravel(), y.ravel()]))
        grid += np.moveaxis((u @ amplitudes[basis.n_rays:]).reshape(len(xs), len(ys), 2), -1, 0)
    return grid


EdgeFactors = tuple[np.ndarray, np.ndarray,
                    list[tuple[slice, np.ndarray, np.ndarray, float, float]]]
"""What :func:`_edge_factors` returns."""


def _edge_factors(basis: MembraneBasis, edge: EdgeGeometry, stiffness: complex,
                  poisson_ratio: float) -> EdgeFactors:
    r"""The factors of the traces ``u_n, u_t, N_nn, N_nt`` of every node over its exponential on
    ``edge``, (4, nodes) without and with :math:`g` (:func:`membrane_edge_traces`), and the
    boundary-layer groups whose :math:`g` varies along the edge,
    ``(nodes, rates, index, start, slope)`` with :math:`\nu = \mathrm{start} +
    \mathrm{slope}\,s`; on the node's own edge and the opposite one :math:`g` is constant and
    already in the first factors. The factors are :func:`_node_factors`' vectors and
    resultants projected on the edge's normal and tangent: the resultants are formed once per
    basis and material, for its four edges. Kept on the basis by material and edge: they do
    not depend on the points."""
    key = (stiffness, poisson_ratio, tuple(edge.start), tuple(edge.normal))
    if key in basis.edge_factors:
        return basis.edge_factors[key]
    nodes_key = ("nodes", stiffness, poisson_ratio)
    if nodes_key not in basis.edge_factors:
        basis.edge_factors[nodes_key] = _node_factors(basis, stiffness, poisson_ratio)
    d, b, plain, grown = basis.edge_factors[nodes_key]
    n, t = edge.normal, edge.tangent

    def component(vectors: np.ndarray, axis: np.ndarray) -> np.ndarray:
        return vectors[..., 0] * axis[0] + vectors[..., 1] * axis[1]

    def on_edge(vectors: np.ndarray, resultants: np.ndarray) -> np.ndarray:
        traction = component(resultants, n)
        return np.stack([component(vectors, n), component(vectors, t), component(traction, n),
                         component(traction, t)])

    factors, layer_factors = on_edge(d, plain), on_edge(b, grown)  # b = 0 off the layers
    along = []  # the groups whose distance to their edge varies along this one
    for nodes, rates, index in basis.layer_groups:
        group_normal = basis.layer_normal[nodes.start]
        start = float((edge.start - basis.origin[nodes.start]) @ group_normal)
        slope = float(group_normal @ edge.tangent)
        if slope == 0:  # the node's own edge or the opposite one: g is a constant factor
            factors[:, nodes] += (layer_growth(basis.layer_rate[nodes], start)
                                  * layer_factors[:, nodes])
        else:
            along.append((nodes, rates, index, start, slope))
    basis.edge_factors[key] = factors, layer_factors, along
    return factors, layer_factors, along


def membrane_edge_traces(basis: MembraneBasis, edge: EdgeGeometry, s: np.ndarray,
                         stiffness: complex, poisson_ratio: float,
                         cache: dict | None = None) -> dict[str, np.ndarray]:
    r"""Traces of the shape functions at the arc lengths ``s`` of ``edge``: ``u_n``, ``u_t``,
    ``N_nn``, ``N_nt``, each (len(s), n_dof). ``cache`` (a dict, optional) keeps them by basis
    object, material, edge and points: identical plates sharing one basis compute them once.

    For a node :math:`E[\mathbf d + g\mathbf b]` (:func:`_node_factors`), with
    :math:`\mathbf N_0, \mathbf N_1` its resultant factors without and with :math:`g`:

    .. math::
        u_n = E[d_n + g\,b_n],\quad u_t = E[d_t + g\,b_t],\quad
        N_{n\alpha} = E[\boldsymbol\alpha\cdot\mathbf N_0\mathbf n
            + g\,\boldsymbol\alpha\cdot\mathbf N_1\mathbf n],\quad
        \boldsymbol\alpha\in\{\mathbf n, \mathbf t\};

    for a plain wave (:math:`\mathbf b = 0`)
    :math:`N_{nn} = A^*[(1-\nu)d_nk_n + \nu\,\mathbf d\cdot\mathbf k]`,
    :math:`N_{nt} = A^*\tfrac{1-\nu}{2}(d_tk_n + d_nk_t)`. A boundary-layer node's distance to
    its edge, :math:`\nu = \nu_0 + s\,\mathbf t\cdot\mathbf n_q`, is constant on its own edge
    and on the opposite one, where :math:`g` joins the factors; on the two others it is the
    coordinate along the edge, and :math:`g` is evaluated once per distinct
    :math:`(\delta_q, \nu_0, \mathbf t\cdot\mathbf n_q)`, which the nodes of :math:`\pm\beta`
    and of opposite edges share.
    """
    key = ("membrane", id(basis), stiffness, poisson_ratio, edge.name, np.asarray(s).tobytes())
    if cache is not None and key in cache:
        return cache[key]
    s = np.asarray(s, dtype=float)
    factors, layer_factors, along = _edge_factors(basis, edge, stiffness, poisson_ratio)
    nodal = edge_exponentials(basis, edge, s)
    traces = basis.sector_means(nodal, factors)
    for nodes, rates, index, start, slope in along:
        growth = layer_growth(rates, start + slope * s[:, None])[:, index]
        dofs = slice(nodes.start // basis.n_q, nodes.stop // basis.n_q)
        traces[:, :, dofs] += _layer_sector_means(basis, nodes, nodal[:, nodes] * growth,
                                                  layer_factors[:, nodes])
    if basis.corners:
        u, resultants = corner_fields(basis.corners, edge.start + s[:, None] * edge.tangent,
                                      stiffness, poisson_ratio)
        traction = np.einsum("pijf,j->pif", resultants, edge.normal)
        traces = np.concatenate([traces, np.stack([
            np.einsum("pif,i->pf", vectors, direction)
            for vectors, direction in ((u, edge.normal), (u, edge.tangent),
                                       (traction, edge.normal), (traction, edge.tangent))])],
            axis=2)
    traces = dict(zip(("u_n", "u_t", "N_nn", "N_nt"), traces))
    if cache is not None:
        cache[key] = traces
    return traces
