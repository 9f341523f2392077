r"""Finite-element reference for an L fold of two plates (bending and membrane), scikit-fem,
written apart from the VTCR solver.

The structure
-------------
Steel, ``E* = E (1 + j eta)`` (E = 210 GPa, nu = 0.3, rho = 7800 kg/m^3, eta = 0.01), h = 2 mm,
``D* = E* h^3 / (12 (1 - nu^2))``, ``A* = E* h / (1 - nu^2)``; time factor ``exp(+j omega t)``.
Plate ``p`` occupies its local ``[0, L_p] x [0, 0.5]`` and is placed in space by its frame
``(o_p, e_x, e_y, e_z = e_x x e_y)``; its displacement is the 3D vector
``u e_x + v e_y + w e_z``:

* A: ``L = 0.4``, ``o = 0``, ``e_x = (1, 0, 0)``, ``e_y = (0, 1, 0)``, ``e_z = (0, 0, 1)``;
* B: ``L = 0.3``, ``o = (0.4, 0, 0)``, ``e_x = (0, 0, 1)``, ``e_y = (0, 1, 0)``,
  ``e_z = (-1, 0, 0)``.

A's edge ``x = 0.4`` and B's edge ``x = 0`` are the fold line ``Gamma`` (``y`` is the same
coordinate on both). The far edges (A's ``x = 0``, B's ``x = 0.3``) are simply supported and
fixed in plane; the ends ``y = 0, 0.5`` of both plates are simply supported in bending and,
in plane, either shear diaphragms (``u = 0``, ``N_yy = 0`` natural) or rollers (``v = 0``,
``N_xy = 0`` natural). A unit force along A's ``e_z`` acts at A's ``(0.15, 0.2)``.

The rigid fold (every sign)
---------------------------
*Translation.* On ``Gamma`` the 3D displacements agree:
``u_A (1,0,0) + v_A (0,1,0) + w_A (0,0,1) = u_B (0,0,1) + v_B (0,1,0) + w_B (-1,0,0)``, so

    u_A(0.4, y) = -w_B(0, y),   v_A(0.4, y) = v_B(0, y),   w_A(0.4, y) = u_B(0, y).

*Rotation.* A Kirchhoff plate moves the point at ``z'`` along ``e_z`` by
``-z' (w_x e_x + w_y e_y) + w e_z``; writing this as ``theta x (z' e_z)`` with
``theta = t_x e_x + t_y e_y`` (``e_x x e_z = -e_y``, ``e_y x e_z = e_x``) gives
``t_y = -w_x``, ``t_x = w_y``: the rotation about ``e_y = (0, 1, 0)`` (the line's direction
in both plates) is ``-w_x``, and the right angle between the plates is kept iff

    w_A,x(0.4, y) = w_B,x(0, y).

(Check: the rigid rotation ``theta (0, 1, 0)`` about the line gives ``w_A = -theta (x - 0.4)``,
``w_B = -theta x``: both ``w_x = -theta``.)

Weak form (bilinear, no conjugation)
------------------------------------
Find ``(w_p, u_p, v_p)`` in the space ``V`` of fields that meet the essential conditions and
the four fold constraints above such that for every ``(w^_p, u^_p, v^_p)`` in ``V``

    sum_p int_p { D* [(1 - nu) w_,ab w^_,ab + nu lap w lap w^] - omega^2 rho h w w^
                + A* [(1 - nu) eps_ab(u) eps_ab(u^) + nu eps_aa(u) eps_bb(u^)]
                - omega^2 rho h (u u^ + v v^) } dA  =  1 * w^_A(0.15, 0.2),

``eps_ab(u) = (u_a,b + u_b,a) / 2`` (plane stress: ``N = A* [(1 - nu) eps + nu tr(eps) I]``).
The forces and the couple the plates exchange on the line are the multipliers of the
constraints; they do no virtual work in ``V``, so the balance of the line is natural.

Discretisation and coupling
---------------------------
One mesh of the unfolded strip ``[0, 0.7] x [0, 0.5]`` (A left of ``x = 0.4``, B right of it,
B's local ``x`` shifted by ``0.4``) is graded and split along the line, so both plates have
the same vertices and edges on ``Gamma``. ``w``: Argyris quintic triangles with
``fem_clamped.ArgyrisLocal`` (per-triangle scaled monomials, no round-off floor) and the
forms of ``fem_argyris``. ``(u, v)``: Lagrange P5 triangles (:class:`ElementTriP5`, defined
here: scikit-fem stops at P4).

The choice of P5 makes the coupling exact, so no mortar is needed: on a line edge the trace
of an Argyris ``w`` is the quintic Hermite interpolant of ``(w, w_y, w_yy)`` at the two
vertices (``C^2`` piecewise quintic along ``Gamma``), and that of a P5 component is any
``C^0`` piecewise quintic, which contains it. So the constraints hold identically on
``Gamma`` (not only in a projected sense) when

* every P5 node of B on ``Gamma`` has ``u_B`` equal to A's Hermite trace there (6 nodes per
  edge determine a quintic), and every P5 node of A has ``u_A`` equal to minus B's trace;
* ``v_B = v_A`` node by node (the same P5 nodes);
* B's normal-derivative dofs on ``Gamma`` equal A's: ``w_x`` and ``w_xy`` at each vertex,
  and the edge-midpoint ``w_n = n_x w_x`` times the ratio ``n_x^B / n_x^A`` (= -1: each
  element uses its outward normal on a boundary edge). The normal-derivative trace of an
  Argyris field on an edge is the quartic fixed by these five values, so
  ``w_A,x = w_B,x`` holds everywhere on ``Gamma``.

These are master-slave relations (``u_B``, ``u_A``, ``v_B`` on ``Gamma`` and B's normal
derivatives are slaves of free dofs), so ``x_full = T x`` with a sparse real ``T``, and the
Galerkin system is ``T^T K(omega) T x = T^T f``: a conforming discretisation of the weak form
above (no penalty, no multiplier, no consistency error). The only price: ``u_B``'s trace is
``C^2`` at the line's vertices (it is ``w_A``'s), a restriction the exact trace meets, so the
constrained space approximates as well as its Argyris and P5 parts do. The reduced
matrix is scaled symmetrically by its diagonal, factorised with SuperLU and the solve refined
iteratively.

Meshes
------
:func:`graded_mesh` (``fem_clamped.corner_refined_mesh`` with one grading rate per point)
refines squares of side ``0.05 / n`` until the element size is about ``min(0.05, 2 r) / n``,
``r`` the distance to the nearest grading point, floored at ``h_min``: the family is a plain
``h``-refinement in ``n`` (``refinement`` below). The grading points are the four corners
where the fold meets the ends (``h_min = 1e-6``: with roller ends ``w_A = u_B`` is odd in
``y`` on the bending side and even on the membrane side, so the fields carry ``log r`` line
loads and ``r log r`` membrane terms there) and the point force (``w ~ r^2 log r``; it sits
on a mesh vertex, so its load vector is the unit ``w`` dof; ``h_min = 1e-3``, because smaller
elements where ``w`` is large cost round-off: ``3e-4`` moves ``w`` by 1.4e-8 at 300 Hz). The
far corners need no grading (simple support with a diaphragm or a roller is a mirror plane,
across which the fields continue smoothly); grading them anyway moves ``w`` by 1e-9.

Ends
----
``ends`` is 'diaphragm', 'roller' (both simply supported in bending) or 'symmetric' (a
symmetry plane: ``w_y = 0`` and the roller in-plane condition), the last only to check the
roller's in-plane condition against the exact solution, which exists for diaphragm and
symmetric ends but not for roller ends; or 'symmetric_diaphragm' (``w_y = 0`` with the
diaphragm's in-plane condition, another mix of the halves of a plane of symmetry than
'roller'; not in :func:`main`'s self-checks: level 4 to 6 changes ``w`` by 6e-9 to 3e-7) or
'symmetric_fixed' (``w_y = 0`` with ``u = v = 0``, the third such mix; level 4 to 6
changes ``w`` by 6e-9 to 2.9e-7 and ``(u, v)`` by 2.8e-7 to 1.4e-5). Two more leave the
line's ends unheld along it: 'free' (nothing fixed: free corners) and 'sliding' (simply
supported in bending, nothing fixed in plane: vtcr's ``in_plane = "free"``), the references
of ``tests/test_free_ends.py`` (:func:`write_ends_data`).

Self-checks
-----------
Run ``OPENBLAS_NUM_THREADS=1 python bench/fem_folded.py [n ...]`` (default n = 2 3 4 6 8;
17 minutes on one core, 9 GB at n = 8). It prints, per kind of ends and frequency, the change
of each field between successive meshes and, for diaphragm and symmetric ends, its error
against the exact prismatic solution (``tests/support.folded_reference``, moving line, 600
harmonics), relative L2 norms over the 225 points of a plate; it saves the finest fields to
``/tmp/fem_folded/fields_<ends>_<freq>.npz`` (:func:`save`); ``python bench/fem_folded.py
--test-data`` then packs the roller fields, and the symmetric_diaphragm ones solved at level
6, into ``tests/data/fem_fold_mixed_ends.npz``, the reference of
``tests/test_moving_lines.py`` (:func:`write_test_data`). Measured (w_A / w_B):

* diaphragm, error against the exact solution, n = 2, 3, 4, 6, 8: 300 Hz 1.7e-6 / 6.2e-7,
  7.2e-8 / 4.8e-8, 3.5e-8 / 6.6e-9, 1.6e-9 / 9.6e-10, 1.8e-9 / 1.3e-9; 1 kHz 9.0e-5 / 1.4e-4,
  3.3e-6 / 5.0e-6, 3.5e-7 / 5.9e-7, 1.8e-8 / 3.4e-8, 4.6e-9 / 6.6e-9; ``(u, v)`` at n = 8
  1.3e-9 to 2.2e-8;
* roller, change from the previous n, n = 3, 4, 6, 8: 300 Hz 1.7e-6 / 6.3e-7, 8.4e-8 /
  4.7e-8, 3.6e-8 / 6.8e-9, 2.3e-9 / 8.5e-10; 1 kHz 8.7e-5 / 1.3e-4, 3.0e-6 / 4.6e-6, 3.4e-7 /
  5.7e-7, 1.6e-8 / 3.2e-8; ``(u, v)`` from 6 to 8 4e-9 to 2.5e-7. The same steps with
  diaphragm ends overstate the true error of the finer mesh 2 to 20 times, so the error of
  n = 8 is below about 3e-8 in ``w`` and 3e-7 in ``(u, v)``. Hidden by the family (at n = 6):
  ``h_min`` 1e-6 -> 1e-8 at the fold's corners moves ``w`` by 1e-9, grading the far corners by
  1e-9; the LU's round-off (another ordering) is 2e-10;
* symmetric, error against the exact solution at n = 8: ``w`` 1.3e-9 / 1.3e-9 (300 Hz),
  5.6e-9 / 6.2e-9 (1 kHz): the roller in-plane condition is right; ``(u, v)`` only 1.3e-7 to
  9.8e-7, the round-off of this case (another LU ordering moves them by 1e-6, ``w`` by 1e-9).
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.optimize import brentq
from scipy.sparse import block_diag, bmat, coo_matrix, diags
from scipy.sparse.linalg import splu
from skfem import Basis, BilinearForm, MeshTri, asm
from skfem.element import ElementH1
from skfem.refdom import RefTri

sys.path.insert(0, str(Path(__file__).resolve().parent))  # fem_clamped imports fem_argyris
from fem_argyris import mass_form
from fem_clamped import PlateFE

E, NU, RHO, H, ETA = 210e9, 0.3, 7800.0, 0.002, 0.01
D_STAR = E * (1 + 1j * ETA) * H ** 3 / (12 * (1 - NU ** 2))
A_STAR = E * (1 + 1j * ETA) * H / (1 - NU ** 2)
RHO_H = RHO * H
LY = 0.5
LENGTHS = {"A": 0.4, "B": 0.3}
FOLD_X = LENGTHS["A"]  # the line in the unfolded strip; B's local x = unfolded x - FOLD_X
LOAD = (0.15, 0.2)  # on A, along A's e_z, 1 N
# The ends y = 0, LY: the Argyris dofs w = 0 (simply supported) or w_y = 0 (a symmetry plane)
# fixes on them, and the in-plane component fixed there (u: diaphragm, v: roller)
ENDS = {"diaphragm": (["u", "u_x", "u_xx"], "u"),
        "roller": (["u", "u_x", "u_xx"], "v"),
        "symmetric": (["u_y", "u_xy", "u_n"], "v"),
        "symmetric_diaphragm": (["u_y", "u_xy", "u_n"], "u"),
        "symmetric_fixed": (["u_y", "u_xy", "u_n"], "uv"),
        "fixed": (["u", "u_x", "u_xx"], "uv"),  # simply supported, fixed in plane
        "free": ([], ""),  # nothing fixed: the line's ends are free corners
        "sliding": (["u", "u_x", "u_xx"], "")}  # simply supported, free in plane
SELF_CHECKED_ENDS = ("diaphragm", "roller", "symmetric")
OUT = Path("/tmp/fem_folded")

# Argyris nodal dofs (scikit-fem's rows of ``nodal_dofs``); on an edge x = const the trace
# is fixed by (u, u_y, u_yy) and the normal derivative's vertex data are (u_x, u_xy)
ARGYRIS_NODAL = ["u", "u_x", "u_y", "u_xx", "u_xy", "u_yy"]
ALONG_Y = [ARGYRIS_NODAL.index(name) for name in ("u", "u_y", "u_yy")]
ACROSS_Y = [ARGYRIS_NODAL.index(name) for name in ("u_x", "u_xy")]
SS_X_EDGE = ["u", "u_y", "u_yy"]  # simply supported edge x = const


def inner_grid(length: float, width: float = LY, n: int = 15) -> np.ndarray:
    """``tests/support.py``'s ``inner_grid`` (copied so that this module imports nothing of
    the project): ``n x n`` points (n * n, 2), 2 % in from the edges, x fastest."""
    x, y = np.meshgrid(np.linspace(0.02, 0.98, n) * length, np.linspace(0.02, 0.98, n) * width)
    return np.column_stack([x.ravel(), y.ravel()])


# ---------------------------------------------------------------------------------------------
# The P5 Lagrange triangle
# ---------------------------------------------------------------------------------------------
def _p5_nodes() -> np.ndarray:
    """Reference nodes in scikit-fem's order: vertices (0,0), (1,0), (0,1); the four nodes of
    the edges 0-1, 1-2, 0-2, each from its first vertex to its second (so that the facet dofs
    of neighbours agree on meshes with sorted ``t``, as ``MeshTri`` keeps); six interior."""
    j = np.arange(1, 5) / 5
    edges = [np.column_stack([j, 0 * j]), np.column_stack([1 - j, j]),
             np.column_stack([0 * j, j])]
    interior = [(a / 5, b / 5) for b in range(1, 4) for a in range(1, 5 - b)]
    return np.vstack([[[0, 0], [1, 0], [0, 1]], *edges, interior])


P5_POWERS = [(a, d - a) for d in range(6) for a in range(d + 1)]
"""Exponents ``(a, b)`` of the 21 monomials ``x^a y^b`` of degree <= 5."""


def _p5_coefficients(nodes: np.ndarray) -> np.ndarray:
    """Inverse Vandermonde matrix: column ``i`` holds the monomial coefficients of the basis
    function that is 1 at node ``i`` and 0 at the others."""
    return np.linalg.inv(np.array([[x ** a * y ** b for a, b in P5_POWERS] for x, y in nodes]))


class ElementTriP5(ElementH1):
    """Quintic Lagrange triangle: ``phi_i = sum_m C_mi x^a_m y^b_m``, ``C`` the inverse of
    the Vandermonde matrix of the monomials of degree <= 5 at the 21 nodes."""

    nodal_dofs, facet_dofs, interior_dofs, maxdeg = 1, 4, 6, 5
    dofnames = ["u"] * 11
    doflocs = _p5_nodes()
    refdom = RefTri
    _coef = _p5_coefficients(doflocs)

    def lbasis(self, X, i):
        x, y = X
        phi, dx, dy = 0 * x, 0 * x, 0 * x
        for (a, b), c in zip(P5_POWERS, self._coef[:, i]):
            phi = phi + c * x ** a * y ** b
            if a:
                dx = dx + c * a * x ** (a - 1) * y ** b
            if b:
                dy = dy + c * b * x ** a * y ** (b - 1)
        return phi, np.array([dx, dy])


@BilinearForm
def _membrane_uu(u, v, w):
    """Trial u, test u^: ``u_x u^_x + (1 - nu)/2 u_y u^_y`` (unit ``A*``)."""
    return u.grad[0] * v.grad[0] + 0.5 * (1 - w.nu) * u.grad[1] * v.grad[1]


@BilinearForm
def _membrane_vv(u, v, w):
    """Trial v, test v^: ``v_y v^_y + (1 - nu)/2 v_x v^_x``."""
    return u.grad[1] * v.grad[1] + 0.5 * (1 - w.nu) * u.grad[0] * v.grad[0]


@BilinearForm
def _membrane_vu(u, v, w):
    """Trial v, test u^: ``nu v_y u^_x + (1 - nu)/2 v_x u^_y``."""
    return w.nu * u.grad[1] * v.grad[0] + 0.5 * (1 - w.nu) * u.grad[0] * v.grad[1]


def membrane_matrices(membrane: Basis, nu: float):
    """``(K, M)`` of the P5 ``membrane`` basis on ``(u, v)``: the plane-stress stiffness of unit
    ``A*`` (the three forms above) and the mass of unit ``rho h``, both sparse CSR."""
    uu = asm(_membrane_uu, membrane, nu=nu)
    vv = asm(_membrane_vv, membrane, nu=nu)
    vu = asm(_membrane_vu, membrane, nu=nu)
    mass = asm(mass_form, membrane)
    return bmat([[uu, vu], [vu.T, vv]]).tocsr(), block_diag([mass, mass]).tocsr()


# ---------------------------------------------------------------------------------------------
# Meshes
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MeshLevel:
    """Mesh parameters: base square cells of side ``0.05 / n``, each triangle then refined
    (red-green-blue) until its longest edge is ``<= sqrt(2) max(r / c, h_min)`` for every
    grading point ``(r`` the distance from its nearest vertex to the point)."""

    n: float
    c_fold: float
    h_fold: float
    c_load: float
    h_load: float

    @classmethod
    def of(cls, refinement: float) -> MeshLevel:
        """The family ``size(x) = min(0.05, 2 r(x)) / n`` (``n = refinement``, a multiple of
        1/2: :func:`on_grid`), floored at ``h_fold = 1e-6`` at the fold's corners and
        ``h_load = 1e-3`` at the force."""
        c = on_grid(refinement) / 2
        return cls(refinement, c_fold=c, h_fold=1e-6, c_load=c, h_load=1e-3)

    @classmethod
    def plain(cls, n: float, grade_load: bool) -> MeshLevel:
        """Squares of side ``0.05 / n`` (``n`` a multiple of 1/2: :func:`on_grid`), graded
        only towards the force as in :meth:`of` (``grade_load``) or not at all: the meshes a
        finite-element user would take for diaphragm ends, whose fields are smooth at the
        fold's corners (``bench_fold_fe.py``). A floor ``h`` of 1 m grades nothing."""
        on_grid(n)
        no_grading = (1.0, 1.0)
        return cls(n, *no_grading, *((n / 2, 1e-3) if grade_load else no_grading))


def on_grid(n: float) -> float:
    """``n``, checked to be a positive multiple of 1/2: the squares of ``0.05 / n`` m then have
    the fold (0.4 m) and the plates' ends on their grid."""
    if not (n > 0 and (2 * n) % 1 == 0):
        raise ValueError(f"a mesh level must be a positive multiple of 1/2 (the fold on the "
                         f"grid), got {n}")
    return n


def graded_mesh(nx: int, ny: int, lx: float, ly: float, points) -> MeshTri:
    """``nx x ny`` squares on ``[0, lx] x [0, ly]`` (two triangles each), refined until every
    triangle's longest edge is at most ``sqrt(2) max(r / c, h_min)`` for each grading point
    ``(x, y, c, h_min)`` (``fem_clamped.corner_refined_mesh`` with one ``c`` per point)."""
    mesh = MeshTri.init_tensor(np.linspace(0, lx, nx + 1), np.linspace(0, ly, ny + 1))
    while True:
        P = mesh.p[:, mesh.t]
        edges = np.stack([P[:, 0] - P[:, 1], P[:, 1] - P[:, 2], P[:, 2] - P[:, 0]])
        size = np.sqrt((edges ** 2).sum(axis=1)).max(axis=0)
        target = np.full(mesh.t.shape[1], np.inf)
        for x, y, c, h_min in points:
            r = np.sqrt((P[0] - x) ** 2 + (P[1] - y) ** 2).min(axis=0)
            target = np.minimum(target, np.maximum(r / c, h_min))
        marked = np.nonzero(size > np.sqrt(2) * target * (1 + 1e-9))[0]
        if marked.size == 0:
            return MeshTri(np.ascontiguousarray(mesh.p), np.ascontiguousarray(mesh.t))
        mesh = mesh.refined(marked)


def fold_meshes(params: MeshLevel) -> dict[str, MeshTri]:
    """The graded unfolded mesh split along the line: ``{"A": mesh, "B": mesh}`` in each
    plate's local coordinates, with bitwise identical vertices on the line."""
    total = FOLD_X + LENGTHS["B"]
    points = [(FOLD_X, 0.0, params.c_fold, params.h_fold),
              (FOLD_X, LY, params.c_fold, params.h_fold),
              (*LOAD, params.c_load, params.h_load)]
    mesh = graded_mesh(round(total / 0.05 * params.n), round(LY / 0.05 * params.n), total, LY,
                       points)
    centre_x = mesh.p[0, mesh.t].mean(axis=0)
    meshes = {}
    for name, cells, shift in (("A", centre_x < FOLD_X, 0.0), ("B", centre_x > FOLD_X, FOLD_X)):
        t = mesh.t[:, cells]
        used, t_new = np.unique(t, return_inverse=True)
        p = mesh.p[:, used] - np.array([[shift], [0.0]])
        meshes[name] = MeshTri(np.ascontiguousarray(p),
                               np.ascontiguousarray(t_new.reshape(t.shape)))
    return meshes


# ---------------------------------------------------------------------------------------------
# One plate's discretisation
# ---------------------------------------------------------------------------------------------
class FoldPlate:
    """Argyris ``w`` and P5 ``(u, v)`` on one plate; unit-stiffness matrices."""

    def __init__(self, mesh: MeshTri, length: float, line_x: float):
        assert (np.diff(mesh.t, axis=0) > 0).all(), "P5 facet dofs need sorted triangles"
        self.mesh, self.length, self.line_x = mesh, length, line_x
        self.bending = PlateFE(None, None, NU, mesh=mesh)
        self.membrane = Basis(mesh, ElementTriP5(), intorder=10)
        self.K_membrane, self.M_membrane = membrane_matrices(self.membrane, NU)
        self.n_w = self.bending.N
        self.n_m = self.membrane.N
        self.size = self.n_w + 2 * self.n_m

    def dynamic(self, omega: float):
        """``blockdiag(D* K_w - omega^2 rho h M_w, A* K_m - omega^2 rho h M_m)``."""
        return block_diag([D_STAR * self.bending.K - omega ** 2 * RHO_H * self.bending.M,
                           A_STAR * self.K_membrane - omega ** 2 * RHO_H * self.M_membrane])

    # ---- dof bookkeeping (plate-local indices: w, then u, then v) ------------------------
    def edge(self, axis: int, value: float) -> np.ndarray:
        """Boundary facets on ``x_axis = value``."""
        return self.mesh.facets_satisfying(lambda x: np.abs(x[axis] - value) < 1e-12,
                                           boundaries_only=True)

    def u_dofs(self, facets) -> np.ndarray:
        return self.n_w + self.membrane.get_dofs(facets=facets).all()

    def v_dofs(self, facets) -> np.ndarray:
        return self.n_w + self.n_m + self.membrane.get_dofs(facets=facets).all()

    def fixed(self, far_x: float, ends: str) -> np.ndarray:
        """Far edge: simply supported (``w`` and its tangential derivatives at the vertices),
        ``u = v = 0``; ends ``y = 0, LY`` as ``ENDS[ends]``: simply supported (``w, w_x,
        w_xx``) or symmetric (``w_y, w_xy`` at the vertices and the midpoint ``w_n``, so the
        quartic trace of ``w_y`` vanishes), and ``u = 0``, ``v = 0`` or both."""
        far = self.edge(0, far_x)
        end = np.concatenate([self.edge(1, 0.0), self.edge(1, LY)])
        argyris = self.bending.basis
        bending, held = ENDS[ends]
        held_in_plane = [dofs(end) for component, dofs in (("u", self.u_dofs), ("v", self.v_dofs))
                         if component in held]
        return np.unique(np.concatenate([
            argyris.get_dofs(facets=far).all(SS_X_EDGE),
            argyris.get_dofs(facets=end).all(bending) if bending else np.zeros(0, int),
            self.u_dofs(far), self.v_dofs(far), *held_in_plane]))

    def line(self):
        """The line's vertices (sorted by y), its facets (sorted by midpoint y) and the P5
        nodes on it (scalar basis indices and their y, sorted)."""
        facets = self.edge(0, self.line_x)
        vertices = np.unique(self.mesh.facets[:, facets])
        vertices = vertices[np.argsort(self.mesh.p[1, vertices])]
        mid = self.mesh.p[1, self.mesh.facets[:, facets]].mean(axis=0)
        facets = facets[np.argsort(mid)]
        nodes = self.membrane.get_dofs(facets=facets).all()
        y = self.membrane.doflocs[1, nodes]
        order = np.argsort(y)
        return vertices, facets, nodes[order], y[order]

    def line_cells(self, y: np.ndarray) -> np.ndarray:
        """The cell on the line edge holding each ``y`` (no point search on the boundary)."""
        vertices, facets, _, _ = self.line()
        yv = self.mesh.p[1, vertices]
        e = np.clip(np.searchsorted(yv, y, side="right") - 1, 0, len(yv) - 2)
        return self.mesh.f2t[0, facets[e]]

    def probes(self, points: np.ndarray, cells: np.ndarray | None = None):
        """Sparse (n x n_m) values of the P5 basis at ``points`` (2, n) in ``cells``
        (:func:`p5_probes`)."""
        return p5_probes(self.membrane, self.mesh, points, cells)

    def values(self, x: np.ndarray, points: np.ndarray, cells: np.ndarray | None = None):
        """``w``, ``w_x``, ``u``, ``v`` of the plate's part ``x`` of the solution at local
        ``points`` (n, 2), optionally in given ``cells``."""
        w = x[:self.n_w]
        probe = self.probes(points.T, cells)
        return {"w": self.bending.eval_matrix(points.T, cells) @ w,
                "w_x": self.bending.eval_matrix(points.T, cells, what="dx") @ w,
                "u": probe @ x[self.n_w:self.n_w + self.n_m],
                "v": probe @ x[self.n_w + self.n_m:]}

    def normal_x(self, facets) -> np.ndarray:
        """``n_x`` of the normal in the ``u_n`` dof of each line facet
        (:func:`facet_normal_x`)."""
        return facet_normal_x(self.mesh, self.bending, facets)


def p5_probes(basis, mesh: MeshTri, points: np.ndarray, cells: np.ndarray | None = None):
    """Sparse (n x dofs) values of the P5 ``basis`` at ``points`` (2, n) in ``cells``, found
    in ``mesh`` when not given (``Basis.probes`` with the cells given)."""
    if cells is None:
        cells = mesh.element_finder(mapping=basis.mapping)(*points)
    X = basis.mapping.invF(points[:, :, None], tind=cells)
    values = np.array([basis.elem.gbasis(basis.mapping, X, k, tind=cells)[0].value[:, 0]
                       for k in range(basis.Nbfun)])
    rows = np.tile(np.arange(points.shape[1]), basis.Nbfun)
    cols = basis.element_dofs[:, cells].ravel()
    return coo_matrix((values.ravel(), (rows, cols)),
                      shape=(points.shape[1], basis.N)).tocsr()


def facet_normal_x(mesh: MeshTri, bending, facets) -> np.ndarray:
    """``n_x`` of the normal in the ``u_n`` dof of each of ``facets``: the gradient of that
    dof's Argyris basis function (``bending``) at the facet midpoint (its trace vanishes
    there, so the gradient is the normal)."""
    mid = mesh.p[:, mesh.facets[:, facets]].mean(axis=1)
    dx = bending.eval_matrix(mid, mesh.f2t[0, facets], what="dx")
    dofs = bending.basis.facet_dofs[0, facets]
    return np.asarray(dx[np.arange(len(facets)), dofs]).ravel()


# ---------------------------------------------------------------------------------------------
# The fold constraints
# ---------------------------------------------------------------------------------------------
def _hermite_quintic() -> np.ndarray:
    """``C`` (6 monomials x 6) with ``H_k(t) = sum_i C_ik t^i`` the quintic Hermite basis on
    [0, 1] for the data (p(0), p'(0), p''(0), p(1), p'(1), p''(1))."""
    rows = []
    for t in (0.0, 1.0):
        rows += [[t ** i for i in range(6)],
                 [i * t ** (i - 1) if i else 0.0 for i in range(6)],
                 [i * (i - 1) * t ** (i - 2) if i > 1 else 0.0 for i in range(6)]]
    return np.linalg.inv(np.array(rows))


HERMITE = _hermite_quintic()


def trace_weights(plate: FoldPlate, vertices: np.ndarray, y: np.ndarray):
    """The Argyris trace ``w(line_x, y)`` at ``y`` as weights on ``(u, u_y, u_yy)`` of the two
    vertices of the line edge holding each ``y``: ``w = sum_k H_k(t) d_k``, ``t = (y - y0)/L``,
    ``d = (w0, L w0_y, L^2 w0_yy, w1, L w1_y, L^2 w1_yy)``. Returns (dofs, weights), (n, 6)."""
    yv = plate.mesh.p[1, vertices]
    e = np.clip(np.searchsorted(yv, y, side="right") - 1, 0, len(yv) - 2)
    L = yv[e + 1] - yv[e]
    t = (y - yv[e]) / L
    H = np.array([t ** i for i in range(6)]).T @ HERMITE  # (n, 6)
    H[t == 0.0] = [1, 0, 0, 0, 0, 0]  # exact at the vertices (no round-off)
    H[t == 1.0] = [0, 0, 0, 1, 0, 0]
    scale = np.column_stack([np.ones_like(L), L, L ** 2] * 2)
    nodal = plate.bending.basis.nodal_dofs
    dofs = np.column_stack([nodal[ALONG_Y][:, vertices[e]].T,
                            nodal[ALONG_Y][:, vertices[e + 1]].T])
    return dofs, H * scale


def fold_relations(A: FoldPlate, B: FoldPlate, offset_B: int) -> dict[int, tuple]:
    """The slave relations of the module docstring, in full indices (A first, then B):
    ``{slave: (master dofs, weights)}``."""
    vA, fA, nodes_A, yA = A.line()
    vB, fB, nodes_B, yB = B.line()
    assert np.array_equal(A.mesh.p[1, vA], B.mesh.p[1, vB]), "line vertices differ"
    assert len(fA) == len(fB) and np.abs(yA - yB).max() < 1e-13, "line nodes differ"
    relations = {}
    # w_A(0.4, y) = u_B(0, y) at B's P5 nodes; u_A(0.4, y) = -w_B(0, y) at A's
    dofs, weights = trace_weights(A, vA, yB)
    for node, d, c in zip(nodes_B, dofs, weights):
        relations[offset_B + B.n_w + node] = (d, c)
    dofs, weights = trace_weights(B, vB, yA)
    for node, d, c in zip(nodes_A, dofs, weights):
        relations[A.n_w + node] = (offset_B + d, -c)
    # v_B = v_A node by node
    for a, b in zip(nodes_A, nodes_B):
        relations[offset_B + B.n_w + B.n_m + b] = (np.array([A.n_w + A.n_m + a]), np.ones(1))
    # w_B,x = w_A,x: u_x, u_xy at the vertices, u_n (with its normal's sign) at the midpoints
    nodal_A, nodal_B = A.bending.basis.nodal_dofs, B.bending.basis.nodal_dofs
    for row in ACROSS_Y:
        for a, b in zip(nodal_A[row, vA], nodal_B[row, vB]):
            relations[offset_B + b] = (np.array([a]), np.ones(1))
    ratio = B.normal_x(fB) / A.normal_x(fA)
    assert np.allclose(np.abs(ratio), 1.0, atol=1e-9), ratio
    for a, b, r in zip(A.bending.basis.facet_dofs[0, fA], B.bending.basis.facet_dofs[0, fB],
                       np.round(ratio)):
        relations[offset_B + b] = (np.array([a]), np.array([r]))
    return relations


def reduction(size: int, fixed: np.ndarray, relations: dict[int, tuple]):
    """``T`` (size x n) with ``x_full = T x``: identity on the free masters, the relations on
    the slaves (fixed masters dropped), zero rows for fixed dofs. A dof both fixed and slave
    must be a relation among fixed dofs (checked), but for one free master, which it fixes:
    with ``symmetric_diaphragm`` ends each plate's in-plane displacement across the fold is
    held at the fold's end, so the other plate's deflection there, its single master, is 0."""
    is_fixed = np.zeros(size, bool)
    is_fixed[fixed] = True
    for slave, (dofs, weights) in relations.items():
        if is_fixed[slave]:
            free = dofs[(weights != 0.0) & ~is_fixed[dofs]]
            if len(free) == 1:
                is_fixed[free] = True
    is_slave = np.zeros(size, bool)
    is_slave[list(relations)] = True
    masters = np.nonzero(~is_fixed & ~is_slave)[0]
    column = np.full(size, -1)
    column[masters] = np.arange(masters.size)
    rows, cols, vals = [masters], [column[masters]], [np.ones(masters.size)]
    for slave, (dofs, weights) in relations.items():
        keep = (weights != 0.0) & ~is_fixed[dofs]
        assert not is_slave[dofs[keep]].any(), "a slave depends on a slave"
        if is_fixed[slave]:
            assert not keep.any(), f"fixed dof {slave} tied to free dofs"
            continue
        rows.append(np.full(keep.sum(), slave))
        cols.append(column[dofs[keep]])
        vals.append(weights[keep])
    T = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                   shape=(size, masters.size))
    return T.tocsr()


# ---------------------------------------------------------------------------------------------
# The model and its solution
# ---------------------------------------------------------------------------------------------
class FoldModel:
    """Both plates, the constraints ``T`` and the load on the mesh ``MeshLevel.of(refinement)``
    (or on ``refinement`` itself, a :class:`MeshLevel`), for one kind of ends."""

    def __init__(self, refinement: int | MeshLevel, ends: str):
        if ends not in ENDS:
            raise ValueError(f"ends must be one of {sorted(ENDS)}, got {ends!r}")
        t0 = time.perf_counter()
        level = refinement if isinstance(refinement, MeshLevel) else MeshLevel.of(refinement)
        meshes = fold_meshes(level)
        self.n_triangles = sum(mesh.t.shape[1] for mesh in meshes.values())
        self.A = FoldPlate(meshes["A"], LENGTHS["A"], FOLD_X)
        self.B = FoldPlate(meshes["B"], LENGTHS["B"], 0.0)
        self.offset_B = self.A.size
        self.size = self.A.size + self.B.size
        fixed = np.concatenate([self.A.fixed(0.0, ends),
                                self.offset_B + self.B.fixed(LENGTHS["B"], ends)])
        self.T = reduction(self.size, fixed, fold_relations(self.A, self.B, self.offset_B))
        self.load = np.zeros(self.size)
        force = self.A.bending.eval_matrix(np.array(LOAD, float)[:, None])
        self.load[:self.A.n_w] = force.toarray()[0]
        self.t_setup = time.perf_counter() - t0

    @property
    def n_dofs(self) -> int:
        return self.T.shape[1]

    def solve(self, frequency: float) -> np.ndarray:
        """Full solution vector at ``frequency`` (Hz): ``T^T K T x = T^T f`` scaled by the
        diagonal, SuperLU (minimum degree on ``A^T + A``), three steps of iterative
        refinement; ``self.residual`` is the final relative residual."""
        t0 = time.perf_counter()
        omega = 2 * math.pi * frequency
        K = block_diag([self.A.dynamic(omega), self.B.dynamic(omega)]).tocsr()
        Kr = (self.T.T @ K @ self.T).tocsc()
        s = diags(1.0 / np.sqrt(np.abs(Kr.diagonal())))
        Ks = (s @ Kr @ s).tocsc()
        b = s @ (self.T.T @ self.load).astype(complex)
        lu = splu(Ks, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        x = lu.solve(b)
        for _ in range(3):
            x = x + lu.solve(b - Ks @ x)
        self.residual = float(np.linalg.norm(b - Ks @ x) / np.linalg.norm(b))
        self.t_solve = time.perf_counter() - t0
        return self.T @ (s @ x)

    def plate_parts(self, x: np.ndarray) -> dict[str, tuple]:
        """``{plate: (FoldPlate, its part of x)}``."""
        return {"A": (self.A, x[:self.offset_B]), "B": (self.B, x[self.offset_B:])}

    def line_mismatch(self, x: np.ndarray, n: int = 401) -> dict[str, float]:
        """The fold constraints at ``n`` points of the line, each as the largest difference
        relative to the largest value of its two sides: ``u_A = -w_B``, ``v_A = v_B``,
        ``w_A = u_B``, ``w_A,x = w_B,x``."""
        y = np.linspace(0.0, LY, n)
        side = {}
        for name, (plate, xp) in self.plate_parts(x).items():
            points = np.column_stack([np.full(n, plate.line_x), y])
            side[name] = plate.values(xp, points, plate.line_cells(y))
        A, B = side["A"], side["B"]
        return relative_mismatch([("u_A + w_B", A["u"], -B["w"]), ("v_A - v_B", A["v"], B["v"]),
                                  ("w_A - u_B", A["w"], B["u"]),
                                  ("w_A,x - w_B,x", A["w_x"], B["w_x"])])


def relative_mismatch(pairs) -> dict[str, float]:
    """``{key: max |a - b| / max(max |a|, max |b|)}`` for each ``(key, a, b)`` of ``pairs``:
    how well a constraint ``a = b`` sampled along a line holds."""
    return {key: float(np.abs(a - b).max() / max(np.abs(a).max(), np.abs(b).max()))
            for key, a, b in pairs}


@dataclass
class FoldSolution:
    """Fields on the ``inner_grid`` points of each plate and the run's figures."""

    w: dict[str, np.ndarray]
    uv: dict[str, np.ndarray]
    n_dofs: int
    n_triangles: int
    t_setup: float
    t_solve: float
    residual: float
    mismatch: dict[str, float]


def solve_fold(frequency: float, ends: str, refinement: int,
               model: FoldModel | None = None) -> FoldSolution:
    """Solve at ``frequency`` (Hz) with ``ends`` ('diaphragm' or 'roller') on the mesh
    ``MeshLevel.of(refinement)``, reusing ``model`` (built for these) if given."""
    model = model or FoldModel(refinement, ends)
    x = model.solve(frequency)
    w, uv = {}, {}
    for name, (plate, xp) in model.plate_parts(x).items():
        values = plate.values(xp, inner_grid(plate.length))
        w[name], uv[name] = values["w"], np.column_stack([values["u"], values["v"]])
    return FoldSolution(w, uv, model.n_dofs, model.n_triangles, model.t_setup, model.t_solve,
                        model.residual, model.line_mismatch(x))


def folded_fields(frequency: float, ends: str, refinement: int
                  ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """``(w, uv)`` at ``frequency`` (Hz), ``ends`` 'diaphragm' or 'roller', mesh
    ``MeshLevel.of(refinement)`` (2, 3, 4, 6, 8: base cells of 0.05 / refinement m):
    ``w[p]`` complex (225,) along plate ``p``'s normal ``e_z`` and ``uv[p]`` complex (225, 2),
    ``(u, v)`` along its ``(e_x, e_y)``, for ``p`` in "A", "B", at ``inner_grid(L_p, 0.5)``
    in ``p``'s local coordinates (point ``15 i_y + i_x``)."""
    solution = solve_fold(frequency, ends, refinement)
    return solution.w, solution.uv


# ---------------------------------------------------------------------------------------------
# Self-checks
# ---------------------------------------------------------------------------------------------
ROOT = Path(__file__).resolve().parents[1]
FREQUENCIES = (300.0, 1000.0)
LEVELS = (2, 3, 4, 6, 8)
N_TERMS = 600  # the exact solution's harmonics, as tests/test_moving_lines.py
EXACT_ENDS = ("diaphragm", "symmetric")  # the ends tests/exact_prismatic.py solves
# tests/test_moving_lines.py's L fold: {plate: (length, origin, x_axis, thickness, right
# edge)}, {line: {plate: (edge, log10 k)}}, (plate, x0, y0)
L_FOLD = ({"A": (0.4, (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), H, "simply_supported"),
           "B": (0.3, (0.4, 0.0, 0.0), (0.0, 0.0, 1.0), H, "simply_supported")},
          {"F": {"A": ("right", math.inf), "B": ("left", math.inf)}}, ("A", *LOAD))


def exact_fields(frequency: float, ends: str) -> tuple[dict, dict]:
    """``(w, uv)`` of the exact prismatic solution with a moving line and ``ends``
    'diaphragm' or 'symmetric' (``tests/support.folded_reference(..., held=False,
    ends=ends)``) on the same points as :func:`folded_fields`."""
    sys.path.insert(0, str(ROOT / "tests"))
    from support import folded_reference
    from support import inner_grid as support_grid

    reference = folded_reference(*L_FOLD, frequency, False, LY, N_TERMS, ends=ends)
    w, uv = {}, {}
    for name, length in LENGTHS.items():
        points = inner_grid(length)
        assert np.array_equal(points, support_grid(length, LY))
        w[name] = reference.w(name, *points.T)
        uv[name] = np.column_stack([reference.u(name, *points.T),
                                    reference.v(name, *points.T)])
    return w, uv


def relative(a: np.ndarray, b: np.ndarray) -> float:
    """``||a - b|| / ||b||`` over all entries."""
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def richardson(ns: list[int], changes: list[float]) -> float:
    """Error of the finest of three meshes ``ns`` from the two changes between them, for an
    error ``C n^-p``: ``p`` solves ``(n0^-p - n1^-p) / (n1^-p - n2^-p) = d1 / d2`` and the
    error is ``d2 n2^-p / (n1^-p - n2^-p)``; ``d2`` itself if no ``p`` in (0.5, 30) fits."""
    (n0, n1, n2), (d1, d2) = ns, changes

    def mismatch(p):
        return (n0 ** -p - n1 ** -p) / (n1 ** -p - n2 ** -p) - d1 / d2

    if mismatch(0.5) * mismatch(30.0) > 0:
        return d2
    p = brentq(mismatch, 0.5, 30.0)
    return d2 * n2 ** -p / (n1 ** -p - n2 ** -p)


def run_levels(ends: str, levels, frequencies) -> dict[tuple[float, int], FoldSolution]:
    """Solve every level at every frequency (one model per level)."""
    solutions = {}
    for n in levels:
        model = FoldModel(n, ends)
        for frequency in frequencies:
            solutions[frequency, n] = solve_fold(frequency, ends, n, model)
        del model
    return solutions


def field_columns(fields: list[str], levels, values: dict, exact: dict | None = None
                  ) -> tuple[list[str], dict, dict]:
    """The field columns of a convergence table, one row per level ``n`` of ``levels``
    (``values[n]``: ``{field: array}``): each field's relative change from the previous level
    (blank at the first) and, with ``exact``, its error. Returns the rows, the changes
    ``{field: [one per step]}`` and the finest level's errors."""
    changes = {f: [] for f in fields}
    errors, rows, previous = {}, [], None
    for n in levels:
        row = ""
        for f in fields:
            if previous is None:
                row += f" {'':>9}"
            else:
                changes[f].append(relative(values[n][f], previous[f]))
                row += f" {changes[f][-1]:>9.2e}"
        if exact is not None:
            errors = {f: relative(values[n][f], exact[f]) for f in fields}
            row += "".join(f" {errors[f]:>9.2e}" for f in fields)
        rows.append(row)
        previous = values[n]
    return rows, changes, errors


def print_table(ends: str, frequency: float, levels, solutions, exact=None) -> dict:
    """One convergence table; returns the finest level's error estimates (and, with
    ``exact``, its true errors) per field."""
    print(f"\n{ends} ends, {frequency:g} Hz")
    fields = ["w_A", "w_B", "uv_A", "uv_B"]
    head = f"  {'n':>2} {'tri':>6} {'dofs':>7} {'setup':>6} {'solve':>6} {'line':>7} {'resid':>7}"
    head += "".join(f" {'chg ' + f:>9}" for f in fields)
    if exact is not None:
        head += "".join(f" {'err ' + f:>9}" for f in fields)
    print(head)
    values = {n: {"w_A": solutions[frequency, n].w["A"], "w_B": solutions[frequency, n].w["B"],
                  "uv_A": solutions[frequency, n].uv["A"], "uv_B": solutions[frequency, n].uv["B"]}
              for n in levels}
    rows, changes, errors = field_columns(fields, levels, values, exact)
    for n, columns in zip(levels, rows):
        s = solutions[frequency, n]
        print(f"  {n:>2} {s.n_triangles:>6} {s.n_dofs:>7} {s.t_setup:>5.1f}s"
              f" {s.t_solve:>5.1f}s {max(s.mismatch.values()):>7.1e} {s.residual:>7.1e}" + columns)
    estimates = {f: richardson(list(levels[-3:]), changes[f][-2:]) for f in fields}
    print(f"  error estimate of n = {levels[-1]} (Richardson on the last two changes): "
          + ", ".join(f"{f} {estimates[f]:.1e}" for f in fields))
    return {"estimate": estimates, "error": errors}


def save(ends: str, frequency: float, n: int, s: FoldSolution, estimate: dict) -> Path:
    """``fields_<ends>_<freq>.npz``: ``w_A`` (225,), ``w_B`` (225,), ``uv_A`` (225, 2),
    ``uv_B`` (225, 2) complex at ``points_A``, ``points_B`` (225, 2) (``inner_grid``, x
    fastest), and ``frequency``, ``ends``, ``refinement``, ``n_dofs``, ``error_estimate``
    (the Richardson estimates of ``w_A, w_B, uv_A, uv_B``)."""
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / f"fields_{ends}_{frequency:g}.npz"
    np.savez(path, w_A=s.w["A"], w_B=s.w["B"], uv_A=s.uv["A"], uv_B=s.uv["B"],
             points_A=inner_grid(LENGTHS["A"]), points_B=inner_grid(LENGTHS["B"]),
             frequency=frequency, ends=ends, refinement=n, n_dofs=s.n_dofs,
             error_estimate=np.array([estimate[f] for f in ("w_A", "w_B", "uv_A", "uv_B")]))
    return path


def main(levels=LEVELS) -> None:
    """Diaphragm ends against the exact solution, roller ends by self-convergence; columns:
    triangles, free dofs, set-up and solve times (s), the fold constraints' largest relative
    mismatch on the line, the scaled system's residual, the relative L2 change of each field
    from the previous level and (diaphragm) its relative L2 error; saves the finest fields."""
    levels = sorted(levels)
    if len(levels) < 3:
        raise SystemExit("give at least three levels (the error estimate needs two changes)")
    for ends in SELF_CHECKED_ENDS:
        solutions = run_levels(ends, levels, FREQUENCIES)
        for frequency in FREQUENCIES:
            exact = None
            if ends in EXACT_ENDS:
                w, uv = exact_fields(frequency, ends)
                exact = {"w_A": w["A"], "w_B": w["B"], "uv_A": uv["A"], "uv_B": uv["B"]}
            summary = print_table(ends, frequency, levels, solutions, exact)
            path = save(ends, frequency, levels[-1], solutions[frequency, levels[-1]],
                        summary["estimate"])
            print(f"  saved {path}")


TEST_DATA = ROOT / "tests" / "data" / "fem_fold_mixed_ends.npz"
SYMMETRIC_MIXES = ("symmetric_diaphragm", "symmetric_fixed")


LOW_FREQUENCY = 100.0
"""Where the count of a line's wavenumbers is farthest below what its mixed ends need
(``solver.joint_rules.mixed_end_legendre_count``): the roller fields there are test data too."""


def write_test_data(mixed_level: int = 6) -> None:
    """Pack the roller fields :func:`main` saved (``fields_roller_<freq>.npz``, finest level)
    into ``tests/data/fem_fold_mixed_ends.npz``, the reference of
    ``tests/test_moving_lines.py``: ``w_A_300``, ``uv_B_1000``, ... and the error estimates
    ``error_estimate_300``, ``error_estimate_1000``; and, solved here at ``mixed_level``
    (level 4 to 6 changes them by 6e-9 to 3e-7 in ``w``), the fields of the
    :data:`SYMMETRIC_MIXES`, ``symmetric_diaphragm_w_A_300``, ``symmetric_fixed_uv_B_1000``,
    ..., and the roller fields at :data:`LOW_FREQUENCY`, ``w_A_100``, ``uv_B_100``, ... (level
    4 to 6 changes them by 5e-10 and 9e-9 in ``w``; ten minutes in all)."""
    packed = {}
    w, uv = folded_fields(LOW_FREQUENCY, "roller", mixed_level)
    for plate in LENGTHS:
        packed[f"w_{plate}_{LOW_FREQUENCY:g}"] = w[plate]
        packed[f"uv_{plate}_{LOW_FREQUENCY:g}"] = uv[plate]
    for frequency in FREQUENCIES:
        saved = np.load(OUT / f"fields_roller_{frequency:g}.npz")
        for key in ("w_A", "w_B", "uv_A", "uv_B"):
            packed[f"{key}_{frequency:g}"] = saved[key]
        packed[f"error_estimate_{frequency:g}"] = saved["error_estimate"]
        for ends in SYMMETRIC_MIXES:
            w, uv = folded_fields(frequency, ends, mixed_level)
            for plate in LENGTHS:
                packed[f"{ends}_w_{plate}_{frequency:g}"] = w[plate]
                packed[f"{ends}_uv_{plate}_{frequency:g}"] = uv[plate]
    np.savez_compressed(TEST_DATA, **packed)
    print(f"wrote {TEST_DATA}")


ENDS_DATA = {"free": ROOT / "tests" / "data" / "fem_fold_free_ends.npz",
             "sliding": ROOT / "tests" / "data" / "fem_fold_sliding_ends.npz",
             "fixed": ROOT / "tests" / "data" / "fem_fold_fixed_ends.npz"}
FREE_ENDS_FREQUENCIES = (300.0, 1000.0)


def write_ends_data(ends: str, levels: tuple[int, int] = (4, 6)) -> None:
    """The L fold whose line's ends nothing holds along it (``ends``: 'free', nothing fixed on
    ``y = 0, LY``, so the fold line's ends are free corners; or 'sliding', simply supported and
    free in plane), or holds in every direction ('fixed': simply supported and fixed in plane), at
    :data:`FREE_ENDS_FREQUENCIES`, into ``ENDS_DATA[ends]``, the references of
    ``tests/test_free_ends.py``, ``bench/bench_free_ends.py`` and ``tests/test_held_ends.py``:
    at 300 Hz ``w_A``, ``w_B``, ``uv_A``, ``uv_B`` at the finer level, and ``change``, the
    relative L2 change of ``w_A``, ``w_B``, ``uv_A``, ``uv_B`` from the coarser; at 1 kHz the
    same keys ending ``_1000`` (about four minutes each)."""
    packed = {}
    for frequency in FREE_ENDS_FREQUENCIES:
        coarse, fine = (folded_fields(frequency, ends, n) for n in levels)
        change = [relative(fine[0][p], coarse[0][p]) for p in LENGTHS]
        change += [relative(fine[1][p], coarse[1][p]) for p in LENGTHS]
        suffix = "" if frequency == FREE_ENDS_FREQUENCIES[0] else f"_{frequency:g}"
        for plate in LENGTHS:
            packed[f"w_{plate}{suffix}"] = fine[0][plate]
            packed[f"uv_{plate}{suffix}"] = fine[1][plate]
        packed[f"change{suffix}"] = np.array(change)
        print(f"{frequency:g} Hz: changes from level {levels[0]} "
              + ", ".join(f"{c:.1e}" for c in change))
    np.savez_compressed(ENDS_DATA[ends], **packed)
    print(f"wrote {ENDS_DATA[ends]}")


if __name__ == "__main__":
    if sys.argv[1:] == ["--test-data"]:
        write_test_data()
    elif sys.argv[1:] == ["--free-ends"]:
        write_ends_data("free")
    elif sys.argv[1:] == ["--sliding-ends"]:
        write_ends_data("sliding")
    elif sys.argv[1:] == ["--fixed-ends"]:
        write_ends_data("fixed")
    else:
        main([int(n) for n in sys.argv[1:]] or LEVELS)
