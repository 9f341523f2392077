r"""Complex-ray shape functions of one rectangular plate.

Every ray is an exponential :math:`e^{\mathbf k\cdot(\mathbf x - \mathbf x_r)}` with a complex
wave vector on one of the loci of ``docs/method.md`` section 5.1 (all satisfy
:math:`(\mathbf k\cdot\mathbf k)^2 = \kappa^4`, hence the plate equation, exactly):

=========================  ============================================================  ==============
family                     wave vector :math:`\mathbf k`                                  reference
=========================  ============================================================  ==============
interior                   :math:`-j\kappa(\cos\theta, \sin\theta)`, :math:`\theta\in[0,2\pi)`  plate centre
edge, propagating (H)      :math:`\mp j\kappa\cosh\psi\,\mathbf t + \kappa\sinh\psi\,\mathbf n`,
                           :math:`0\le\psi\le\cosh^{-1}\tau`                              edge start
edge, evanescent (M)       :math:`-j\beta\,\mathbf t + \sqrt{\beta^2+\kappa^2}\,\mathbf n`,
                           :math:`|\beta|\le\tau\kappa_0`                                 edge start
corner                     :math:`-\kappa(\cos\theta, \sin\theta)`, :math:`\theta` in the
                           corner's inward quadrant                                       the corner
=========================  ============================================================  ==============

(:math:`\mathbf n` is the outward normal, so the edge and corner rays decay into the plate;
square roots have :math:`\mathrm{Re} > 0`.) The propagating edge rays use the equivalent
parametrisation :math:`\beta = \pm\kappa\cosh\psi`, so that
:math:`\sqrt{\beta^2-\kappa^2} = \kappa\sinh\psi` is entire in :math:`\psi`. With real
:math:`\beta` the root has a branch point at :math:`\beta = \kappa`, only
:math:`\kappa_0\eta/4` from the first sector, and an 8-point rule there is wrong by 1 %;
in :math:`\psi` the sector means converge like any entire integrand. The sector boundaries
are :math:`\psi_i = \cosh^{-1}(\beta_i/\kappa_0)` for equally spaced :math:`\beta_i`, so
the resolution rule below still holds in :math:`\beta`. Each locus is cut into sectors on which the
amplitude is constant (the paper's eqs. 22–23); the shape function of a sector is the mean of
the exponential over the sector,
:math:`\Phi_i(\mathbf x) = |\mathcal C_i|^{-1}\int_{\mathcal C_i} e^{\mathbf k(\alpha)\cdot(\mathbf x-\mathbf x_r)}d\alpha`,
computed by Gauss–Legendre quadrature with ``n_q`` nodes. A basis is therefore stored as
*nodes* (one wave vector per quadrature node, with its weight) grouped by sector:
``n_nodes = n_dof * n_q``, nodes of dof ``i`` at ``i*n_q:(i+1)*n_q``. The nodes are placed
exactly (to the last bit) symmetrically: :math:`\pm\beta`, :math:`\pm\theta` and
:math:`\theta+\pi`, the same loci on opposite edges and the four corners related by quarter
turns, so that the rectangle's symmetries map nodes onto nodes and
:func:`line_exponentials` can share their edge exponentials.

Resolution rule (``docs/method.md`` section 5.2): a sector of width :math:`\Delta\beta` makes a
wave packet about :math:`2\pi/\Delta\beta` long along its edge, so carrying a boundary layer
along an edge of length :math:`L_e` needs :math:`N_M \gtrsim \tau\kappa_0 L_e/\pi` evanescent
sectors, :math:`N_H \gtrsim (\tau - 1)\kappa_0 L_e/(2\pi)` propagating sectors per sign, and
:math:`N_{int} \gtrsim 2\kappa_0 R_{max}` interior sectors (:math:`R_{max}` the distance from
the centre to the furthest corner). :func:`automatic_ray_counts` applies it, scaled by a
``resolution`` factor.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from assembly.geometry import EdgeGeometry, plate_edges
from solver.plate_corners import WedgeFamily, wedge_field

__all__ = [
    "RayCounts",
    "RayBasis",
    "WedgeBasis",
    "automatic_ray_counts",
    "tensor_grid_field",
    "build_ray_basis",
    "ray_field",
    "node_exponentials",
    "line_exponentials",
    "edge_exponentials",
    "gauss_legendre",
    "CORNER_GRADING",
    "end_graded_rule",
    "edge_rule",
]


@dataclass(frozen=True)
class RayCounts:
    """Number of sectors per ray family of one plate.

    ``edge_propagating`` and ``edge_evanescent`` hold one count per edge, in :data:`EDGE_NAMES`
    order; ``edge_propagating`` counts both signs of :math:`\\beta` (it is even).
    """

    interior: int
    edge_propagating: tuple[int, int, int, int]
    edge_evanescent: tuple[int, int, int, int]
    corner: int

    @property
    def total(self) -> int:
        """Number of ray unknowns of the plate."""
        return (
            self.interior
            + sum(self.edge_propagating)
            + sum(self.edge_evanescent)
            + 4 * self.corner
        )


# Smallest kappa0 * R_max the counts are sized for (see automatic_ray_counts).
QUASI_STATIC_KAPPA_R = 5.0


def automatic_ray_counts(kappa0: float, size: tuple[float, float], resolution: float = 1.0,
                         tau: float = 2.5, edge_resolution: float | None = None) -> RayCounts:
    r"""Sector counts from the resolution rule of ``docs/method.md`` section 5.2.

    .. math::
        N_{int} = \lceil 2.6\, s \kappa_0 R_{max}\rceil_4,\qquad
        N_H = 2\lceil s (\tau-1)\kappa_0 L_e / (2\pi)\rceil,\qquad
        N_M = \lceil s\,\tau\kappa_0 L_e/\pi\rceil,\qquad N_c = 1,

    with :math:`s` the ``resolution`` factor and :math:`\lceil\cdot\rceil_4` rounding up to a
    multiple of 4 (so the interior sectors respect the rectangle's symmetries). The interior
    constant was raised from 2 to 2.6: on the simply supported plate under a point force
    (0.5 x 0.4 m, 400 Hz) the error stalls near 1e-3 with :math:`2\kappa_0R_{max}` sectors and
    falls below 1e-6 with :math:`2.6\kappa_0R_{max}`, for 10 % more unknowns.

    Below the plate's first resonances the wavelength no longer sizes the field: a plate
    smaller than a wavelength deforms quasi-statically, and counts sized from :math:`\kappa_0`
    fall to their floors and stop growing with :math:`s` (a simply supported 0.5 x 0.4 m plate at
    1 Hz kept 28 unknowns at every resolution and a 10 % error). The counts are therefore sized
    from :math:`\max(\kappa_0, 5/R_{max})` (:data:`QUASI_STATIC_KAPPA_R`), i.e. from the plate
    when it spans less than about 1.6 wavelengths: 1.8e-1 -> 3.6e-3 at 1 Hz, and the counts grow
    with :math:`s` again, so the a-posteriori estimate (:mod:`solver.estimate`) sees the error.
    Mid-frequency plates (:math:`\kappa_0R_{max} > 5`) are unchanged.

    Parameters
    ----------
    kappa0 : float
        Real bending wavenumber :math:`\mathrm{Re}\,\kappa`, 1/m.
    size : (float, float)
        ``(Lx, Ly)`` in m.
    resolution : float
        Multiplier on every count (1.0 is the default rule).
    tau : float
        :math:`\tau_{max}`, the largest edge wavenumber in units of :math:`\kappa_0`.
    edge_resolution : float, optional
        The :math:`s` of :math:`N_H` and :math:`N_M` (default ``resolution``): lower where the
        reach grows with the resolution, so that the edge sectors widen instead of multiplying
        (:func:`solver.line_ends.reach_growth`).
    """
    edge_resolution = resolution if edge_resolution is None else edge_resolution
    lx, ly = size
    r_max = 0.5 * math.hypot(lx, ly)
    kappa0 = max(kappa0, QUASI_STATIC_KAPPA_R / r_max)
    interior = max(8, 4 * math.ceil(resolution * 2.6 * kappa0 * r_max / 4.0))
    lengths = (lx, ly, lx, ly)
    propagating = tuple(
        2 * max(1, math.ceil(edge_resolution * (tau - 1.0) * kappa0 * le / (2 * math.pi)))
        for le in lengths
    )
    evanescent = tuple(
        max(2, math.ceil(edge_resolution * tau * kappa0 * le / math.pi)) for le in lengths
    )
    return RayCounts(interior, propagating, evanescent, 1)


@dataclass(frozen=True)
class RayBasis:
    r"""Sector-averaged complex rays of one plate, stored node by node.

    Attributes
    ----------
    k : ndarray of complex, shape (n_nodes, 2)
        Wave vector of each quadrature node.
    origin : ndarray of float, shape (n_nodes, 2)
        Reference point of each node's exponential.
    weight : ndarray of float, shape (n_nodes,)
        Normalised sector-quadrature weight (sums to 1 over each sector).
    n_q : int
        Nodes per sector; the nodes of dof ``i`` are ``i*n_q:(i+1)*n_q``.
    family : tuple of str
        Family of each dof (``"interior"``, ``"edge_propagating:<edge>"``, ...).
    graded_edges : tuple of str
        Edges whose rules are graded towards both ends though the plate has no corner functions
        there: every edge of a member of a moving line whose loads are singular at an end fixed
        in its plane, :math:`t^{\lambda - 1}` (:func:`solver.problems.plate_basis`).
    """

    k: np.ndarray
    origin: np.ndarray
    weight: np.ndarray
    n_q: int
    family: tuple[str, ...]
    graded_edges: tuple[str, ...] = field(default=(), kw_only=True)

    @property
    def n_dof(self) -> int:
        return self.n_rays

    @property
    def wedges(self) -> tuple[WedgeFamily, ...]:
        """The corner functions after the rays (none here; see :class:`WedgeBasis`)."""
        return ()

    @property
    def n_rays(self) -> int:
        """The dofs that are sector means of rays, the first ones (all of them here; a
        :class:`solver.membrane_basis.MembraneBasis` may add corner functions after them)."""
        return len(self.family)

    def sector_means(self, nodal: np.ndarray, factors: np.ndarray) -> np.ndarray:
        r"""Shape-function values from node exponentials, for several derivative factors.

        :math:`T_c[p, i] = \sum_{q\in i} \omega_q f_{c,q}\, E[p, q]`, done as one batched
        matrix product over sectors.

        Parameters
        ----------
        nodal : ndarray of complex, shape (n_points, n_nodes)
            Node exponentials :math:`E`.
        factors : ndarray of complex, shape (n_factors, n_nodes)
            Derivative factor of each node (1 for the value itself).

        Returns
        -------
        ndarray of complex, shape (n_factors, n_points, n_rays)
        """
        n_points = nodal.shape[0]
        blocks = nodal.reshape(n_points, self.n_rays, self.n_q).transpose(1, 0, 2)
        weighted = (factors * self.weight).reshape(-1, self.n_rays, self.n_q).transpose(1, 2, 0)
        return np.matmul(blocks, weighted).transpose(2, 1, 0)


@dataclass(frozen=True)
class WedgeBasis(RayBasis):
    r"""A plate's rays followed by its corner functions (:mod:`solver.plate_corners`: at
    clamped-free corners, and the logarithmic families at a moving line's mixed ends), dofs
    ``n_rays`` on.

    Attributes
    ----------
    kappa : complex
        The plate's bending wavenumber, which the corner functions are built with.
    corner_wedges : tuple of :class:`solver.plate_corners.WedgeFamily`
    """

    kappa: complex
    corner_wedges: tuple[WedgeFamily, ...]

    @classmethod
    def extending(cls, rays: RayBasis, kappa: complex,
                  wedges: tuple[WedgeFamily, ...]) -> WedgeBasis:
        """``rays`` followed by the corner functions ``wedges``."""
        return cls(rays.k, rays.origin, rays.weight, rays.n_q, rays.family, kappa, wedges,
                   graded_edges=rays.graded_edges)

    @property
    def n_dof(self) -> int:
        return self.n_rays + sum(len(family) for family in self.corner_wedges)

    @property
    def wedges(self) -> tuple[WedgeFamily, ...]:
        return self.corner_wedges


CORNER_GRADING = (6, 0.15)
r"""Panels and ratio of an edge rule's geometric grading towards a corner with corner functions
(:func:`end_graded_rule`): the innermost panel is :math:`0.25\cdot0.15^5 = 1.9\times10^{-5}` of
the edge. In-plane (:func:`solver.membrane.membrane_edge_rule`), where the tractions grow as
:math:`r^{\lambda - 1}` (:math:`\lambda = 0.758`), :math:`\int_0^\epsilon r^{\lambda - 1}ds`
is 2.6e-4 of the whole there, itself integrated by that panel's Gauss rule; on
``cases/stiffened_panel.toml`` at 184.8 Hz the in-plane changes between resolutions are the
same to two digits with (12, 0.2), (8, 0.2) or (4, 0.15), and up to 40 % larger without
grading; at 1 kHz the far bay's weak in-plane field moves with the grading at the coarsest
step (its change from resolution 1.25 to 1.875: 9e-2 here, 5.5e-1 with (4, 0.15)). In bending
(:func:`solver.plate.boundary_traces`) the Kirchhoff shear of the corner functions grows as
:math:`r^{\mu - 3}`, :math:`\mathrm{Re}\,\mu - 3 = -0.93`; a plate clamped on one edge,
0.3 x 0.4 m, 2 mm, at 300 Hz: ``w`` the same to 7e-7 with 4, 6, 9 or 14 panels, 4.5e-5 off
without grading."""


def end_graded_rule(length: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    r"""Gauss points (arc lengths) and weights on an edge of ``length`` whose two end quarters are
    cut into geometric panels (:data:`CORNER_GRADING`), each with as many points per unit
    length as an ``n``-point rule on the whole edge and at least 8. Both ends are graded alike,
    so that the points stay symmetric (:func:`line_exponentials`)."""
    panels, ratio = CORNER_GRADING
    fractions = 0.25 * ratio ** np.arange(panels)
    cuts = np.concatenate([[0.0], fractions[::-1], 1.0 - fractions, [1.0]]) * length
    points, weights = [], []
    for a, b in zip(cuts[:-1], cuts[1:]):
        x, w = gauss_legendre(max(8, math.ceil(n * (b - a) / length) + 2))
        points.append(a + 0.5 * (b - a) * (x + 1.0))
        weights.append(0.5 * (b - a) * w)
    return np.concatenate(points), np.concatenate(weights)


def edge_rule(edges: Sequence[EdgeGeometry], n: int,
              corners: Iterable[ArrayLike] = ()) -> tuple[np.ndarray, np.ndarray]:
    """Gauss points (arc lengths) and weights of an ``n``-point rule on edges of one length (an
    edge, or two opposite ones that share their rule): uniform, or graded towards both ends
    (:func:`end_graded_rule`) where one of ``corners`` (points of the plate with corner
    functions, whose tractions are singular there) ends one of the edges."""
    length = edges[0].length
    if any(np.allclose(corner, end) for corner in corners for edge in edges
           for end in (edge.start, edge.start + edge.length * edge.tangent)):
        return end_graded_rule(length, n)
    x, w = gauss_legendre(n)
    return 0.5 * length * (x + 1.0), 0.5 * length * w


def _sector_nodes(lower: float, upper: float, n_sectors: int,
                  n_q: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and normalised weights on ``n_sectors`` equal sectors."""
    return _sector_nodes_mapped(np.linspace(lower, upper, n_sectors + 1), n_q)


def _sector_nodes_mapped(edges: np.ndarray, n_q: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and normalised weights on the sectors ``[edges[i], edges[i+1]]``."""
    x, w = gauss_legendre(n_q)
    half = 0.5 * (edges[1:] - edges[:-1])
    mid = 0.5 * (edges[1:] + edges[:-1])
    nodes = (mid[:, None] + half[:, None] * x[None, :]).ravel()
    weights = np.broadcast_to(0.5 * w, (len(half), n_q)).ravel()
    return nodes, weights


def _circle_nodes(n_sectors: int, n_q: int) -> tuple[np.ndarray, np.ndarray]:
    r"""Directions :math:`(\cos\theta, \sin\theta)` and weights of the interior-ray nodes.

    The directions are made exactly (in floating point) symmetric under :math:`\theta\to-\theta`
    (node ``i`` to node ``N-1-i``) and, for an even number of sectors, under
    :math:`\theta\to\theta+\pi` (node ``i`` to node ``i+N/2``): nodes related by the
    rectangle's symmetries then have wave-vector components equal up to sign, and share their
    edge exponentials (:func:`line_exponentials`). ``(a - b) = -(b - a)`` exactly, so each
    half-sum below is exactly even or odd and the second keeps the parity of the first.
    """
    theta, w = _sector_nodes(0.0, 2 * np.pi, n_sectors, n_q)
    c, s = np.cos(theta), np.sin(theta)
    c, s = 0.5 * (c + c[::-1]), 0.5 * (s - s[::-1])
    if n_sectors % 2 == 0:
        half = len(theta) // 2
        c, s = 0.5 * (c - np.roll(c, half)), 0.5 * (s - np.roll(s, half))
    return np.stack([c, s], axis=1), w


@functools.lru_cache(maxsize=256)
def gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre points and weights on [-1, 1] (``numpy``'s ``leggauss``), computed once
    per ``n`` and read-only: every plate edge, joint and sector of a build asks for them."""
    x, w = np.polynomial.legendre.leggauss(n)
    x.flags.writeable = w.flags.writeable = False
    return x, w


def _root_positive_real(z: np.ndarray) -> np.ndarray:
    r"""Square root with :math:`\mathrm{Re} \ge 0` (the decaying branch)."""
    s = np.sqrt(z + 0j)
    return np.where(s.real < 0, -s, s)


def _propagating_locus(kappa: complex, n_sectors: int, n_q: int,
                       tau: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Propagating edge rays, :math:`\mathbf k = \mp j\kappa\cosh\psi\,\mathbf t
    + \kappa\sinh\psi\,\mathbf n`: ``(along, across, weights)``, half the sectors per sign."""
    n_half = n_sectors // 2
    psi, w = _sector_nodes_mapped(np.arccosh(np.linspace(1.0, tau, n_half + 1)), n_q)
    sign = np.repeat([-1.0, 1.0], len(psi))
    psi, w = np.concatenate([psi, psi]), np.concatenate([w, w])
    return -1j * sign * kappa * np.cosh(psi), kappa * np.sinh(psi), w


def _evanescent_locus(kappa: complex, n_sectors: int, n_q: int,
                      tau: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Evanescent edge rays, :math:`\mathbf k = -j\beta\,\mathbf t
    + \sqrt{\beta^2+\kappa^2}\,\mathbf n`: ``(along, across, weights)``."""
    kappa0 = kappa.real
    beta, w = _sector_nodes(-tau * kappa0, tau * kappa0, n_sectors, n_q)
    beta = 0.5 * (beta - beta[::-1])  # exactly odd: +-beta share edge exponentials
    return -1j * beta, _root_positive_real(beta**2 + kappa**2), w


def _corner_locus(kappa: complex, n_sectors: int, n_q: int,
                  tau: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    r"""Corner rays, :math:`\mathbf k = -\kappa(\cos\varphi\,\mathbf t - \sin\varphi\,\mathbf n)`,
    :math:`\varphi\in[0, \pi/2]` from the edge leaving the corner into the plate
    (:math:`-\mathbf n` points inwards): ``(along, across, weights)``; ``tau`` is unused."""
    phi, w = _sector_nodes(0.0, 0.5 * np.pi, n_sectors, n_q)
    return -kappa * np.cos(phi), kappa * np.sin(phi), w


def build_ray_basis(size: tuple[float, float], kappa: complex, counts: RayCounts, n_q: int = 8,
                    tau: float = 2.5) -> RayBasis:
    """Shape functions of one plate for the given sector counts.

    Parameters
    ----------
    size : (float, float)
        ``(Lx, Ly)``, m.
    kappa : complex
        Complex bending wavenumber.
    counts : RayCounts
    n_q : int
        Gauss nodes per sector.
    tau : float
        Largest edge-ray wavenumber in units of :math:`\\mathrm{Re}\\,\\kappa`.

    Returns
    -------
    RayBasis
    """
    ks, origins, weights, family = [], [], [], []

    def add(k: np.ndarray, origin: np.ndarray, weight: np.ndarray, n_sectors: int,
            name: str) -> None:
        ks.append(k)
        origins.append(np.broadcast_to(origin, k.shape).copy())
        weights.append(weight)
        family.extend([name] * n_sectors)

    centre = 0.5 * np.asarray(size, dtype=float)
    directions, w = _circle_nodes(counts.interior, n_q)
    add(-1j * kappa * directions, centre, w, counts.interior, "interior")

    # edge and corner wave vectors are (along) t + (across) n; opposite edges have the same
    # counts, so each locus is sampled once per count
    loci = {}

    def locus(kind: Callable[[complex, int, int, float], tuple[np.ndarray, np.ndarray, np.ndarray]],
              n_sectors: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if (kind, n_sectors) not in loci:
            loci[kind, n_sectors] = kind(kappa, n_sectors, n_q, tau)
        return loci[kind, n_sectors]

    edges = plate_edges(size)
    for i, edge in enumerate(edges):
        for kind, name, n_sectors in (
                (_propagating_locus, "edge_propagating", 2 * (counts.edge_propagating[i] // 2)),
                (_evanescent_locus, "edge_evanescent", counts.edge_evanescent[i])):
            if n_sectors:
                along, across, w = locus(kind, n_sectors)
                k = along[:, None] * edge.tangent + across[:, None] * edge.normal
                add(k, edge.start, w, n_sectors, f"{name}:{edge.name}")
    if counts.corner:
        for i, edge in enumerate(edges):
            # corner i is the start of edge i; its inward quadrant starts at the edge direction
            along, across, w = locus(_corner_locus, counts.corner)
            k = along[:, None] * edge.tangent + across[:, None] * edge.normal
            add(k, edge.start, w, counts.corner, f"corner:{i}")

    return RayBasis(
        k=np.concatenate(ks),
        origin=np.concatenate(origins),
        weight=np.concatenate(weights),
        n_q=n_q,
        family=tuple(family),
    )


_DERIVATIVE_ORDERS = {
    "w": (0, 0), "w_x": (1, 0), "w_y": (0, 1),
    "w_xx": (2, 0), "w_xy": (1, 1), "w_yy": (0, 2),
}


FIELD_CHUNK_ENTRIES = 2_000_000
"""Node exponentials formed at once by :func:`ray_field` (32 MB of complex values)."""


def ray_field(basis: RayBasis, points: ArrayLike,
              quantities: Sequence[str] = ("w",)) -> dict[str, np.ndarray]:
    r"""Values of the shape functions and their derivatives at points.

    :math:`\partial_x^a\partial_y^b \Phi_i(\mathbf x) = \sum_{q} \omega_q\, k_{x,q}^a k_{y,q}^b
    e^{\mathbf k_q\cdot(\mathbf x - \mathbf x_{r,q})}` over the nodes of sector :math:`i`.

    Parameters
    ----------
    basis : RayBasis
    points : ndarray of float, shape (n, 2)
    quantities : sequence of str
        Any of ``"w", "w_x", "w_y", "w_xx", "w_xy", "w_yy"``.

    Returns
    -------
    dict of str to ndarray of complex, shape (n, n_dof)

    Notes
    -----
    The node exponentials are n_q times larger than the result; they are formed for at most
    :data:`FIELD_CHUNK_ENTRIES` entries at a time, so that a field on 1e5 measurement points
    (two plates) peaks at the size of its result instead of 1.6 GB.
    """
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    orders = [_DERIVATIVE_ORDERS[name] for name in quantities]
    factors = np.array([basis.k[:, 0] ** a * basis.k[:, 1] ** b for a, b in orders])
    step = max(1, FIELD_CHUNK_ENTRIES // max(1, len(basis.k)))
    out = {name: np.empty((len(points), basis.n_dof), dtype=complex) for name in quantities}
    for start in range(0, len(points), step):
        chunk = slice(start, start + step)
        means = basis.sector_means(node_exponentials(basis, points[chunk]), factors)
        for name, values in zip(quantities, means):
            out[name][chunk, :basis.n_rays] = values
    if basis.wedges:
        for name, values in wedge_field(basis.wedges, basis.kappa, points, quantities).items():
            out[name][:, basis.n_rays:] = values
    return out


def tensor_grid_field(basis: RayBasis, amplitudes: ArrayLike, xs: ArrayLike,
                      ys: ArrayLike) -> np.ndarray:
    r"""The shape functions' part of :math:`w` on the tensor grid ``xs`` x ``ys``, shape (len(xs), len(ys));
    for amplitudes of shape (n_dof, m), m fields of one basis, shape (m, len(xs), len(ys)).

    Every node exponential separates, :math:`e^{k_x(x - x_r) + k_y(y - y_r)} =
    e^{k_x(x - x_r)}e^{k_y(y - y_r)}`, so the field is one matrix product
    :math:`W = E_x^T\,\mathrm{diag}(\omega_q U_{i(q)})\,E_y` with :math:`E_x` (n_nodes, n_x) and
    :math:`E_y` (n_nodes, n_y): :math:`n_q(n_x + n_y)` exponentials instead of
    :math:`n_qn_xn_y`, and those are the cost, so the fields of the plates that share a basis
    are evaluated together. Each factor is bounded on the plate, as the full exponential is
    (edge and corner rays decay away from their own edge or corner in each coordinate).
    """
    amplitudes = np.asarray(amplitudes)
    columns = amplitudes.reshape(len(amplitudes), -1)
    node_amplitudes = basis.weight[:, None] * np.repeat(columns[:basis.n_rays], basis.n_q, axis=0)
    ex = np.exp(basis.k[:, 0, None] * (np.asarray(xs)[None, :] - basis.origin[:, 0, None]))
    ey = np.exp(basis.k[:, 1, None] * (np.asarray(ys)[None, :] - basis.origin[:, 1, None]))
    fields = np.stack([ex.T @ (a[:, None] * ey) for a in node_amplitudes.T])
    if basis.wedges:  # the corner functions point by point: they do not separate
        x, y = np.meshgrid(xs, ys, indexing="ij")
        values = wedge_field(basis.wedges, basis.kappa, np.column_stack([x.ravel(), y.ravel()]))
        fields += np.moveaxis((values["w"] @ columns[basis.n_rays:]).reshape(
            x.shape + (-1,)), -1, 0)
    return fields[0] if amplitudes.ndim == 1 else fields


def node_exponentials(basis: RayBasis, points: ArrayLike) -> np.ndarray:
    r"""Node exponentials :math:`e^{\mathbf k_q\cdot(\mathbf x_p - \mathbf x_{r,q})}`, shape (n_points, n_nodes)."""
    points = np.asarray(points, dtype=float)
    exponent = (points[:, None, 0] - basis.origin[None, :, 0]) * basis.k[None, :, 0]
    exponent += (points[:, None, 1] - basis.origin[None, :, 1]) * basis.k[None, :, 1]
    return np.exp(exponent)


def line_exponentials(basis: RayBasis, axis: int, u: np.ndarray,
                      offsets: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    r"""Node exponentials on segments parallel to a coordinate axis, through shared factors.

    On the segment :math:`x_{axis} = u \in [0, U]`, :math:`x_{other} = c` each node's
    exponential factors as

    .. math::
        e^{\mathbf k_q\cdot(\mathbf x - \mathbf x_{r,q})} = C_q(c)\,G_q(u), \qquad
        G_q(u) = e^{a_q (u - u_q)},\quad a_q = k_{q,axis},

    with :math:`u_q` the end (0 or :math:`U`) where :math:`\mathrm{Re}(a_q u)` is largest,
    so :math:`|G_q| \le 1`, and :math:`C_q(c)` the node's value at that end, bounded as
    every ray is on the plate. Neither factor can overflow, and :math:`C_q` underflows only
    where the whole segment does. :math:`G_q` depends on :math:`a_q` alone, up to the mirror
    :math:`u \to U - u` when :math:`a_q` changes sign; the rectangle's symmetries make many
    nodes share :math:`\pm a_q` exactly (both segments of a pair of opposite edges, both
    signs of the propagating edge rays, :math:`\pm\beta`, the interior rays at
    :math:`\pm\theta` and :math:`\theta+\pi`). The points are symmetric too, so half of
    the :math:`G` values are a division, :math:`e^{a(U - u)} = e^{aU}/e^{au}`, where both
    exponentials are normal numbers (:math:`\mathrm{Re}(a)U \ge -700`). The exponentials
    then cost ``len(u)/2`` per distinct :math:`\pm a_q` (about a quarter of the nodes) plus
    one per (node, segment), instead of ``len(u)`` per (node, segment).

    Parameters
    ----------
    basis : RayBasis
    axis : int
        0 for segments along :math:`x`, 1 along :math:`y`.
    u : ndarray of float, shape (n_u,)
        Ascending, from 0 to :math:`U`, symmetric: ``u[::-1]`` is ``U - u`` (to round-off).
    offsets : sequence of float
        The other coordinate :math:`c` of each segment.

    Returns
    -------
    shared : ndarray of complex, shape (n_u, n_nodes)
        :math:`G_q(u_p)`.
    constants : ndarray of complex, shape (len(offsets), n_nodes)
        :math:`C_q(c)`; the exponentials on segment ``j`` are ``constants[j] * shared``.
    """
    other = 1 - axis
    a = basis.k[:, axis]
    # anchor at u = U where Re(a u) grows with u (tie Re a = 0 broken on Im a, so that a and
    # -a always anchor at opposite ends and meet in one canonical value, with Re <= 0)
    far = (a.real > 0) | ((a.real == 0) & (a.imag > 0))
    distinct, index = np.unique(np.where(far, -a, a), return_inverse=True)
    n_u, n_distinct = len(u), len(distinct)
    g = np.empty((n_u, 2 * n_distinct), dtype=complex)
    n_head = n_u - n_u // 2
    head, tail = g[:n_head, :n_distinct], g[n_head:, :n_distinct]
    np.multiply.outer(u[:n_head], distinct, out=head)
    np.exp(head, out=head)
    # the points past U/2 mirror those before: e^{a(U - u)} = e^{aU} / e^{au}, a division
    # instead of an exponential while e^{aU} (and so e^{au}, u <= U/2) is a normal number
    shallow = distinct.real * u[-1] >= -700.0
    tail[:, shallow] = np.exp(u[-1] * distinct[shallow]) / head[n_u // 2 - 1::-1, shallow]
    tail[:, ~shallow] = np.exp(np.multiply.outer(u[n_head:], distinct[~shallow]))
    # a node anchored at U reads g at U - u, i.e. in reverse order
    g[:, n_distinct:] = g[::-1, :n_distinct]
    shared = g.take(index.ravel() + far * n_distinct, axis=1)
    anchor = np.where(far, u[-1], 0.0)
    offsets = np.asarray(offsets, dtype=float)[:, None]
    exponent = ((anchor - basis.origin[:, axis]) * a
                + (offsets - basis.origin[:, other]) * basis.k[:, other])
    return shared, np.exp(exponent)


def edge_exponentials(basis: RayBasis, edge: EdgeGeometry, s: np.ndarray) -> np.ndarray:
    r"""Node exponentials :math:`e^{\mathbf k_q\cdot(\mathbf x - \mathbf x_{r,q})}` at the arc
    lengths ``s`` of one of the plate's edges, shape (len(s), n_nodes): those of
    :func:`node_exponentials`.

    Where the points lie symmetrically on the edge (its Gauss rules, a joint's), the
    exponentials factor through :func:`line_exponentials`: about a seventh of the
    exponentials of the direct evaluation on a 50-point rule (a quarter of the nodes share
    their wavenumber along the edge, and half of the points mirror the others). ``basis``
    is any basis of plane-wave nodes (a bending :class:`RayBasis` or a membrane one)."""
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
