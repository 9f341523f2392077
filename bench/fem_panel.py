r"""Finite-element reference for ``cases/stiffened_panel.toml`` (moving junction lines): a skin
of four bays with a stiffener on each of the three inner bay lines, bending and membrane in
every plate, scikit-fem, written apart from the VTCR solver (it imports only the bench's own
finite-element modules ``fem_junction``, ``fem_folded``, ``fem_clamped``).

The structure (the case's model, not its ``[truth]``)
------------------------------------------------------
Steel: ``E* = E (1 + j eta)``, E = 210 GPa, nu = 0.3, rho = 7800 kg/m^3, eta = 0.01; a plate
of thickness ``h`` has ``D* = E* h^3 / (12 (1 - nu^2))``, ``A* = E* h / (1 - nu^2)`` and
``rho h``; time factor ``exp(+j omega t)``. Plate ``p`` occupies its local ``[0, L_p] x [0,
0.4]``, placed by its frame ``(o, e_x, e_y, e_z = e_x x e_y)``; its displacement is the 3D
vector ``u e_x + v e_y + w e_z``:

* B1..B4 (skin bays): ``L = 0.5``, h = 1 mm, ``o = (0.5 (i - 1), 0, 0)``, ``e_x = (1, 0, 0)``,
  ``e_y = (0, 1, 0)``, ``e_z = (0, 0, 1)``;
* T1..T3 (stiffeners): ``L = 0.15``, h = 2 mm, ``o = (0.5 i, 0, 0)``, ``e_x = (0, 0, 1)``,
  ``e_y = (0, 1, 0)``, ``e_z = (0, 0, 1) x (0, 1, 0) = (-1, 0, 0)``.

Weld ``Wi`` is the line ``x = 0.5 i, z = 0`` (direction ``e = (0, 1, 0)``, the ``e_y`` of all
its members, so ``y`` is the same coordinate on all three): ``Bi.right | B(i+1).left |
Ti.left``. ``Bi`` and ``B(i+1)`` are rigid members (``log10 k = inf``), ``Ti`` is tied by a
rotational spring ``k = 10^3.5`` N m/m/rad, loss factor 0 (``k* = k``).

Outer edges: the skin's outline (B1's ``x = 0``, B4's ``x = 0.5``, every bay's ``y = 0`` and
``y = 0.4``) simply supported (``w = 0``) and fixed in plane (``u = v = 0``); the stiffeners'
ends ``y = 0, 0.4`` simply supported and fixed in plane; their tops ``x = 0.15`` free (bending
and in plane: all natural). A unit force along B1's ``e_z = (0, 0, 1)`` acts at B1's ``(0.17,
0.13)``.

Every line (every sign: ``fem_junction``'s, line by line)
--------------------------------------------------------
For weld ``Wi`` write ``S1 = Bi`` (its line at local ``x = 0.5``), ``S2 = B(i+1)`` (line at
``x = 0``), ``T = Ti`` (line at ``x = 0``). The frames are those of ``fem_junction``'s S1, S2,
T1, so its derivation holds unchanged:

*Translation* (3D displacement continuous across the three members):

    u_S1 = u_S2 = -w_T,   v_S1 = v_S2 = v_T,   w_S1 = w_S2 = u_T     on the line.

*Rotation.* About ``e = e_y`` every member turns by ``Theta_p = -w_p,x`` (a Kirchhoff plate
moves the point at ``z'`` by ``theta x (z' e_z)`` with ``t_y = -w_x``); the rigid members
turn with the line, so ``w_S1,x = w_S2,x`` (the skin is ``C^1`` across the line), and the
stiffener's couple ``C_T = k (Theta_line - Theta_T)`` is the energy

    1/2 k int_0^0.4 (w_T,x(0, y) - w_S1,x(0.5, y))^2 dy     per weld.

(Check: the rigid rotation ``theta e`` about the line gives ``w_S = -theta (x - x_line)``
on the skin and ``w_T = -theta z`` on the stiffener: equal ``w_x``, no spring energy.)
The moment balance of each line (``M_S1 - M_S2 - M_T = 0``) and its force balance are
natural: the line forces are the multipliers of the translation constraints.

Weak form (bilinear, no conjugation): ``sum_p`` of every plate's bending and plane-stress
membrane forms minus ``omega^2 rho h`` times its mass, plus the three spring terms, equals
``1 * w^_B1(0.17, 0.13)``, on the space of fields meeting the supports and the ties above
(``fem_junction``'s, with the sum over seven plates and three springs).

Discretisation
--------------
As ``fem_junction``, for three lines. ``w``: Argyris quintics (``fem_clamped``); ``(u, v)``:
P5 Lagrange (``fem_folded.ElementTriP5``). One bending and one membrane mesh of the whole
skin ``[0, 2] x [0, 0.4]``: squares of ``0.05 / n`` (bending) and ``0.05 * 2^min(v2(n), 2)
/ n`` (membrane), two triangles each, refined red-green-blue until the element size is about

* bending: ``min(0.05, 2 r) / n`` towards the six points where the lines meet the supported
  ends (``h_min = 1e-6``) and towards the force (``h_min = 1e-3``);
* membrane: the same at the six line ends, and ``max(0.05 / n, 2 d / n)``, ``d`` the distance
  to the nearest line (the bending traces the line passes to the membranes decay away from
  it);
* both, with ends fixed in plane (this case): also towards the stiffeners' top corners
  ``(x_i + 0.15, 0)``, ``(x_i + 0.15, 0.4)`` (``h_min = 1e-6``), where a free edge meets a
  fixed one (plane stress: the stress is singular there); the skin is refined around those
  points too, at no harm but a few more unknowns.

The two meshes are refined further until they have the same vertices on each line, then cut
into the bays (``x`` in ``[0.5 (i - 1), 0.5 i]``) and the stiffeners (``Ti``: the skin's cells
in ``[0.5 i, 0.5 i + 0.15]``, ``fem_junction.cut``), each shifted to local coordinates: the
members of a line share its vertices. Each bay is its own Argyris plate (Argyris is ``C^2`` at
vertices, so one skin could not jump its moment at a line: ``fem_junction``). The ties are
``fem_junction.line_relations`` (exact master-slave relations: B(i+1)'s ``w, w_x, w_y, w_xy,
w_yy`` at the line vertices and its edge-midpoint ``w_n`` (times -1) slaves of Bi's; Ti's
``u`` at its P5 line nodes the Hermite trace of Bi's ``w``; Bi's and B(i+1)'s ``u`` there
minus Ti's trace of ``w``; ``v`` node by node), applied to each weld with each plate seen at
that line (:func:`at_line`). Each spring term is integrated exactly (5 Gauss points per line
edge). ``T^T K T x = T^T f`` is scaled by its diagonal, factorised by SuperLU and refined
iteratively (``fem_junction``'s recipe), with several loads at once.

The module is parametrised by a :class:`Layout`; :data:`PANEL` is the case,
:data:`T_JUNCTION` ``fem_junction``'s T junction (diaphragm ends, free top), on which
:func:`check_junction` compares this module with ``fem_junction`` on the same meshes.

Self-checks
-----------
``OPENBLAS_NUM_THREADS=1 python bench/fem_panel.py --levels 1 2 3 4 --check-junction`` prints,
per frequency, the relative L2 change of ``w`` and of ``(u, v)`` of each plate between
successive levels on ``fem_folded.inner_grid(L_p, 0.4)`` (15 x 15 points, 2 % in from the
edges), reciprocity (a second unit force on B3 at ``(0.31, 0.27)``: ``w_B3`` there under the
first force against ``w_B1(0.17, 0.13)`` under the second), the relative residual of the
reduced system, and the ties sampled at 401 points of every line (the 3D displacements of
the three members computed from their frames, independently of the hand-derived relations,
and the skin's ``w_x``); ``--check-junction`` first compares with ``fem_junction``. It saves
every level's fields to ``/tmp/fem_panel/fields_panel_<freq>.npz`` (:func:`save`);
``--summary`` prints from them each level's difference from the finest and the Richardson
estimate of ``w``; ``--check-membrane 2 4`` solves level 2 with a membrane four times finer
at the lines (:func:`check_membrane`). Measured on a 2-core AMD EPYC, one BLAS thread,
2026-11-28:

* ``fem_junction``'s T junction (diaphragm ends, free top), level 2, 1 kHz: this module's
  fields against ``fem_junction``'s on the same meshes, 7.7e-11 to 7.9e-11 in ``w`` and
  ``(u, v)`` of S1, S2, T1 (43 928 unknowns both): the generalisation to several lines
  (plates seen at a line, shifted relations, springs at any offset) is exact;
* levels 1, 2, 3, 4: 156 319, 179 386, 714 690, 652 090 unknowns (level 3's membrane mesh is
  uniform at 0.05 / 3, level 4's graded from 0.05: not nested), set-up 14 / 15 / 71 / 76 s,
  a solve 5-9 / 8-11 / 44-63 / 36-58 s, 4.9 GB peak; 9 min 47 s for the twelve solves;
* change of ``w`` from level 3 to 4, per plate: 1.0e-8 to 5.9e-8 (184.8 Hz), 9.1e-8 to
  2.0e-7 (230 Hz), 1.2e-7 to 7.0e-7 (257 Hz, T1), after 1e-4 to 1.8e-3 (1 to 2) and 2.7e-7
  to 8.1e-6 (2 to 3); the Richardson estimate of level 4 from levels 2, 3, 4 is 1.2e-9 to
  1.6e-7 (T1 at 257 Hz). Of ``(u, v)``: 1.7e-7 to 5.4e-6 (184.8 Hz), 9.0e-7 to 5.5e-6
  (230 Hz), 3.4e-6 to 2.0e-5 (257 Hz);
* level 2 with the membrane four times finer towards the lines (495 094 unknowns, 3.7 GB,
  4 min 24 s) against level 4 within 0.05 m of the lines: ``(u, v)`` 2.6e-7 to 1.4e-6,
  2.2e-6 to 6.5e-6, 1.9e-6 to 6.5e-6 at the three frequencies (against level 2 itself up to
  2.5e-4 at 257 Hz): level 4's membrane is converged to a few 1e-6 where the lines drive it;
* reciprocity 5e-14 to 2.3e-9, reduced residual 1.3e-13 to 1.8e-9, line ties (3D
  displacement and the skin's ``w_x``) 2e-12 to 4e-11 of the line's largest values, at every
  level and frequency.

So level 4 is taken as the reference, within about 1e-7 in ``w`` (7e-7 for T1 at 257 Hz) and
about 2e-5 in ``(u, v)``. ``bench/bench_panel.py`` compares vtcr with it; ``bench/README.md``
(section ``bench_panel.py``) holds the comparison.
"""

from __future__ import annotations

import argparse
import copy
import itertools
import math
import resource
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.sparse import block_diag, diags
from scipy.sparse.linalg import splu
from skfem import MeshTri

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fem_folded import SS_X_EDGE, inner_grid, reduction, relative_mismatch, richardson
from fem_junction import (
    JunctionPlate,
    cut,
    line_relations,
    point_grading,
    refined_to,
    split_line_edges,
    spring_matrix,
)

SS_Y_EDGE = ["u", "u_x", "u_xx"]  # Argyris dofs fixed on a simply supported edge y = const
TOL = 1e-12  # coordinates closer than this are the same point
OUT = Path("/tmp/fem_panel")


# ---------------------------------------------------------------------------------------------
# The structure
# ---------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Layout:
    """A skin of bays in a row along ``x`` (local ``[0, L] x [0, ly]`` each), a stiffener
    standing along ``+z`` on every inner bay line (its local ``x`` up from the skin), all
    ends ``y = 0, ly`` simply supported with ``end_in_plane`` fixed ('uv' fixed, 'u'
    diaphragm, 'v' roller), the skin's two far edges simply supported and fixed in plane,
    the stiffeners' tops free; ``loads``: unit forces ``(plate, x, y)`` along its ``e_z``."""

    bays: dict[str, float]
    stiffeners: dict[str, float]
    ly: float
    skin_h: float
    stiffener_h: float
    log10_k: float
    end_in_plane: str
    loads: tuple[tuple[str, float, float], ...]
    spring_loss: float = 0.0

    @property
    def bay_x(self) -> dict[str, float]:
        """Each bay's origin along the skin."""
        starts = itertools.accumulate(self.bays.values(), initial=0.0)
        return dict(zip(self.bays, starts))

    @property
    def lines(self) -> list[float]:
        """The skin's ``x`` of the inner bay lines, one per stiffener."""
        return list(self.bay_x.values())[1:]

    @property
    def width(self) -> float:
        return sum(self.bays.values())

    @property
    def lengths(self) -> dict[str, float]:
        return {**self.bays, **self.stiffeners}

    def welds(self) -> list[tuple[str, str, str, float]]:
        """``(left bay, right bay, stiffener, line x)`` per line."""
        bays = list(self.bays)
        return [(a, b, t, x) for (a, b), t, x in zip(itertools.pairwise(bays), self.stiffeners,
                                                     self.lines)]

    def frame(self, plate: str) -> np.ndarray:
        """Rows ``e_x, e_y, e_z`` of the plate's frame."""
        e_x = np.array([1.0, 0, 0]) if plate in self.bays else np.array([0, 0, 1.0])
        e_y = np.array([0, 1.0, 0])
        return np.array([e_x, e_y, np.cross(e_x, e_y)])


PANEL = Layout(bays={"B1": 0.5, "B2": 0.5, "B3": 0.5, "B4": 0.5},
               stiffeners={"T1": 0.15, "T2": 0.15, "T3": 0.15}, ly=0.4, skin_h=0.001,
               stiffener_h=0.002, log10_k=3.5, end_in_plane="uv",
               loads=(("B1", 0.17, 0.13), ("B3", 0.31, 0.27)))
"""``cases/stiffened_panel.toml``'s model (:func:`check_case` compares with the toml); the
second force is the reciprocity check's."""

T_JUNCTION = Layout(bays={"S1": 0.4, "S2": 0.35}, stiffeners={"T1": 0.1}, ly=0.5,
                    skin_h=0.001, stiffener_h=0.002, log10_k=2.5, end_in_plane="u",
                    loads=(("S1", 0.17, 0.13),))
"""``fem_junction``'s T junction with diaphragm ends and a free top."""

FREQUENCIES = (184.8, 230.0, 257.0)
CASE = Path(__file__).resolve().parents[1] / "cases" / "stiffened_panel.toml"


def check_case(layout: Layout = PANEL, path: Path = CASE) -> None:
    """Assert that :data:`PANEL` is the toml's model (read with ``tomllib``, not the project's
    loader): sizes, frames, thicknesses, material, springs, supports, load, frequencies."""
    import tomllib

    case = tomllib.loads(path.read_text())
    steel = case["materials"]["steel"]
    assert (steel["young_modulus"], steel["poisson_ratio"], steel["density"],
            steel["loss_factor"]) == (210e9, 0.3, 7800.0, 0.01)
    for name, length in layout.lengths.items():
        plate = case["plates"][name]
        assert plate["size"] == [length, layout.ly], name
        h = layout.skin_h if name in layout.bays else layout.stiffener_h
        assert plate["thickness"] == h, name
        frame = layout.frame(name)
        assert plate["frame"]["x_axis"] == list(frame[0]), name
        assert plate["frame"]["y_axis"] == list(frame[1]), name
        x0 = layout.bay_x[name] if name in layout.bays else layout.lines[
            list(layout.stiffeners).index(name)]
        assert plate["frame"]["origin"] == [x0, 0.0, 0.0], name
    for i, (a, b, t, _) in enumerate(layout.welds(), 1):
        joint = case["joints"][f"W{i}"]
        assert joint["between"] == [f"{a}.right", f"{b}.left", f"{t}.left"]
        assert joint["log10_stiffness"] == {a: math.inf, b: math.inf, t: layout.log10_k}
        assert joint.get("loss_factor", 0.0) == layout.spring_loss and not joint.get("held")
    bays = list(layout.bays)
    supported = {f"{bays[0]}.left", f"{bays[-1]}.right"} | {
        f"{p}.{e}" for p in layout.lengths for e in ("bottom", "top")}
    boundaries = {b["edge"]: b for b in case["boundaries"]}
    assert set(boundaries) == supported
    assert all(b["condition"] == "simply_supported" and b.get("in_plane", "fixed") == "fixed"
               for b in boundaries.values())
    (load,) = case["loads"]
    assert (load["plate"], *load["at"], load["amplitude"]) == (*layout.loads[0], 1.0)
    assert tuple(case["frequencies"]) == FREQUENCIES


# ---------------------------------------------------------------------------------------------
# Meshes
# ---------------------------------------------------------------------------------------------
def grading_points(layout: Layout) -> list[tuple[float, float]]:
    """Where the meshes are graded to ``h_min = 1e-6``: the lines' ends and, with ends fixed
    in plane, the stiffeners' top corners (skin coordinates)."""
    points = [(x, y) for x in layout.lines for y in (0.0, layout.ly)]
    if layout.end_in_plane == "uv":
        points += [(x + h, y) for x, h in zip(layout.lines, layout.stiffeners.values())
                   for y in (0.0, layout.ly)]
    return points


def skin_grid(layout: Layout, cell: float) -> MeshTri:
    """Squares of side ``cell`` on the skin, two triangles each, with the lines and the
    stiffeners' tops on the grid exactly (each stretch between them its own ``linspace``)."""
    tops = [x + h for x, h in zip(layout.lines, layout.stiffeners.values())]
    breaks = sorted({0.0, layout.width, *layout.lines, *tops})
    x = np.concatenate([np.linspace(a, b, max(1, round((b - a) / cell)) + 1)[:-1]
                        for a, b in itertools.pairwise(breaks)] + [[layout.width]])
    y = np.linspace(0, layout.ly, round(layout.ly / cell) + 1)
    return MeshTri.init_tensor(x, y)


def skin_meshes(layout: Layout, n: int, line_refinement: int = 1
                ) -> tuple[MeshTri, MeshTri]:
    """The skin's bending and membrane meshes at level ``n`` (module docstring), before they
    are matched on the lines; ``fem_junction.skin_meshes`` for several lines. With
    ``line_refinement`` (a power of 2) the membrane's grading towards the lines is that many
    times finer (size ``max(0.05 / n, 2 d / n) / line_refinement``): a check of the
    membrane's convergence where the lines drive it (its meshes are not nested from level
    to level, and a finer mesh everywhere would not fit in memory)."""
    c = n / 2
    corners = grading_points(layout)
    load_plate, lx, ly = layout.loads[0]
    load = (layout.bay_x[load_plate] + lx, ly)

    def bending(P):
        sizes = [point_grading(P, x, y, c, 1e-6) for x, y in corners]
        return np.minimum.reduce(sizes + [point_grading(P, *load, c, 1e-3)])

    def membrane(P):
        sizes = [point_grading(P, x, y, c, 1e-6) for x, y in corners]
        d = np.min([np.abs(P[0] - x).min(axis=0) for x in layout.lines], axis=0)
        return np.minimum.reduce(sizes + [np.maximum(d / c, 0.05 / n) / line_refinement])

    power = min((n & -n).bit_length() - 1, 2)  # 2-adic valuation of n, at most 2
    return (refined_to(skin_grid(layout, 0.05 / n), bending),
            refined_to(skin_grid(layout, 0.05 * 2 ** power / n), membrane))


def line_ys(mesh: MeshTri, x0: float) -> np.ndarray:
    """Sorted ``y`` of the vertices on ``x = x0``."""
    return np.sort(mesh.p[1, np.abs(mesh.p[0] - x0) < TOL])


def matched_on_lines(a: MeshTri, b: MeshTri, lines: list[float]) -> tuple[MeshTri, MeshTri]:
    """Refine both meshes until they have the same vertices on every line (each refines the
    edges that hold a vertex of the other), then snap them to bitwise equal coordinates."""
    while True:
        changed = False
        for x0 in lines:
            ya, yb = line_ys(a, x0), line_ys(b, x0)
            if ya.size == yb.size and np.abs(ya - yb).max() < TOL:
                continue
            a, b, changed = split_line_edges(a, x0, yb), split_line_edges(b, x0, ya), True
        if not changed:
            break
    pa, pb = a.p.copy(), b.p.copy()
    for x0 in lines:
        ya = line_ys(a, x0)
        on_a, on_b = np.abs(pa[0] - x0) < TOL, np.abs(pb[0] - x0) < TOL
        pa[0, on_a], pb[0, on_b] = x0, x0
        pb[1, on_b] = ya[np.searchsorted(ya, pb[1, on_b] - TOL)]
    return MeshTri(pa, a.t), MeshTri(pb, b.t)


# ---------------------------------------------------------------------------------------------
# Lines: plates seen at a line, spring
# ---------------------------------------------------------------------------------------------
def at_line(plate: JunctionPlate, line_x: float) -> JunctionPlate:
    """``plate`` seen at its line ``x = line_x`` (a shallow copy sharing its bases): every
    ``JunctionPlate`` method that reads the line reads ``line_x``, so a bay with a line on
    each side is seen once per line."""
    view = copy.copy(plate)
    view.line_x = line_x
    return view


def shifted(relations: dict[int, tuple], offset: int) -> dict[int, tuple]:
    """``fem_junction.line_relations`` numbers S1's unknowns from 0: move them to ``offset``."""
    return {slave + offset: (dofs + offset, weights)
            for slave, (dofs, weights) in relations.items()}


# ---------------------------------------------------------------------------------------------
# The model
# ---------------------------------------------------------------------------------------------
class PanelModel:
    """Every plate of ``layout`` on the meshes of level ``n``: matrices, springs, ties,
    supports (``self.T``) and loads. Unknowns: the bays' in order, then the stiffeners'."""

    def __init__(self, layout: Layout, n: int, line_refinement: int = 1):
        t0 = time.perf_counter()
        self.layout, self.n = layout, n
        bending, membrane = matched_on_lines(*skin_meshes(layout, n, line_refinement),
                                             layout.lines)
        pieces = {name: (x0, x0 + layout.bays[name]) for name, x0 in layout.bay_x.items()}
        pieces |= {t: (x, x + layout.stiffeners[t]) for t, x in zip(layout.stiffeners,
                                                                     layout.lines)}
        self.plates, self.offsets, self.size = {}, {}, 0
        for name, (x0, x1) in pieces.items():
            h = layout.skin_h if name in layout.bays else layout.stiffener_h
            plate = JunctionPlate(cut(bending, x0, x1), cut(membrane, x0, x1), h, 0.0)
            self.plates[name], self.offsets[name] = plate, self.size
            self.size += plate.size
        self.n_triangles = {name: (p.mesh.t.shape[1], p.membrane_mesh.t.shape[1])
                            for name, p in self.plates.items()}
        k = 10.0 ** layout.log10_k * (1 + 1j * layout.spring_loss)
        relations, self.spring = {}, None
        for a, b, t, _ in layout.welds():
            members = {"S1": self.seen(a, "right"), "S2": self.seen(b, "left"),
                       "T1": self.seen(t, "left")}
            local = {"S2": self.offsets[b] - self.offsets[a],
                     "T1": self.offsets[t] - self.offsets[a]}
            relations |= shifted(line_relations(members, local), self.offsets[a])
            spring = spring_matrix(members["S1"], members["T1"], self.offsets[t], self.size, k,
                                   offset_S=self.offsets[a])
            self.spring = spring if self.spring is None else self.spring + spring
        self.T = reduction(self.size, self.fixed(), relations)
        self.loads = np.zeros((self.size, len(layout.loads)))
        for j, (name, x, y) in enumerate(layout.loads):
            plate, o = self.plates[name], self.offsets[name]
            self.loads[o:o + plate.n_w, j] = plate.bending.eval_matrix(
                np.array([[x], [y]])).toarray()[0]
        self.t_setup = time.perf_counter() - t0

    def seen(self, name: str, edge: str) -> JunctionPlate:
        """Plate ``name`` seen at its ``left`` (x = 0) or ``right`` (x = L) edge."""
        return at_line(self.plates[name], 0.0 if edge == "left" else
                       self.layout.lengths[name])

    def fixed(self) -> np.ndarray:
        """Full indices of the supported unknowns (module docstring)."""
        layout = self.layout
        end = (SS_Y_EDGE, list(layout.end_in_plane))
        outline = (SS_X_EDGE, ["u", "v"])
        bays = list(layout.bays)
        out = []
        for name, plate in self.plates.items():
            edges = {"y=0": end, f"y={layout.ly}": end}
            if name == bays[0]:
                edges["x=0"] = outline
            if name == bays[-1]:
                edges[f"x={layout.bays[name]}"] = outline
            out.append(self.offsets[name] + plate.fixed(edges))
        return np.concatenate(out)

    def solve(self, frequency: float) -> np.ndarray:
        """Full solutions (size, n_loads) at ``frequency`` (Hz): ``T^T K T x = T^T f`` scaled
        by its diagonal, SuperLU, three steps of iterative refinement; ``self.residual`` the
        final relative residual (worst load), ``self.t_solve`` the time."""
        t0 = time.perf_counter()
        omega = 2 * math.pi * frequency
        K = block_diag([p.dynamic(omega) for p in self.plates.values()]).tocsr() + self.spring
        Kr = (self.T.T @ K @ self.T).tocsc()
        s = diags(1.0 / np.sqrt(np.abs(Kr.diagonal())))
        Ks = (s @ Kr @ s).tocsc()
        del K, Kr
        b = s @ (self.T.T @ self.loads).astype(complex)
        lu = splu(Ks, permc_spec="MMD_AT_PLUS_A", options={"SymmetricMode": True})
        x = lu.solve(b)
        for _ in range(3):
            x = x + lu.solve(b - Ks @ x)
        self.residual = float(np.max(np.linalg.norm(b - Ks @ x, axis=0)
                                     / np.linalg.norm(b, axis=0)))
        self.t_solve = time.perf_counter() - t0
        return self.T @ (s @ x)

    def part(self, name: str, x: np.ndarray) -> np.ndarray:
        plate, o = self.plates[name], self.offsets[name]
        return x[o:o + plate.size]

    def fields(self, x: np.ndarray) -> tuple[dict, dict]:
        """``(w, uv)`` of one load's solution per plate at ``inner_grid(L_p, ly)``."""
        w, uv = {}, {}
        for name, plate in self.plates.items():
            values = plate.values(self.part(name, x), self.grid(name))
            w[name], uv[name] = values["w"], np.column_stack([values["u"], values["v"]])
        return w, uv

    def grid(self, name: str) -> np.ndarray:
        return inner_grid(self.layout.lengths[name], self.layout.ly)

    def w_at(self, x: np.ndarray, name: str, point) -> complex:
        plate = self.plates[name]
        values = plate.values(self.part(name, x), np.array([point], float))
        return complex(values["w"][0])

    def line_mismatch(self, x: np.ndarray, n: int = 401) -> dict[str, float]:
        """Every line's ties at ``n`` points, each the largest difference relative to the
        largest value of its two sides: the 3D displacement of B(i+1) and of Ti against Bi's
        (from the frames, not from the relations' signs) and the skin's slope ``w_x``."""
        y = np.linspace(0.0, self.layout.ly, n)
        out = {}
        for i, (a, b, t, _) in enumerate(self.layout.welds(), 1):
            side = {}
            for name, edge in ((a, "right"), (b, "left"), (t, "left")):
                plate = self.seen(name, edge)
                points = np.column_stack([np.full(n, plate.line_x), y])
                values = plate.values(self.part(name, x), points, True)
                uvw = np.column_stack([values["u"], values["v"], values["w"]])
                side[name] = (uvw @ self.layout.frame(name), values["w_x"])
            for name in (b, t):
                d = np.linalg.norm(side[name][0] - side[a][0], axis=1).max()
                scale = max(np.linalg.norm(side[p][0], axis=1).max() for p in (a, name))
                out[f"W{i} 3D {name}-{a}"] = float(d / scale)
            out |= relative_mismatch([(f"W{i} w_x {b}-{a}", side[b][1], side[a][1])])
        return out


# ---------------------------------------------------------------------------------------------
# Runs
# ---------------------------------------------------------------------------------------------
@dataclass
class LevelSolution:
    """One level at one frequency: fields of the first load, the checks, the run's figures."""

    w: dict[str, np.ndarray]
    uv: dict[str, np.ndarray]
    reciprocity: float
    mismatch: dict[str, float]
    residual: float
    n_dofs: int
    t_setup: float
    t_solve: float
    max_rss_gb: float


def solve_level(model: PanelModel, frequency: float) -> LevelSolution:
    x = model.solve(frequency)
    w, uv = model.fields(x[:, 0])
    reciprocity = math.nan
    if len(model.layout.loads) > 1:
        (p1, *at1), (p2, *at2) = model.layout.loads[:2]
        w21, w12 = model.w_at(x[:, 0], p2, at2), model.w_at(x[:, 1], p1, at1)
        reciprocity = abs(w21 - w12) / abs(w21)
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2 ** 20
    return LevelSolution(w, uv, reciprocity, model.line_mismatch(x[:, 0]), model.residual,
                         model.T.shape[1], model.t_setup, model.t_solve, rss)


def relative(a: np.ndarray, b: np.ndarray) -> float:
    """``||a - b|| / ||b||`` over all entries."""
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


def print_levels(frequency: float, levels, solutions: dict[int, LevelSolution]) -> dict:
    """The convergence table of one frequency; returns the finest level's change per plate
    and field (``{"w_B1": ..., "uv_B1": ...}``)."""
    plates = list(solutions[levels[0]].w)
    print(f"\n{frequency:g} Hz: change of w | (u, v) from the previous level, per plate")
    print(f"  {'n':>2} {'dofs':>7} {'setup':>6} {'solve':>6} {'RSS':>5} {'resid':>7} "
          f"{'recip':>7} {'ties':>7} " + " ".join(f"{p:>17}" for p in plates))
    change = {}
    for previous, n in zip([None, *levels], levels):
        s = solutions[n]
        row = (f"  {n:>2} {s.n_dofs:>7} {s.t_setup:>5.0f}s {s.t_solve:>5.0f}s "
               f"{s.max_rss_gb:>4.1f}G {s.residual:>7.1e} {s.reciprocity:>7.1e} "
               f"{max(s.mismatch.values()):>7.1e} ")
        for p in plates:
            if previous is None:
                row += f" {'':>17}"
                continue
            change[f"w_{p}"] = relative(s.w[p], solutions[previous].w[p])
            change[f"uv_{p}"] = relative(s.uv[p], solutions[previous].uv[p])
            row += f" {change[f'w_{p}']:>8.1e}|{change[f'uv_{p}']:>8.1e}"
        print(row, flush=True)
    finest = solutions[levels[-1]]
    print("  ties at the finest level: " + ", ".join(f"{k} {v:.1e}"
                                                    for k, v in finest.mismatch.items()))
    return change


def save(frequency: float, levels, solutions: dict[int, LevelSolution], change: dict,
         layout: Layout = PANEL) -> Path:
    """``fields_panel_<freq>.npz``: per plate ``p`` ``points_<p>`` (225, 2; local,
    ``inner_grid(L_p, ly)``), and for every level ``n`` ``w_<p>_n<n>`` (225,) and
    ``uv_<p>_n<n>`` (225, 2) complex (first load); ``w_<p>``, ``uv_<p>`` the finest level's;
    ``levels``, ``finest``, ``change_w_<p>`` / ``change_uv_<p>`` (finest against the previous
    level), ``frequency``."""
    OUT.mkdir(parents=True, exist_ok=True)
    path = OUT / f"fields_panel_{frequency:g}.npz"
    data = {"levels": np.array(levels), "finest": levels[-1], "frequency": frequency}
    for p, length in layout.lengths.items():
        data[f"points_{p}"] = inner_grid(length, layout.ly)
        data[f"w_{p}"], data[f"uv_{p}"] = solutions[levels[-1]].w[p], solutions[levels[-1]].uv[p]
        for n in levels:
            data[f"w_{p}_n{n}"], data[f"uv_{p}_n{n}"] = solutions[n].w[p], solutions[n].uv[p]
        data[f"change_w_{p}"] = change.get(f"w_{p}", math.nan)
        data[f"change_uv_{p}"] = change.get(f"uv_{p}", math.nan)
    np.savez(path, **data)
    return path


def summary(frequencies=FREQUENCIES, layout: Layout = PANEL) -> None:
    """From the saved fields: per frequency and plate, each level's difference from the
    finest (w | (u, v)) and the Richardson estimate of the finest ``w``'s error from the last
    three levels (``fem_folded.richardson``; the bending meshes are one h-family, the membrane
    meshes are not: level 3's are finer than level 4's away from the lines, so no Richardson
    estimate of ``(u, v)``)."""
    for frequency in frequencies:
        saved = np.load(OUT / f"fields_panel_{frequency:g}.npz")
        levels = [int(n) for n in saved["levels"]]
        print(f"\n{frequency:g} Hz: difference from level {levels[-1]}, w | (u, v); "
              f"Richardson estimate of w at level {levels[-1]} from levels {levels[-3:]}")
        for p in layout.lengths:
            w, uv = saved[f"w_{p}"], saved[f"uv_{p}"]
            row = "  ".join(f"n{n} {relative(saved[f'w_{p}_n{n}'], w):.1e}|"
                            f"{relative(saved[f'uv_{p}_n{n}'], uv):.1e}" for n in levels[:-1])
            steps = [relative(saved[f"w_{p}_n{b}"], saved[f"w_{p}_n{a}"])
                     for a, b in itertools.pairwise(levels[-3:])]
            print(f"  {p}: {row}  Richardson w {richardson(levels[-3:], steps):.1e}")


def near_lines(layout: Layout, plate: str, points: np.ndarray, d: float = 0.05):
    """Which of the plate's ``points`` lie within ``d`` of one of its lines."""
    if plate in layout.stiffeners:
        return points[:, 0] < d
    bays = list(layout.bays)
    near = np.zeros(len(points), bool)
    if plate != bays[0]:
        near |= points[:, 0] < d
    if plate != bays[-1]:
        near |= points[:, 0] > layout.bays[plate] - d
    return near


def check_membrane(n: int = 4, line_refinement: int = 2, frequencies=FREQUENCIES) -> None:
    """Level ``n`` with the membrane's grading towards the lines ``line_refinement`` times
    finer, against the saved levels: at level ``n`` the change of ``(u, v)`` it brings is
    the error of the saved membrane near the lines. Saves its fields to
    ``fields_panel_<freq>_n<n>_lines<line_refinement>.npz`` (``w_<p>``, ``uv_<p>``,
    ``points_<p>``)."""
    model = PanelModel(PANEL, n, line_refinement)
    print(f"level {n}, membrane {line_refinement} times finer towards the lines: "
          f"{model.T.shape[1]} "
          f"unknowns, triangles (bending, membrane) {model.n_triangles}, setup "
          f"{model.t_setup:.0f} s", flush=True)
    for frequency in frequencies:
        s = solve_level(model, frequency)
        saved = np.load(OUT / f"fields_panel_{frequency:g}.npz")
        levels = [int(m) for m in saved["levels"]]
        print(f"{frequency:g} Hz: solve {s.t_solve:.0f} s, RSS {s.max_rss_gb:.1f} GB, resid "
              f"{s.residual:.1e}, recip {s.reciprocity:.1e}, ties "
              f"{max(s.mismatch.values()):.1e}; difference w | (u, v) from the saved levels")
        for p in PANEL.lengths:
            near = near_lines(PANEL, p, model.grid(p))
            print(f"  {p}: " + "  ".join(
                f"n{m} {relative(saved[f'w_{p}_n{m}'], s.w[p]):.1e}|"
                f"{relative(saved[f'uv_{p}_n{m}'], s.uv[p]):.1e}" for m in levels[1:])
                + "; (u, v) within 0.05 m of a line: " + "  ".join(
                f"n{m} {relative(saved[f'uv_{p}_n{m}'][near], s.uv[p][near]):.1e}"
                for m in levels[1:]),
                flush=True)
        np.savez(OUT / f"fields_panel_{frequency:g}_n{n}_lines{line_refinement}.npz",
                 **{f"w_{p}": s.w[p] for p in PANEL.lengths},
                 **{f"uv_{p}": s.uv[p] for p in PANEL.lengths},
                 **{f"points_{p}": model.grid(p) for p in PANEL.lengths})


def check_junction(level: int = 2, frequency: float = 1000.0) -> None:
    """This module on :data:`T_JUNCTION` against ``fem_junction`` (diaphragm ends, free top)
    at the same level: the same meshes, so the same fields to round-off."""
    from fem_junction import JunctionModel, solve_junction

    reference = solve_junction(frequency, "diaphragm", "free", JunctionModel(level))
    model = PanelModel(T_JUNCTION, level)
    ours = solve_level(model, frequency)
    print(f"T junction, level {level}, {frequency:g} Hz, this module against fem_junction "
          f"({model.T.shape[1]} against {reference.n_dofs} unknowns):")
    for p in T_JUNCTION.lengths:
        grid = inner_grid(T_JUNCTION.lengths[p], T_JUNCTION.ly)
        assert np.array_equal(grid, inner_grid(T_JUNCTION.lengths[p]))
        print(f"  {p}: w {relative(ours.w[p], reference.w[p]):.1e}, "
              f"(u, v) {relative(ours.uv[p], reference.uv[p]):.1e}")
    print("  ties: " + ", ".join(f"{k} {v:.1e}" for k, v in ours.mismatch.items()), flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--levels", type=int, nargs="+", default=[1, 2, 3, 4])
    parser.add_argument("--frequencies", type=float, nargs="+", default=list(FREQUENCIES))
    parser.add_argument("--check-junction", action="store_true")
    parser.add_argument("--no-save", action="store_true")
    parser.add_argument("--summary", action="store_true",
                        help="only print the saved fields' differences and estimates")
    parser.add_argument("--check-membrane", type=int, nargs=2, metavar=("LEVEL", "FACTOR"),
                        help="only solve LEVEL with a membrane FACTOR times finer at the lines")
    args = parser.parse_args()
    if args.summary:
        summary(args.frequencies)
        return
    if args.check_membrane:
        check_membrane(*args.check_membrane, frequencies=args.frequencies)
        return
    check_case()
    if args.check_junction:
        check_junction()
    levels = sorted(args.levels)
    solutions = {}
    for n in levels:
        model = PanelModel(PANEL, n)
        print(f"level {n}: {model.T.shape[1]} unknowns, triangles (bending, membrane) "
              f"{model.n_triangles}, setup {model.t_setup:.0f} s", flush=True)
        for frequency in args.frequencies:
            solutions[frequency, n] = solve_level(model, frequency)
            print(f"  {frequency:g} Hz: solve {model.t_solve:.0f} s", flush=True)
        del model
    for frequency in args.frequencies:
        per_level = {n: solutions[frequency, n] for n in levels}
        change = print_levels(frequency, levels, per_level)
        if not args.no_save:
            print(f"  saved {save(frequency, levels, per_level, change)}")


if __name__ == "__main__":
    main()
