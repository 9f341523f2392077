r"""VTCR of one rectangular Kirchhoff plate: boundary operators, assembly, solution.

Variational form (``docs/method.md`` section 4.1). Find :math:`w = w_p + w_T`, with
:math:`w_p` the point-force particular solution and :math:`w_T = \sum_l x_l\Phi_l` a
combination of complex rays, such that for every ray :math:`\delta w`:

.. math::
    \sum_{\alpha\in s}\int (g_\alpha(w) - g_{\alpha,d})\,q_\alpha(\delta w)^*ds
    - \sum_{\alpha\in k}\int g_\alpha(\delta w)^*(q_\alpha(w) - q_{\alpha,d})\,ds
    + \sum_{c\ \mathrm{static}} (R_c(w) - R_{c,d})\,\delta w_c^*
    - \sum_{c\ \mathrm{kin}} R_c(\delta w)^*(w_c - w_{c,d}) = 0,

with :math:`q = (w, \partial_n w)` and :math:`g = (K_n, -M_n)`. Each term has the form
:math:`\sigma\int A(\delta w)^*\,(B(w) - d)\,ds`; per edge component:

===========================  ======  ==================  ==================  ===========
component                    sigma   test A              trial B             datum d
===========================  ======  ==================  ==================  ===========
shear static (free)          +1      :math:`w`           :math:`K_n`         :math:`T_d`
deflection kinematic         -1      :math:`K_n`         :math:`w`           0
moment static (free, SS)     -1      :math:`\partial_n w` :math:`M_n`        :math:`M_d`
slope kinematic (clamped)    +1      :math:`M_n`         :math:`\partial_n w` 0
===========================  ======  ==================  ==================  ===========

so the matrix is :math:`K = \sum \sigma A^H \mathrm{diag}(\omega_q) B` and the right-hand
side :math:`F = \sum\sigma A^H\mathrm{diag}(\omega_q)(d - B(w_p))`. Corners: kinematic when
either adjacent edge has :math:`w` kinematic (then :math:`\sigma=-1`, :math:`A = R_c`,
:math:`B = w_c`), static otherwise (:math:`\sigma=+1`, :math:`A = w_c`, :math:`B = R_c`), with
:math:`R_c = M_{nt}^{(e^+)}(c) - M_{nt}^{(e^-)}(c)`.

Departure (``docs/method.md`` section 5.3): the edge integrals are not evaluated in closed form
node pair by node pair. A product of two node exponentials is an entire function of the arc
length whose bandwidth is bounded by :math:`2\max|\mathbf k|`, so a Gauss–Legendre rule of
:math:`Q \approx 0.75\max|\mathbf k|\,L + 10` points integrates it to round-off (checked against
the closed form :math:`\int_0^L e^{zs}ds = \mathrm{expm1}(zL)/z` in the tests), and it
treats data and particular-solution terms with the same points. Opposite edges get the same
rule (the larger of their two), so their points share the coordinate along the edges; there a
node's exponential is a constant per edge times a function of that coordinate alone, which
nodes whose wave vectors have equal components up to sign share
(:func:`solver.rays.line_exponentials`; the ray loci are sampled exactly symmetrically for
this). The exponentials then cost about :math:`Q\,n_{nodes}/4` per pair of edges, instead of
:math:`Q\,n_{nodes}` per edge point by point or :math:`n_{nodes}^2` per edge in closed form.
Every term, corners included, has the form :math:`\sigma A^H\mathrm{diag}(\omega)[B \mid d]`,
so :math:`K` and :math:`F` come out of one matrix product of the stacked terms. :math:`K_n(w_p)` is
integrated by parts along the edge (:math:`\int K_n\varphi^* = \int Q_n\varphi^*
- \int M_{nt}\partial_s\varphi^* + [M_{nt}\varphi^*]`) so no third derivative of the Green
function is needed.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from assembly.geometry import EDGE_NAMES, EdgeGeometry, edge_geometry, plate_edges
from solver.dense import solve_dense
from solver.kirchhoff import point_force_derivatives, wave_edge_factors
from solver.plate_corners import wedge_edge_traces
from solver.rays import (
    RayBasis,
    edge_exponentials,
    edge_rule,
    end_graded_rule,
    line_exponentials,
    ray_field,
)

__all__ = [
    "EdgeLoad",
    "EdgeCondition",
    "PointForce",
    "PlateProblem",
    "EdgeTraces",
    "PlateBoundary",
    "boundary_traces",
    "assemble_plate",
    "edge_projection",
    "edge_values",
    "shape_traces",
    "edge_rule_size",
    "particular_traces",
    "PlateSolution",
    "solve_plate",
]

KINEMATIC_DEFLECTION = frozenset({"clamped", "simply_supported"})


@dataclass(frozen=True)
class EdgeLoad:
    """A load distributed along an edge: ``amplitude`` (uniform) or ``amplitude*sin(pi s/L)``."""

    amplitude: complex
    distribution: str = "uniform"

    def values(self, s: np.ndarray, length: float) -> np.ndarray:
        """Load at arc lengths ``s`` of an edge of length ``length``."""
        if self.distribution == "half_sine":
            return self.amplitude * np.sin(np.pi * s / length)
        return np.full(s.shape, self.amplitude, dtype=complex)


@dataclass(frozen=True)
class EdgeCondition:
    r"""Condition on one edge: ``clamped``, ``simply_supported``, ``free`` or ``symmetric``
    (:math:`\partial_n w = 0`, :math:`K_n = 0`: a plane of symmetry).

    ``shear`` prescribes :math:`K_n` (free and symmetric edges), ``moment`` prescribes
    :math:`M_n` (free or simply supported edges).
    """

    kind: str = "free"
    shear: EdgeLoad | None = None
    moment: EdgeLoad | None = None


@dataclass(frozen=True)
class PointForce:
    """Transverse force ``amplitude`` (N) at plate-local ``position`` (m)."""

    position: tuple[float, float]
    amplitude: complex


@dataclass(frozen=True)
class PlateProblem:
    """One plate at one circular frequency: geometry, material, conditions and loads.

    Attributes
    ----------
    size : (float, float)
        ``(Lx, Ly)``, m.
    bending_stiffness : complex
        :math:`D^*`, N·m.
    poisson_ratio : float
    mass_per_area : float
        :math:`\\rho h`, kg/m².
    omega : float
        Circular frequency, rad/s.
    edges : dict of str to EdgeCondition
        One entry per edge name of :data:`assembly.geometry.EDGE_NAMES`; missing edges are free.
    point_forces : tuple of PointForce
    """

    size: tuple[float, float]
    bending_stiffness: complex
    poisson_ratio: float
    mass_per_area: float
    omega: float
    edges: dict = field(default_factory=dict)
    point_forces: tuple = ()

    @property
    def kappa(self) -> complex:
        """Complex bending wavenumber."""
        return (self.mass_per_area * self.omega**2 / complex(self.bending_stiffness)) ** 0.25

    def condition(self, edge: str) -> EdgeCondition:
        return self.edges.get(edge, EdgeCondition())


@dataclass(frozen=True)
class EdgeTraces:
    """Traces of the shape functions (and of the particular solution) at an edge's Gauss points.

    Every ray array has shape ``(Q, n_dof)``; the particular-solution arrays have shape ``(Q,)``
    (zero when the plate carries no point force). ``tangential`` is only computed where the
    point-force term needs it (free edges of a loaded plate), and is None elsewhere.
    """

    name: str
    s: np.ndarray
    weights: np.ndarray
    points: np.ndarray
    length: float
    w: np.ndarray
    slope: np.ndarray
    moment: np.ndarray
    shear: np.ndarray
    tangential: np.ndarray | None  # d/ds of the shape functions
    particular: dict


@dataclass(frozen=True)
class PlateBoundary:
    """All boundary traces of one plate: edges, and corner values and corner forces."""

    edges: dict
    corner_w: np.ndarray  # (4, n_dof): shape functions at corner i
    corner_force: np.ndarray  # (4, n_dof): R_c of the shape functions at corner i
    corner_w_p: np.ndarray  # (4,)
    corner_force_p: np.ndarray  # (4,)
    edge_end_w: np.ndarray  # (4, 2, n_dof): shape functions at the start/end of edge i


def edge_rule_size(length: float, k_max: float, sources: Iterable[tuple[float, float]],
                   edge: EdgeGeometry) -> int:
    """Number of Gauss–Legendre points for one edge, sized to the wavelength and to sources.

    Bandwidth: products of traces oscillate or decay at rates up to :math:`2\\max|k|`; a
    Gauss rule of :math:`Q = 0.75\\max|k|\\,L + 10` points integrates them to round-off
    (1e-14 against the closed form in the tests; 0.6 max|k| L + 8 already loses 3 digits). Sources: the
    Green function is analytic in a Bernstein ellipse reaching the source at distance
    :math:`d`, so :math:`Q \\approx 12\\sqrt{L/d}` gives 1e-12.
    """
    q = math.ceil(0.75 * k_max * length) + 10
    for source in sources:
        rel = np.asarray(source) - edge.start
        d_along = float(np.clip(rel @ edge.tangent, 0.0, length))
        dist = float(np.linalg.norm(rel - d_along * edge.tangent))
        q = max(q, math.ceil(12.0 * math.sqrt(length / max(dist, 1e-12 * length))))
    return min(q, 4000)


def particular_traces(problem: PlateProblem, points: np.ndarray, normal: ArrayLike,
                      tangent: ArrayLike) -> dict[str, np.ndarray]:
    """Edge quantities of the point-force particular solution at ``points``.

    ``normal`` and ``tangent`` are one unit vector each, shape (2,), or one per point.
    """
    n = len(points)
    normal, tangent = np.broadcast_to(normal, points.shape), np.broadcast_to(tangent, points.shape)
    out = {key: np.zeros(n, dtype=complex)
           for key in ("w", "slope", "tangential", "moment", "twist", "shear_q")}
    for force in problem.point_forces:
        f = point_force_derivatives(points, force.position, problem.kappa,
                                    problem.bending_stiffness, force.amplitude)
        hess = f["hess"]
        w_nn = np.einsum("ni,nij,nj->n", normal, hess, normal)
        w_tt = np.einsum("ni,nij,nj->n", tangent, hess, tangent)
        w_nt = np.einsum("ni,nij,nj->n", normal, hess, tangent)
        d, nu = problem.bending_stiffness, problem.poisson_ratio
        out["w"] += f["w"]
        out["slope"] += np.einsum("ni,ni->n", f["grad"], normal)
        out["tangential"] += np.einsum("ni,ni->n", f["grad"], tangent)
        out["moment"] += -d * (w_nn + nu * w_tt)
        out["twist"] += -d * (1.0 - nu) * w_nt
        out["shear_q"] += np.einsum("ni,ni->n", f["shear_force"], normal)
    return out


_TRACE_KEYS = ("w", "slope", "moment", "shear")


def _trace_factors(problem: PlateProblem, basis: RayBasis, edge: EdgeGeometry,
                   keys: Iterable[str]) -> np.ndarray:
    r"""Factor of each node for each trace in ``keys``, shape (len(keys), n_nodes): those of
    :func:`solver.kirchhoff.wave_edge_factors`, ``w`` and ``shear_q`` (:math:`Q_n = K_n -
    \partial_sM_{nt}`)."""
    factors = wave_edge_factors(basis.k, edge.normal, edge.tangent, problem.bending_stiffness,
                                problem.poisson_ratio) | {"w": np.ones(len(basis.k))}
    factors["shear_q"] = factors["shear"] - factors["tangential"] * factors["twist"]
    return np.array([factors[key] for key in keys])


def _pair_traces(
    problem: PlateProblem, basis: RayBasis, edges: Sequence[EdgeGeometry], q: int,
    keys: Sequence[tuple[str, ...]],
) -> tuple[np.ndarray, np.ndarray, list[dict[str, np.ndarray]]]:
    r"""Traces of the shape functions on two opposite edges at ``[0, s_1..s_q, L]`` along each
    edge.

    Both edges get the same Gauss rule, so that their points share the coordinate along
    the edges and the node exponentials factor through :func:`solver.rays.line_exponentials`.
    Where a corner function's corner ends one of them, the rule is graded towards both ends
    (:func:`solver.rays.end_graded_rule`): their Kirchhoff shear goes like
    :math:`r^{\mu - 3}`, nearly :math:`1/r`.

    Returns
    -------
    s, weights : ndarray of float, shape (q,)
        The common Gauss rule in arc length.
    traces : list of dict of str to ndarray of complex
        Per edge, the traces named in its entry of ``keys`` at the edge's start, Gauss points
        and end, shape ``(q + 2, n_dof)``, and ``"twist"`` (:math:`M_{nt}`, needed at the
        corners only) at its start and end, shape ``(2, n_dof)``.
    """
    axis = int(np.argmax(np.abs(edges[0].tangent)))
    length = edges[0].length
    if any(edge.name in basis.graded_edges for edge in edges):
        s, weights = end_graded_rule(length, q)
    else:
        s, weights = edge_rule(edges, q, [family.point for family in basis.wedges])
    u = np.concatenate([[0.0], s, [length]])  # symmetric: u[::-1] = length - u
    shared, constants = line_exponentials(basis, axis, u, [e.start[1 - axis] for e in edges])
    # each edge's node constants fold into its trace factors: one sector-mean product serves
    # both edges; the corner twist is only needed at the two ends
    factors = [_trace_factors(problem, basis, e, edge_keys + ("twist",)) * c
               for e, edge_keys, c in zip(edges, keys, constants)]
    values = basis.sector_means(shared, np.concatenate([f[:-1] for f in factors]))
    twists = basis.sector_means(shared[[0, -1]], np.array([f[-1] for f in factors]))
    if basis.wedges:  # both edges at once, at arc lengths u along each (u is symmetric)
        wedges = wedge_edge_traces(
            basis.wedges, basis.kappa, problem.bending_stiffness, problem.poisson_ratio,
            np.concatenate([e.start + u[:, None] * e.tangent for e in edges]),
            np.repeat([e.normal for e in edges], len(u), axis=0),
            np.repeat([e.tangent for e in edges], len(u), axis=0),
            tuple(set().union(*keys)) + ("twist",))
    traces, start = [], 0
    for i, (edge, edge_keys) in enumerate(zip(edges, keys)):
        step = int(np.sign(edge.tangent[axis]))  # an edge against the axis runs backwards
        block = values[start:start + len(edge_keys), ::step]
        start += len(edge_keys)
        edge_traces = dict(zip(edge_keys, block)) | {"twist": twists[i, ::step]}
        if basis.wedges:
            rows = slice(i * len(u), (i + 1) * len(u))
            edge_traces = {key: np.hstack([value, wedges[key][rows][[0, -1]] if key == "twist"
                                           else wedges[key][rows]])
                           for key, value in edge_traces.items()}
        traces.append(edge_traces)
    return s, weights, traces


def shape_traces(problem: PlateProblem, basis: RayBasis, edge: EdgeGeometry, s: np.ndarray,
                 keys: Sequence[str]) -> dict[str, np.ndarray]:
    """The traces ``keys`` (those of :func:`_trace_factors`) of every shape function, rays and
    corner functions (:func:`solver.plate_corners.wedge_edge_traces`), at arc lengths ``s`` of
    ``edge``: each (len(s), n_dof)."""
    values = basis.sector_means(edge_exponentials(basis, edge, s),
                                _trace_factors(problem, basis, edge, keys))
    traces = dict(zip(keys, values))
    if basis.wedges:
        wedges = wedge_edge_traces(basis.wedges, basis.kappa, problem.bending_stiffness,
                                   problem.poisson_ratio, edge.start + s[:, None] * edge.tangent,
                                   edge.normal, edge.tangent, keys)
        traces = {key: np.hstack([value, wedges[key]]) for key, value in traces.items()}
    return traces


def boundary_traces(problem: PlateProblem, basis: RayBasis) -> PlateBoundary:
    """Traces of every shape function on the four edges and at the four corners.

    Opposite edges share one Gauss rule (the larger of their two) and their node
    exponentials (:func:`solver.rays.line_exponentials`); all edge quantities of a node are
    scalar multiples of its exponential (:func:`solver.kirchhoff.wave_edge_factors`). The
    particular solution is evaluated at all four edges' points at once.
    """
    k_max = float(np.max(np.abs(basis.k)))
    sources = [f.position for f in problem.point_forces]
    geometry = plate_edges(problem.size)
    rules, rays = [None] * 4, [None] * 4
    # the tangential derivative only serves the by-parts term of a point force on a free edge
    keys = [_TRACE_KEYS + ("tangential",)
            if sources and _static_shear(problem.condition(e.name)) else _TRACE_KEYS
            for e in geometry]
    for pair in ((0, 2), (1, 3)):
        pair_edges = [geometry[i] for i in pair]
        q = max(edge_rule_size(e.length, k_max, sources, e) for e in pair_edges)
        s, wq, pair_traces = _pair_traces(problem, basis, pair_edges, q, [keys[i] for i in pair])
        for i, traces in zip(pair, pair_traces):
            rules[i], rays[i] = (s, wq), traces
    # every edge's points: its start, its Gauss points, its end
    arcs = [np.concatenate([[0.0], s, [edge.length]]) for (s, _), edge in zip(rules, geometry)]
    sizes = [len(arc) for arc in arcs]
    part = particular_traces(
        problem, np.concatenate([e.start + a[:, None] * e.tangent for e, a in zip(geometry, arcs)]),
        np.repeat([e.normal for e in geometry], sizes, axis=0),
        np.repeat([e.tangent for e in geometry], sizes, axis=0))
    parts = [{key: value[start:start + size] for key, value in part.items()}
             for start, size in zip(np.cumsum([0] + sizes[:-1]), sizes)]
    edges = {}
    for edge, (s, wq), traces, p in zip(geometry, rules, rays, parts):
        inner = slice(1, len(s) + 1)
        edges[edge.name] = EdgeTraces(
            name=edge.name, s=s, weights=wq, points=edge.start + s[:, None] * edge.tangent,
            length=edge.length, w=traces["w"][inner], slope=traces["slope"][inner],
            moment=traces["moment"][inner], shear=traces["shear"][inner],
            tangential=traces["tangential"][inner] if "tangential" in traces else None,
            particular={key: value[inner] for key, value in p.items()}
            | {"twist_ends": p["twist"][[0, -1]], "w_ends": p["w"][[0, -1]]},
        )
    # edge i starts at corner i (outgoing edge e+) and ends at corner i+1 (incoming e-)
    twist_out = np.array([traces["twist"][0] for traces in rays])
    twist_in = np.roll([traces["twist"][-1] for traces in rays], 1, axis=0)
    twist_p_out = np.array([p["twist"][0] for p in parts])
    twist_p_in = np.roll([p["twist"][-1] for p in parts], 1)
    return PlateBoundary(
        edges=edges,
        corner_w=np.array([traces["w"][0] for traces in rays]),
        corner_force=twist_out - twist_in,
        corner_w_p=np.array([p["w"][0] for p in parts]),
        corner_force_p=twist_p_out - twist_p_in,
        edge_end_w=np.array([traces["w"][[0, -1]] for traces in rays]),
    )


def edge_values(
    problem: PlateProblem, basis: RayBasis, edge_name: str, s: ArrayLike,
    cache: dict[tuple[int, complex, float, str, bytes], dict[str, np.ndarray]] | None = None,
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    r"""Deflection and outward slope of the shape functions at arc lengths ``s`` of an edge.

    ``cache`` (a dict, optional) keeps the rays' values by basis object, plate stiffness, edge
    and points: identical plates sharing one basis (:func:`solver.problems.
    plate_bases`) then compute their joint traces once. The particular solution,
    which differs with the loads, is computed every time.

    Returns
    -------
    rays : dict of str to ndarray of complex, shape (len(s), n_dof)
        ``"w"`` and ``"slope"`` (:math:`\partial_n w`) of every shape function.
    particular : dict of str to ndarray of complex, shape (len(s),)
        The same quantities of the particular solution.
    """
    edge = edge_geometry(problem.size, edge_name)
    s = np.asarray(s, dtype=float)
    points = edge.start + s[:, None] * edge.tangent
    key = (id(basis), problem.bending_stiffness, problem.poisson_ratio, edge_name, s.tobytes())
    rays = None if cache is None else cache.get(key)
    if rays is None:
        rays = shape_traces(problem, basis, edge, s, ("w", "slope"))
        if cache is not None:
            cache[key] = rays
    part = particular_traces(problem, points, edge.normal, edge.tangent)
    return rays, {"w": part["w"], "slope": part["slope"]}


def _edge_terms(condition: EdgeCondition) -> list[tuple[float, str, str, EdgeLoad | None]]:
    """``(sigma, test, trial, datum)`` for the two components of an edge condition."""
    if condition.kind == "clamped":
        return [(-1.0, "shear", "w", None), (+1.0, "moment", "slope", None)]
    if condition.kind == "simply_supported":
        return [(-1.0, "shear", "w", None), (-1.0, "slope", "moment", condition.moment)]
    if condition.kind == "free":
        return [(+1.0, "w", "shear", condition.shear), (-1.0, "slope", "moment", condition.moment)]
    if condition.kind == "symmetric":
        return [(+1.0, "w", "shear", condition.shear), (+1.0, "moment", "slope", None)]
    raise ValueError(f"unknown edge condition {condition.kind!r}")


def _static_shear(condition: EdgeCondition) -> bool:
    """Whether the edge prescribes its Kirchhoff shear (``free`` and ``symmetric``): its
    weak form then tests with :math:`w`, and a point force needs the by-parts term of
    :func:`_twist_remainder`."""
    return any(trial == "shear" for _, _, trial, _ in _edge_terms(condition))


def _twist_remainder(traces: EdgeTraces, end_w: np.ndarray) -> np.ndarray:
    r""":math:`\int K_n(w_p)\,w^*ds - \int Q_n(w_p)\,w^*ds` for every test function :math:`w`.

    By parts along the edge, :math:`\int K_n\varphi^* = \int Q_n\varphi^*
    - \int M_{nt}\partial_s\varphi^* + [M_{nt}\varphi^*]_0^L`, so that no third derivative
    of the Green function is needed.
    """
    p = traces.particular
    inner = (traces.weights * p["twist"]).conj() @ traces.tangential
    ends = p["twist_ends"][1].conj() * end_w[1] - p["twist_ends"][0].conj() * end_w[0]
    return (ends - inner).conj()


def _boundary_terms(
    problem: PlateProblem, boundary: PlateBoundary,
) -> Iterator[tuple[float, np.ndarray, np.ndarray, np.ndarray, np.ndarray]]:
    r"""Every term :math:`\sigma\sum_q \omega_q A_q^*(B_q(w) - d_q)` of the variational form.

    Yields ``(sigma, weights, A, B, d)`` with ``A``, ``B`` of shape ``(m, n_dof)`` (the test
    and trial traces at ``m`` points) and ``d`` of shape ``(m,)`` (the datum minus the trial
    quantity of the particular solution; for :math:`B = K_n` only its :math:`Q_n` part, see
    :func:`_twist_remainder`): the edges' Gauss points, then the corners.
    """
    kinematic_edge = []
    for name in EDGE_NAMES:
        traces = boundary.edges[name]
        condition = problem.condition(name)
        kinematic_edge.append(condition.kind in KINEMATIC_DEFLECTION)
        for sigma, test_key, trial_key, datum in _edge_terms(condition):
            d = -traces.particular["shear_q" if trial_key == "shear" else trial_key]
            if datum is not None:
                d = d + datum.values(traces.s, traces.length)
            yield (sigma, traces.weights, getattr(traces, test_key), getattr(traces, trial_key),
                   d)
    one = np.ones(1)
    for c in range(4):
        # corner c joins edge c-1 (incoming) and edge c (outgoing)
        w_c, force_c = boundary.corner_w[c][None], boundary.corner_force[c][None]
        if kinematic_edge[c] or kinematic_edge[c - 1]:
            yield -1.0, one, force_c, w_c, -boundary.corner_w_p[c:c + 1]
        else:
            yield +1.0, one, w_c, force_c, -boundary.corner_force_p[c:c + 1]


def assemble_plate(problem: PlateProblem,
                   boundary: PlateBoundary) -> tuple[np.ndarray, np.ndarray]:
    r"""VTCR matrix and right-hand side of one plate (see the module docstring).

    :math:`[K \mid F] = \sum\sigma A^H\mathrm{diag}(\omega)\,[B \mid d]` over the terms of
    :func:`_boundary_terms`, done as one matrix product: the (conjugated) test traces and the
    weighted trial traces with their data are stacked, term after term, into two arrays.

    Returns
    -------
    K : ndarray of complex, shape (n_dof, n_dof)
    F : ndarray of complex, shape (n_dof,)
    """
    n = boundary.corner_w.shape[1]
    terms = list(_boundary_terms(problem, boundary))
    rows = sum(len(weights) for _, weights, *_ in terms)
    tests = np.empty((rows, n), dtype=complex)
    trials = np.empty((rows, n + 1), dtype=complex)
    start = 0
    for sigma, weights, test, trial, d in terms:
        block = slice(start, start + len(weights))
        start = block.stop
        np.conjugate(test, out=tests[block])
        np.multiply(trial, (sigma * weights)[:, None], out=trials[block, :n])
        trials[block, n] = sigma * weights * d
    product = tests.T @ trials
    K, F = product[:, :n], product[:, n]
    for i, name in enumerate(EDGE_NAMES):
        for sigma, _, trial_key, _ in _edge_terms(problem.condition(name)):
            if trial_key == "shear" and problem.point_forces:
                F -= sigma * _twist_remainder(boundary.edges[name], boundary.edge_end_w[i])
    return K, F


def edge_projection(traces: EdgeTraces, component: str, values: np.ndarray) -> np.ndarray:
    r"""Columns of the load operator of an edge datum given at the edge's Gauss points.

    For a static datum :math:`d_m(s)` (one column per function ``m``), returns
    :math:`\sigma\int A(\Phi_k)^* d_m\,ds`: with ``component="shear"`` the datum is a
    prescribed :math:`K_n` (:math:`\sigma=+1`, :math:`A=w`), with ``"moment"`` a prescribed
    :math:`M_n` (:math:`\sigma=-1`, :math:`A=\partial_n w`).

    Parameters
    ----------
    values : ndarray, shape (Q, m)
    """
    if component == "shear":
        return traces.w.conj().T @ (traces.weights[:, None] * values)
    if component == "moment":
        return -(traces.slope.conj().T @ (traces.weights[:, None] * values))
    raise ValueError(f"unknown component {component!r}")


@dataclass(frozen=True)
class PlateSolution:
    """Field of one plate: ray amplitudes plus the particular solution."""

    problem: PlateProblem
    basis: RayBasis
    amplitudes: np.ndarray
    rcond: float

    @property
    def condition_estimate(self) -> float:
        """1-norm condition estimate of the system the plate's truncated solve solved
        (:func:`factorise_dense`)."""
        return 1.0 / self.rcond if self.rcond > 0 else math.inf

    def field(self, points: ArrayLike,
              quantities: Sequence[str] = ("w",)) -> dict[str, np.ndarray]:
        """Displacement and derivatives at plate-local points (see :func:`evaluate_field`)."""
        return evaluate_field(self.problem, self.basis, self.amplitudes, points, quantities)


def evaluate_field(problem: PlateProblem, basis: RayBasis, amplitudes: np.ndarray,
                   points: ArrayLike,
                   quantities: Sequence[str] = ("w",)) -> dict[str, np.ndarray]:
    """``w`` and its derivatives (``w_x, w_y, w_xx, w_xy, w_yy``) at points, vectorised.

    Parameters
    ----------
    amplitudes : ndarray of complex, shape (n_dof,) or (n_dof, m)

    Returns
    -------
    dict of str to ndarray of complex, shape (n,) or (n, m)
    """
    points = np.atleast_2d(np.asarray(points, dtype=float))
    rays = ray_field(basis, points, quantities)
    out = {name: rays[name] @ amplitudes for name in quantities}
    for name, value in particular_field(problem, points, quantities).items():
        out[name] = out[name] + (value if out[name].ndim == 1 else value[:, None])
    return out


def particular_field(problem: PlateProblem, points: ArrayLike,
                     quantities: Sequence[str] = ("w",)) -> dict[str, np.ndarray]:
    """The particular solution's part of :func:`evaluate_field` (the point forces' infinite
    plate fields), shape (n,) per quantity; zero without point forces."""
    points = np.atleast_2d(np.asarray(points, dtype=float))
    out = {name: np.zeros(len(points), dtype=complex) for name in quantities}
    for force in problem.point_forces:
        f = point_force_derivatives(points, force.position, problem.kappa,
                                    problem.bending_stiffness, force.amplitude)
        extra = {"w": f["w"], "w_x": f["grad"][:, 0], "w_y": f["grad"][:, 1],
                 "w_xx": f["hess"][:, 0, 0], "w_xy": f["hess"][:, 0, 1],
                 "w_yy": f["hess"][:, 1, 1]}
        for name in quantities:
            out[name] = out[name] + extra[name]
    return out


def solve_plate(problem: PlateProblem, basis: RayBasis) -> PlateSolution:
    """Assemble and solve the VTCR of one plate."""
    boundary = boundary_traces(problem, basis)
    K, F = assemble_plate(problem, boundary)
    x, rcond = solve_dense(K, F)
    return PlateSolution(problem, basis, x, rcond)
