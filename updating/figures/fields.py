r"""Field maps: :math:`|w|` (or Re w) of the measurements, of the initial and of the updated model,
plates laid out in the assembly plane on one colour scale (the paper's Figs. 12-13):
``field_<f>Hz.png`` of ``vtcr update --plot``. Plates placed in 3D are drawn in space
(:mod:`updating.figures.fields_space`).

:func:`field_map_data` computes what is drawn (numpy only), :func:`draw_field_maps` draws it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from updating.figures.fields_space import draw_field_maps_in_space
from updating.figures.figure_tools import costs_text, field_colours, new_figure, powers_of_ten_bar
from updating.forward.sweep import plate_deflection
from updating.inverse.cost import direct_amplitudes

__all__ = ["SpaceLayout", "FieldMapData", "field_map_data", "draw_field_maps"]


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
