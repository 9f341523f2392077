r"""Finite-element reference for the T junction of ``tests/test_moving_lines.py``
(``T_JUNCTION``): a skin of two plates and a stiffener on a moving line, bending and membrane
in every plate, scikit-fem, written apart from the VTCR solver.

The structure
-------------
Steel (``tests/support.py`` ``MATERIAL``): ``E* = E (1 + j eta)``, E = 210 GPa, nu = 0.3,
rho = 7800 kg/m^3, eta = 0.01; a plate of thickness ``h`` has ``D* = E* h^3 / (12 (1 -
nu^2))``, ``A* = E* h / (1 - nu^2)`` and ``rho h``; time factor ``exp(+j omega t)``. Plate
``p`` occupies its local ``[0, L_p] x [0, 0.5]``, placed by its frame ``(o, e_x, e_y, e_z =
e_x x e_y)``; its displacement is the 3D vector ``u e_x + v e_y + w e_z``:

* S1: ``L = 0.4``, h = 1 mm, ``o = 0``, ``e_x = (1, 0, 0)``, ``e_y = (0, 1, 0)``,
  ``e_z = (0, 0, 1)``;
* S2: ``L = 0.35``, h = 1 mm, ``o = (0.4, 0, 0)``, the same axes;
* T1: ``L = 0.1``, h = 2 mm, ``o = (0.4, 0, 0)``, ``e_x = (0, 0, 1)``, ``e_y = (0, 1, 0)``,
  ``e_z = (0, 0, 1) x (0, 1, 0) = (-1, 0, 0)``.

The line ``Gamma`` (``x = 0.4, z = 0`` in space, direction ``e = (0, 1, 0)``, the ``e_y`` of
every member, so ``y`` is the same coordinate on all three) carries S1's right edge, S2's
left edge and T1's left edge. S1 and S2 are rigid members (``log10 k = inf``): they translate
and turn with the line, so together they are one flat skin ``[0, 0.75] x [0, 0.5]`` (S1 its
part ``x < 0.4``, S2 its part ``x > 0.4``, S2's local ``x`` = skin ``x - 0.4``) whose ``w`` is
``C^1`` across the line but whose moment jumps there by T1's couple (so whose ``w_xx`` jumps).
T1 is tied rigidly in translation and through a
rotational spring ``k = 10^2.5`` N m/m/rad in rotation; ``docs/description.md`` (junction):
``C_i = k_i (1 + j zeta_i) (Theta - theta_i)``, ``loss_factor`` default 0, so ``k* = k``.
``--stiffener-ends free`` leaves T1's ends ``y = 0, 0.5`` free (a stiffener not attached at its
ends; ``tests/test_held_ends.py``).

Outer edges: the skin's ``x = 0`` and ``x = 0.75`` simply supported and fixed in plane
(``u = v = 0``); the ends ``y = 0, 0.5`` of every plate simply supported in bending and, in
plane, shear diaphragms (``u = 0``, ``N_yy = 0`` natural), rollers (``v = 0``, ``N_xy = 0``
natural) or fixed (``u = v = 0``, ``--ends fixed``); T1's top ``x = 0.1`` free (bending and
in plane: all natural) or simply supported and fixed in plane. A unit force along the skin's
``e_z = (0, 0, 1)`` acts at S1's ``(0.17, 0.13)``.

The line (every sign)
---------------------
*Translation.* On ``Gamma`` T1's edge moves with the skin: ``u_S (1,0,0) + v_S (0,1,0) + w_S
(0,0,1) = u_T (0,0,1) + v_T (0,1,0) + w_T (-1,0,0)``, so

    u_S(0.4, y) = -w_T(0, y),   v_S(0.4, y) = v_T(0, y),   w_S(0.4, y) = u_T(0, y).

*Rotation.* A Kirchhoff plate moves its point at ``z'`` along ``e_z`` by ``-z' (w_x e_x +
w_y e_y) + w e_z``; as ``theta x (z' e_z)`` with ``theta = t_x e_x + t_y e_y`` (``e_x x e_z =
-e_y``, ``e_y x e_z = e_x`` in any right-handed frame) this is ``t_y = -w_x``, ``t_x = w_y``.
The rotation about the line's direction ``e = e_y`` (the same vector for all members) is
therefore ``Theta_p = -w_p,x`` for S1, S2 and T1 alike (``tests/exact_prismatic.py``:
``Theta_i = -sigma w_x`` with ``sigma = e_y . e = +1``). Check, the rigid rotation
``theta e`` about the line, displacement ``theta e x (X - (0.4, y, 0))``: on the skin
``(0, 0, -theta (x - 0.4))``, so ``w_S = -theta (x - 0.4)``; on T1 at height ``z`` (its local
``x``) ``(theta z, 0, 0) = w_T e_z`` gives ``w_T = -theta z``: both ``w_x = -theta``, so the
spring below stores nothing, as it must.

The rigid members turn with the line, ``Theta_J = Theta_S = -w_S,x(0.4, y)`` (one value: the
skin's ``w`` is ``C^1`` across the line); T1 has the moment ``C_T = k* (Theta_J - Theta_T)``
and the line the opposite couple, which is the energy

    1/2 k* int_Gamma (Theta_T - Theta_S)^2 dy
        = 1/2 k* int_0^0.5 (w_T,x(0, y) - w_S1,x(0.4, y))^2 dy.

Its variation gives T1's edge moment and the opposite couple on the skin, which the skin's
moment balance across the line takes: ``M_S1 - M_S2 - M_T1 = 0`` with ``M = -D* (w_xx + nu
w_yy)`` on each member's edge (the couples ``M_n (e_z x n)`` of S1's right, S2's left and
T1's left edges are ``+M_S1 e``, ``-M_S2 e``, ``-M_T1 e``).

Weak form (bilinear, no conjugation)
------------------------------------
Find ``(w_p, u_p, v_p)`` (p = S1, S2, T1) in the space ``V`` of fields meeting the essential
conditions, the rigid joint of S1 and S2 (``w, w_x, u, v`` continuous) and the three
translation constraints of T1 such that for every ``(w^_p, u^_p, v^_p)`` in ``V``

    sum_p int_p { D*_p [(1 - nu) w_,ab w^_,ab + nu lap w lap w^] - omega^2 rho h_p w w^
                + A*_p [(1 - nu) eps_ab(u) eps_ab(u^) + nu eps_aa(u) eps_bb(u^)]
                - omega^2 rho h_p (u u^ + v v^) } dA
    + k* int_0^0.5 (w_T,x - w_S1,x)(w^_T,x - w^_S1,x) dy  =  1 * w^_S1(0.17, 0.13).

The line's forces are the multipliers of the translation constraints and do no work in
``V``; the moment balance of the line (``sum C_i = 0``) is natural.

Discretisation
--------------
``w``: Argyris quintics (``fem_clamped.ArgyrisLocal``, ``fem_argyris`` forms); ``(u, v)``:
P5 Lagrange (``fem_folded.ElementTriP5``). Within a plate bending and membrane do not
couple, so each plate has *two* meshes: a bending mesh (uniform cells of ``0.05 / n``, graded
as ``fem_folded``: element size ``min(0.05, 2 r) / n`` towards the two points where the line
meets the ends, floored at 1e-6, and towards the force, floored at 1e-3) and a membrane mesh
graded towards the line (size ``max(0.05 / n, 2 d / n)``, ``d`` the distance to the line,
capped at ``0.05 * 2^min(v2(n), 2) / n``, and graded to the line's ends like the bending
mesh). The in-plane waves are a metre long, but the line drives the membranes with the
bending traces of the other plates, whose content decays like ``exp(-k_y d)`` from the line:
fine there, coarse away (the P5 unknowns would otherwise be 85 % of the total). Both meshes
of the whole skin are refined until they have the same vertices on the line, then cut into
S1 (``x < 0.4``), S2 (``x > 0.4``) and T1 (the skin's cells in ``0.4 < x < 0.5``), each
shifted to its local coordinates: all six meshes share the line's vertices.

S1 and S2 are separate Argyris plates, not one: Argyris is ``C^2`` at its vertices (``w_xx``
is a nodal unknown), so a skin meshed as one plate could not jump its moment at the line's
vertices, and T1's couple would converge like ``1 / n`` (found out the hard way: 45 % off at
n = 4 with a stiff spring). The coupling is exact, as in ``fem_folded``: on a line edge the
Argyris trace of ``w`` is the quintic Hermite interpolant of ``(w, w_y, w_yy)`` at its
vertices, its normal derivative the quartic fixed by ``(w_x, w_xy)`` at the vertices and
``w_n`` at the midpoint, and a P5 trace is any quintic, so these master-slave relations hold
the constraints identically on the line:

* S2's ``u, u_x, u_y, u_xy, u_yy`` at each line vertex = S1's and S2's midpoint ``u_n`` =
  S1's times the ratio of their normals (-1): ``w`` and ``w_x`` continuous, ``w_xx`` free
  on each side;
* every P5 node of T1 on the line has ``u_T`` = S1's Hermite trace of ``w``;
* every P5 node of S1 and of S2 on the line has ``u`` = minus T1's trace of ``w_T``;
* ``v_S2 = v_S1`` and ``v_T = v_S1`` node by node

(``x_full = T x``, ``fem_folded.reduction``). The spring term is integrated exactly (5 Gauss
points per line edge: ``w_x`` is a quartic there). The system ``T^T K T x = T^T f`` is scaled by its
diagonal, factorised by SuperLU and refined iteratively (``fem_folded``'s recipe).

Self-checks
-----------
``OPENBLAS_NUM_THREADS=1 python bench/fem_junction.py --levels 2 3 4 6 8 --frequencies 1000``
prints, per ends, top and frequency, the change of each field between successive levels
and, for diaphragm ends, its error against the exact prismatic solution
(``tests/support.folded_reference``, moving line, 600 harmonics); relative L2 over the 225
points of a plate, ``(u, v)`` together. It saves the finest fields to
``/tmp/fem_T/fields_T_<ends>_<top>_<freq>.npz`` (:func:`save`); ``python
bench/fem_junction.py --test-data`` then packs the 1 kHz roller fields into
``tests/data/fem_junction_roller.npz``, ``--test-data fixed`` the fixed-end ones into
``tests/data/fem_junction_fixed.npz`` (:func:`write_test_data`). Measured with
``--levels 2 4 6 8 --frequencies 1000 3000`` (32 solves, 45 minutes on one core; n = 8 has
5.0e5 unknowns, 80 s set-up, 50 to 125 s per solve, 7.0 GB):

* diaphragm ends, error against the exact solution at n = 4, 6, 8 (w_S1 / w_S2 / w_T1):
  1 kHz free top 1.3e-6 / 3.8e-6 / 1.6e-6, 7.2e-8 / 1.6e-7 / 6.0e-8, 1.1e-8 / 1.8e-8 / 6.2e-9
  (``(u, v)`` at n = 8: 7e-10 to 1.2e-8); fixed top the same in ``w`` and 6.8e-9 to 1.1e-8
  in the skin's ``(u, v)`` but 2.4e-6 in T1's (its in-plane field is small and its mesh
  coarse at the top); 3 kHz, n = 8: ``w`` 6.5e-7 to 1.0e-6, ``(u, v)`` 1.5e-7 to 7.2e-7
  (T1's with the fixed top 5.2e-6);
* the change from n = 6 to 8 overstates the error of n = 8 by 4 to 12 times; the Richardson
  estimate of three levels matches the true error within 10 % in ``w``. Roller ends converge
  like diaphragm ends: at n = 8 the estimates are 6e-9 to 1.8e-8 (``w``, 1 kHz), 6e-7 to
  9e-7 (``w``, 3 kHz), T1's ``(u, v)`` with the fixed top 6e-6 (1 kHz), 1e-5 (3 kHz).
"""

from __future__ import annotations

import argparse
import itertools
import math
import resource
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.sparse import block_diag, coo_matrix, diags
from scipy.sparse.linalg import splu
from skfem import Basis, MeshTri

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fem_clamped import PlateFE
from fem_folded import (
    ETA,
    LY,
    NU,
    RHO,
    SS_X_EDGE,
    E,
    ElementTriP5,
    facet_normal_x,
    field_columns,
    inner_grid,
    membrane_matrices,
    p5_probes,
    reduction,
    relative_mismatch,
    richardson,
    trace_weights,
)

LINE_X = 0.4  # the line in the skin's coordinates (S1's right edge, S2's left)
SKIN_X = 0.75  # S1 + S2
STIFFENER = 0.1  # T1's length
LENGTHS = {"S1": 0.4, "S2": 0.35, "T1": STIFFENER}
THICKNESS = {"skin": 0.001, "T1": 0.002}
LOG10_K = 2.5  # T1's rotational spring (N m/m/rad), lossless (docs: loss_factor default 0)
SPRING_LOSS = 0.0
LOAD = (0.17, 0.13)  # on S1 (= skin coordinates), along e_z = (0, 0, 1), 1 N
END_IN_PLANE = {"diaphragm": ("u",), "roller": ("v",), "fixed": ("u", "v")}
"""The in-plane components fixed on the ends y = 0, LY."""
TOPS = ("free", "fixed")
STIFFENER_ENDS = ("same", "free")
SS_Y_EDGE = ["u", "u_x", "u_xx"]  # Argyris dofs fixed on a simply supported edge y = const
OUT = Path("/tmp/fem_T")
TOL = 1e-12  # coordinates closer than this are the same point


# ---------------------------------------------------------------------------------------------
# Meshes
# ---------------------------------------------------------------------------------------------
def refined_to(mesh: MeshTri, target) -> MeshTri:
    """Refine ``mesh`` (red-green-blue) until every triangle's longest edge is at most
    ``sqrt(2) target(P)``, ``P`` (2, 3, n_t) the vertices of the triangles."""
    while True:
        P = mesh.p[:, mesh.t]
        edges = np.stack([P[:, 0] - P[:, 1], P[:, 1] - P[:, 2], P[:, 2] - P[:, 0]])
        size = np.sqrt((edges ** 2).sum(axis=1)).max(axis=0)
        marked = np.nonzero(size > np.sqrt(2) * target(P) * (1 + 1e-9))[0]
        if marked.size == 0:
            return mesh
        mesh = mesh.refined(marked)


def point_grading(P, x, y, c, h_min):
    """``max(r / c, h_min)``, ``r`` the distance from the nearest vertex to ``(x, y)``."""
    r = np.sqrt((P[0] - x) ** 2 + (P[1] - y) ** 2).min(axis=0)
    return np.maximum(r / c, h_min)


def tensor_mesh(cell: float) -> MeshTri:
    """Squares of side ``cell`` on the skin (``cell`` divides 0.05), two triangles each."""
    return MeshTri.init_tensor(np.linspace(0, SKIN_X, round(SKIN_X / cell) + 1),
                               np.linspace(0, LY, round(LY / cell) + 1))


def segment_mesh(cell: float) -> MeshTri:
    """Near-squares of side about ``cell`` on the skin, two triangles each: each of the skin's
    stretches across ``x`` (S1, T1's foot, the rest of S2) cut into ``round(length / cell)``
    equal cells, so that the line and T1's top stay on the grid for any ``cell``."""
    breaks = [0.0, LINE_X, LINE_X + STIFFENER, SKIN_X]
    x = np.concatenate([np.linspace(a, b, max(1, round((b - a) / cell)) + 1)[:-1]
                        for a, b in itertools.pairwise(breaks)] + [[SKIN_X]])
    return MeshTri.init_tensor(x, np.linspace(0, LY, round(LY / cell) + 1))


GRADINGS = ("reference", "load", "none")
"""How the meshes of a level are graded where the line meets the ends: as the reference's
(module docstring), or not at all, the bending mesh then graded towards the force (``load``)
or uniform (``none``); at an integer level the membrane mesh keeps its coarser cells graded
towards the line, at another it is the bending mesh's grid (:func:`segment_mesh`). The last
two are what a finite-element user would take for diaphragm ends, whose fields are smooth
where the line meets the ends (``bench_fold_fe.py``)."""


def skin_meshes(n: float, grading: str = "reference") -> tuple[MeshTri, MeshTri]:
    """The skin's bending and membrane meshes at level ``n`` (module docstring; an integer
    for ``grading = "reference"``), before they are matched on the line, graded as
    ``grading`` (:data:`GRADINGS`) says."""
    if grading not in GRADINGS:
        raise ValueError(f"grading must be one of {GRADINGS}, got {grading!r}")
    if n != int(n):
        if grading == "reference":
            raise ValueError(f"the reference's levels are integers, got {n}")
        grid = segment_mesh(0.05 / n)
        if grading == "none":
            return grid, grid
        return refined_to(grid, lambda P: point_grading(P, *LOAD, n / 2, 1e-3)), grid
    n = int(n)
    c = n / 2
    corners = [(LINE_X, 0.0), (LINE_X, LY)] if grading == "reference" else []

    def bending(P):
        sizes = [point_grading(P, x, y, c, 1e-6) for x, y in corners]
        if grading != "none":
            sizes.append(point_grading(P, *LOAD, c, 1e-3))
        return np.minimum.reduce(sizes) if sizes else np.full(P.shape[2], np.inf)

    def membrane(P):
        sizes = [point_grading(P, x, y, c, 1e-6) for x, y in corners]
        d = np.abs(P[0] - LINE_X).min(axis=0)
        return np.minimum.reduce(sizes + [np.maximum(d / c, 0.05 / n)])

    power = min((n & -n).bit_length() - 1, 2)  # 2-adic valuation of n, at most 2
    cell = 0.05 * 2 ** power / n
    return (refined_to(tensor_mesh(0.05 / n), bending),
            refined_to(tensor_mesh(cell), membrane))


def line_ys(mesh: MeshTri, x0: float = LINE_X) -> np.ndarray:
    """Sorted ``y`` of the vertices on ``x = x0``."""
    return np.sort(mesh.p[1, np.abs(mesh.p[0] - x0) < TOL])


def matched_on_line(a: MeshTri, b: MeshTri) -> tuple[MeshTri, MeshTri]:
    """Refine both meshes until they have the same vertices on the line (each refines the
    triangles beside a line edge that holds a vertex of the other inside it), then give
    ``b``'s line vertices ``a``'s coordinates bit for bit. Both are refinements of tensor
    meshes whose ``y`` breakpoints along the line are dyadic subdivisions of common cells,
    so this ends."""
    while True:
        ya, yb = line_ys(a), line_ys(b)
        if ya.size == yb.size and np.abs(ya - yb).max() < TOL:
            break
        a, b = split_line_edges(a, LINE_X, yb), split_line_edges(b, LINE_X, ya)
    p = b.p.copy()
    on_line = np.nonzero(np.abs(p[0] - LINE_X) < TOL)[0]
    p[0, on_line] = LINE_X
    p[1, on_line] = ya[np.searchsorted(ya, p[1, on_line] - TOL)]
    p2 = a.p.copy()
    p2[0, np.abs(p2[0] - LINE_X) < TOL] = LINE_X
    return MeshTri(p2, a.t), MeshTri(p, b.t)


def split_line_edges(mesh: MeshTri, x0: float, ys: np.ndarray) -> MeshTri:
    """``mesh`` with the triangles beside every edge on the line ``x = x0`` that holds one of
    ``ys`` strictly inside it refined."""
    facets = mesh.facets_satisfying(lambda x: np.abs(x[0] - x0) < TOL)
    y = np.sort(mesh.p[1, mesh.facets[:, facets]], axis=0)
    holds = np.array([np.any((ys > y0 + TOL) & (ys < y1 - TOL)) for y0, y1 in y.T])
    if not holds.any():
        return mesh
    cells = mesh.f2t[:, facets[holds]].ravel()
    return mesh.refined(np.unique(cells[cells >= 0]))


def cut(skin: MeshTri, x0: float, x1: float) -> MeshTri:
    """The skin's triangles in ``x0 < x < x1``, shifted by ``-x0`` to local coordinates, with
    the vertices within ``TOL`` of the local 0 and ``x1 - x0`` snapped to them."""
    centre = skin.p[0, skin.t].mean(axis=0)
    t = skin.t[:, (centre > x0) & (centre < x1)]
    used, t_new = np.unique(t, return_inverse=True)
    p = skin.p[:, used] - np.array([[x0], [0.0]])
    for value in (0.0, x1 - x0):
        p[0, np.abs(p[0] - value) < TOL] = value
    return MeshTri(np.ascontiguousarray(p), np.ascontiguousarray(t_new.reshape(t.shape)))


PIECES = {"S1": (0.0, LINE_X), "S2": (LINE_X, SKIN_X), "T1": (LINE_X, LINE_X + STIFFENER)}
"""Where each plate's meshes are cut from the skin's (``x0, x1``; local ``x`` = ``x - x0``)."""


# ---------------------------------------------------------------------------------------------
# One plate
# ---------------------------------------------------------------------------------------------
class JunctionPlate:
    """Argyris ``w`` on ``mesh`` and P5 ``(u, v)`` on ``membrane_mesh`` for one plate of
    thickness ``h``, with its line at local ``x = line_x``; unknowns ``w``, then ``u``, then
    ``v``. (``mesh`` and ``bending`` are the names ``fem_folded.trace_weights`` reads.)"""

    def __init__(self, mesh: MeshTri, membrane_mesh: MeshTri, h: float, line_x: float):
        for m in (mesh, membrane_mesh):
            assert (np.diff(m.t, axis=0) > 0).all(), "P5 facet dofs need sorted triangles"
        self.mesh, self.membrane_mesh, self.line_x = mesh, membrane_mesh, line_x
        self.D = E * (1 + 1j * ETA) * h ** 3 / (12 * (1 - NU ** 2))
        self.A = E * (1 + 1j * ETA) * h / (1 - NU ** 2)
        self.rho_h = RHO * h
        self.bending = PlateFE(None, None, NU, mesh=mesh)
        self.membrane = Basis(membrane_mesh, ElementTriP5(), intorder=10)
        self.K_membrane, self.M_membrane = membrane_matrices(self.membrane, NU)
        self.n_w, self.n_m = self.bending.N, self.membrane.N
        self.size = self.n_w + 2 * self.n_m

    def dynamic(self, omega: float):
        """``blockdiag(D* K_w - omega^2 rho h M_w, A* K_m - omega^2 rho h M_m)``."""
        return block_diag([self.D * self.bending.K - omega ** 2 * self.rho_h * self.bending.M,
                           self.A * self.K_membrane - omega ** 2 * self.rho_h * self.M_membrane])

    @staticmethod
    def facets(mesh: MeshTri, axis: int, value: float) -> np.ndarray:
        """Facets of ``mesh`` on ``x_axis = value``."""
        return mesh.facets_satisfying(lambda x: np.abs(x[axis] - value) < TOL)

    def fixed(self, edges: dict[str, tuple[list[str], list[str]]]) -> np.ndarray:
        """Plate-local indices of the fixed unknowns: ``edges`` maps ``"x=a"`` / ``"y=b"`` to
        (Argyris dof names, in-plane components) fixed on that edge."""
        out = []
        for edge, (bending, in_plane) in edges.items():
            axis, value = {"x": 0, "y": 1}[edge[0]], float(edge[2:])
            if bending:
                out.append(self.bending.basis.get_dofs(
                    facets=self.facets(self.mesh, axis, value)).all(bending))
            nodes = self.membrane.get_dofs(
                facets=self.facets(self.membrane_mesh, axis, value)).all()
            for component in in_plane:
                out.append(self.n_w + {"u": 0, "v": self.n_m}[component] + nodes)
        return np.unique(np.concatenate(out))

    def line(self):
        """The line's bending vertices (sorted by y), its bending facets (sorted alike) and
        its P5 nodes (membrane basis indices and their y, sorted)."""
        facets = self.facets(self.mesh, 0, self.line_x)
        vertices = np.unique(self.mesh.facets[:, facets])
        vertices = vertices[np.argsort(self.mesh.p[1, vertices])]
        facets = facets[np.argsort(self.mesh.p[1, self.mesh.facets[:, facets]].mean(axis=0))]
        nodes = self.membrane.get_dofs(
            facets=self.facets(self.membrane_mesh, 0, self.line_x)).all()
        y = self.membrane.doflocs[1, nodes]
        order = np.argsort(y)
        return vertices, facets, nodes[order], y[order]

    def line_cells(self, mesh: MeshTri, y: np.ndarray) -> np.ndarray:
        """The cell of ``mesh`` on the line edge holding each ``y`` (no point search on the
        boundary)."""
        facets = self.facets(mesh, 0, self.line_x)
        mid = mesh.p[1, mesh.facets[:, facets]].mean(axis=0)
        facets = facets[np.argsort(mid)]
        lower = np.sort(mesh.p[1, mesh.facets[:, facets]].min(axis=0))
        e = np.clip(np.searchsorted(lower, y, side="right") - 1, 0, len(lower) - 1)
        return mesh.f2t[0, facets[e]]

    def normal_x(self, facets) -> np.ndarray:
        """``n_x`` of the normal in the ``u_n`` dof of each line facet
        (``fem_folded.facet_normal_x``)."""
        return facet_normal_x(self.mesh, self.bending, facets)

    def probes(self, points: np.ndarray, cells: np.ndarray | None = None):
        """Sparse (n x n_m) values of the P5 basis at ``points`` (2, n), found in the
        membrane's own mesh (``fem_folded.p5_probes``)."""
        return p5_probes(self.membrane, self.membrane_mesh, points, cells)

    def values(self, x: np.ndarray, points: np.ndarray, on_line: bool = False) -> dict:
        """``w``, ``w_x``, ``u``, ``v`` of the plate's part ``x`` of the solution at local
        ``points`` (n, 2); ``on_line``: the points are on the line."""
        cells_w = self.line_cells(self.mesh, points[:, 1]) if on_line else None
        cells_m = self.line_cells(self.membrane_mesh, points[:, 1]) if on_line else None
        w = x[:self.n_w]
        probe = self.probes(points.T, cells_m)
        return {"w": self.bending.eval_matrix(points.T, cells_w) @ w,
                "w_x": self.bending.eval_matrix(points.T, cells_w, what="dx") @ w,
                "u": probe @ x[self.n_w:self.n_w + self.n_m],
                "v": probe @ x[self.n_w + self.n_m:]}


# ---------------------------------------------------------------------------------------------
# The line: constraints and spring
# ---------------------------------------------------------------------------------------------
C1_NODAL = [0, 1, 2, 4, 5]  # Argyris nodal rows u, u_x, u_y, u_xy, u_yy (not u_xx)


def line_relations(plates: dict[str, JunctionPlate], offsets: dict[str, int]
                   ) -> dict[int, tuple]:
    """The slave relations of the module docstring, in full indices: ``{slave: (master
    dofs, weights)}``."""
    S1, S2, T = plates["S1"], plates["S2"], plates["T1"]
    o2, oT = offsets["S2"], offsets["T1"]
    line = {name: plate.line() for name, plate in plates.items()}
    v1, f1, nodes_1, y1 = line["S1"]
    for name in ("S2", "T1"):
        v, _, _, y = line[name]
        assert np.array_equal(S1.mesh.p[1, v1], plates[name].mesh.p[1, v]), "line vertices"
        assert len(y) == len(y1) and np.abs(y - y1).max() < TOL, "line P5 nodes differ"
    v2, f2, nodes_2, _ = line["S2"]
    vT, _, nodes_T, yT = line["T1"]
    relations = {}
    # S2 rigid to S1: w, w_y, w_yy, w_x, w_xy at the vertices, w_n at the midpoints
    nodal_1, nodal_2 = S1.bending.basis.nodal_dofs, S2.bending.basis.nodal_dofs
    for row in C1_NODAL:
        for a, b in zip(nodal_1[row, v1], nodal_2[row, v2]):
            relations[o2 + b] = (np.array([a]), np.ones(1))
    ratio = S2.normal_x(f2) / S1.normal_x(f1)
    assert np.allclose(ratio, -1.0, atol=1e-9), ratio
    for a, b in zip(S1.bending.basis.facet_dofs[0, f1], S2.bending.basis.facet_dofs[0, f2]):
        relations[o2 + b] = (np.array([a]), -np.ones(1))
    # w_S1(0.4, y) = u_T(0, y) at T1's P5 nodes
    dofs, weights = trace_weights(S1, v1, yT)
    for node, d, c in zip(nodes_T, dofs, weights):
        relations[oT + T.n_w + node] = (d, c)
    # u_S(0.4, y) = -w_T(0, y) at S1's and S2's P5 nodes
    dofs, weights = trace_weights(T, vT, y1)
    for node_1, node_2, d, c in zip(nodes_1, nodes_2, dofs, weights):
        relations[S1.n_w + node_1] = (oT + d, -c)
        relations[o2 + S2.n_w + node_2] = (oT + d, -c)
    # v_S2 = v_T = v_S1 node by node
    for a, b, t in zip(nodes_1, nodes_2, nodes_T):
        master = (np.array([S1.n_w + S1.n_m + a]), np.ones(1))
        relations[o2 + S2.n_w + S2.n_m + b] = master
        relations[oT + T.n_w + T.n_m + t] = master
    return relations


def spring_matrix(S: JunctionPlate, T: JunctionPlate, offset_T: int, size: int, k: complex,
                  offset_S: int = 0):
    """``k int (w_T,x(0, y) - w_S,x(0.4, y)) (w^_T,x - w^_S,x) dy`` as a (size x size)
    matrix, ``S`` (S1, the skin member at its line) at ``offset_S`` in the unknowns, ``T``
    (T1, the stiffener) at ``offset_T``: 5 Gauss points on each line edge (exact for the
    quartic ``w_x`` traces)."""
    y = S.mesh.p[1, S.line()[0]]
    assert np.array_equal(y, T.mesh.p[1, T.line()[0]])
    g, gw = np.polynomial.legendre.leggauss(5)
    lengths = np.diff(y)
    yq = (y[:-1, None] + lengths[:, None] * 0.5 * (g + 1)).ravel()
    wq = (lengths[:, None] * 0.5 * gw).ravel()
    rows, cols, vals = [], [], []
    for plate, offset, sign in ((S, offset_S, -1.0), (T, offset_T, 1.0)):
        slope = plate.bending.eval_matrix(np.vstack([np.full(yq.size, plate.line_x), yq]),
                                          plate.line_cells(plate.mesh, yq), what="dx").tocoo()
        rows.append(slope.row)
        cols.append(slope.col + offset)
        vals.append(sign * slope.data)
    B = coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                   shape=(yq.size, size)).tocsr()  # Theta_S - Theta_T
    return (k * (B.T @ diags(wq) @ B)).tocsr()


# ---------------------------------------------------------------------------------------------
# The model
# ---------------------------------------------------------------------------------------------
class JunctionModel:
    """S1, S2 and T1 on the meshes of level ``n``: matrices (independent of the boundary
    conditions), spring, line relations and load; :meth:`reduced` adds the boundary
    conditions of given ends and top. Unknowns: S1's, then S2's, then T1's. ``grading`` as
    for :func:`skin_meshes`."""

    def __init__(self, n: float, grading: str = "reference"):
        t0 = time.perf_counter()
        self.n = n
        bending, membrane = matched_on_line(*skin_meshes(n, grading))
        self.plates, self.offsets, self.size = {}, {}, 0
        for name, (x0, x1) in PIECES.items():
            h = THICKNESS["T1" if name == "T1" else "skin"]
            line_x = LINE_X if name == "S1" else 0.0
            plate = JunctionPlate(cut(bending, x0, x1), cut(membrane, x0, x1), h, line_x)
            self.plates[name], self.offsets[name] = plate, self.size
            self.size += plate.size
        self.n_triangles = {name: (p.mesh.t.shape[1], p.membrane_mesh.t.shape[1])
                            for name, p in self.plates.items()}
        self.spring = spring_matrix(self.plates["S1"], self.plates["T1"], self.offsets["T1"],
                                    self.size, 10.0 ** LOG10_K * (1 + 1j * SPRING_LOSS))
        self.relations = line_relations(self.plates, self.offsets)
        self.load = np.zeros(self.size)
        S1 = self.plates["S1"]
        self.load[:S1.n_w] = S1.bending.eval_matrix(np.array(LOAD, float)[:, None]).toarray()[0]
        self.t_setup = time.perf_counter() - t0

    def reduced(self, ends: str, top: str, stiffener_ends: str = "same"):
        """``T`` (size x n_free) for ``ends`` ('diaphragm', 'roller', 'fixed') and ``top``
        ('free', 'fixed'); ``stiffener_ends`` 'free' leaves T1's ends y = 0, LY free (no
        condition: a stiffener not attached at its ends), 'same' gives them ``ends``."""
        if ends not in END_IN_PLANE or top not in TOPS or stiffener_ends not in STIFFENER_ENDS:
            raise ValueError(f"ends in {sorted(END_IN_PLANE)}, top in {TOPS}, stiffener ends "
                             f"in {STIFFENER_ENDS}: {ends}, {top}, {stiffener_ends}")
        end = (SS_Y_EDGE, list(END_IN_PLANE[ends]))
        support = (SS_X_EDGE, ["u", "v"])  # simply supported, fixed in plane
        edges = {"S1": {"x=0": support},
                 "S2": {f"x={LENGTHS['S2']}": support},
                 "T1": {f"x={STIFFENER}": support} if top == "fixed" else {}}
        ends_of = {name: {} if name == "T1" and stiffener_ends == "free"
                   else {"y=0": end, f"y={LY}": end} for name in edges}
        fixed = [self.offsets[name] + self.plates[name].fixed({**e, **ends_of[name]})
                 for name, e in edges.items() if {**e, **ends_of[name]}]
        return reduction(self.size, np.concatenate(fixed), self.relations)

    def solve(self, frequency: float, T) -> np.ndarray:
        """Full solution at ``frequency`` (Hz) in the constrained space ``T``: ``T^T K T x =
        T^T f`` scaled by the diagonal, SuperLU, three steps of iterative refinement;
        ``self.residual`` the final relative residual, ``self.t_solve`` the time."""
        t0 = time.perf_counter()
        omega = 2 * math.pi * frequency
        K = block_diag([p.dynamic(omega) for p in self.plates.values()]).tocsr() + self.spring
        Kr = (T.T @ K @ T).tocsc()
        s = diags(1.0 / np.sqrt(np.abs(Kr.diagonal())))
        Ks = (s @ Kr @ s).tocsc()
        b = s @ (T.T @ self.load).astype(complex)
        lu = splu(Ks, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        x = lu.solve(b)
        for _ in range(3):
            x = x + lu.solve(b - Ks @ x)
        self.residual = float(np.linalg.norm(b - Ks @ x) / np.linalg.norm(b))
        self.t_solve = time.perf_counter() - t0
        return T @ (s @ x)

    def parts(self, x: np.ndarray) -> dict[str, tuple[JunctionPlate, np.ndarray]]:
        """``{plate: (JunctionPlate, its part of x)}``."""
        return {name: (plate, x[self.offsets[name]:self.offsets[name] + plate.size])
                for name, plate in self.plates.items()}

    def fields(self, x: np.ndarray) -> tuple[dict, dict]:
        """``(w, uv)`` per plate at its ``inner_grid`` (local coordinates)."""
        w, uv = {}, {}
        for name, (plate, xp) in self.parts(x).items():
            values = plate.values(xp, inner_grid(LENGTHS[name]))
            w[name], uv[name] = values["w"], np.column_stack([values["u"], values["v"]])
        return w, uv

    def line_mismatch(self, x: np.ndarray, n: int = 401) -> dict[str, float]:
        """The line constraints at ``n`` points of the line, each as the largest difference
        relative to the largest value of its two sides: T1's translation and S2's ``w``,
        ``w_x``, ``u``, ``v`` against S1's."""
        y = np.linspace(0.0, LY, n)
        side = {name: plate.values(xp, np.column_stack([np.full(n, plate.line_x), y]), True)
                for name, (plate, xp) in self.parts(x).items()}
        S1, S2, T = side["S1"], side["S2"], side["T1"]
        pairs = [("u_S + w_T", S1["u"], -T["w"]), ("v_S - v_T", S1["v"], T["v"]),
                 ("w_S - u_T", S1["w"], T["u"])]
        pairs += [(f"{key}_S1 - {key}_S2", S1[key], S2[key]) for key in ("w", "w_x", "u", "v")]
        return relative_mismatch(pairs)


@dataclass
class JunctionSolution:
    """Fields on the ``inner_grid`` points of S1, S2, T1 and the run's figures."""

    w: dict[str, np.ndarray]
    uv: dict[str, np.ndarray]
    n_dofs: int
    t_setup: float
    t_solve: float
    residual: float
    mismatch: float
    max_rss_gb: float


def solve_junction(frequency: float, ends: str, top: str, model: JunctionModel,
                   T=None) -> JunctionSolution:
    """Solve ``model`` at ``frequency`` with ``ends`` and ``top`` (``T`` reused if given, as
    :meth:`JunctionModel.reduced` makes it)."""
    T = model.reduced(ends, top) if T is None else T
    x = model.solve(frequency, T)
    w, uv = model.fields(x)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2 ** 20
    return JunctionSolution(w, uv, T.shape[1], model.t_setup, model.t_solve, model.residual,
                            max(model.line_mismatch(x).values()), rss)


def junction_fields(frequency: float, ends: str, top: str, refinement: int
                    ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """``(w, uv)`` at ``frequency`` (Hz), ``ends`` 'roller' or 'diaphragm', ``top`` 'free'
    or 'fixed', on the meshes of level ``refinement`` (bending cells 0.05 / refinement m):
    ``w[p]`` complex (225,) along plate ``p``'s ``e_z`` and ``uv[p]`` complex (225, 2),
    ``(u, v)`` along its ``(e_x, e_y)``, for ``p`` in "S1", "S2", "T1", at
    ``inner_grid(L_p, 0.5)`` in ``p``'s local coordinates (point ``15 i_y + i_x``)."""
    solution = solve_junction(frequency, ends, top, JunctionModel(refinement))
    return solution.w, solution.uv


# ---------------------------------------------------------------------------------------------
# Self-checks
# ---------------------------------------------------------------------------------------------
ROOT = Path(__file__).resolve().parents[1]
N_TERMS = 600
FIELDS = ["w_S1", "w_S2", "w_T1", "uv_S1", "uv_S2", "uv_T1"]


def exact_fields(frequency: float, top: str) -> dict[str, np.ndarray]:
    """The exact prismatic solution of ``T_JUNCTION`` (diaphragm ends, moving line; T1's top
    free, or ``simply_supported`` and so fixed in plane) on the points of
    :func:`junction_fields`, keyed as :data:`FIELDS`."""
    sys.path.insert(0, str(ROOT / "tests"))
    from support import folded_reference
    from test_moving_lines import T_JUNCTION

    plates, lines, load = T_JUNCTION
    assert load == ("S1", *LOAD)
    assert lines["W"]["T1"] == ("left", LOG10_K)
    for name, (length, _, _, h, _) in plates.items():
        assert length == LENGTHS[name] and h == THICKNESS["T1" if name == "T1" else "skin"]
    if top == "fixed":
        plates = dict(plates)
        plates["T1"] = (*plates["T1"][:4], "simply_supported")
    reference = folded_reference(plates, lines, load, frequency, False, LY, N_TERMS)
    out = {}
    for name, length in LENGTHS.items():
        points = inner_grid(length)
        out[f"w_{name}"] = reference.w(name, *points.T)
        out[f"uv_{name}"] = np.column_stack([reference.u(name, *points.T),
                                             reference.v(name, *points.T)])
    return out


def as_fields(s: JunctionSolution) -> dict[str, np.ndarray]:
    return {**{f"w_{p}": s.w[p] for p in LENGTHS}, **{f"uv_{p}": s.uv[p] for p in LENGTHS}}


def print_table(title: str, levels, solutions, exact=None) -> dict:
    """One convergence table; returns the finest level's changes, Richardson estimates and
    (with ``exact``) errors per field."""
    print(f"\n{title}", flush=True)
    head = f"  {'n':>2} {'dofs':>7} {'setup':>6} {'solve':>6} {'RSS':>5} {'line':>7} {'resid':>7}"
    head += "".join(f" {'d ' + f:>9}" for f in FIELDS)
    if exact is not None:
        head += "".join(f" {'e ' + f:>9}" for f in FIELDS)
    print(head)
    rows, changes, errors = field_columns(FIELDS, levels,
                                          {n: as_fields(solutions[n]) for n in levels}, exact)
    for n, columns in zip(levels, rows):
        s = solutions[n]
        print(f"  {n:>2} {s.n_dofs:>7} {s.t_setup:>5.0f}s {s.t_solve:>5.0f}s "
              f"{s.max_rss_gb:>4.1f}G {s.mismatch:>7.1e} {s.residual:>7.1e}" + columns,
              flush=True)
    last = {f: changes[f][-1] if changes[f] else math.nan for f in FIELDS}
    estimates = ({f: richardson(list(levels[-3:]), changes[f][-2:]) for f in FIELDS}
                 if len(levels) >= 3 else last)
    print(f"  n = {levels[-1]}: change from n = {levels[-2] if len(levels) > 1 else '-'}: "
          + ", ".join(f"{f} {last[f]:.1e}" for f in FIELDS))
    print("  Richardson estimate: " + ", ".join(f"{f} {estimates[f]:.1e}" for f in FIELDS))
    return {"change": last, "estimate": estimates, "error": errors}


def save(ends: str, top: str, frequency: float, n: int, previous: int,
         s: JunctionSolution, summary: dict) -> Path:
    """``fields_T_<ends>_<top>_<freq>.npz``: ``w_S1, w_S2, w_T1`` (225,) and ``uv_S1, uv_S2,
    uv_T1`` (225, 2) complex at ``points_<p>`` (``inner_grid``, x fastest, local
    coordinates); ``refinement`` (n), ``previous_refinement``, ``fields`` (the order of the
    following arrays), ``change`` (relative L2 change of each field from the previous level:
    the error estimate), ``richardson`` (the Richardson estimates), ``exact_error`` (against
    the exact solution, diaphragm ends; NaN otherwise), ``n_dofs``, ``frequency``, ``ends``,
    ``top``."""
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / f"fields_T_{ends}_{top}_{int(frequency)}.npz"
    error = summary["error"] or {f: math.nan for f in FIELDS}
    np.savez(path, **as_fields(s), **{f"points_{p}": inner_grid(L) for p, L in LENGTHS.items()},
             refinement=n, previous_refinement=previous, fields=np.array(FIELDS),
             change=np.array([summary["change"][f] for f in FIELDS]),
             richardson=np.array([summary["estimate"][f] for f in FIELDS]),
             exact_error=np.array([error[f] for f in FIELDS]),
             n_dofs=s.n_dofs, frequency=frequency, ends=ends, top=top)
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--levels", type=int, nargs="+", default=[2, 3, 4, 6, 8])
    parser.add_argument("--frequencies", type=float, nargs="+", default=[1000.0])
    parser.add_argument("--ends", nargs="+", default=["diaphragm", "roller"])
    parser.add_argument("--tops", nargs="+", default=list(TOPS))
    parser.add_argument("--stiffener-ends", choices=STIFFENER_ENDS, default="same")
    parser.add_argument("--no-save", action="store_true")
    args = parser.parse_args()
    stiffener = "" if args.stiffener_ends == "same" else f"_stiffener_{args.stiffener_ends}"
    levels = sorted(args.levels)
    cases = [(e, t) for e in args.ends for t in args.tops]
    solutions = {}
    for n in levels:
        model = JunctionModel(n)
        print(f"level {n}: triangles (bending, membrane) {model.n_triangles}, "
              f"setup {model.t_setup:.0f} s", flush=True)
        for ends, top in cases:
            T = model.reduced(ends, top, args.stiffener_ends)
            for frequency in args.frequencies:
                solutions[ends, top, frequency, n] = solve_junction(frequency, ends, top,
                                                                    model, T)
        del model
    for ends, top in cases:
        for frequency in args.frequencies:
            exact = (exact_fields(frequency, top)
                     if ends == "diaphragm" and not stiffener else None)
            summary = print_table(f"{ends} ends{stiffener}, {top} top, {frequency:g} Hz", levels,
                                  {n: solutions[ends, top, frequency, n] for n in levels},
                                  exact)
            if not args.no_save and len(levels) > 1:
                path = save(ends + stiffener, top, frequency, levels[-1], levels[-2],
                            solutions[ends, top, frequency, levels[-1]], summary)
                print(f"  saved {path}")


TEST_DATA = ROOT / "tests" / "data" / "fem_junction_roller.npz"
FIXED_TEST_DATA = ROOT / "tests" / "data" / "fem_junction_fixed.npz"
STIFFENER_FREE_TEST_DATA = ROOT / "tests" / "data" / "fem_junction_stiffener_free.npz"


def write_test_data(ends: str = "roller") -> None:
    """Pack fields :func:`main` saved (finest level) into a reference of the tests:
    ``ends = "roller"``, both tops at 1 kHz, into ``tests/data/fem_junction_roller.npz``
    (``tests/test_moving_lines.py``: ``w_S1_free``, ``uv_T1_fixed``, ...); ``ends = "fixed"``,
    the top fixed at 300 Hz and 1 kHz (``--ends fixed --tops fixed --frequencies 300 1000``),
    into ``tests/data/fem_junction_fixed.npz`` (``tests/test_held_ends.py``: ``w_S1_300``,
    ``uv_T1_1000``, ...); ``ends = "stiffener_free"``, the skin's ends fixed, the stiffener's
    ends and top free at 300 Hz and 1 kHz (``--ends fixed --tops free --stiffener-ends free
    --frequencies 300 1000``), into ``tests/data/fem_junction_stiffener_free.npz``, keyed as
    the fixed ones. With each suffix, ``change_<suffix>``: each field's change from the
    previous level, in the order of ``FIELDS``."""
    saved = {"roller": {top: f"fields_T_roller_{top}_1000.npz" for top in TOPS},
             "fixed": {f"{f}": f"fields_T_fixed_fixed_{f}.npz" for f in (300, 1000)},
             "stiffener_free": {f"{f}": f"fields_T_fixed_stiffener_free_free_{f}.npz"
                                for f in (300, 1000)}}[ends]
    packed = {}
    for suffix, name in saved.items():
        fields = np.load(OUT / name)
        packed |= {f"{key}_{suffix}": fields[key] for key in FIELDS}
        packed[f"change_{suffix}"] = fields["change"]
    path = {"roller": TEST_DATA, "fixed": FIXED_TEST_DATA,
            "stiffener_free": STIFFENER_FREE_TEST_DATA}[ends]
    np.savez_compressed(path, **packed)
    print(f"wrote {path}")


if __name__ == "__main__":
    if sys.argv[1:2] == ["--test-data"]:
        write_test_data(*sys.argv[2:3])
    else:
        main()
