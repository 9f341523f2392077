r"""A frequency sweep written as Universal File Format datasets (optional extra ``vtcr[uff]``).

The file is what test-analysis software imports from a measurement campaign, so that a model
sweep and a test can be compared in the same tool, and it reads back through
:func:`updating.data.uff.read_uff` with the same node map:

* dataset 164, units: SI (metre, newton, kelvin offsets as the standard gives them), every
  conversion factor 1;
* dataset 15, geometry: one node per probe point at its place in the description's layout
  (``Plate.to_global``, z = 0), or in space for plates placed by a ``frame``
  (``PlateFrame.to_space``: a stiffened panel's stiffeners stand on its skin);
* one dataset 58 per probe point, response direction +Z (the plate's +w, local z = x × y),
  abscissa the sweep's frequencies in Hz (uneven where the sweep was refined), complex double
  ordinates; ASCII (12 significant digits; the standard gives an uneven abscissa only 6,
  E13.5), or binary 58b (IEEE doubles throughout) when the file name ends in ``.58b``,
  ``.ufb`` or ``.bunv``:

  - when the description's loads are one point force of amplitude :math:`F`, a frequency
    response function (function type 4) :math:`H = w / F`, displacement per newton, with the
    force's position as the reference (its node when a probe is there, else node 0 named
    ``FORCE``);
  - otherwise the response spectrum of ``w`` in metres (function type 12) under all the loads.

Nodes are the probe file's ``node`` column when it has one (a node map ``node,plate,x,y``
serves as probe file), else 1, 2, ... in probe order; the response entity name is the plate.
"""

from __future__ import annotations

import tempfile
import warnings
from collections.abc import Sequence
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np

from assembly.models import Plate, PointForce
from updating.data.files import atomic_output
from updating.errors import InputError

if TYPE_CHECKING:
    from assembly import Case
    from updating.forward.sweep import Sweep

__all__ = ["sweep_datasets", "write_uff"]

ENTITY_WIDTH = 10  # record 6 entity names are 10 characters (Format 10A1)
BINARY_SUFFIXES = (".58b", ".ufb", ".bunv")


def _pyuff() -> ModuleType:
    try:
        import pyuff
    except ImportError:
        raise InputError("--uff: writing UFF needs pyuff: pip install 'pyuff>=2.4' (the extra "
                         "uff of vtcr)") from None
    return pyuff


def frf_force(case: Case) -> PointForce | None:
    """The single point force the sweep is normalised by, or None (several or edge loads)."""
    loads = [load for load in case.loads if load is not None]
    if len(loads) == 1 and isinstance(loads[0], PointForce) and loads[0].amplitude != 0:
        return loads[0]
    return None


def _node_position(plate: Plate, x: float, y: float) -> np.ndarray:
    """A probe's node: in space by the plate's frame, else in the layout plane at z = 0."""
    if plate.frame is not None:
        return plate.frame.to_space(x, y)
    return np.array([*np.ravel(plate.to_global(x, y)), 0.0])


def sweep_datasets(case: Case, sweep: Sweep, order: Sequence[tuple[str, int]],
                   nodes: Sequence[int] | None = None,
                   binary: bool = False) -> list[dict[str, Any]]:
    """The pyuff dictionaries of a sweep: units (164), geometry (15), one 58 per probe.

    Parameters
    ----------
    case : assembly.Case
    sweep : updating.forward.sweep.Sweep
    order : sequence of (plate, index)
        The probe points in file order (``sweep.points[plate][index]``).
    nodes : sequence of int, optional
        Node number of each probe, in ``order`` (default 1, 2, ...).
    binary : bool
        Datasets 58b instead of ASCII 58.
    """
    pyuff = _pyuff()
    nodes = list(range(1, len(order) + 1)) if nodes is None else [int(n) for n in nodes]
    force = frf_force(case)
    placed = np.array([_node_position(case.plates[pid], *sweep.points[pid][i])
                       for pid, i in order])
    datasets = [
        pyuff.prepare_164(units_code=1, units_description="SI", temp_mode=2, length=1.0,
                          force=1.0, temp=1.0, temp_offset=273.15),
        pyuff.prepare_15(node_nums=nodes, def_cs=[0] * len(nodes), disp_cs=[0] * len(nodes),
                         color=[1] * len(nodes), x=placed[:, 0], y=placed[:, 1],
                         z=placed[:, 2]),
    ]
    reference = {"ref_node": 0, "ref_ent_name": "NONE", "ref_dir": 0}
    if force is not None:
        at = (force.plate, *map(float, force.at))
        drive = [n for n, (pid, i) in zip(nodes, order)
                 if (pid, *map(float, sweep.points[pid][i])) == at]
        reference = {"ref_node": drive[0] if drive else 0,
                     "ref_ent_name": force.plate[:ENTITY_WIDTH] if drive else "FORCE",
                     "ref_dir": 3}
    scale = 1.0 / complex(force.amplitude) if force is not None else 1.0
    frequencies = np.asarray(sweep.frequencies, dtype=float)
    steps = np.diff(frequencies)
    even = len(steps) > 0 and np.allclose(steps, steps[0], rtol=1e-9, atol=0.0)
    what = (f"w / F, F = {complex(force.amplitude):g} N at {force.plate} {tuple(force.at)}"
            if force is not None else "w under the description's loads")
    for node, (pid, i) in zip(nodes, order):
        x, y = sweep.points[pid][i]
        data = np.array([values[pid][i] for values in sweep.values], dtype=complex) * scale
        datasets.append(pyuff.prepare_58(
            binary=int(binary), id1=f"vtcr frf {case.name}"[:80],
            id2=f"plate {pid} x = {x:.9g} m, y = {y:.9g} m"[:80], id3="NONE",
            id4=what[:80], id5="NONE",
            func_type=4 if force is not None else 12, ver_num=0, load_case_id=0,
            rsp_ent_name=pid[:ENTITY_WIDTH], rsp_node=node, rsp_dir=3, **reference,
            ord_data_type=6, num_pts=len(frequencies), abscissa_spacing=1 if even else 0,
            abscissa_min=float(frequencies[0]),
            abscissa_inc=float(steps[0]) if even else 0.0, z_axis_value=0.0,
            abscissa_spec_data_type=18, abscissa_axis_units_lab="Hz",
            ordinate_spec_data_type=8, ordinate_len_unit_exp=1, ordinate_axis_units_lab="m",
            orddenom_spec_data_type=13 if force is not None else 0,
            orddenom_force_unit_exp=1 if force is not None else 0,
            orddenom_axis_units_lab="N" if force is not None else "NONE",
            z_axis_spec_data_type=0, data=data, x=frequencies))
    return datasets


def write_uff(path: str | Path, case: Case, sweep: Sweep, order: Sequence[tuple[str, int]],
              nodes: Sequence[int] | None = None) -> Path:
    """Write :func:`sweep_datasets` to ``path`` (binary 58b for :data:`BINARY_SUFFIXES`,
    ASCII otherwise), atomically.

    pyuff writes to a file name, so the file is written in a temporary directory first and
    then copied through :func:`updating.data.files.atomic_output` (a reader never sees half a file).
    """
    binary = Path(path).suffix.lower() in BINARY_SUFFIXES
    datasets = sweep_datasets(case, sweep, order, nodes, binary)
    pyuff = _pyuff()
    with tempfile.TemporaryDirectory() as folder:
        scratch = Path(folder) / "sweep.uff"
        with warnings.catch_warnings():  # pyuff's own deprecation notices say nothing here
            warnings.simplefilter("ignore")
            pyuff.UFF(str(scratch)).write_sets(datasets, mode="add")
        content = scratch.read_bytes()
    with atomic_output(path, binary=True) as handle:
        handle.write(content)
    return Path(path)
