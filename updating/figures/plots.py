r"""Figures of an updating run (optional extra ``vtcr[plot]``: matplotlib, Agg backend).

``vtcr update CASE.toml --plot DIR`` writes, into ``DIR``:

* ``cost_<joint>.png`` — :math:`E_{mod}^2`, :math:`E_{int}^2`, :math:`E_{mes}^2` and the
  joint's :math:`E_\Gamma^2` against its :math:`\log_{10}k`, the other joints at their final
  values (the paper's Figs. 6–9 and 14), for every joint corrected in the run;
* ``field_<f>Hz.png`` — :math:`|w|` of the measurements, of the initial and of the updated
  model, plates laid out in the assembly plane, one colour scale (Figs. 12–13);
* ``residuals.png`` — :math:`E_{\Gamma_i}^2` per joint and :math:`E_{mod}^2` per step
  (Table 4); above :data:`~updating.figures.plots_map.MAP_JOINTS` joints, the residual map of the last
  step (:mod:`updating.figures.plots_map`: the joints on the structure's layout, coloured by residual
  over threshold, the corrected ones marked), and ``residuals_initial.png`` that of the first;
* ``frf.png`` — spatial RMS of :math:`|w|` over the measurement points against frequency, for
  the initial, updated (and true) joints, around the analysed frequencies (Fig. 11 right),
  sampled as ``vtcr frf`` samples (refined until the resonance peaks are resolved).

``vtcr frf CASE.toml --band F1 F2 --plot DIR`` writes ``frf.png`` (the sweep's spatial RMS, each
solved frequency marked) and ``power.png`` (injected power, power dissipated in the plates and
in the joints, and the power transmitted by the joints that carry the most).

The module is split in two layers: ``*_data`` functions compute what is drawn (numpy arrays,
no matplotlib; tested on their own), ``draw_*`` functions turn those into a
:class:`matplotlib.figure.Figure`. matplotlib is imported only inside the drawing layer, so
``import updating.figures.plots`` works without it; :func:`require_matplotlib` turns its absence into a
one-line :class:`~updating.data.files.InputError`. Figures are written atomically (a temporary file
in the same directory, then :func:`os.replace`): an interrupted run never leaves a half-written
PNG.

Model fields. The "initial model" and "updated model" panels of the field maps show the
model's own response (the direct problem, r = 0) with the initial and with the identified joint
parameters: the paper's Fig. 13 shows "the response of the updated structure", and only the
model's own response shows how wrong the initial model was. ``field_source="modified"`` draws
instead the field of the modified problem, the minimiser of :math:`E_{mod}^2` at those
parameters (a compromise between the joint laws and the measurements, r = ``[updating] r``):
at the optimum it is close to the updated response, but at the initial parameters the
measurement term pulls it towards the measurements and hides most of the model error. The
frequency response also uses the model's own response (no measurement exists off the analysed
frequencies).
"""

from __future__ import annotations

import math
import textwrap
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from updating.inverse.cost import cost_curve, direct_amplitudes, log_grid
from updating.figures.figure_tools import (
    costs_text,
    field_colours,
    new_figure,
    powers_of_ten_bar,
    require_matplotlib,
    save_figure_atomic,
)
from updating.figures.plots_map import MAP_JOINTS, draw_residual_map, residual_map_data
from updating.figures.plots_space import draw_field_maps_in_space
from updating.inverse.strategy import thresholds
from updating.forward.sweep import (
    FrequencyResponseData,
    frequency_band,
    frequency_response_data,
    plate_deflection,
    spatial_rms,
)

__all__ = [
    "CostCurveData",
    "FieldMapData",
    "ResidualBarsData",
    "SpaceLayout",
    "cost_curve_data",
    "draw_cost_curve",
    "draw_field_maps",
    "draw_frequency_response",
    "draw_power_flow",
    "draw_residual_bars",
    "field_map_data",
    "residual_bars_data",
    "write_curve_figure",
    "write_sweep_figures",
    "write_update_figures",
]

_LOG_K = r"$\log_{10} k$  ($k$ in N·m/m per rad)"





def _true_parameters(case):
    """Joint parameters of ``[truth.joints]`` (None when the description has none)."""
    if not case.truth.joints:
        return None
    return case.true_case().updatable_parameters()


def _true_log_k(case, joint):
    return case.true_log10_stiffness().get(joint)


# ----------------------------------------------------------------------------------------------
# data (no matplotlib)
# ----------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class CostCurveData:
    """One joint's cost curve; costs dimensionless (fractions, drawn in %).

    Attributes
    ----------
    joint : str
    log10_k, e_mod, e_int, e_mes, e_joint : ndarray of float, shape (n,)
    identified, true, initial : float or None
        log10 k marked on the curve (identified value, ``[truth]`` value, model start).
    interval : tuple of float or None
        log10 k range to shade (the confidence interval), labelled ``interval_label``.
    note : str
        What the other joints are held at (subtitle).
    identified_label : str
        Legend of the ``identified`` mark.
    """

    joint: str
    log10_k: np.ndarray
    e_mod: np.ndarray
    e_int: np.ndarray
    e_mes: np.ndarray
    e_joint: np.ndarray
    identified: float | None = None
    true: float | None = None
    initial: float | None = None
    interval: tuple | None = None
    note: str = ""
    identified_label: str = "identified"
    interval_label: str = "interval"


def cost_curve_data(rows, joint, identified=None, true=None, initial=None, interval=None,
                    note="", interval_label="interval"):
    """Arrays of a cost curve from :func:`updating.inverse.cost.cost_curve` rows.

    Parameters
    ----------
    rows : sequence of (log10_k, e_mod, e_int, e_mes, e_joint)
    joint : str
    identified : float, optional
        Marked value; default the curve's minimum of :math:`E_{mod}^2`.

    Returns
    -------
    CostCurveData
    """
    table = np.asarray(rows, dtype=float).reshape(-1, 5)
    order = np.argsort(table[:, 0])
    table = table[order]
    label = "identified"
    if identified is None and len(table):
        identified = float(table[np.argmin(table[:, 1]), 0])
        label = "minimum"
    return CostCurveData(joint, *(table[:, i].copy() for i in range(5)), identified=identified,
                         true=true, initial=initial, interval=interval, note=note,
                         identified_label=label, interval_label=interval_label)


@dataclass(frozen=True)
class SpaceLayout:
    """What a field map draws, placed in 3D by the plates' frames (every plate framed).

    Attributes
    ----------
    surfaces : dict of str to (X, Y, Z)
        Per plate, the 3D coordinates of :attr:`FieldMapData.grids`' points, (ny, nx) each.
    measured : dict of str to ndarray, shape (n, 3)
        The measurement points.
    outlines : dict of str to ndarray, shape (5, 3)
    joints : dict of str to ndarray, shape (2, 3)
        Each joint's line (the first member edge's ends).
    forces : ndarray, shape (n, 3)
        Point forces.
    """

    surfaces: dict
    measured: dict
    outlines: dict
    joints: dict
    forces: np.ndarray


def _space_layout(case, local_grids, measured_points):
    """A :class:`SpaceLayout` from plate-local grids ``{pid: (x, y)}`` and points
    ``{pid: (n, 2)}``, or None unless every plate has a frame."""
    if any(plate.frame is None for plate in case.plates.values()):
        return None
    surfaces = {pid: tuple(np.moveaxis(case.plates[pid].frame.to_space(x, y), -1, 0))
                for pid, (x, y) in local_grids.items()}
    measured = {pid: case.plates[pid].frame.to_space(p[:, 0], p[:, 1])
                for pid, p in measured_points.items()}
    outlines = {}
    for pid, plate in case.plates.items():
        lx, ly = plate.size
        outlines[pid] = plate.frame.to_space(np.array([0.0, lx, lx, 0.0, 0.0]),
                                             np.array([0.0, 0.0, ly, ly, 0.0]))
    joints = {jid: np.array(case.plates[j.sides[0].plate].edge_in_space(j.sides[0].edge)[:2])
              for jid, j in case.joints.items()}
    forces = [case.plates[load.plate].frame.to_space(*load.at)
              for load in case.loads if load.kind == "point_force"]
    return SpaceLayout(surfaces, measured, outlines, joints, np.array(forces).reshape(-1, 3))


@dataclass(frozen=True)
class FieldMapData:
    r"""Measured and model fields at one frequency, in the assembly plane.

    Attributes
    ----------
    frequency : float
        Hz.
    quantity : {"abs", "real"}
        ``|w|`` or ``Re w`` (m).
    grids : dict of str to (X, Y)
        Per plate, assembly-plane coordinates of the evaluation grid, shape (ny, nx) each.
    initial, updated : dict of str to ndarray, shape (ny, nx)
        Model fields on the grids.
    measured : dict of str to (points, values)
        Per plate, plate-local measurement points (n, 2) and the measured quantity (n,).
    measured_global : dict of str to ndarray, shape (n, 2)
        The measurement points in the assembly plane.
    outlines : dict of str to ndarray, shape (5, 2)
        Closed plate outlines in the assembly plane.
    joints : dict of str to ndarray, shape (2, 2)
        Joint lines (end points) in the assembly plane.
    cells : dict of str to (x_edges, y_edges) or None
        When a plate's measurement points form the cell centres of a tensor grid, the
        plate-local cell edges (drawn as cells), else None (drawn as markers).
    e_mod : (float, float)
        :math:`E_{mod}^2` at the initial and updated parameters (summed over the
        ``n_frequencies`` measured frequencies).
    misfit : (float, float)
        Relative misfit :math:`\|w - \tilde w\| / \|\tilde w\|` of the drawn initial and
        updated fields at the measurement points.
    source : {"direct", "modified"}
    n_frequencies : int
    limits : (float, float)
        Common colour range of the three panels: the measured field's (0 to its largest
        value for ``|w|``, symmetric for ``Re w``); model values beyond it saturate, and the
        colour bar says so with arrows.
    loads : (ndarray (n, 2), list of ndarray (2, 2))
        Point forces and loaded edges in the assembly plane, marked on every panel.
    space : SpaceLayout or None
        The same grids, points and lines placed in 3D when every plate has a frame (the
        figure is then drawn in 3D); None for a plane layout.
    """

    frequency: float
    quantity: str
    grids: dict
    initial: dict
    updated: dict
    measured: dict
    measured_global: dict
    outlines: dict
    joints: dict
    cells: dict
    e_mod: tuple
    misfit: tuple
    source: str
    n_frequencies: int
    limits: tuple
    loads: tuple = (np.zeros((0, 2)), [])
    space: SpaceLayout | None = None


def _transform(values, quantity):
    if quantity == "abs":
        return np.abs(values)
    if quantity == "real":
        return np.real(values)
    raise ValueError(f"quantity must be 'abs' or 'real', got {quantity!r}")


def _plate_outline(plate):
    lx, ly = plate.size
    x, y = plate.to_global([0.0, lx, lx, 0.0, 0.0], [0.0, 0.0, ly, ly, 0.0])
    return np.column_stack([x, y])


def _joint_line(case, joint):
    return _edge_line(case, joint.sides[0])


def _edge_line(case, side):
    """End points of a plate edge (``side.plate``, ``side.edge``) in the assembly plane."""
    plate = case.plates[side.plate]
    start, tangent, _, length = plate.edge_frame(side.edge)
    local = np.array([start, start + length * tangent])
    x, y = plate.to_global(local[:, 0], local[:, 1])
    return np.column_stack([x, y])


def _tensor_cells(points, size, tol=1e-9):
    """Cell edges when ``points`` are the cell centres of a tensor grid on ``[0, L]^2``."""
    if len(points) < 2:
        return None
    edges = []
    for axis in range(2):
        values = np.unique(np.round(points[:, axis] / tol) * tol)
        inner = 0.5 * (values[1:] + values[:-1])
        bounds = np.concatenate([[0.0], inner, [size[axis]]])
        centres = 0.5 * (bounds[1:] + bounds[:-1])
        if not np.allclose(centres, values, atol=1e-6 * size[axis]):
            return None
        edges.append(bounds)
    if len(points) != (len(edges[0]) - 1) * (len(edges[1]) - 1):
        return None
    return tuple(edges)


def _grid_counts(size, kappa, points_per_wavelength=12, minimum=24, maximum=160):
    wavelength = 2.0 * math.pi / kappa
    return tuple(int(np.clip(math.ceil(points_per_wavelength * length / wavelength) + 1,
                             minimum, maximum)) for length in size)


def field_map_data(case, problem, measurements, frequency, initial, updated,
                   quantity="abs", source="direct", points_per_wavelength=12):
    r"""Measured, initial and updated fields at one measured frequency.

    Parameters
    ----------
    case : assembly.Case
    problem : updating.inverse.cost.ModifiedProblem
    measurements : updating.data.measurements.Measurements
    frequency : float
        One of ``measurements.frequencies`` (Hz).
    initial, updated : dict
        Joint parameters ``{joint: {log10_stiffness, loss_factor, mass}}``.
    quantity : {"abs", "real"}
        Draw :math:`|w|` or :math:`\mathrm{Re}\,w`.
    source : {"direct", "modified"}
        Model field: the model's own response (r = 0; default, the paper's Fig. 13), or the
        minimiser of :math:`E_{mod}^2` at the parameters (see the module notes).
    points_per_wavelength : int
        Grid density of the model fields (bending wavelength of each plate).

    Returns
    -------
    FieldMapData
    """
    if source not in ("modified", "direct"):
        raise ValueError(f"source must be 'modified' or 'direct', got {source!r}")
    system = problem.frequencies[frequency].system
    evaluations = {"initial": problem.evaluate(initial), "updated": problem.evaluate(updated)}
    fields = {}
    for name, parameters in (("initial", initial), ("updated", updated)):
        if source == "modified":
            s = evaluations[name].interface[frequency]
            fields[name] = problem.field(frequency, s)
        else:
            fields[name] = direct_amplitudes(system, parameters, problem.alpha)
    grids, local_grids, model = {}, {}, {"initial": {}, "updated": {}}
    for pid, plate in case.plates.items():
        nx, ny = _grid_counts(plate.size, system.problems[pid].kappa.real, points_per_wavelength)
        x, y = np.meshgrid(np.linspace(0.0, plate.size[0], nx),
                           np.linspace(0.0, plate.size[1], ny))
        points = np.column_stack([x.ravel(), y.ravel()])
        gx, gy = plate.to_global(x, y)
        grids[pid], local_grids[pid] = (gx, gy), (x, y)
        for name, values in model.items():
            w = plate_deflection(system, fields[name], pid, points)
            values[pid] = _transform(w, quantity).reshape(x.shape)
    measured, measured_global, cells = {}, {}, {}
    residual = {"initial": 0.0, "updated": 0.0}
    reference = 0.0
    for pid, (points, values) in measurements.data[frequency].items():
        points, values = np.asarray(points, dtype=float), np.asarray(values)
        for name in residual:
            w = plate_deflection(system, fields[name], pid, points)
            residual[name] += float(np.sum(np.abs(w - values) ** 2))
        reference += float(np.sum(np.abs(values) ** 2))
        measured[pid] = (points, _transform(values, quantity))
        gx, gy = case.plates[pid].to_global(points[:, 0], points[:, 1])
        measured_global[pid] = np.column_stack([gx, gy])
        cells[pid] = _tensor_cells(points, case.plates[pid].size)
    # the colour range is the measured field's: it is what the model panels are compared with
    # (an initial model three times too strong, or an unmeasured driven plate, would otherwise
    # set the scale and leave the data a third of it); model values beyond it saturate
    every = [v for _, v in measured.values()]
    if quantity == "abs":
        limits = (0.0, max(float(np.max(v)) for v in every))
    else:
        top = max(float(np.max(np.abs(v))) for v in every)
        limits = (-top, top)
    return FieldMapData(
        frequency, quantity, grids, model["initial"], model["updated"], measured,
        measured_global, {pid: _plate_outline(p) for pid, p in case.plates.items()},
        {jid: _joint_line(case, j) for jid, j in case.joints.items()}, cells,
        (evaluations["initial"].e_mod, evaluations["updated"].e_mod),
        tuple(math.sqrt(residual[n] / reference) for n in ("initial", "updated")), source,
        len(problem.frequencies), limits, _load_marks(case),
        _space_layout(case, local_grids, {pid: p for pid, (p, _) in measured.items()}))


def _load_marks(case):
    """Point forces (n, 2) and loaded edges (end points) in the assembly plane."""
    forces = [np.ravel(case.plates[load.plate].to_global([load.at[0]], [load.at[1]]))
              for load in case.loads if load.kind == "point_force"]
    edges = [_edge_line(case, load.edge) for load in case.loads if load.kind != "point_force"]
    return np.array(forces).reshape(-1, 2), edges


@dataclass(frozen=True)
class ResidualBarsData:
    r"""Per-step joint residuals (Table 4), in %.

    Attributes
    ----------
    labels : tuple of str
        One per step (``"initial"``, ``"step 1"``, ...).
    joints : tuple of str
    residuals : ndarray, shape (n_steps, n_joints)
        :math:`E_{\Gamma_i}^2` in %.
    thresholds : ndarray, shape (n_steps, n_joints)
        Each joint's threshold in % (a joint above it stands out:
        :func:`updating.inverse.strategy.thresholds`).
    selected : tuple of (int or None)
        Column of the joint corrected in each step.
    e_mod : ndarray, shape (n_steps,)
        :math:`E_{mod}^2` in %.
    log10_k : ndarray, shape (n_steps, n_joints)
    """

    labels: tuple
    joints: tuple
    residuals: np.ndarray
    thresholds: np.ndarray
    selected: tuple
    e_mod: np.ndarray
    log10_k: np.ndarray


def residual_bars_data(result, stop_ratio=1.0):
    """Arrays of :func:`draw_residual_bars` from an :class:`~updating.inverse.strategy.UpdateResult`."""
    joints = tuple(result.steps[0].parameters)
    labels = tuple("initial" if s.step == 0 else f"step {s.step}" for s in result.steps)
    residuals = np.array([[100.0 * s.residuals[j] for j in joints] for s in result.steps])
    limits = [thresholds(s, stop_ratio) for s in result.steps]
    levels = np.array([[100.0 * at_step[j] for j in joints] for at_step in limits])
    selected = tuple(joints.index(s.selected) if s.selected in joints else None
                     for s in result.steps)
    e_mod = np.array([100.0 * s.e_mod for s in result.steps])
    log10_k = np.array([[s.parameters[j]["log10_stiffness"] for j in joints]
                        for s in result.steps])
    return ResidualBarsData(labels, joints, residuals, levels, selected, e_mod, log10_k)


# ----------------------------------------------------------------------------------------------
# drawing (matplotlib)
# ----------------------------------------------------------------------------------------------

def _positive(values):
    """Values for a log axis: non-positive entries become NaN (gaps, not warnings)."""
    values = np.asarray(values, dtype=float).copy()
    values[~(values > 0)] = np.nan
    return values


def draw_cost_curve(data, title=""):
    """Figure of a :class:`CostCurveData` (log y axis, costs in %)."""
    figure = new_figure(figsize=(7.5, 5.0))
    ax = figure.add_subplot()
    styles = [
        (data.e_mod, r"$E_{mod}^2$ (cost)", {"color": "black", "lw": 2.2}),
        (data.e_int, r"$E_{int}^2$ (interface error)", {"color": "tab:blue", "lw": 1.5}),
        (data.e_mes, r"$E_{mes}^2$ (measurement term)", {"color": "tab:orange", "lw": 1.5}),
        (data.e_joint, rf"$E_\Gamma^2$ of {data.joint}",
         {"color": "tab:green", "lw": 1.5, "ls": "--"}),
    ]
    for values, label, style in styles:
        ax.plot(data.log10_k, _positive(100.0 * values), label=label, **style)
    ax.set_yscale("log")
    if data.interval is not None and data.interval[1] > data.interval[0]:
        ax.axvspan(*data.interval, color="tab:red", alpha=0.08, label=data.interval_label)
    if data.initial is not None:
        ax.axvline(data.initial, color="grey", ls=":", lw=1.3,
                   label=f"model start {data.initial:.2f}")
    if data.identified is not None:
        ax.axvline(data.identified, color="tab:red", lw=1.5,
                   label=f"{data.identified_label} {data.identified:.2f}")
    if data.true is not None:
        ax.axvline(data.true, color="tab:purple", ls="--", lw=1.5, label=f"true {data.true:.2f}")
    ax.set_xlabel(_LOG_K)
    ax.set_ylabel("error [%] (log scale)")
    ax.set_xlim(data.log10_k.min(), data.log10_k.max())
    ax.grid(True, which="major", alpha=0.4)
    ax.grid(True, which="minor", alpha=0.12)
    title = title or f"cost against $\\log_{{10}} k$ of joint {data.joint}"
    ax.set_title(f"{title}\n{data.note}" if data.note else title, fontsize="medium")
    ax.legend(fontsize="small", loc="best", framealpha=0.9)
    return figure


def _draw_plate_frame(ax, data, labels=False):
    """Plate outlines, joint lines (dashed white) and measurement points (black dots)."""
    for pid, outline in data.outlines.items():
        ax.plot(outline[:, 0], outline[:, 1], color="black", lw=0.8)
        if labels:
            corner = outline[0] + 0.04 * (outline[2] - outline[0])
            ax.text(*corner, pid, fontsize="small", ha="left", va="bottom", color="white",
                    fontweight="bold",
                    bbox={"boxstyle": "round,pad=0.15", "fc": "black", "alpha": 0.45, "lw": 0})
    for jid, line in data.joints.items():
        ax.plot(line[:, 0], line[:, 1], color="white", lw=1.2, ls="--")
        if labels:
            ax.text(*line.mean(axis=0), jid, fontsize="small", ha="center", va="center",
                    bbox={"boxstyle": "round,pad=0.15", "fc": "white", "alpha": 0.8, "lw": 0})
    n_points = sum(len(xy) for xy in data.measured_global.values())
    for xy in data.measured_global.values():
        ax.plot(xy[:, 0], xy[:, 1], ".", color="black", ms=3 if n_points < 200 else 1.5)
    forces, edges = data.loads
    for line in edges:
        ax.plot(line[:, 0], line[:, 1], color="tab:orange", lw=3.0, solid_capstyle="butt",
                label="edge load" if labels else None)
    if len(forces):
        ax.plot(forces[:, 0], forces[:, 1], "*", color="tab:orange", ms=13, mec="black",
                mew=0.8, label="point force" if labels else None)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (assembly plane)")
    ax.set_ylabel("y [m]")


def draw_field_maps(data, title=""):
    """Three panels (measured, initial, updated) of a :class:`FieldMapData`, one colour scale;
    in 3D when its plates are placed in space."""
    if data.space is not None:
        return draw_field_maps_in_space(data, title)
    every = np.vstack(list(data.outlines.values()))
    span = every.max(axis=0) - every.min(axis=0)
    stacked = span[0] > 2.2 * span[1]
    ratio = span[1] / span[0]
    if stacked:  # long assemblies: panels one above the other
        width = 8.0
        figsize = (width + 1.6, 3 * (width * ratio + 0.75) + 0.9)
        bar_height = 0.6
        axes = new_figure(figsize=figsize).subplots(3, 1, sharex=True, sharey=True)
    else:
        panel = 4.4
        figsize = (3 * panel + 1.0, panel * ratio + 2.0)
        bar_height = float(np.clip(panel * ratio / (panel * ratio + 1.0), 0.5, 0.9))
        axes = new_figure(figsize=figsize).subplots(1, 3, sharex=True, sharey=True)
    figure = axes[0].figure
    cmap, label = field_colours(data.quantity)
    norm = {"vmin": data.limits[0], "vmax": data.limits[1], "cmap": cmap}
    mappable = None
    ax = axes[0]
    for pid, (points, values) in data.measured.items():
        cells = data.cells.get(pid)
        plate_outline = data.outlines[pid]
        if cells is not None:
            xe, ye = np.meshgrid(*cells)
            origin = plate_outline[0]
            # plate-local cell corners -> assembly plane (same affine map as the outline)
            ex = (plate_outline[1] - origin) / cells[0][-1]
            ey = (plate_outline[3] - origin) / cells[1][-1]
            gx = origin[0] + ex[0] * xe + ey[0] * ye
            gy = origin[1] + ex[1] * xe + ey[1] * ye
            nx, ny = len(cells[0]) - 1, len(cells[1]) - 1
            grid = np.full((ny, nx), np.nan)
            ix = np.searchsorted(cells[0], points[:, 0]) - 1
            iy = np.searchsorted(cells[1], points[:, 1]) - 1
            grid[iy, ix] = values
            mappable = ax.pcolormesh(gx, gy, grid, shading="flat", **norm)
        else:
            xy = data.measured_global[pid]
            mappable = ax.scatter(xy[:, 0], xy[:, 1], c=values, s=40, marker="s",
                                  edgecolors="none", **norm)
    for pid, outline in data.outlines.items():
        if pid not in data.measured:
            ax.text(*outline[:4].mean(axis=0), "not measured", ha="center", va="center",
                    color="grey", fontsize="small")
    ax.set_title(f"measured\n{sum(len(v) for _, v in data.measured.values())} points")
    for ax, name in ((axes[1], "initial"), (axes[2], "updated")):
        fields = getattr(data, name)
        for pid, (gx, gy) in data.grids.items():
            mappable = ax.pcolormesh(gx, gy, fields[pid], shading="gouraud", **norm)
        i = 0 if name == "initial" else 1
        ax.set_title(f"{name} model\nmisfit {100 * data.misfit[i]:.1f} %")
    for i, ax in enumerate(axes):
        _draw_plate_frame(ax, data, labels=(i == 0))
        ax.set_facecolor("whitesmoke")
        if stacked and i < 2:
            ax.set_xlabel("")
        if not stacked and i > 0:
            ax.set_ylabel("")
    if len(data.loads[0]) or data.loads[1]:
        axes[0].legend(fontsize="small", loc="lower right", framealpha=0.8)
    # pad and fraction are relative to all three panels: keep the bar close to them
    low = min(float(np.min(f[pid])) for f in (data.initial, data.updated) for pid in f)
    high = max(float(np.max(f[pid])) for f in (data.initial, data.updated) for pid in f)
    extend = {(False, False): "neither", (False, True): "max", (True, False): "min",
              (True, True): "both"}[low < data.limits[0], high > data.limits[1]]
    bar = figure.colorbar(mappable, ax=list(axes), label=label, pad=0.015, fraction=0.03,
                          shrink=bar_height, extend=extend)
    powers_of_ten_bar(bar)
    source = ("model panels: minimisers of $E_{mod}^2$ at the initial and updated joints"
              if data.source == "modified" else
              "model panels: response of the model with the initial and updated joints")
    costs = costs_text(data)
    misfit = r"misfit = $\|w - \tilde w\| / \|\tilde w\|$ there"
    figure.suptitle(f"{title or 'field'} at {data.frequency:g} Hz; {costs}\n{source}; dots: "
                    f"measurement points; {misfit}", fontsize="medium")
    return figure


def draw_residual_bars(data, title=""):
    r"""Draw grouped bars of :math:`E_{\Gamma_i}^2` per step and :math:`E_{mod}^2` (Table 4)."""
    from matplotlib.patches import Patch

    n_bars = len(data.labels) * max(1, len(data.joints))
    figure = new_figure(figsize=(float(np.clip(0.45 * n_bars + 3.0, 7.0, 14.0)), 6.5))
    top, bottom = figure.subplots(2, 1, sharex=True, height_ratios=(2.2, 1.0))
    n_steps, n_joints = data.residuals.shape
    width = 0.8 / max(n_joints, 1)
    colours = [f"C{i % 10}" for i in range(n_joints)]
    x = np.arange(n_steps)
    for j, joint in enumerate(data.joints):
        offsets = x - 0.4 + (j + 0.5) * width
        chosen = np.array([s == j for s in data.selected])
        top.bar(offsets, _positive(data.residuals[:, j]), width, color=colours[j],
                edgecolor=np.where(chosen, "black", colours[j]).tolist(),
                linewidth=np.where(chosen, 2.0, 0.5).tolist(),
                hatch=None, label=joint)
        top.plot(offsets, _positive(data.thresholds[:, j]), "_", color="black", ms=10, mew=1.5)
    top.set_yscale("log")
    top.set_ylabel(r"$E_{\Gamma_i}^2$ [%] (log scale)")
    handles = [Patch(color=c, label=j) for c, j in zip(colours, data.joints)]
    handles.append(Patch(facecolor="white", edgecolor="black", linewidth=2.0,
                         label="joint corrected in the step"))
    from matplotlib.lines import Line2D

    handles.append(Line2D([], [], marker="_", ls="none", color="black", ms=10, mew=1.5,
                          label="threshold (stands out above)"))
    top.legend(handles=handles, fontsize="small", loc="upper left", bbox_to_anchor=(1.01, 1.0))
    top.grid(True, axis="y", which="major", alpha=0.4)
    width = int(figure.get_figwidth() * 11)  # characters per title line
    title = "\n".join(textwrap.fill(line, width) for line in
                      (title or "joint residuals per step").splitlines())
    figure.suptitle(title, fontsize="medium")
    bottom.plot(x, data.e_mod, "o-", color="black")
    for i, value in enumerate(data.e_mod):
        bottom.annotate(f"{value:.2f} %", (x[i], value), xytext=(0, 6),
                        textcoords="offset points", ha="center", fontsize="small")
    bottom.set_ylabel(r"$E_{mod}^2$ [%]")
    bottom.set_ylim(0.0, 1.3 * max(float(np.max(data.e_mod)), 1e-12))
    bottom.grid(True, axis="y", alpha=0.4)
    ticks = []
    for i, label in enumerate(data.labels):
        s = data.selected[i]
        ticks.append(label if s is None else f"{label}\n{data.joints[s]} → "
                     f"{data.log10_k[i, s]:.2f}")
    bottom.set_xticks(x, ticks)
    bottom.set_xlabel(r"step (corrected joint → its new $\log_{10} k$)")
    return figure


def draw_frequency_response(data, title=""):
    """RMS ``|w|`` against frequency; analysed frequencies and measured RMS marked."""
    figure = new_figure(figsize=(8.0, 5.0))
    ax = figure.add_subplot()
    styles = {"initial": {"color": "tab:blue", "lw": 1.4, "ls": "--", "label": "initial model"},
              "updated": {"color": "tab:red", "lw": 1.8, "label": "updated model"},
              "true": {"color": "black", "lw": 1.0, "ls": ":", "label": "true structure ([truth])"},
              "sweep": {"color": "tab:blue", "lw": 1.2, "marker": ".", "ms": 3,
                        "label": "model (dots: solved frequencies)"}}
    for label, values in data.curves.items():
        style = styles.get(label, {"label": label})
        ax.plot(data.frequencies, _positive(values), **style)
    for i, frequency in enumerate(data.analysed):
        ax.axvline(frequency, color="grey", lw=1.0, alpha=0.7,
                   label="analysed frequency" if i == 0 else None)
    if len(data.measured):
        ax.plot(data.analysed[:len(data.measured)], data.measured, "o", color="tab:green",
                mfc="none", ms=8, mew=1.5, label="measurements")
    ax.set_yscale("log")
    ax.set_xlim(data.frequencies.min(), data.frequencies.max())
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("spatial RMS of |w| [m]")
    ax.grid(True, which="major", alpha=0.4)
    ax.grid(True, which="minor", alpha=0.12)
    ax.set_title(title or "frequency response")
    ax.legend(fontsize="small", loc="best", framealpha=0.9)
    return figure


# ----------------------------------------------------------------------------------------------
# files
# ----------------------------------------------------------------------------------------------

def _frequency_name(frequency):
    return f"field_{frequency:g}Hz.png"


def _corrected_joints(result):
    joints = []
    for step in result.steps:
        joints += [joint for joint in step.corrected if joint not in joints]
    return joints


def write_update_figures(case, problem, measurements, result, directory, curve_points=41,
                         frf_points=40, frf_width=0.1, quantity="abs", field_source="direct",
                         on_work=None, executor=None):
    """Write the figures of an updating run into ``directory`` (created if needed).

    Parameters
    ----------
    case : assembly.Case
    problem : updating.inverse.cost.ModifiedProblem
    measurements : updating.data.measurements.Measurements
    result : updating.inverse.strategy.UpdateResult
    directory : str or Path
    curve_points : int
        Points of each cost curve over ``[updating] bounds``.
    frf_points : int
        Initial frequencies of the response curve over ``(1 -/+ frf_width)`` times the
        analysed band, refined until the resonances are resolved (at most 400 frequencies).
    quantity : {"abs", "real"}
        Field maps of ``|w|`` or ``Re w``.
    field_source : {"direct", "modified"}
        See :func:`field_map_data`.
    on_work : callable, optional
        Called with a label before each cost curve and after each round of response-curve
        frequencies (progress display).
    executor : updating.executor.Executor, optional
        Solves the response curve's frequencies in parallel.

    Returns
    -------
    list of Path
        ``residuals.png`` (and ``residuals_initial.png`` above ``MAP_JOINTS`` joints),
        ``cost_<joint>.png`` per corrected joint, ``field_<f>Hz.png`` per
        measured frequency, ``frf.png``.

    Raises
    ------
    InputError
        When matplotlib is not installed.
    """
    require_matplotlib()
    directory = Path(directory)
    written = []
    name = case.name
    stopped = f"stopped: {result.message}"
    if len(result.parameters) > MAP_JOINTS:  # bars of tens of joints are unreadable: maps
        corrected = _corrected_joints(result)
        for label, step, path in (("first localisation", result.steps[0], "residuals_initial"),
                                  ("end of the run", result.steps[-1], "residuals")):
            data = residual_map_data(case, step, case.updating.stop_ratio,
                                     corrected if step is result.steps[-1] else ())
            written.append(save_figure_atomic(
                draw_residual_map(data, new_figure(figsize=(9.0, 7.0)),
                                  f"{name}: joint residuals, {label}\n{stopped}"),
                directory / f"{path}.png"))
    else:
        bars = residual_bars_data(result, case.updating.stop_ratio)
        written.append(save_figure_atomic(
            draw_residual_bars(bars, f"{name}: joint residuals per step\n{stopped}"),
            directory / "residuals.png"))

    final = {j: dict(p) for j, p in result.parameters.items()}
    initial = problem.initial_parameters()
    base_grid = log_grid(case.updating.bounds, curve_points)
    frequencies = ", ".join(f"{f:g}" for f in problem.frequencies)
    for joint in _corrected_joints(result):
        marks = [final[joint]["log10_stiffness"], _true_log_k(case, joint)]
        lo, hi = case.updating.bounds
        grid = np.union1d(base_grid, [v for v in marks if v is not None and lo <= v <= hi])
        if on_work:
            on_work(f"cost curve of {joint}")
        rows = cost_curve(problem, final, joint, grid)
        data = cost_curve_data(rows, joint, identified=final[joint]["log10_stiffness"],
                               true=_true_log_k(case, joint),
                               initial=initial[joint]["log10_stiffness"],
                               interval=result.intervals[joint].span(case.updating.bounds),
                               interval_label=result.intervals[joint].text,
                               note=f"other joints at their final values; {frequencies} Hz")
        written.append(save_figure_atomic(
            draw_cost_curve(data, f"{name}: cost against $\\log_{{10}} k$ of {joint}"),
            directory / f"cost_{joint}.png"))

    for frequency in measurements.frequencies:
        data = field_map_data(case, problem, measurements, frequency, initial, final,
                              quantity=quantity, source=field_source)
        shown = "|w|" if quantity == "abs" else "Re w"
        written.append(save_figure_atomic(draw_field_maps(data, f"{name}: {shown}"),
                                          directory / _frequency_name(frequency)))

    analysed = measurements.frequencies
    points = {pid: np.asarray(p, dtype=float)
              for pid, (p, _) in measurements.data[analysed[0]].items()}
    sets = {"initial": initial, "updated": final}
    truth = _true_parameters(case)
    if truth is not None:
        sets["true"] = truth
    measured_rms = [spatial_rms(v for _, v in measurements.data[f].values()) for f in analysed]
    frf = frequency_response_data(
        case, sets, frequency_band(analysed, frf_width, frf_points), points, measured_rms,
        analysed, executor=executor,
        on_round=lambda n: on_work(f"response curve: {n} frequencies") if on_work else None)
    written.append(save_figure_atomic(
        draw_frequency_response(frf, f"{name}: spatial RMS of |w| over the measurement points"),
        directory / "frf.png"))
    return written


def draw_power_flow(sweep, title="", joints_shown=8):
    """Power against frequency of an :class:`updating.forward.sweep.Sweep`: injected, dissipated in
    the plates and in the joints (top), transmitted by the ``joints_shown`` joints that carry
    the most (bottom, absolute values)."""
    figure = new_figure(figsize=(8.0, 7.0))
    top, bottom = figure.subplots(2, 1, sharex=True)
    f = sweep.frequencies
    injected = [p.total_injected for p in sweep.powers]
    plates = [sum(p.dissipated.values()) for p in sweep.powers]
    joints = [sum(p.joint_dissipated.values()) for p in sweep.powers]
    top.plot(f, _positive(injected), color="black", lw=1.6, label="injected")
    top.plot(f, _positive(plates), color="tab:blue", lw=1.2, ls="--",
             label="dissipated in the plates")
    if sweep.powers and sweep.powers[0].joint_dissipated:
        top.plot(f, _positive(joints), color="tab:red", lw=1.2, ls=":",
                 label="dissipated in the joints")
    top.set_yscale("log")
    top.set_ylabel("time-averaged power [W]")
    top.set_title(title or "power flow")
    top.legend(fontsize="small", loc="best", framealpha=0.9)
    names = list(sweep.powers[0].transmitted) if sweep.powers else []
    carried = {j: np.abs([p.transmitted[j] for p in sweep.powers]) for j in names}
    shown = sorted(names, key=lambda j: -carried[j].max())[:joints_shown]
    for joint in shown:
        bottom.plot(f, _positive(carried[joint]), lw=1.0, label=joint)
    if shown:
        bottom.set_yscale("log")
        bottom.legend(fontsize="small", loc="best", framealpha=0.9,
                      ncol=2 if len(shown) > 4 else 1)
    bottom.set_ylabel("|power transmitted| [W]")
    bottom.set_xlabel("frequency [Hz]")
    for ax in (top, bottom):
        ax.grid(True, which="major", alpha=0.4)
        ax.set_xlim(f.min(), f.max())
    return figure


def write_sweep_figures(case, sweep, directory):
    """Write ``frf.png`` and ``power.png`` of a ``vtcr frf`` sweep into ``directory``."""
    require_matplotlib()
    directory = Path(directory)
    data = FrequencyResponseData(sweep.frequencies, {"sweep": sweep.spatial_rms()}, (),
                                 np.zeros(0))
    response = draw_frequency_response(
        data, f"{case.name}: spatial RMS of |w| over the probes, "
              f"{len(sweep.frequencies)} frequencies")
    return [save_figure_atomic(response, directory / "frf.png"),
            save_figure_atomic(draw_power_flow(sweep, f"{case.name}: power flow"),
                               directory / "power.png")]


def write_curve_figure(case, rows, joint, directory, parameters_note="other joints at their "
                       "initial values"):
    """Write ``cost_<joint>.png`` for :func:`updating.inverse.cost.cost_curve` rows (``vtcr curve``)."""
    require_matplotlib()
    frequencies = ", ".join(f"{f:g}" for f in case.frequencies)
    data = cost_curve_data(rows, joint, true=_true_log_k(case, joint),
                           initial=case.updatable_parameters()[joint]["log10_stiffness"],
                           note=f"{parameters_note}; {frequencies} Hz")
    return save_figure_atomic(draw_cost_curve(data, f"{case.name}: cost against "
                                                    f"$\\log_{{10}} k$ of {joint}"),
                              Path(directory) / f"cost_{joint}.png")


def draw_plan(plans, frequencies, title=""):
    """Grouped bars of each joint's field sensitivity (% per 0.1 decade of log10 k) per
    frequency, the joints labelled with their verdict (:mod:`updating.inverse.plan`)."""
    joints = list(plans)
    figure = new_figure(figsize=(float(np.clip(0.6 * len(joints) * len(frequencies) + 3.0, 7.0,
                                            14.0)), 4.8))
    ax = figure.subplots()
    width = 0.8 / max(len(frequencies), 1)
    x = np.arange(len(joints))
    for i, frequency in enumerate(frequencies):
        values = [100 * plans[j].stiffness_sensitivity[frequency] for j in joints]
        ax.bar(x - 0.4 + (i + 0.5) * width, _positive(np.array(values)), width,
               label=f"{frequency:g} Hz")
    ax.set_xticks(x, [f"{j}\n{plans[j].verdict}" for j in joints])
    ax.set_yscale("log")
    ax.set_ylabel("field change [%] per +0.1 decade of log10 k")
    ax.grid(True, axis="y", alpha=0.4)
    ax.legend(fontsize="small")
    ax.set_title(title or "sensitivity of the planned measurement", fontsize="medium")
    return figure


def write_plan_figure(plans, frequencies, directory, name):
    """``DIR/plan.png`` (:func:`draw_plan`); the directory is created if needed."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    return save_figure_atomic(draw_plan(plans, frequencies,
                                        f"{name}: what the planned measurement can tell"),
                              directory / "plan.png")
