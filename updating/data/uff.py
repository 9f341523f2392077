r"""Measured data from measurement systems: Universal File Format dataset 58 (optional extra).

Dataset 58 ("function at nodal DOF") holds one function of frequency per response node and
direction: a frequency response function (FRF, function type 4) or a response spectrum /
operating deflection shape (function type 12), in ASCII or in the binary variant 58b. The files
are read through `pyuff <https://github.com/ladisk/pyuff>`_, an optional dependency
(``pip install 'pyuff>=2.4'``, or ``pip install '.[uff]'`` in a checkout) imported only
here, so the core runs without it.

Placing the nodes
-----------------
A UFF file names response *nodes*, not points of vtcr's plates. A correspondence table, CSV
``node,plate,x,y`` (plate-local metres, read by :mod:`updating.data.uff_map`), places each
node: its ``node`` is the response node number of the dataset (record 6, field 6). Exporters
that leave that field 0 or write a name in it are matched by the name (record 6 field 6 text,
or the response entity name, field 5).
Nodes of the file that the table does not list are ignored; every node of the table needs
exactly one usable dataset (a complex response, see below) in the Z direction;
coherences and other functions of the same node beside it are skipped.

From the ordinate to ``w``
--------------------------
Only Z translations (direction ``3`` or ``-3``) are used; ``-3`` flips the sign, so that
``+Z`` is the plate's ``+w`` (local z = x × y). Other directions are ignored. With the
``exp(+j omega t)`` convention of vtcr (and of FFT analysers, whose spectra are the complex
amplitudes ``X`` of ``x(t) = Re(X exp(j omega t))``), at the angular frequency
:math:`\omega = 2 \pi f` of the line

.. math::

    w = d, \qquad w = \frac{v}{j\omega}, \qquad w = -\frac{a}{\omega^2}

for a displacement ``d`` (specific data type 8), velocity ``v`` (11) or acceleration ``a``
(12). Units: a units dataset 164 before the functions gives the factors that convert file
units to SI (SI value = file value / factor): lengths divide by the length factor, FRFs per
unit force multiply by the force factor. An ordinate axis-units label ``g`` (or ``g/N``) means
accelerations in standard gravities (9.80665 m/s²). An FRF ``H = response / force`` is used as
the displacement per newton: it is the field of the description's loads when those are the
unit force the FRF is normalised by (e.g. a ``point_force`` of amplitude 1 N at the shaker).

Frequencies
-----------
Each description frequency takes the nearest spectral line, which must lie within half a
line spacing of it (the smaller of the two spacings around the line; a single-line dataset
must match to the six significant digits the ASCII abscissa keeps). Values are never
interpolated between lines: the response of a lightly damped structure varies too fast
between lines for that. A frequency outside the measured band, or between lines of an uneven
abscissa farther than that, is reported.
"""

from __future__ import annotations

import math
import re
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np

from updating.data.measurements import Measurements
from updating.data.uff_map import MapEntry, map_rows, node_key
from updating.errors import InputError

if TYPE_CHECKING:
    from pyuff import UFF

    from assembly import Case

_T = TypeVar("_T")

__all__ = ["UFF_SUFFIXES", "is_uff", "read_uff"]

UFF_SUFFIXES = (".uff", ".unv", ".58", ".58b", ".ufb", ".bunv")
STANDARD_GRAVITY = 9.80665  # m/s^2, for ordinates labelled "g"
SINGLE_LINE_RTOL = 5e-6  # half a unit of the 6th significant digit (E13.5 abscissa)

# record 6 field 1 (function type) and records 8-10 field 1 (specific data type), for messages
FUNCTION_TYPES = {
    0: "general or unknown", 1: "time response", 2: "auto spectrum", 3: "cross spectrum",
    4: "frequency response function", 5: "transmissibility", 6: "coherence",
    7: "auto correlation", 8: "cross correlation", 9: "power spectral density",
    10: "energy spectral density", 11: "probability density function", 12: "spectrum",
}
DATA_TYPES = {
    0: "unknown", 1: "general", 2: "stress", 3: "strain", 5: "temperature", 6: "heat flux",
    8: "displacement", 9: "reaction force", 11: "velocity", 12: "acceleration",
    13: "excitation force", 15: "pressure", 16: "mass", 17: "time", 18: "frequency", 19: "rpm",
    20: "order",
}
DIRECTIONS = {1: "X", 2: "Y", 3: "Z", 4: "RX", 5: "RY", 6: "RZ"}
RESPONSES = {8: "displacement", 11: "velocity", 12: "acceleration"}


def is_uff(path: str | Path) -> bool:
    """True when ``path`` has a UFF suffix (:data:`UFF_SUFFIXES`, any case)."""
    return Path(path).suffix.lower() in UFF_SUFFIXES


def _pyuff(path: str | Path) -> ModuleType:
    try:
        import pyuff
    except ImportError:
        raise InputError(f"{path}: reading UFF needs pyuff: pip install 'pyuff>=2.4' (the "
                         "extra uff of vtcr)") from None
    return pyuff


def _direction_label(direction: int) -> str:
    if direction == 0:
        return "scalar"
    name = DIRECTIONS.get(abs(direction), str(abs(direction)))
    return f"{'+' if direction > 0 else '-'}{name}"


def _first_line(path: Path, length: int = 60) -> str:
    """What the file starts with, for a message: its first line cut to ``length``, or
    "binary data" (or "nothing")."""
    with open(path, "rb") as handle:
        line = handle.readline(4 * length).decode("utf-8", errors="replace").rstrip("\r\n")
    if not line:
        return "it is empty"
    if "\ufffd" in line or any(ord(c) < 32 and c != "\t" for c in line):
        return "it starts with binary data"
    return f"its first line is {line[:length] + ('...' if len(line) > length else '')!r}"


# --------------------------------------------------------------------------------------------
# the UFF file
# --------------------------------------------------------------------------------------------

@dataclass
class _Function:
    """Header of one dataset 58 and the units in force where it stands."""

    index: int  # 1-based position in the file
    node: str | None
    direction: int
    header: dict
    length_factor: float
    force_factor: float

    def label(self, path: Path) -> str:
        node = self.node if self.node is not None else "?"
        return (f"{path}: dataset {self.index} (node {node}, direction "
                f"{_direction_label(self.direction)})")


def _quiet(call: Callable[..., _T], *args: Any, **kwargs: Any) -> _T:
    # pyuff is noisy in ways that say nothing about the data: it warns about its own deprecated
    # arguments (FutureWarning), numpy may warn while it converts a malformed block, and its 58b
    # code leaves file handles to the garbage collector (ResourceWarning). vtcr checks every
    # value it uses itself (count, finiteness, abscissa order) and reports problems as
    # InputError; under ``-W error`` (our pytest setting) such a warning would instead turn a
    # readable file into a crash.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return call(*args, **kwargs)


def _raw_record6(path: Path, uff: UFF, position: int) -> str | None:
    """Record 6 of dataset ``position`` (0-based) as raw text, or None when unavailable.

    pyuff parses record 6 in fixed columns and silently turns a non-numeric node into 0; an
    over-long entity name shifts every later field (ladisk/pyuff#21). The raw line lets us
    recover the node and direction in both cases. ``_block_ind`` is pyuff's private table of
    dataset offsets; without it (another pyuff version) pyuff's own fields are used.
    """
    try:
        start = int(uff._block_ind[position][0])
        with open(path, "rb") as handle:
            handle.seek(start)
            head = handle.read(13 * 84)
        lines = head.splitlines()
        return lines[7].decode("ascii", errors="replace") if len(lines) > 7 else None
    except Exception:  # noqa: BLE001 - private detail of pyuff; fall back to its fields
        return None


def _node_and_direction(raw: str | None, header: Mapping[str, Any]) -> tuple[str | None, int]:
    """``(node key or None, direction)`` of record 6, robust to vendor layouts."""
    node_text, entity, direction = None, str(header.get("rsp_ent_name", "")), None
    if raw is not None:
        # Format(2(I5,I10),2(1X,10A1,I10,I4)): entity 30:41, node 41:51, direction 51:55
        fixed_node, fixed_dir = raw[41:51].strip(), raw[51:55].strip()
        try:
            direction = int(fixed_dir)
            node_text, entity = fixed_node, raw[30:41].strip()
            if " " in node_text:
                raise ValueError
        except ValueError:
            tokens = raw.split()
            if len(tokens) == 10:  # whitespace-separated record (shifted columns)
                try:
                    direction = int(tokens[6])
                    node_text, entity = tokens[5], tokens[4]
                except ValueError:
                    direction = None
            else:
                direction = None
    if direction is None:
        node_text = str(header.get("rsp_node", 0))
        direction = int(header.get("rsp_dir", 0))
    node: str | None = node_key(node_text) if node_text is not None else ""
    if node in ("", "0"):
        entity = entity.strip()
        node = node_key(entity) if entity and entity.upper() != "NONE" else None
    return node, direction


def _scan(pyuff: ModuleType, path: Path) -> tuple[UFF, list[int], list[_Function], list[str]]:
    """Headers of the datasets 58 and the problems met; other datasets are skipped."""
    try:
        uff = _quiet(pyuff.UFF, str(path))
        types = [int(t) for t in uff.get_set_types()]
    except Exception as err:  # noqa: BLE001 - pyuff raises bare Exception
        raise InputError(f"{path}: pyuff cannot split the file into datasets ({err}); check "
                         "that every dataset starts and ends with a line '    -1'") from None
    functions, problems = [], []
    length_factor = force_factor = 1.0
    for position, kind in enumerate(types):
        index = position + 1
        if kind == 164:
            try:
                units = _quiet(uff.read_sets, position)
                length_factor, force_factor = float(units["length"]), float(units["force"])
            except Exception:  # noqa: BLE001
                problems.append(f"{path}: dataset {index} (units, 164): unreadable; fix its two "
                                "records (units code, then the length, force and temperature "
                                "factors)")
                continue
            if not all(math.isfinite(f) and f > 0 for f in (length_factor, force_factor)):
                problems.append(f"{path}: dataset {index} (units, 164): length factor "
                                f"{length_factor}, force factor {force_factor}; both must be "
                                "finite and > 0 (file units per SI unit)")
                length_factor = force_factor = 1.0
            continue
        if kind != 58:  # geometry (15, 2411), traces, results...: not ours
            continue
        try:
            header = _header(uff, position)
        except Exception:  # noqa: BLE001
            problems.append(f"{path}: dataset {index}: pyuff cannot read its header (records 1 "
                            "to 11 of dataset 58); fix the header: 11 lines after the "
                            "'    58' line, numeric fields in their columns")
            continue
        node, direction = _node_and_direction(_raw_record6(path, uff, position), header)
        functions.append(_Function(index, node, direction, header, length_factor,
                                   force_factor))
    return uff, types, functions, problems


def _header(uff: UFF, position: int) -> dict[str, Any]:
    try:
        return _quiet(uff.read_sets, position, header_only=True)
    except TypeError:  # pyuff without header_only
        return _quiet(uff.read_sets, position)


def _read_values(uff: UFF, function: _Function, path: Path) -> tuple[np.ndarray, np.ndarray]:
    """``(x, data)`` of one dataset, or raise InputError naming it."""
    try:
        dataset = _quiet(uff.read_sets, function.index - 1)
        x = np.asarray(dataset["x"], dtype=float)
        data = np.asarray(dataset["data"])
    except Exception:  # noqa: BLE001
        binary = function.header.get("binary", 0)
        fix = ("binary 58b: the byte count of the ID line must match the data, and the closing "
               "'    -1' must follow the data (pyuff.fix_58b repairs the common case, "
               "ladisk/pyuff#61)" if binary else
               "ASCII: values in the columns of record 7's case (6E13.5 or 4E20.12; "
               "E13.5,2E20.12 for complex uneven), exponents written with E")
        raise InputError(f"{function.label(path)}: pyuff cannot read the data values; fix "
                         f"them ({fix})") from None
    return x, data


def _check_kind(function: _Function, path: Path) -> str | None:
    """Message when the dataset is not a complex frequency-domain response (None when it is)."""
    h, label = function.header, function.label(path)
    func_type = int(h.get("func_type", 0))
    abscissa = int(h.get("abscissa_spec_data_type", 0))
    if func_type not in (4, 12) and not (func_type == 0 and abscissa == 18):
        name = FUNCTION_TYPES.get(func_type, "unknown code")
        return (f"{label}: function type {func_type} ({name}); vtcr needs a complex response "
                "against frequency: export FRFs (type 4) or spectra / operating deflection "
                "shapes (type 12)")
    if abscissa not in (0, 18):
        return (f"{label}: the abscissa is {DATA_TYPES.get(abscissa, abscissa)} (specific data "
                f"type {abscissa}); vtcr needs frequency in Hz (18)")
    if int(h.get("ord_data_type", 0)) not in (5, 6):
        return (f"{label}: real ordinates (data type {h.get('ord_data_type')}) carry no phase; "
                "export complex data (ordinate data type 5 or 6)")
    quantity = int(h.get("ordinate_spec_data_type", 0))
    if quantity not in RESPONSES:
        return (f"{label}: the ordinate is {DATA_TYPES.get(quantity, 'unknown')} (specific "
                f"data type {quantity}); vtcr needs displacement (8), velocity (11) or "
                "acceleration (12) in record 9")
    denominator = int(h.get("orddenom_spec_data_type", 0))
    if denominator not in (0, 13):
        return (f"{label}: the ordinate is divided by "
                f"{DATA_TYPES.get(denominator, denominator)} (record 10, specific data type "
                f"{denominator}), a ratio of responses; vtcr needs a response or a response "
                "per unit force (13)")
    return None


def _pick_line(x: np.ndarray, frequency: float) -> tuple[int, None] | tuple[None, str]:
    """``(index, None)`` of the line taken for ``frequency``, or ``(None, reason)``."""
    i = int(np.argmin(np.abs(x - frequency)))
    band = f"{x[0]:g}-{x[-1]:g} Hz"
    if len(x) == 1:
        if abs(x[0] - frequency) <= SINGLE_LINE_RTOL * frequency:
            return i, None
        return None, (f"{frequency:g} Hz is not the single line {x[0]:g} Hz; set the "
                      f"description's frequency to {x[0]:g}")
    gaps = np.diff(x)
    spacing = min(gaps[max(i - 1, 0)], gaps[min(i, len(gaps) - 1)])
    if abs(x[i] - frequency) <= 0.5 * spacing:
        return i, None
    if frequency < x[0] or frequency > x[-1]:
        return None, (f"{frequency:g} Hz is outside the measured band {band}; set the "
                      "description's frequencies inside it or export that band")
    j = i + 1 if x[i] < frequency else i - 1
    lo, hi = sorted((x[i], x[j]))
    return None, (f"{frequency:g} Hz lies between the lines {lo:g} and {hi:g} Hz, farther "
                  "than half a line spacing from both (values are not interpolated between "
                  "lines); set the description's frequency to a measured line")


def _to_displacement(function: _Function, value: complex, line_frequency: float) -> complex:
    """Convert one ordinate value to ``w`` in metres (per newton for FRFs)."""
    h = function.header
    quantity = int(h["ordinate_spec_data_type"])
    label = str(h.get("ordinate_axis_units_lab", "")).strip().lower().replace(" ", "")
    if quantity == 12 and re.fullmatch(r"g(/n)?", label):
        scale = STANDARD_GRAVITY  # "g" is an absolute unit, not the file's length unit
    else:
        scale = 1.0 / function.length_factor
    if int(h.get("func_type", 0)) == 4 or int(h.get("orddenom_spec_data_type", 0)) == 13:
        scale *= function.force_factor  # per file force unit -> per newton
    scale = math.copysign(scale, function.direction)  # -Z: the sensor points along -w
    omega = 2.0 * np.pi * line_frequency
    if quantity == 11:
        return scale * value / (1j * omega)
    if quantity == 12:
        return -scale * value / omega**2
    return scale * value


def read_uff(path: str | Path, case: Case, uff_map: str | Path | None) -> Measurements:
    """Read measured fields from a UFF file (datasets 58 / 58b) through a node map.

    Parameters
    ----------
    path : str or Path
        The UFF file (ASCII 58 or binary 58b datasets; other datasets are skipped).
    case : assembly.Case
        The description: its plates check the map, its ``frequencies`` pick the lines.
    uff_map : str or Path or None
        CSV ``node,plate,x,y`` placing each response node on a plate (plate-local metres).

    Returns
    -------
    Measurements
        ``data[frequency][plate] = (points (n, 2), w (n,) complex)``, ``w`` in metres (per
        newton for FRFs), one entry per description frequency, points in map order.

    Raises
    ------
    InputError
        pyuff missing; no map given; every problem of the map; datasets that cannot be read
        or used (named by their 1-based position in the file, node and direction); map nodes
        without exactly one usable Z response; frequencies not on a measured line; non-finite
        values.

    Examples
    --------
    >>> measurements = read_uff("rig.uff", case, "rig_map.csv")  # doctest: +SKIP
    >>> measurements.frequencies  # doctest: +SKIP
    (155.0,)
    """
    pyuff = _pyuff(path)
    path = Path(path)
    entries, map_problems = _node_map(path, case, uff_map)
    uff, types, functions, problems = _datasets_58(pyuff, path, map_problems)
    problems = map_problems + problems  # the valid map rows are still checked below
    z_functions, other = _z_functions(path, uff_map, entries, functions, types, problems)
    values, node_problems = _node_values(path, uff_map, case, uff, entries, z_functions, other)
    problems += node_problems
    if problems:
        raise InputError(problems)
    return _measurements(path, case, entries, values)


def _node_map(path: Path, case: Case,
              uff_map: str | Path | None) -> tuple[dict[str, MapEntry], list[str]]:
    """``({node: MapEntry}, problems)`` of the node map of the UFF file ``path`` (none given:
    :class:`InputError`)."""
    if uff_map is None:
        raise InputError(f"{path}: a UFF file needs --uff-map MAP.csv (header node,plate,x,y, "
                         "plate-local metres) to place its response nodes on the plates")
    return map_rows(uff_map, case)


def _datasets_58(pyuff: ModuleType, path: Path, map_problems: Sequence[str]
                 ) -> tuple[UFF, list[int], list[_Function], list[str]]:
    """:func:`_scan` of the UFF file ``path``; a missing file (reported with the map's
    ``map_problems``) or one holding no UFF dataset is an :class:`InputError`."""
    if not path.is_file():
        what = "is a directory, not a file" if path.is_dir() else "no such file"
        raise InputError([*map_problems, f"{path}: {what}; give an existing UFF file "
                                         "(datasets 58 or 58b)"])
    uff, types, functions, problems = _scan(pyuff, path)
    if not types and not functions:  # not a universal file: say so rather than blame the map
        raise InputError(f"{path}: holds no UFF dataset ({_first_line(path)}); give a "
                         "universal file with datasets 58 or 58b, or a CSV measurement file "
                         "named .csv")
    return uff, types, functions, problems


def _z_functions(path: Path, uff_map: str | Path | None, entries: Mapping[str, MapEntry],
                 functions: Sequence[_Function], types: Sequence[int], problems: Sequence[str]
                 ) -> tuple[dict[str, list[_Function]], dict[str, list[str]]]:
    """``({node: its datasets in direction +Z or -Z}, {node: labels of its other
    directions})`` of the map's nodes; when none of the file's Z nodes is in the map (and no
    other ``problems`` explain it), an :class:`InputError` naming both."""
    z_functions: dict[str, list[_Function]] = {}
    other: dict[str, list[str]] = {}
    for function in functions:
        if function.node not in entries:
            continue  # not in the map: ignored by design (README)
        if abs(function.direction) == 3:
            z_functions.setdefault(function.node, []).append(function)
        else:
            other.setdefault(function.node, []).append(_direction_label(function.direction))
    if entries and not z_functions and not problems:
        found = sorted({f.node for f in functions if f.node is not None and
                        abs(f.direction) == 3}, key=_sort_key)
        kinds = sorted(set(types))
        raise InputError(
            f"{path}: none of its Z-direction response nodes "
            f"({_some(found) if found else 'none found'}) is in {uff_map} "
            f"(nodes {_some(sorted(entries, key=_sort_key))}); the map's node column must hold "
            f"the UFF response node numbers (record 6, field 6); dataset types in the file: "
            f"{', '.join(map(str, kinds)) or 'none'}")
    return z_functions, other


def _node_values(path: Path, uff_map: str | Path | None, case: Case, uff: UFF,
                 entries: Mapping[str, MapEntry], z_functions: Mapping[str, list[_Function]],
                 other: Mapping[str, list[str]]
                 ) -> tuple[dict[str, dict[float, complex]], list[str]]:
    """``({node: {frequency: w}}, problems)``: each map node's values from its one usable Z
    response (:func:`_node_response`), then one problem per frequency and reason shared by
    the datasets it names."""
    frequency_problems: dict[tuple[float, str], list[int]] = {}
    values: dict[str, dict[float, complex]] = {}
    problems: list[str] = []
    for node, entry in entries.items():
        where = f"{uff_map}: row {entry.row}: node {node}"
        picked, node_problems = _node_response(path, where, z_functions.get(node, []),
                                               other.get(node), uff, case.frequencies,
                                               frequency_problems)
        problems.extend(node_problems)
        if picked is not None:
            values[node] = picked
    for (frequency, reason), indices in frequency_problems.items():
        problems.append(f"{path}: {_datasets(indices)}: {reason}")
    return values, problems


def _node_response(path: Path, where: str, found: Sequence[_Function],
                   other: Sequence[str] | None, uff: UFF, frequencies: Sequence[float],
                   frequency_problems: dict[tuple[float, str], list[int]]
                   ) -> tuple[dict[float, complex] | None, list[str]]:
    """``({frequency: w}, [])`` of one map node (``where``) from its Z datasets ``found``
    (``other``: the labels of its other directions), ``(None, [])`` when a frequency is off
    the measured lines (that goes to ``frequency_problems``), else ``(None, problems)``."""
    if not found:
        extra = (f" (it has directions {', '.join(sorted(set(other)))} only)"
                 if other is not None else "")
        return None, [(f"{where} has no dataset 58 in direction +Z or -Z in {path}{extra}; "
                       "remove the row or export that node's Z response")]
    # coherences, auto spectra... of the same node and direction travel with the FRFs:
    # only the complex responses count
    kinds = [_check_kind(f, path) for f in found]
    usable = [f for f, kind in zip(found, kinds) if kind is None]
    if not usable:
        return None, [kind for kind in kinds if kind is not None]
    if len(usable) > 1:
        refs = ", ".join(f"dataset {f.index} (reference node {f.header.get('ref_node')}, "
                         f"{_direction_label(int(f.header.get('ref_dir', 0)))})"
                         for f in usable)
        return None, [(f"{where} has {len(usable)} Z responses in {path}: {refs}; keep one "
                       "per node (one excitation, one response quantity)")]
    function = usable[0]
    try:
        x, data = _read_values(uff, function, path)
    except InputError as err:
        return None, err.lines
    picked, problem = _pick(function, x, data, frequencies, path, frequency_problems)
    return (None, [problem]) if problem else (picked, [])


def _measurements(path: Path, case: Case, entries: Mapping[str, MapEntry],
                  values: Mapping[str, Mapping[float, complex]]) -> Measurements:
    """The :class:`Measurements` of the map's nodes at the description's frequencies, points
    in map order; a frequency where every value is zero is an :class:`InputError`."""
    data: dict[float, dict[str, tuple[np.ndarray, np.ndarray]]] = {}
    for frequency in case.frequencies:
        by_plate: dict[str, list[tuple[tuple[float, float], complex]]] = {}
        for node, entry in entries.items():
            by_plate.setdefault(entry.plate, []).append(((entry.x, entry.y),
                                                         values[node][frequency]))
        data[frequency] = {pid: (np.array([p for p, _ in rows], dtype=float),
                                 np.array([w for _, w in rows], dtype=complex))
                           for pid, rows in by_plate.items()}
        if not any(np.abs(w).max() > 0 for _, w in data[frequency].values()):
            raise InputError(f"{path}: every value at {frequency:g} Hz is zero; the measurement "
                             "term needs a non-zero field")
    return Measurements(data)


def _pick(function: _Function, x: np.ndarray, data: np.ndarray, frequencies: Sequence[float],
          path: Path, frequency_problems: dict[tuple[float, str], list[int]]
          ) -> tuple[dict[float, complex] | None, str | None]:
    """``({frequency: w}, None)``, or ``(None, message)``; line problems go to the shared dict."""
    label = function.label(path)
    n = int(function.header.get("num_pts", len(data)))
    if len(data) < n or len(x) < n or n < 1:
        return None, (f"{label}: {min(len(data), len(x))} values but record 7 announces {n}; "
                      "the dataset is truncated: export it again")
    # some exporters pad the last record with zeros beyond num_pts (ladisk/pyuff#22)
    x, data = x[:n], data[:n]
    if not np.all(np.isfinite(x)) or (n > 1 and not np.all(np.diff(x) > 0)):
        return None, (f"{label}: the abscissa is not finite and increasing (record 7 minimum "
                      "and increment, or the x values); fix the frequency axis")
    picked, bad = {}, False
    for frequency in frequencies:
        i, reason = _pick_line(x, frequency)
        if reason:
            frequency_problems.setdefault((frequency, reason), []).append(function.index)
            bad = True
            continue
        value = complex(data[i])
        if not (math.isfinite(value.real) and math.isfinite(value.imag)):
            return None, (f"{label}: the value at {x[i]:g} Hz is {value}; give a finite value "
                          "(remeasure the point, or remove its row from the map)")
        picked[frequency] = _to_displacement(function, value, float(x[i]))
    return (None if bad else picked), None


def _sort_key(node: str) -> tuple[int, int, str]:
    return (0, int(node), "") if node.lstrip("-").isdigit() else (1, 0, node)


def _some(items: Iterable[str], limit: int = 6) -> str:
    items = list(items)
    head = ", ".join(items[:limit])
    return head + (f", ... ({len(items)} in all)" if len(items) > limit else "")


def _datasets(indices: Sequence[int]) -> str:
    if len(indices) == 1:
        return f"dataset {indices[0]}"
    return f"datasets {_some(map(str, indices))}"
