r"""What a field map draws (numpy only): the measured field, the initial and the updated model's
fields on grids over the plates, in the assembly plane and, for framed plates, in 3D.

:func:`field_map_data` computes it; :mod:`updating.figures.fields` (plane) and
:mod:`updating.figures.fields_space` (3D) draw it.

Model fields. The "initial model" and "updated model" panels show the model's own response
(the direct problem, r = 0) with the initial and with the identified joint parameters (the
paper's Fig. 13); ``source="modified"`` shows instead the minimiser of :math:`E_{mod}^2` at those
parameters (see :mod:`updating.figures.plots`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from assembly import Case, EdgeId, Plate
from assembly.joints import Joint
from updating.data.measurements import Measurements
from updating.forward.sweep import plate_deflection
from updating.inverse.cost import ModifiedProblem, direct_amplitudes

__all__ = ["SpaceLayout", "FieldMapData", "field_map_data", "costs_text"]

JointParameters = Mapping[str, Mapping[str, Any]]
"""``{joint: {log10_stiffness, loss_factor, mass}}``."""


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

    surfaces: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]
    measured: dict[str, np.ndarray]
    outlines: dict[str, np.ndarray]
    joints: dict[str, np.ndarray]
    forces: np.ndarray


def _space_layout(case: Case, local_grids: Mapping[str, tuple[np.ndarray, np.ndarray]],
                  measured_points: Mapping[str, np.ndarray]) -> SpaceLayout | None:
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
    grids: dict[str, tuple[np.ndarray, np.ndarray]]
    initial: dict[str, np.ndarray]
    updated: dict[str, np.ndarray]
    measured: dict[str, tuple[np.ndarray, np.ndarray]]
    measured_global: dict[str, np.ndarray]
    outlines: dict[str, np.ndarray]
    joints: dict[str, np.ndarray]
    cells: dict[str, tuple[np.ndarray, np.ndarray] | None]
    e_mod: tuple[float, float]
    misfit: tuple[float, float]
    source: str
    n_frequencies: int
    limits: tuple[float, float]
    loads: tuple[np.ndarray, list[np.ndarray]] = (np.zeros((0, 2)), [])
    space: SpaceLayout | None = None


def _transform(values: np.ndarray, quantity: str) -> np.ndarray:
    if quantity == "abs":
        return np.abs(values)
    if quantity == "real":
        return np.real(values)
    raise ValueError(f"quantity must be 'abs' or 'real', got {quantity!r}")


def _plate_outline(plate: Plate) -> np.ndarray:
    lx, ly = plate.size
    x, y = plate.to_global([0.0, lx, lx, 0.0, 0.0], [0.0, 0.0, ly, ly, 0.0])
    return np.column_stack([x, y])


def _joint_line(case: Case, joint: Joint) -> np.ndarray:
    return _edge_line(case, joint.sides[0])


def _edge_line(case: Case, side: EdgeId) -> np.ndarray:
    """End points of a plate edge (``side.plate``, ``side.edge``) in the assembly plane."""
    plate = case.plates[side.plate]
    start, tangent, _, length = plate.edge_frame(side.edge)
    local = np.array([start, start + length * tangent])
    x, y = plate.to_global(local[:, 0], local[:, 1])
    return np.column_stack([x, y])


def _tensor_cells(points: np.ndarray, size: tuple[float, float], tol: float = 1e-9
                  ) -> tuple[np.ndarray, np.ndarray] | None:
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


def _grid_counts(size: tuple[float, float], kappa: float, points_per_wavelength: int = 12,
                 minimum: int = 24, maximum: int = 160) -> tuple[int, ...]:
    wavelength = 2.0 * math.pi / kappa
    return tuple(int(np.clip(math.ceil(points_per_wavelength * length / wavelength) + 1,
                             minimum, maximum)) for length in size)


def field_map_data(case: Case, problem: ModifiedProblem, measurements: Measurements,
                   frequency: float, initial: JointParameters, updated: JointParameters,
                   quantity: str = "abs", source: str = "direct",
                   points_per_wavelength: int = 12) -> FieldMapData:
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


def _load_marks(case: Case) -> tuple[np.ndarray, list[np.ndarray]]:
    """Point forces (n, 2) and loaded edges (end points) in the assembly plane."""
    forces = [np.ravel(case.plates[load.plate].to_global([load.at[0]], [load.at[1]]))
              for load in case.loads if load.kind == "point_force"]
    edges = [_edge_line(case, load.edge) for load in case.loads if load.kind != "point_force"]
    return np.array(forces).reshape(-1, 2), edges


def costs_text(data: FieldMapData) -> str:
    """:math:`E_{mod}^2` at the initial and updated parameters of a :class:`FieldMapData`."""
    summed = f" (sum over {data.n_frequencies} frequencies)" if data.n_frequencies > 1 else ""
    return (f"$E_{{mod}}^2$ {100 * data.e_mod[0]:.2f} % initial, "
            f"{100 * data.e_mod[1]:.2f} % updated{summed}")
