r"""Finite-element reference for a trihedral corner of three plates (bending and membrane),
scikit-fem, written apart from the VTCR solver (it imports only the bench modules
``fem_folded``, ``fem_clamped``, ``fem_argyris``; the L-fold check reads
``tests/exact_prismatic.py`` directly, not ``tests/support.py``, which imports the solver).

The structure
-------------
Steel, ``E* = E (1 + j eta)`` (E = 210 GPa, nu = 0.3, rho = 7800 kg/m^3, eta = 0.01), h = 2 mm,
``D* = E* h^3 / (12 (1 - nu^2))``, ``A* = E* h / (1 - nu^2)``; time factor ``exp(+j omega t)``;
Kirchhoff bending and plane-stress membrane in each plate. Plate ``p`` occupies its local
``[0, Lx] x [0, Ly]``, placed by its frame ``(o, e_x, e_y, e_z = e_x x e_y)``: the local point
``(x, y)`` is ``o + x e_x + y e_y`` and the displacement the 3D vector ``u e_x + v e_y + w e_z``
(:data:`CORNER`):

* A: 0.4 x 0.3, ``o = (0, 0.3, 0)``, ``e_x = (1, 0, 0)``, ``e_y = (0, -1, 0)``,
  ``e_z = (0, 0, -1)``: ``(x, y) -> (x, 0.3 - y, 0)``, displacement ``(u, -v, -w)``;
* B: 0.4 x 0.25, ``o = 0``, ``e_x = (1, 0, 0)``, ``e_y = (0, 0, 1)``, ``e_z = (0, -1, 0)``:
  ``(x, y) -> (x, 0, y)``, displacement ``(u, -w, v)``;
* C: 0.3 x 0.25, ``o = (0, 0.3, 0)``, ``e_x = (0, -1, 0)``, ``e_y = (0, 0, 1)``,
  ``e_z = (-1, 0, 0)``: ``(x, y) -> (0, 0.3 - x, y)``, displacement ``(-w, -u, v)``.

Folds (rigid): AB = A's top (y = 0.3) with B's bottom (y = 0), along X; AC = A's left (x = 0)
with C's bottom (y = 0), along Y; BC = B's left (x = 0) with C's right (x = 0.3), along Z; all
meet at the origin. Every other edge (A right and bottom, B right and top, C left and top) is
simply supported (``w = 0``) and fixed in plane (``u = v = 0``). Loads: 1 N along A's ``e_z`` at
A's (0.17, 0.13) (the fields kept) and, for reciprocity, 1 N along C's ``e_z`` at C's
(0.11, 0.09). Weak form: ``fem_folded``'s, summed over the three plates, in the space of
fields meeting the supports and the fold ties below (their multipliers, the line forces and
couples, do no virtual work there).

The rigid folds (every sign)
----------------------------
*Translation*: the 3D displacements agree on the line. With the displacements above:

* AB (``(x, 0.3)`` of A = ``(x, 0)`` of B = ``(x, 0, 0)``): ``(u_A, -v_A, -w_A) = (u_B, -w_B,
  v_B)``, so ``u_A = u_B``, ``v_A = w_B``, ``v_B = -w_A``;
* AC (``(0, y)`` of A = ``(y, 0)`` of C = ``(0, 0.3 - y, 0)``): ``(u_A, -v_A, -w_A) = (-w_C,
  -u_C, v_C)``, so ``u_A = -w_C``, ``v_A = u_C``, ``v_C = -w_A``;
* BC (``(0, y)`` of B = ``(0.3, y)`` of C = ``(0, 0, y)``): ``(u_B, -w_B, v_B) = (-w_C, -u_C,
  v_C)``, so ``u_B = -w_C``, ``u_C = w_B``, ``v_B = v_C``.

*Rotation*: a Kirchhoff plate moves its point at ``z'`` along ``e_z`` by ``-z' (w_x e_x + w_y
e_y) + w e_z = theta x (z' e_z)`` with ``theta = w_y e_x - w_x e_y`` (``e_x x e_z = -e_y``,
``e_y x e_z = e_x``); the angle between two plates is kept iff their ``theta . t`` agree, ``t``
the line's direction:

* AB, ``t = (1, 0, 0)``: ``theta_A . t = w_A,y``, ``theta_B . t = w_B,y``: ``w_A,y(x, 0.3) =
  w_B,y(x, 0)``;
* AC, ``t = (0, -1, 0)`` (= A's ``e_y`` = C's ``e_x``, so ``s = y_A = x_C``): ``theta_A . t =
  -w_A,x``, ``theta_C . t = w_C,y``: ``-w_A,x(0, s) = w_C,y(s, 0)``;
* BC, ``t = (0, 0, 1)``: ``theta_B . t = -w_B,x``, ``theta_C . t = -w_C,x``: ``w_B,x(0, y) =
  w_C,x(0.3, y)``.

Checks: the rotation ``phi`` about X moves ``X`` by ``phi (0, -Z, Y)``: on A ``w_A = -phi
(0.3 - y)``, on B ``w_B = phi y``, both ``w_,y = phi``; about ``(0, -1, 0)``: ``phi (-Z, 0,
X)``, ``w_A = -phi x`` and ``w_C = phi y``, so ``-w_A,x = w_C,y = phi``; about Z: ``phi (-Y,
X, 0)``, ``w_B = -phi x``, ``w_C = phi (0.3 - x)``, both ``-w_,x = phi``.

The code derives the same signs from the frames, for any right-angled fold (:class:`FoldGeometry`,
P the fold's first plate, ``t`` = the tangent axis ``e_a`` of P's edge, ``b`` each edge's normal
axis): ``d_b,P = (e_b,P . e_z,Q) w_Q``, ``d_b,Q = (e_b,Q . e_z,P) w_P``, ``d_a,Q = sigma_Q
d_a,P`` (``sigma_Q = e_a,Q . t``), ``kappa_P w_P,b = kappa_Q w_Q,b`` with ``kappa = e_x . t``
(``b = y``) or ``-e_y . t`` (``b = x``); along the line ``d/ds = sigma e_a . grad``, so the
mixed derivatives are tied by ``kappa_P w_P,ab = kappa_Q sigma_Q w_Q,ab`` (here: ``w_A,xy =
w_B,xy``, ``-w_A,xy = w_C,xy``, ``w_B,xy = w_C,xy``). Run on ``fem_folded``'s L fold it gives
``fem_folded``'s hand-derived ties (below).

Discretisation and ties
-----------------------
``w``: Argyris (``fem_clamped.ArgyrisLocal`` via ``PlateFE``), ``(u, v)``: P5 Lagrange
(``fem_folded.ElementTriP5``), as ``fem_folded``, whose exact coupling is reused fold by fold
(master-slave, ``x_full = T x``): every P5 node of a plate on a fold has its normal in-plane
component equal to the other plate's Hermite quintic trace of ``w`` there (times the sign
above; the trace is the quintic Hermite interpolant of ``(w, w_s, w_ss)`` at the edge's
vertices, ``fem_folded.HERMITE``); the tangential components are tied node by node; Q's
normal-derivative dofs are slaved to P's: ``w_,b`` and ``w_,ab`` at the vertices and the
midpoint ``w_n`` with the ratio of the two elements' normals. The constraints then hold
identically along every fold.

The corner: at the origin the ties of the three folds act on the same vertex dofs and are
redundant. All ties located at the origin (15 rows: per fold the two normal and the
tangential displacements of the vertex nodes and the two rotation ties) involve only the 18
free vertex dofs there (per plate ``w, w_x, w_y, w_xy`` and the P5 ``u, v``); they are
gathered and these dofs replaced by an orthonormal basis of the null space of those rows (SVD,
:func:`reduction`). Its rank is 12, as it must be: the 9 displacement values are 3 copies of
the corner's 3D displacement (rank 6), the 3 rotation ties act on different first derivatives
(rank 3), and the twist ties ``w_A,xy = w_B,xy = w_C,xy = -w_A,xy`` force ``w_,xy = 0`` in all
three plates (rank 3; the exact solution meets this when it is ``C^2`` there: the in-plane
rotation field of a Kirchhoff plate is divergence-free, so the three derivatives of ``theta .
t`` along the folds, each shared by two plates, sum pairwise to zero). Elsewhere the ties are
master-slave; where a fold meets the simply supported, fixed edges its ties' slaves are fixed
and so are their masters (no free dof was forced to zero: printed as ``forced``). The full set
of ties, redundant ones included, is checked on every column of ``T`` (``max |C T|``).

Meshes
------
Per plate, ``fem_folded.graded_mesh`` of its rectangle: squares of ``0.05 / n``, elements
``min(0.05, 2 r) / n`` towards the origin and the six fold ends (floor 1e-6) and towards the
load on the plate (floor 1e-3; C is graded towards the reciprocity load too), then refined
beside the folds until the two plates of each fold have the same vertices on it
(:func:`structure_meshes`). The solve is ``fem_folded``'s (diagonal scaling, SuperLU,
``MMD_AT_PLUS_A``) but with the refinement residual computed in extended precision
(``clongdouble``), which removes the LU's round-off (below).

Self-checks
-----------
``OPENBLAS_NUM_THREADS=1 python bench/fem_corner.py --write`` (levels 4 6 8, 14 minutes on one
core, 11 GB; n = 8: 30300 triangles, 8.9e5 unknowns, 75 s set-up, 135 s per solve of both
loads) prints the tables and writes ``tests/data/fem_corner.npz`` (level 8: ``w_{A,B,C}_{300,
1000}`` (225,), ``uv_..`` (225, 2) on ``inner_grid(Lx, Ly)``, and ``change_{300,1000}``, the
6 -> 8 change of ``w`` per plate). ``python bench/fem_corner.py 2 3 4 6`` gives the coarser
table; ``python bench/fem_corner.py --lfold 3`` the L-fold check. Measured (relative L2 change
from the previous level on the 225 points of a plate, A / B / C):

* ``w``, 300 Hz: 2 -> 3 2.7e-6 / 1.3e-6 / 1.3e-6, 3 -> 4 1.9e-7 / 8.6e-8 / 4.7e-8, 4 -> 6
  2.9e-8 / 3.7e-8 / 1.5e-8, 6 -> 8 1.3e-8 / 3.1e-8 / 3.4e-9 (4 -> 8: 3.5e-8 / 1.6e-8 / 1.5e-8);
  1 kHz: 2.6e-5 / 2.7e-5 / 3.2e-5, 1.4e-6 / 1.5e-6 / 2.0e-6, 2.0e-7 / 2.2e-7 / 3.4e-7, 2.8e-8 /
  2.9e-8 / 6.1e-8;
* ``(u, v)``, 1 kHz: 4 -> 6 2.5e-6 / 1.4e-6 / 6.5e-6, 6 -> 8 1.4e-6 / 3.7e-7 / 2.0e-6; 300 Hz:
  4 -> 6 1.7e-5 / 4.5e-6 / 2.6e-6 and 6 -> 8 the same, because level 6 is the odd one out
  (4 -> 8: 1.7e-6 / 6.5e-7 / 4.5e-7): its difference is at the grid points nearest the origin
  (8 mm from it, 1.9e-4 of the plate's RMS there; the median point moves by 3e-6). Not
  understood; the in-plane field near the trihedral corner is the least resolved part;
* so the error of level 8 is about 3e-8 (300 Hz) to 6e-8 (1 kHz) in ``w``, and a few 1e-6 in
  ``(u, v)`` (up to ~1e-5 at the points nearest the origin at 300 Hz); slower than the L fold
  (whose ``w`` reached 2e-9 at n = 8);
* reciprocity (``w_C(0.11, 0.09)`` under the load on A against ``w_A(0.17, 0.13)`` under the
  load on C; exact for the symmetric discrete system, so this measures round-off): 3.5e-9 to
  1.9e-8 at 300 Hz, 3.1e-8 to 5.8e-8 at 1 kHz (the value is 1/30 of A's RMS ``w`` there): the
  rounding of ``T^T K T`` (not exactly symmetric in floating point) on a system of condition
  ~1e10. The LU's own round-off is gone: with the residual in double, refinement stalls and two
  orderings differ by up to 1.6e-8 in ``w`` and 4.6e-6 in ``(u, v)`` (level 4); with the
  extended-precision residual by 1e-11 and 2e-9;
* ties: ``max |C T|`` = 2.0e-15 at every level; sampled at 401 points of each fold, the 3D
  displacements of the two plates differ by at most 1.9e-12 of their largest value, the
  rotations about the line by 3.8e-12 (the Argyris evaluation's round-off); the junction
  cluster has 15 rows, 18 dofs, rank 12; no free dof forced to zero;
* rigid motions (3 translations, 3 rotations of the whole corner, interpolated in every plate):
  tie residual <= 3e-14, distance from the range of ``T`` (without supports) <= 1e-15,
  ``|K x| / ||K| |x||`` <= 3e-16 (unit-rigidity bending and membrane stiffness);
* the L fold of ``fem_folded`` (diaphragm ends) built by this module from its frames
  (:data:`L_FOLD`) on ``fem_folded``'s meshes of level 3: the same fields as
  ``fem_folded.FoldModel`` to its solve's round-off (3e-10; bit for bit, difference 0, with
  ``fem_folded``'s double-precision refinement, the same ``T``), error against the exact prismatic
  solution 7.2e-8 / 4.8e-8 (300 Hz), 3.3e-6 / 5.0e-6 (1 kHz) in ``w``, as ``fem_folded``'s
  docstring; rigid motions as above. (75 s.)

The floating corner
-------------------
:data:`FLOATING`: the same corner with every simply supported edge free in plane (``w = 0``
there, ``u``, ``v`` free: traction-free, the natural condition); each plate is held in its
plane only by the other plates' bending at the folds. ``OPENBLAS_NUM_THREADS=1 python
bench/fem_corner.py --write-floating`` (levels 4 6 8, 300 Hz, 9 minutes on one core, 11.5 GB;
``--floating 4 6`` prints the tables only, ``--1khz`` adds 1 kHz) writes
``tests/data/fem_corner_floating.npz`` (level 8: ``w_{A,B,C}_300``, ``uv_{A,B,C}_300``,
``change_300``, as above). Measured (A / B / C):

* ``w``: 4 -> 6 3.2e-7 / 5.3e-7 / 3.5e-7, 6 -> 8 2.4e-7 / 3.8e-7 / 2.5e-7 (4 -> 8: 9.0e-8 /
  2.0e-7 / 1.0e-7); ``(u, v)``: 4 -> 6 1.2e-5 / 9.8e-6 / 7.6e-6, 6 -> 8 6.9e-6 / 7.3e-6 /
  5.8e-6 (4 -> 8: 5.1e-6 / 2.5e-6 / 2.1e-6); the differences are smooth over each plate
  (median point 1/3 to 2/3 of the largest). They are round-off, not discretisation: a random
  relative change of 2.2e-16 of the entries of ``K`` moves the level-4 solution by 1.4e-7 /
  2.1e-7 / 1.4e-7 in ``w`` and 6.7e-6 / 4.3e-6 / 3.6e-6 in ``(u, v)`` (the fixed corner:
  <= 1e-8 and ~1e-6), the in-plane near-mechanism held only by bending making the system far
  worse conditioned. So the written fields are good to ~3e-7 in ``w`` and ~1e-5 in ``(u, v)``;
* the in-plane motion is ~100 times the fixed corner's (relative difference of ``(u, v)``
  from it 1.1e2 / 8.1e1 / 3.7e1), ``w`` differs by 3.4e-2 / 4.6e-2 / 2.9e-2;
* reciprocity 9.8e-9 / 8.5e-9 / 1.0e-8 (levels 4 / 6 / 8); the natural condition: the
  largest in-plane traction on the free edges, relative to the largest membrane force inside,
  1.5e-4 / 4.5e-5 / 1.3e-5;
* ties and supports: ``max |C T|`` = 2.0e-15, fold lines to 3e-13 (``U``) and 7e-11
  (``theta``), junction cluster 15 rows, 18 dofs, rank 12, no free dof forced to zero; at the
  far ends of the folds (two supported edges and a fold on the same vertex) the normal
  in-plane dofs of both plates are zero (equal to the other plate's ``w = 0``), the tangential
  one free and tied, ``w_,b`` of both zero (each plate's derivative along its own supported
  edge), ``w_,xy`` free and tied (printed per level); rigid motions as the fixed
  corner (ties <= 2e-14, range <= 1e-15, stiffness <= 2e-16).
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from scipy.sparse import block_diag, coo_matrix, csr_matrix, diags
from scipy.sparse.linalg import splu
from skfem import Basis, MeshTri

sys.path.insert(0, str(Path(__file__).resolve().parent))  # fem_clamped imports fem_argyris
from fem_clamped import PlateFE
from fem_folded import (
    A_STAR,
    D_STAR,
    HERMITE,
    RHO_H,
    ElementTriP5,
    graded_mesh,
    inner_grid,
    membrane_matrices,
    p5_probes,
    relative,
    richardson,
)

ROOT = Path(__file__).resolve().parents[1]
OUT = Path("/tmp/fem_corner")
TEST_DATA = ROOT / "tests" / "data" / "fem_corner.npz"
FLOATING_DATA = ROOT / "tests" / "data" / "fem_corner_floating.npz"
FREQUENCIES = (300.0, 1000.0)
FLOATING_FREQUENCIES = (300.0,)
LEVELS = (4, 6, 8)
TOL = 1e-12  # coordinates closer than this are the same point
H_CORNER, H_LOAD = 1e-6, 1e-3  # grading floors (fem_folded.MeshLevel.of)

# Argyris nodal rows (scikit-fem's ``nodal_dofs``: u, u_x, u_y, u_xx, u_xy, u_yy)
ROW = {"u": 0, "u_x": 1, "u_y": 2, "u_xx": 3, "u_xy": 4, "u_yy": 5}
ALONG = {0: ("u", "u_x", "u_xx"), 1: ("u", "u_y", "u_yy")}  # trace data along axis a
D_ACROSS = {0: "u_x", 1: "u_y"}  # the derivative across an edge whose normal axis is b
# edge name -> (axis of the fixed coordinate k, 0 (at 0) or 1 (at L_k)); tangent axis a = 1 - k
EDGES = {"left": (0, 0), "right": (0, 1), "bottom": (1, 0), "top": (1, 1)}


# ---------------------------------------------------------------------------------------------
# The structure
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PlateSpec:
    """A plate on its local ``[0, lx] x [0, ly]``, placed by ``origin``, ``ex``, ``ey``
    (``ez = ex x ey``); ``supports``: ``{edge: in-plane components fixed}`` for its simply
    supported edges (bending: ``w`` and its tangential derivatives at the vertices)."""

    lx: float
    ly: float
    origin: tuple
    ex: tuple
    ey: tuple
    supports: dict

    @property
    def axes(self) -> np.ndarray:
        """Rows ``e_x, e_y, e_z``."""
        ex, ey = np.array(self.ex, float), np.array(self.ey, float)
        return np.array([ex, ey, np.cross(ex, ey)])

    def size(self, axis: int) -> float:
        return (self.lx, self.ly)[axis]

    def point3d(self, x, y) -> np.ndarray:
        """Global points (n, 3) of local ``(x, y)``."""
        e = self.axes
        return np.array(self.origin, float) + np.outer(x, e[0]) + np.outer(y, e[1])


@dataclass(frozen=True)
class Structure:
    """Plates, folds ``(name, (plate P, edge), (plate Q, edge))`` (P's ``w`` and normal
    derivative are the masters of the fold's ties) and point loads ``{key: (plate, x, y)}``
    (1 N along the plate's ``e_z``); ``"main"`` is the one whose fields are kept;
    ``grading``: more points ``(plate, x, y, h_min)`` the mesh is graded towards as the fold
    ends, e.g. corners where a supported edge meets a free one; ``h_fold_end``: the grading
    floor at the fold ends."""

    plates: dict
    folds: tuple
    loads: dict
    grading: tuple = ()
    h_fold_end: float = H_CORNER


CORNER = Structure(
    plates={"A": PlateSpec(0.4, 0.3, (0, 0.3, 0), (1, 0, 0), (0, -1, 0),
                           {"right": "uv", "bottom": "uv"}),
            "B": PlateSpec(0.4, 0.25, (0, 0, 0), (1, 0, 0), (0, 0, 1),
                           {"right": "uv", "top": "uv"}),
            "C": PlateSpec(0.3, 0.25, (0, 0.3, 0), (0, -1, 0), (0, 0, 1),
                           {"left": "uv", "top": "uv"})},
    folds=(("AB", ("A", "top"), ("B", "bottom")),
           ("AC", ("A", "left"), ("C", "bottom")),
           ("BC", ("B", "left"), ("C", "right"))),
    loads={"main": ("A", 0.17, 0.13), "recip": ("C", 0.11, 0.09)})


def floating(structure: Structure) -> Structure:
    """``structure`` with every simply supported edge free in plane (``w = 0`` and its
    tangential derivatives only; ``u``, ``v`` free: traction-free, the natural condition)."""
    return replace(structure, plates={
        name: replace(spec, supports=dict.fromkeys(spec.supports, ""))
        for name, spec in structure.plates.items()})


FLOATING = floating(CORNER)

# fem_folded's L fold with diaphragm ends (u = 0 on y = 0, 0.5), load (0.15, 0.2) on A
L_FOLD = Structure(
    plates={"A": PlateSpec(0.4, 0.5, (0, 0, 0), (1, 0, 0), (0, 1, 0),
                           {"left": "uv", "bottom": "u", "top": "u"}),
            "B": PlateSpec(0.3, 0.5, (0.4, 0, 0), (0, 0, 1), (0, 1, 0),
                           {"right": "uv", "bottom": "u", "top": "u"})},
    folds=(("F", ("A", "right"), ("B", "left")),),
    loads={"main": ("A", 0.15, 0.2)})


def edge_line(spec: PlateSpec, edge: str):
    """``(k, c, a, o, e_a)``: the edge is ``x_k = c``, its tangent axis ``a`` and the 3D point
    and direction of its local coordinate ``x_a``: ``X = o + x_a e_a``."""
    k, end = EDGES[edge]
    c = end * spec.size(k)
    a = 1 - k
    local = [0.0, 0.0]
    local[k] = c
    return k, c, a, spec.point3d(*local)[0], spec.axes[a]


@dataclass
class FoldGeometry:
    """A fold's signs, all from the frames (module docstring): ``t = e_a`` of P's edge, the
    line coordinate ``s = x_a`` on P's edge and ``s = sigma_Q x_a + beta`` on Q's;
    ``d_b,P = s_P w_Q``, ``d_b,Q = s_Q w_P``, ``d_a,Q = sigma_Q d_a,P``; the rotation about
    ``t`` is ``kappa w_,b`` on each plate."""

    name: str
    P: str
    Q: str
    edge: dict
    t: np.ndarray
    length: float
    sigma: dict
    beta: float
    cross: dict   # cross[p]: e_b of p . e_z of the other plate
    kappa: dict

    @classmethod
    def of(cls, structure: Structure, name: str, first, second) -> FoldGeometry:
        (P, eP), (Q, eQ) = first, second
        specs = structure.plates
        kP, _, aP, oP, t = edge_line(specs[P], eP)
        kQ, _, aQ, oQ, tQ = edge_line(specs[Q], eQ)
        sigma_Q = float(tQ @ t)
        assert abs(abs(sigma_Q) - 1) < TOL, f"fold {name}: edges not parallel"
        beta = float((oQ - oP) @ t)
        assert np.linalg.norm(np.cross(oQ - oP, t)) < TOL, f"fold {name}: edges not on one line"
        length = specs[P].size(aP)
        ends_Q = sorted([beta, beta + sigma_Q * specs[Q].size(aQ)])
        assert abs(ends_Q[0]) < TOL and abs(ends_Q[1] - length) < TOL, \
            f"fold {name}: edges of different extent"
        eP_, eQ_ = specs[P].axes, specs[Q].axes
        cross = {P: float(eP_[kP] @ eQ_[2]), Q: float(eQ_[kQ] @ eP_[2])}
        for p, value in cross.items():
            assert abs(abs(value) - 1) < TOL, f"fold {name}: not a right angle ({p})"

        def kappa(axes, b):  # theta . t with theta = w_y e_x - w_x e_y: the factor of w_,b
            return float(-(axes[1] @ t) if b == 0 else axes[0] @ t)

        return cls(name, P, Q, {P: eP, Q: eQ}, t, length, {P: 1.0, Q: sigma_Q}, beta, cross,
                   {P: kappa(eP_, kP), Q: kappa(eQ_, kQ)})

    def local(self, plate: str, s: np.ndarray) -> np.ndarray:
        """The plate's tangent coordinate ``x_a`` of line coordinates ``s``."""
        return s if plate == self.P else self.sigma[plate] * (s - self.beta)

    def line_s(self, plate: str, a: np.ndarray) -> np.ndarray:
        """Line coordinates of the plate's tangent coordinates ``a``."""
        return a if plate == self.P else self.sigma[plate] * a + self.beta


def folds_of(structure: Structure) -> list[FoldGeometry]:
    return [FoldGeometry.of(structure, *f) for f in structure.folds]


def junction_points(structure: Structure) -> list[np.ndarray]:
    """3D points where two folds or more end: the corners whose ties are redundant."""
    ends = []
    for _, (P, edge), _ in structure.folds:
        _, _, a, o, e = edge_line(structure.plates[P], edge)
        length = structure.plates[P].size(a)
        ends += [o, o + length * e]
    points = []
    for p in ends:
        count = sum(np.linalg.norm(p - q) < TOL for q in ends)
        if count >= 2 and not any(np.linalg.norm(p - q) < TOL for q in points):
            points.append(p)
    return points


# ---------------------------------------------------------------------------------------------
# Meshes
# ---------------------------------------------------------------------------------------------
def grading_points(structure: Structure, plate: str, c: float) -> list[tuple]:
    """The fold ends on ``plate`` (in its local coordinates, floor ``structure.h_fold_end``),
    ``structure.grading``'s points on it and the loads on it (floor ``H_LOAD``), ``(x, y, c,
    h_min)``."""
    spec = structure.plates[plate]
    points = []
    for _, first, second in structure.folds:
        for p, edge in (first, second):
            if p == plate:
                k, end = EDGES[edge]
                for t in (0.0, 1.0):
                    local = [0.0, 0.0]
                    local[k] = end * spec.size(k)
                    local[1 - k] = t * spec.size(1 - k)
                    points.append((*local, c, structure.h_fold_end))
    points += [(x, y, c, H_LOAD) for p, x, y in structure.loads.values() if p == plate]
    points += [(x, y, c, h) for p, x, y, h in structure.grading if p == plate]
    return sorted(set(points))


def edge_facets(mesh: MeshTri, spec: PlateSpec, edge: str) -> np.ndarray:
    k, end = EDGES[edge]
    c = end * spec.size(k)
    return mesh.facets_satisfying(lambda x: np.abs(x[k] - c) < TOL, boundaries_only=True)


def edge_vertex_coords(mesh: MeshTri, spec: PlateSpec, edge: str) -> np.ndarray:
    """Sorted tangent coordinates of the vertices on ``edge``."""
    k, end = EDGES[edge]
    return np.sort(mesh.p[1 - k, np.abs(mesh.p[k] - end * spec.size(k)) < TOL])


def split_edge(mesh: MeshTri, spec: PlateSpec, edge: str, a_other: np.ndarray):
    """``mesh`` with the triangles beside each edge facet holding one of ``a_other``
    strictly inside refined (None if there is none)."""
    k, _ = EDGES[edge]
    facets = edge_facets(mesh, spec, edge)
    a = np.sort(mesh.p[1 - k, mesh.facets[:, facets]], axis=0)
    holds = np.array([np.any((a_other > a0 + TOL) & (a_other < a1 - TOL)) for a0, a1 in a.T])
    if not holds.any():
        return None
    return mesh.refined(np.unique(mesh.f2t[0, facets[holds]]))


def structure_meshes(structure: Structure, n: float, meshes: dict | None = None,
                     folds: list | None = None) -> dict[str, MeshTri]:
    """Per plate ``fem_folded.graded_mesh`` of its rectangle (squares ``0.05 / n``, size
    ``max(min(0.05, 2 r) / n``, floor``)`` near the grading points), then refined until the two
    plates of every fold have the same vertices on it (dyadic subdivisions of common cells:
    this ends), and the vertex coordinates of Q on a fold snapped to P's. ``folds``: the
    lines to match (:class:`FoldGeometry`-like, ``folds_of(structure)`` by default)."""
    folds = folds_of(structure) if folds is None else folds
    if meshes is None:
        meshes = {}
        for name, spec in structure.plates.items():
            nx, ny = round(spec.lx / 0.05 * n), round(spec.ly / 0.05 * n)
            assert abs(nx - spec.lx / 0.05 * n) < 1e-9 and abs(ny - spec.ly / 0.05 * n) < 1e-9
            meshes[name] = graded_mesh(nx, ny, spec.lx, spec.ly,
                                       grading_points(structure, name, n / 2))
    meshes = dict(meshes)
    changed = True
    while changed:
        changed = False
        for f in folds:
            s = {p: f.line_s(p, edge_vertex_coords(meshes[p], structure.plates[p], f.edge[p]))
                 for p in (f.P, f.Q)}
            for p, other in ((f.P, f.Q), (f.Q, f.P)):
                refined = split_edge(meshes[p], structure.plates[p], f.edge[p],
                                     f.local(p, s[other]))
                if refined is not None:
                    meshes[p], changed = refined, True
    for f in folds:  # snap Q's line vertices to P's values
        sP = edge_vertex_coords(meshes[f.P], structure.plates[f.P], f.edge[f.P])
        spec = structure.plates[f.Q]
        k, end = EDGES[f.edge[f.Q]]
        p = meshes[f.Q].p.copy()
        on = np.nonzero(np.abs(p[k] - end * spec.size(k)) < TOL)[0]
        s_on = f.line_s(f.Q, p[1 - k, on])
        i = np.searchsorted(sP, s_on - 1e-10)
        assert np.abs(sP[i] - s_on).max() < 1e-10, f"line {f.name}: vertices differ"
        p[1 - k, on] = f.local(f.Q, sP[i])
        p[k, on] = end * spec.size(k)
        meshes[f.Q] = MeshTri(p, meshes[f.Q].t)
    return {name: MeshTri(np.ascontiguousarray(m.p), np.ascontiguousarray(m.t))
            for name, m in meshes.items()}


# ---------------------------------------------------------------------------------------------
# One plate
# ---------------------------------------------------------------------------------------------
class CornerPlate:
    """Argyris ``w`` and P5 ``(u, v)`` on one mesh; unknowns ``w``, then ``u``, then ``v``;
    unit-stiffness matrices."""

    def __init__(self, spec: PlateSpec, mesh: MeshTri):
        assert (np.diff(mesh.t, axis=0) > 0).all(), "P5 facet dofs need sorted triangles"
        self.spec, self.mesh = spec, mesh
        self.bending = PlateFE(None, None, 0.3, mesh=mesh)
        self.membrane = Basis(mesh, ElementTriP5(), intorder=10)
        self.K_membrane, self.M_membrane = membrane_matrices(self.membrane, 0.3)
        self.n_w, self.n_m = self.bending.N, self.membrane.N
        self.size = self.n_w + 2 * self.n_m

    def dynamic(self, omega: float):
        return block_diag([D_STAR * self.bending.K - omega ** 2 * RHO_H * self.bending.M,
                           A_STAR * self.K_membrane - omega ** 2 * RHO_H * self.M_membrane])

    def stiffness(self):
        """The unit-rigidity stiffness (``D* = A* = 1``, no mass): what a rigid motion must
        leave at zero."""
        return block_diag([self.bending.K, self.K_membrane]).tocsr()

    def comp(self, c: int) -> int:
        """Offset of in-plane component ``c`` (0: u, 1: v)."""
        return self.n_w + c * self.n_m

    def fixed(self) -> np.ndarray:
        out = []
        for edge, in_plane in self.spec.supports.items():
            k, _ = EDGES[edge]
            facets = edge_facets(self.mesh, self.spec, edge)
            out.append(self.bending.basis.get_dofs(facets=facets).all(list(ALONG[1 - k])))
            nodes = self.membrane.get_dofs(facets=facets).all()
            for c in in_plane:
                out.append(self.comp("uv".index(c)) + nodes)
        return np.unique(np.concatenate(out)) if out else np.zeros(0, int)

    def edge(self, edge: str):
        """Vertices and facets of ``edge`` sorted along it, its P5 nodes and their tangent
        coordinates (sorted)."""
        k, _ = EDGES[edge]
        a = 1 - k
        facets = edge_facets(self.mesh, self.spec, edge)
        facets = facets[np.argsort(self.mesh.p[a, self.mesh.facets[:, facets]].mean(axis=0))]
        vertices = np.unique(self.mesh.facets[:, facets])
        vertices = vertices[np.argsort(self.mesh.p[a, vertices])]
        nodes = self.membrane.get_dofs(facets=facets).all()
        coords = self.membrane.doflocs[a, nodes]
        order = np.argsort(coords)
        return vertices, facets, nodes[order], coords[order]

    def edge_cells(self, edge: str, a: np.ndarray) -> np.ndarray:
        """The cell beside the edge facet holding each tangent coordinate ``a``."""
        k, _ = EDGES[edge]
        _, facets, _, _ = self.edge(edge)
        lower = self.mesh.p[1 - k, self.mesh.facets[:, facets]].min(axis=0)
        e = np.clip(np.searchsorted(lower, a, side="right") - 1, 0, len(lower) - 1)
        return self.mesh.f2t[0, facets[e]]

    def trace_weights(self, edge: str, a: np.ndarray):
        """The Argyris trace ``w`` at tangent coordinates ``a`` of ``edge`` as weights on
        ``(w, w_a, w_aa)`` of the two vertices of the edge facet holding each ``a``
        (``fem_folded.trace_weights`` for either axis). Returns (dofs, weights), (n, 6)."""
        k, _ = EDGES[edge]
        vertices = self.edge(edge)[0]
        av = self.mesh.p[1 - k, vertices]
        e = np.clip(np.searchsorted(av, a, side="right") - 1, 0, len(av) - 2)
        L = av[e + 1] - av[e]
        t = (a - av[e]) / L
        Hm = np.array([t ** i for i in range(6)]).T @ HERMITE
        Hm[np.abs(t) < 1e-9] = [1, 0, 0, 0, 0, 0]  # exact at the vertices
        Hm[np.abs(t - 1) < 1e-9] = [0, 0, 0, 1, 0, 0]
        scale = np.column_stack([np.ones_like(L), L, L ** 2] * 2)
        rows = [ROW[name] for name in ALONG[1 - k]]
        nodal = self.bending.basis.nodal_dofs
        dofs = np.column_stack([nodal[rows][:, vertices[e]].T, nodal[rows][:, vertices[e + 1]].T])
        return dofs, Hm * scale

    def facet_normals(self, facets) -> np.ndarray:
        """(2, n) normal in the ``u_n`` dof of each facet: the gradient of that dof's basis
        function at the facet midpoint (its trace vanishes there)."""
        mid = self.mesh.p[:, self.mesh.facets[:, facets]].mean(axis=1)
        cells = self.mesh.f2t[0, facets]
        dofs = self.bending.basis.facet_dofs[0, facets]
        i = np.arange(len(facets))
        return np.array([np.asarray(self.bending.eval_matrix(mid, cells, what=d)[i, dofs])
                         .ravel() for d in ("dx", "dy")])

    def values(self, x: np.ndarray, points: np.ndarray, cells=None) -> dict:
        """``w``, ``w_x``, ``w_y``, ``u``, ``v`` of the plate's part ``x`` at local ``points``
        (n, 2)."""
        w = x[:self.n_w]
        probe = p5_probes(self.membrane, self.mesh, points.T, cells)
        out = {key: self.bending.eval_matrix(points.T, cells, what=what) @ w
               for key, what in (("w", "value"), ("w_x", "dx"), ("w_y", "dy"))}
        out["u"] = probe @ x[self.comp(0):self.comp(1)]
        out["v"] = probe @ x[self.comp(1):]
        return out

    def membrane_forces(self, x: np.ndarray, points: np.ndarray, cells=None) -> np.ndarray:
        """Unit-rigidity (``A* = 1``) membrane forces ``N_xx, N_yy, N_xy`` (3, n) of the
        plate's part ``x`` at local ``points`` (n, 2) (plane stress, nu = 0.3)."""
        basis, pts = self.membrane, points.T
        if cells is None:
            cells = self.mesh.element_finder(mapping=basis.mapping)(*pts)
        X = basis.mapping.invF(pts[:, :, None], tind=cells)
        grads = np.array([basis.elem.gbasis(basis.mapping, X, k, tind=cells)[0].grad[:, :, 0]
                          for k in range(basis.Nbfun)])  # (Nbfun, 2, n)
        dofs = basis.element_dofs[:, cells]  # (Nbfun, n)
        du = np.einsum("kdn,kn->dn", grads, x[self.comp(0):self.comp(1)][dofs])
        dv = np.einsum("kdn,kn->dn", grads, x[self.comp(1):][dofs])
        nu = 0.3
        return np.array([du[0] + nu * dv[1], dv[1] + nu * du[0], (1 - nu) / 2 * (du[1] + dv[0])])


# ---------------------------------------------------------------------------------------------
# The ties
# ---------------------------------------------------------------------------------------------
@dataclass
class Tie:
    """``x[slave] = sum weights * x[masters]`` at the 3D ``point``, of fold ``fold``."""

    slave: int
    masters: np.ndarray
    weights: np.ndarray
    point: np.ndarray
    fold: str
    kind: str


def fold_ties(f: FoldGeometry, plates: dict[str, CornerPlate], offsets: dict[str, int]
              ) -> list[Tie]:
    """The ties of the module docstring for fold ``f``, in full indices."""
    P, Q = plates[f.P], plates[f.Q]
    oP, oQ = offsets[f.P], offsets[f.Q]
    eP, eQ = f.edge[f.P], f.edge[f.Q]
    vP, fP, nP, aP = P.edge(eP)
    vQ, fQ, nQ, aQ = Q.edge(eQ)
    kP, kQ = EDGES[eP][0], EDGES[eQ][0]
    sP, sQ = f.line_s(f.P, aP), f.line_s(f.Q, aQ)
    # match Q's nodes (and vertices) to P's along the line
    orderQ = np.argsort(sQ)
    nQ, sQ = nQ[orderQ], sQ[orderQ]
    assert len(sP) == len(sQ) and np.abs(sP - sQ).max() < 1e-10, f"{f.name}: P5 nodes differ"
    svP = f.line_s(f.P, P.mesh.p[1 - kP, vP])
    svQ = f.line_s(f.Q, Q.mesh.p[1 - kQ, vQ])
    oq = np.argsort(svQ)
    vQ, svQ = vQ[oq], svQ[oq]
    assert np.abs(svP - svQ).max() < 1e-12, f"{f.name}: vertices differ"
    midP = P.mesh.p[1 - kP, P.mesh.facets[:, fP]].mean(axis=0)
    midQ = Q.mesh.p[1 - kQ, Q.mesh.facets[:, fQ]].mean(axis=0)
    fQ = fQ[np.argsort(f.line_s(f.Q, midQ))]
    specP = P.spec
    k0 = [0.0, 0.0]
    k0[kP] = EDGES[eP][1] * specP.size(kP)
    point = lambda s: specP.point3d(*[(s if i == 1 - kP else k0[i]) for i in (0, 1)])[0]
    ties = []
    # d_b,Q = cross_Q w_P at Q's nodes; d_b,P = cross_P w_Q at P's nodes
    dofs, weights = P.trace_weights(eP, f.local(f.P, sQ))
    for node, s, d, c in zip(nQ, sQ, dofs, weights):
        keep = c != 0
        ties.append(Tie(oQ + Q.comp(kQ) + node, oP + d[keep], f.cross[f.Q] * c[keep], point(s),
                        f.name, "normal displacement"))
    dofs, weights = Q.trace_weights(eQ, f.local(f.Q, sP))
    for node, s, d, c in zip(nP, sP, dofs, weights):
        keep = c != 0
        ties.append(Tie(oP + P.comp(kP) + node, oQ + d[keep], f.cross[f.P] * c[keep], point(s),
                        f.name, "normal displacement"))
    # d_a,Q = sigma_Q d_a,P node by node (sigma_P = 1)
    for a, b, s in zip(nP, nQ, sP):
        ties.append(Tie(oQ + Q.comp(1 - kQ) + b, np.array([oP + P.comp(1 - kP) + a]),
                        np.array([f.sigma[f.Q]]), point(s), f.name, "tangential displacement"))
    # rotation about t: kappa_Q w_Q,b = kappa_P w_P,b; its derivative along s:
    # kappa_Q sigma_Q w_Q,ab = kappa_P w_P,ab; midpoints: w_,b = u_n / n_b
    nodal_P, nodal_Q = P.bending.basis.nodal_dofs, Q.bending.basis.nodal_dofs
    rP, rQ = ROW[D_ACROSS[kP]], ROW[D_ACROSS[kQ]]
    kap_P, kap_Q, sig_Q = f.kappa[f.P], f.kappa[f.Q], f.sigma[f.Q]
    for a, b, s in zip(vP, vQ, svP):
        ties.append(Tie(oQ + nodal_Q[rQ, b], np.array([oP + nodal_P[rP, a]]),
                        np.array([kap_P / kap_Q]), point(s), f.name, "rotation"))
        ties.append(Tie(oQ + nodal_Q[ROW["u_xy"], b], np.array([oP + nodal_P[ROW["u_xy"], a]]),
                        np.array([kap_P / (kap_Q * sig_Q)]), point(s), f.name, "rotation"))
    nbP = P.facet_normals(fP)[kP]
    nbQ = Q.facet_normals(fQ)[kQ]
    assert np.allclose(np.abs(nbP), 1, atol=1e-9) and np.allclose(np.abs(nbQ), 1, atol=1e-9)
    for a, b, r, s in zip(P.bending.basis.facet_dofs[0, fP], Q.bending.basis.facet_dofs[0, fQ],
                          np.round(nbQ / nbP), np.sort(f.line_s(f.P, midP))):
        ties.append(Tie(oQ + b, np.array([oP + a]), np.array([kap_P * r / kap_Q]), point(s),
                        f.name, "rotation"))
    return ties


def tie_rows(ties: list[Tie], size: int) -> csr_matrix:
    """The ties as rows ``x[slave] - sum w x[masters] = 0``."""
    rows, cols, vals = [], [], []
    for i, tie in enumerate(ties):
        rows += [i] * (1 + len(tie.masters))
        cols += [tie.slave, *tie.masters]
        vals += [1.0, *(-tie.weights)]
    return coo_matrix((vals, (rows, cols)), shape=(len(ties), size)).tocsr()


@dataclass
class Reduction:
    """``x_full = T x``; ``clusters``: per junction point, its dofs, the rank of its ties and
    the dimension of their null space."""

    T: csr_matrix
    masters: np.ndarray
    clusters: list = field(default_factory=list)
    forced: int = 0


def reduction(size: int, fixed: np.ndarray, ties: list[Tie], junctions) -> Reduction:
    """Master-slave everywhere but at the junction points: there every tie at the point
    (they involve only the dofs of the plates' vertices at the point) is gathered, and the
    free dofs they involve are replaced by an orthonormal basis of the null space of those
    rows (SVD, rank at 1e-10 of the largest singular value). Fixed dofs are zero rows; a
    fixed slave with one free master fixes it (as ``fem_folded.reduction``; ``forced``
    counts them); chains of slaves are resolved by substitution."""
    is_fixed = np.zeros(size, bool)
    is_fixed[fixed] = True
    at_junction = [[t for t in ties if np.linalg.norm(t.point - p) < 1e-10] for p in junctions]
    in_cluster = {id(t) for group in at_junction for t in group}
    regular = [t for t in ties if id(t) not in in_cluster]
    slaves = [t.slave for t in regular]
    assert len(set(slaves)) == len(slaves), "a dof slaved twice outside the junctions"
    forced = 0
    while True:
        more = 0
        for t in regular:
            if is_fixed[t.slave]:
                free = t.masters[~is_fixed[t.masters]]
                if len(free) == 1:
                    is_fixed[free] = True
                    more += 1
        forced += more
        if not more:
            break
    is_slave = np.zeros(size, bool)
    is_slave[slaves] = True
    clusters, cluster_dofs = [], []
    for group in at_junction:
        dofs = np.unique(np.concatenate([[t.slave, *t.masters] for t in group]).astype(int))
        dofs = dofs[~is_fixed[dofs]]
        assert not is_slave[dofs].any(), "a junction dof is slaved by a tie off the junction"
        index = {d: i for i, d in enumerate(dofs)}
        C = np.zeros((len(group), len(dofs)))
        for i, t in enumerate(group):
            if not is_fixed[t.slave]:
                C[i, index[t.slave]] += 1.0
            for m, w in zip(t.masters, t.weights):
                if not is_fixed[m]:
                    C[i, index[m]] -= w
        _, sv, Vt = np.linalg.svd(C)
        rank = int((sv > 1e-10 * sv[0]).sum())
        N = Vt[rank:].T
        clusters.append({"dofs": dofs, "N": N, "rank": rank, "rows": len(group),
                         "singular": sv, "kinds": [t.kind for t in group]})
        cluster_dofs.append(dofs)
    in_any_cluster = np.zeros(size, bool)
    for dofs in cluster_dofs:
        in_any_cluster[dofs] = True
    masters = np.nonzero(~is_fixed & ~is_slave & ~in_any_cluster)[0]
    n_cols = masters.size
    rows, cols, vals = [masters], [np.arange(masters.size)], [np.ones(masters.size)]
    for c in clusters:
        k = c["N"].shape[1]
        c["columns"] = np.arange(n_cols, n_cols + k)
        r, q = np.meshgrid(c["dofs"], c["columns"], indexing="ij")
        rows.append(r.ravel()), cols.append(q.ravel()), vals.append(c["N"].ravel())
        n_cols += k
    base = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(size, n_cols)).tocsr()
    # slaves: S (size x size) holds the weights on the masters' rows
    sr, sc, sv_ = [], [], []
    for t in regular:
        if is_fixed[t.slave]:
            continue
        keep = ~is_fixed[t.masters]
        sr += [t.slave] * int(keep.sum())
        sc += list(t.masters[keep])
        sv_ += list(t.weights[keep])
    S = coo_matrix((sv_, (sr, sc)), shape=(size, size)).tocsr()
    T = base
    for _ in range(10):
        T_new = (base + S @ T).tocsr()
        if (T_new - T).count_nonzero() == 0 or abs(T_new - T).max() == 0:
            T = T_new
            break
        T = T_new
    else:
        raise RuntimeError("slave chains do not resolve")
    T.eliminate_zeros()
    return Reduction(T, masters, clusters, forced)


def line_traces(parts: dict, f, n: int) -> tuple[dict, dict]:
    """On ``n`` points of the line ``f`` (a :class:`FoldGeometry`), each of its two plates'
    3D displacement ``u e_x + v e_y + w e_z`` (n, 3) and rotation about the line
    ``theta . t`` (``theta = w_y e_x - w_x e_y``); ``parts``: per plate, ``(plate, its
    unknowns)`` (:meth:`CornerModel.parts`)."""
    s = np.linspace(0.0, f.length, n)
    U, R = {}, {}
    for p in (f.P, f.Q):
        plate, xp = parts[p]
        k, end = EDGES[f.edge[p]]
        a = f.local(p, s)
        pts = np.zeros((n, 2))
        pts[:, k] = end * plate.spec.size(k)
        pts[:, 1 - k] = a
        vals = plate.values(xp, pts, plate.edge_cells(f.edge[p], a))
        e = plate.spec.axes
        U[p] = np.outer(vals["u"], e[0]) + np.outer(vals["v"], e[1]) + np.outer(vals["w"], e[2])
        R[p] = vals["w_y"] * (e[0] @ f.t) - vals["w_x"] * (e[1] @ f.t)
    return U, R


# ---------------------------------------------------------------------------------------------
# The model
# ---------------------------------------------------------------------------------------------
class CornerModel:
    """All plates of ``structure`` on the meshes of level ``n`` (or given ``meshes``), the
    ties, the reduction and the loads."""

    def __init__(self, structure: Structure, n: int, meshes: dict | None = None):
        t0 = time.perf_counter()
        self.structure, self.n = structure, n
        self.place_plates(structure, structure_meshes(structure, n, meshes), CornerPlate)
        self.folds = folds_of(structure)
        self.ties = [t for f in self.folds for t in fold_ties(f, self.plates, self.offsets)]
        self.junctions = junction_points(structure)
        fixed = np.concatenate([self.offsets[name] + p.fixed() for name, p in self.plates.items()])
        self.reduction = reduction(self.size, fixed, self.ties, self.junctions)
        self.T = self.reduction.T
        self.loads = self.point_loads(structure)
        self.t_setup = time.perf_counter() - t0

    def place_plates(self, structure: Structure, meshes: dict[str, MeshTri],
                     plate_type: type) -> None:
        """Every plate of ``structure`` as a ``plate_type`` on its mesh, their unknowns one
        after the other (``self.plates``, ``self.offsets``, ``self.size``)."""
        self.plates, self.offsets, self.size = {}, {}, 0
        for name, spec in structure.plates.items():
            self.plates[name] = plate_type(spec, meshes[name])
            self.offsets[name] = self.size
            self.size += self.plates[name].size
        self.n_triangles = sum(m.t.shape[1] for m in meshes.values())

    def point_loads(self, structure: Structure) -> dict[str, np.ndarray]:
        """Per load of ``structure``, the full load vector of its unit force along its plate's
        ``w`` at its point (the Argyris basis functions there)."""
        loads = {}
        for key, (plate, x, y) in structure.loads.items():
            f = np.zeros(self.size)
            p = self.plates[plate]
            f[self.offsets[plate]:self.offsets[plate] + p.n_w] = \
                p.bending.eval_matrix(np.array([[x], [y]], float)).toarray()[0]
            loads[key] = f
        return loads

    @property
    def n_dofs(self) -> int:
        return self.T.shape[1]

    def parts(self, x: np.ndarray) -> dict:
        return {name: (p, x[self.offsets[name]:self.offsets[name] + p.size])
                for name, p in self.plates.items()}

    def solve(self, frequency: float) -> dict[str, np.ndarray]:
        """Full solutions ``{load key: x}`` at ``frequency`` (Hz): ``T^T K T x = T^T f``
        scaled by the diagonal, SuperLU (``fem_folded``'s recipe), three refinement steps."""
        t0 = time.perf_counter()
        omega = 2 * math.pi * frequency
        K = block_diag([p.dynamic(omega) for p in self.plates.values()]).tocsr()
        Kr = (self.T.T @ K @ self.T).tocsc()
        s = diags(1.0 / np.sqrt(np.abs(Kr.diagonal())))
        Ks = (s @ Kr @ s).tocsc()
        keys = list(self.loads)
        b = s @ (self.T.T @ np.column_stack([self.loads[k] for k in keys])).astype(complex)
        lu = splu(Ks, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        x = lu.solve(b)
        # iterative refinement with the residual in extended precision: in double it stalls
        # at ~5e-10 and leaves round-off of ~1e-8 in w and ~1e-6 in (u, v) (two orderings
        # differed by that at level 4); with it two orderings agree to 1e-11 and 1e-9
        KL, bL = Ks.astype(np.clongdouble), b.astype(np.clongdouble)
        for _ in range(3):
            x = x + lu.solve(np.asarray(bL - KL @ x.astype(np.clongdouble), dtype=complex))
        r = np.asarray(bL - KL @ x.astype(np.clongdouble), dtype=complex)
        self.residual = float(np.linalg.norm(r) / np.linalg.norm(b))
        self.t_solve = time.perf_counter() - t0
        full = self.T @ (s @ x)
        return {k: full[:, i] for i, k in enumerate(keys)}

    # ---- checks ---------------------------------------------------------------------------
    def tie_residual(self) -> float:
        """``max |C T|``: every tie (the junctions' included, redundant ones too) on every
        column of ``T`` (weights are O(1) or smaller)."""
        R = tie_rows(self.ties, self.size) @ self.T
        return float(abs(R).max()) if R.nnz else 0.0

    def line_mismatch(self, x: np.ndarray, n: int = 401) -> dict[str, dict[str, float]]:
        """Per fold, at ``n`` points of the line: the largest difference of the two plates'
        3D displacements ``u e_x + v e_y + w e_z`` relative to the largest of them, and the
        same for the rotation about the line ``theta . t`` (``theta = w_y e_x - w_x e_y``)."""
        out = {}
        parts = self.parts(x)
        for f in self.folds:
            U, R = line_traces(parts, f, n)
            out[f.name] = {
                "U": float(np.abs(U[f.P] - U[f.Q]).max() / np.abs(U[f.P]).max()),
                "theta": float(np.abs(R[f.P] - R[f.Q]).max() / np.abs(R[f.P]).max())}
        return out

    def fields(self, x: np.ndarray) -> tuple[dict, dict]:
        """``w`` (225,) and ``uv`` (225, 2) of each plate on its ``inner_grid``."""
        w, uv = {}, {}
        for name, (plate, xp) in self.parts(x).items():
            v = plate.values(xp, inner_grid(plate.spec.lx, plate.spec.ly))
            w[name], uv[name] = v["w"], np.column_stack([v["u"], v["v"]])
        return w, uv

    def free_edge_traction(self, x: np.ndarray, n: int = 201) -> float:
        """The natural condition on the supported edges free in plane: the largest in-plane
        traction ``|(N_nn, N_nt)|`` at ``n`` points of each such edge (ends excluded by 1 %),
        relative to the largest membrane force on the plates' ``inner_grid`` points (nan if
        no edge is free in plane)."""
        worst, scale = 0.0, 0.0
        found = False
        for plate, xp in self.parts(x).values():
            N = plate.membrane_forces(xp, inner_grid(plate.spec.lx, plate.spec.ly))
            scale = max(scale, float(np.abs(N).max()))
            for edge, in_plane in plate.spec.supports.items():
                if in_plane:
                    continue
                found = True
                k, end = EDGES[edge]
                a = np.linspace(0.01, 0.99, n) * plate.spec.size(1 - k)
                pts = np.zeros((n, 2))
                pts[:, k], pts[:, 1 - k] = end * plate.spec.size(k), a
                N = plate.membrane_forces(xp, pts, plate.edge_cells(edge, a))
                worst = max(worst, float(np.hypot(np.abs(N[k]), np.abs(N[2])).max()))
        return worst / scale if found else math.nan

    def far_end_dofs(self) -> dict[str, str]:
        """At the end of every fold away from the junctions, the dofs of both plates' vertex
        there: ``{fold: "A: u 1 v 0 w 0 ..."}``, the number of columns of its row of ``T``
        (0: held at zero by the supports, directly or through a tie)."""
        nnz = self.T.getnnz(axis=1)
        out = {}
        for f in self.folds:
            _, _, a, o, e = edge_line(self.structure.plates[f.P], f.edge[f.P])
            ends = [o, o + self.structure.plates[f.P].size(a) * e]
            far = [X for X in ends if all(np.linalg.norm(X - j) > TOL for j in self.junctions)]
            text = []
            for X in far:
                for name in (f.P, f.Q):
                    p, off = self.plates[name], self.offsets[name]
                    local = (X - np.array(p.spec.origin, float)) @ p.spec.axes[:2].T
                    v = int(np.argmin(np.linalg.norm(p.mesh.p.T - local, axis=1)))
                    nodal = p.bending.basis.nodal_dofs[:, v]
                    m = p.membrane.nodal_dofs[0, v]
                    dofs = {"u": p.comp(0) + m, "v": p.comp(1) + m,
                            **{"w" + key[1:]: nodal[ROW[key]]
                               for key in ("u", "u_x", "u_y", "u_xy")}}
                    text.append(f"{name}: " + " ".join(f"{k} {nnz[off + d]}"
                                                       for k, d in dofs.items()))
            out[f.name] = ", ".join(text)
        return out

    def point_w(self, x: np.ndarray, plate: str, xy) -> complex:
        p, xp = self.parts(x)[plate]
        return complex(p.values(xp, np.array([xy], float))["w"][0])

    def rigid_body_check(self) -> dict:
        """The six rigid motions ``U = c + theta x X`` interpolated on every plate: their
        residual in every tie (``|C x| / |x|``), their distance from the range of the
        reduction without supports (``|T0 y - x| / |x|``, ``y`` the masters' values and the
        junctions' null-space coordinates) and their stiffness (``|K x| / | |K| |x| |``, the
        unit-rigidity bending and membrane stiffness, no mass)."""
        red0 = reduction(self.size, np.zeros(0, int), self.ties, self.junctions)
        T0 = red0.T
        C = tie_rows(self.ties, self.size)
        K = block_diag([p.stiffness() for p in self.plates.values()]).tocsr()
        absK = abs(K)
        # y from x: masters are identity columns; junction columns are N^T x
        results = []
        for mode, x in enumerate(self.rigid_motions()):
            y = np.zeros(T0.shape[1])
            y[:red0.masters.size] = x[red0.masters]
            for cl in red0.clusters:
                y[cl["columns"]] = cl["N"].T @ x[cl["dofs"]]
            results.append({"mode": ("Tx", "Ty", "Tz", "Rx", "Ry", "Rz")[mode],
                            "ties": float(np.abs(C @ x).max() / np.abs(x).max()),
                            "range": float(np.linalg.norm(T0 @ y - x) / np.linalg.norm(x)),
                            "stiffness": float(np.linalg.norm(K @ x)
                                               / np.linalg.norm(absK @ np.abs(x)))})
        return {"modes": results, "clusters": red0.clusters}

    def rigid_motions(self):
        """The six rigid motions, translations along X, Y, Z then rotations about them, each
        the full vector of every plate's dofs (:meth:`rigid_interpolant`)."""
        for mode in range(6):
            c, th = np.zeros(3), np.zeros(3)
            (c if mode < 3 else th)[mode % 3] = 1.0
            yield np.concatenate([self.rigid_interpolant(name, c, th) for name in self.plates])

    def rigid_interpolant(self, name: str, c: np.ndarray, th: np.ndarray) -> np.ndarray:
        """The plate's dofs of the rigid motion ``U(X) = c + th x X``: ``w = U . e_z`` is
        linear (``w_x = (th x e_x) . e_z``, ``w_y = (th x e_y) . e_z``, no curvature),
        ``u = U . e_x``, ``v = U . e_y`` at the P5 nodes."""
        p = self.plates[name]
        e = p.spec.axes
        o = np.array(p.spec.origin, float)
        U0 = c + np.cross(th, o)
        w0, wx, wy = U0 @ e[2], np.cross(th, e[0]) @ e[2], np.cross(th, e[1]) @ e[2]
        x = np.zeros(p.size)
        nodal = p.bending.basis.nodal_dofs
        X, Y = p.mesh.p
        x[nodal[ROW["u"]]] = w0 + wx * X + wy * Y
        x[nodal[ROW["u_x"]]] = wx
        x[nodal[ROW["u_y"]]] = wy
        facets = np.arange(p.mesh.facets.shape[1])
        normal = p.facet_normals(facets)
        x[p.bending.basis.facet_dofs[0]] = normal[0] * wx + normal[1] * wy
        xm, ym = p.membrane.doflocs
        for comp in (0, 1):
            x[p.comp(comp):p.comp(comp) + p.n_m] = (
                U0 @ e[comp] + (np.cross(th, e[0]) @ e[comp]) * xm
                + (np.cross(th, e[1]) @ e[comp]) * ym)
        return x

# ---------------------------------------------------------------------------------------------
# Self-checks
# ---------------------------------------------------------------------------------------------
@dataclass
class LevelRun:
    """One level: fields of the main load per frequency, reciprocity, checks, timings."""

    n: int
    n_dofs: int
    n_triangles: int
    t_setup: float
    t_solve: dict
    residual: dict
    tie_residual: float
    mismatch: dict
    w: dict
    uv: dict
    recip: dict
    rigid: dict | None
    cluster: dict
    far_ends: dict = field(default_factory=dict)
    traction: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)


def run_level(n: int, frequencies=FREQUENCIES, rigid: bool = True,
              structure: Structure = CORNER, extra=None) -> LevelRun:
    """Build the corner (``CORNER`` or ``FLOATING``, or another ``structure``) at level ``n``
    and solve both loads at every frequency; ``extra(model, {load key: x})``, if given, is
    stored per frequency in ``run.extra`` (a structure's own checks)."""
    model = CornerModel(structure, n)
    run = LevelRun(n, model.n_dofs, model.n_triangles, model.t_setup, {}, {},
                   model.tie_residual(), {}, {}, {}, {}, None, {}, model.far_end_dofs())
    # a structure without junction points (folds ending apart) has no cluster
    c = (model.reduction.clusters or [{"rows": 0, "dofs": [], "rank": 0}])[0]
    run.cluster = {"rows": c["rows"], "dofs": len(c["dofs"]), "rank": c["rank"],
                   "forced": model.reduction.forced}
    if rigid:
        run.rigid = model.rigid_body_check()["modes"]
    (pa, *xa), (pc, *xc) = structure.loads["main"], structure.loads["recip"]
    for f in frequencies:
        xs = model.solve(f)
        run.t_solve[f], run.residual[f] = model.t_solve, model.residual
        run.w[f], run.uv[f] = model.fields(xs["main"])
        run.mismatch[f] = {k: model.line_mismatch(x) for k, x in xs.items()}
        run.recip[f] = (model.point_w(xs["main"], pc, xc), model.point_w(xs["recip"], pa, xa))
        run.traction[f] = model.free_edge_traction(xs["main"])
        if extra is not None:
            run.extra[f] = extra(model, xs)
    print(f"  level {n}: {model.n_triangles} triangles, {model.n_dofs} unknowns, set-up "
          f"{model.t_setup:.0f} s, solves " + ", ".join(f"{t:.0f} s" for t in run.t_solve.values()),
          flush=True)
    return run


def print_tables(runs: list[LevelRun], frequencies=FREQUENCIES,
                 structure: Structure = CORNER) -> dict:
    """Changes between levels, reciprocity, ties; returns ``{f: (w changes, uv changes)}`` of
    the last step, per plate."""
    plates = list(structure.plates)
    (pa, xa, ya), (pc, xc, yc) = structure.loads["main"], structure.loads["recip"]
    last = {}
    levels = [r.n for r in runs]
    for f in frequencies:
        print(f"\n{f:g} Hz: relative L2 change from the previous level on the 225 points")
        print(f"  {'n':>2} {'dofs':>7} {'solve':>6} {'resid':>7} "
              + "".join(f" {'w_' + p:>9}" for p in plates)
              + "".join(f" {'uv_' + p:>9}" for p in plates))
        changes = {key: [] for key in [f"w_{p}" for p in plates] + [f"uv_{p}" for p in plates]}
        prev = None
        for r in runs:
            row = f"  {r.n:>2} {r.n_dofs:>7} {r.t_solve[f]:>5.0f}s {r.residual[f]:>7.1e} "
            for kind, data in (("w", r.w[f]), ("uv", r.uv[f])):
                for p in plates:
                    if prev is None:
                        row += f" {'':>9}"
                    else:
                        old = (prev.w if kind == "w" else prev.uv)[f][p]
                        changes[f"{kind}_{p}"].append(relative(data[p], old))
                        row += f" {changes[f'{kind}_{p}'][-1]:>9.2e}"
            print(row)
            prev = r
        if len(runs) >= 3:
            est = {k: richardson(levels[-3:], v[-2:]) for k, v in changes.items()}
            print(f"  Richardson error estimate of level {levels[-1]}: "
                  + ", ".join(f"{k} {v:.1e}" for k, v in est.items()))
        if len(runs) >= 2:
            last[f] = (np.array([changes[f"w_{p}"][-1] for p in plates]),
                       np.array([changes[f"uv_{p}"][-1] for p in plates]))
        print(f"  reciprocity w_{pc}({xc:g}, {yc:g}; load on {pa}) vs w_{pa}({xa:g}, {ya:g}; "
              f"load on {pc}):")
        for r in runs:
            a, b = r.recip[f]
            print(f"    n = {r.n}: {a:.10e}  {b:.10e}  rel. diff {abs(a - b) / abs(a):.1e}")
        print("  fold ties sampled at 401 points (max over both loads), |U_P - U_Q| / max|U|, "
              "|theta_P - theta_Q| / max|theta|:")
        for r in runs:
            worst = {fold: {q: max(m[fold][q] for m in r.mismatch[f].values())
                            for q in ("U", "theta")} for fold in r.mismatch[f]["main"]}
            print(f"    n = {r.n}: " + ", ".join(f"{fold} {v['U']:.1e} / {v['theta']:.1e}"
                                                  for fold, v in worst.items()))
        if not math.isnan(runs[0].traction[f]):
            print("  in-plane traction on the edges free in plane (load on A), max |(N_nn, "
                  "N_nt)| / max |N| inside: "
                  + ", ".join(f"n = {r.n} {r.traction[f]:.1e}" for r in runs))
    print("\nties on the columns of T, max |C T|; junction cluster at the origin (rows, dofs, "
          "rank) and free masters forced to 0 by fixed slaves:")
    for r in runs:
        print(f"  n = {r.n}: {r.tie_residual:.1e}; {r.cluster}")
    print("far ends of the folds: columns of T of the vertex dofs (0: held at zero):")
    for r in runs:
        print(f"  n = {r.n}: " + "; ".join(f"{k} {v}" for k, v in r.far_ends.items()))
    print("rigid motions: tie residual, distance from range(T) without supports, |K x| / "
          "||K| |x||:")
    for r in runs:
        if r.rigid:
            print(f"  n = {r.n}: " + "; ".join(f"{m['mode']} {m['ties']:.0e} {m['range']:.0e} "
                                               f"{m['stiffness']:.0e}" for m in r.rigid))
    return last


def lfold_check(n: int = 3, frequencies=FREQUENCIES) -> None:
    """The L fold of ``fem_folded`` (diaphragm ends) through this module's generic frames and
    ties, on ``fem_folded``'s own meshes of level ``n``: against ``fem_folded.FoldModel`` (the
    same discrete space, so round-off) and against the exact prismatic solution
    (``tests/exact_prismatic.py``, 600 harmonics, imported directly: ``tests/support.py``
    imports the solver)."""
    import fem_folded as ff
    sys.path.insert(0, str(ROOT / "tests"))
    from exact import complex_rigidity
    from exact_prismatic import FoldedPlate, PrismaticLine, membrane_stiffness, prismatic_levy

    meshes = ff.fold_meshes(ff.MeshLevel.of(n))
    model = CornerModel(L_FOLD, n, meshes)
    theirs = ff.FoldModel(n, "diaphragm")
    print(f"\nL fold of fem_folded, diaphragm ends, level {n} ({model.n_dofs} unknowns here, "
          f"{theirs.n_dofs} in fem_folded); tie residual {model.tie_residual():.1e}")
    rb = model.rigid_body_check()["modes"]
    print("  rigid motions (ties, range, stiffness): "
          + "; ".join(f"{m['mode']} {m['ties']:.0e} {m['range']:.0e} {m['stiffness']:.0e}"
                      for m in rb))
    strips = {name: FoldedPlate(spec.lx, complex_rigidity(2.1e11, 0.002, 0.3, 0.01),
                                membrane_stiffness(2.1e11, 0.002, 0.3, 0.01), 0.3, RHO_H,
                                spec.origin, spec.ex, (0.0, 1.0, 0.0), right="simply_supported")
              for name, spec in L_FOLD.plates.items()}
    line = PrismaticLine({"A": ("right", math.inf), "B": ("left", math.inf)}, held=False)
    for f in frequencies:
        x = model.solve(f)["main"]
        w, uv = model.fields(x)
        other = ff.solve_fold(f, "diaphragm", n, theirs)
        exact = prismatic_levy(strips, [line], 0.5, 2 * math.pi * f,
                               forces=[("A", 0.15, 0.2, 1.0)], n_terms=600, ends="diaphragm")
        mism = model.line_mismatch(x)["F"]
        row = []
        for p, spec in L_FOLD.plates.items():
            pts = inner_grid(spec.lx, spec.ly)
            we = exact.w(p, *pts.T)
            uve = np.column_stack([exact.u(p, *pts.T), exact.v(p, *pts.T)])
            row.append(f"{p}: w vs fem_folded {relative(w[p], other.w[p]):.1e}, "
                       f"uv {relative(uv[p], other.uv[p]):.1e}; vs exact w "
                       f"{relative(w[p], we):.1e} (fem_folded {relative(other.w[p], we):.1e}),"
                       f" uv {relative(uv[p], uve):.1e}")
        print(f"  {f:g} Hz: line U {mism['U']:.1e}, theta {mism['theta']:.1e}\n    "
              + "\n    ".join(row))


def write(run: LevelRun, last: dict, frequencies=FREQUENCIES, path: Path = TEST_DATA,
          structure: Structure = CORNER) -> None:
    """``tests/data/fem_corner.npz`` (or ``path``): ``w_{p}_{f}`` (225,), ``uv_{p}_{f}``
    (225, 2) of the finest level and ``change_{f}``: the last level change of ``w`` per
    plate (A, B, C, the order of ``structure.plates``)."""
    packed = {}
    for f in frequencies:
        for p in structure.plates:
            packed[f"w_{p}_{f:g}"] = run.w[f][p]
            packed[f"uv_{p}_{f:g}"] = run.uv[f][p]
        packed[f"change_{f:g}"] = last[f][0]
    np.savez_compressed(path, **packed)
    print(f"wrote {path} (level {run.n})")


def main(argv) -> None:
    """Levels (default 4 6 8) of the corner; ``--write``: write ``tests/data/fem_corner.npz``;
    ``--floating`` (300 Hz; ``--1khz``: 1 kHz too): the floating corner; ``--write-floating``:
    the floating corner, writing ``tests/data/fem_corner_floating.npz``; ``--lfold``."""
    t0 = time.perf_counter()
    write_floating = "--write-floating" in argv
    is_floating = write_floating or "--floating" in argv
    write_npz = "--write" in argv
    lfold = "--lfold" in argv
    levels = sorted(int(a) for a in argv if not a.startswith("--")) or list(LEVELS)
    if lfold:
        lfold_check(levels[0] if argv[1:] else 3)
        return
    structure, frequencies, tag = CORNER, FREQUENCIES, ""
    if is_floating:
        frequencies = FREQUENCIES if "--1khz" in argv else FLOATING_FREQUENCIES
        structure, tag = FLOATING, "_floating"
    OUT.mkdir(parents=True, exist_ok=True)
    runs = []
    for n in levels:
        runs.append(run_level(n, frequencies, structure=structure))
        r = runs[-1]
        np.savez(OUT / f"level_{n}{tag}.npz", **{f"{k}_{p}_{f:g}": getattr(r, k)[f][p]
                                                 for k in ("w", "uv") for f in frequencies
                                                 for p in structure.plates})
    last = print_tables(runs, frequencies)
    if write_floating:
        write(runs[-1], last, frequencies, FLOATING_DATA)
    elif write_npz:
        write(runs[-1], last)
    print(f"total {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main(sys.argv[1:])
