"""What the tests and benchmarks share: where the repository's cases are, the two-plate
description the input checks vary, and plate chains (steel plates along x, simply supported on
y = 0 and y = Ly, at 450 Hz, bending wavelength 0.148 m) with their descriptions, their exact
Levy series (``tests/exact.py``) as measured data, and a mixed chain for the interface solvers.

A support module, like ``exact.py``: test modules import it, never each other. The fixtures
built on it are in ``tests/conftest.py``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

import numpy as np
import scipy.linalg
from exact import Section, complex_rigidity, coplanar, hinge, levy_chain
from exact_prismatic import (
    FoldedPlate,
    PrismaticLine,
    membrane_stiffness,
    prismatic_levy,
)

from assembly import parse_case
from assembly.geometry import plate_edges
from solver.membrane import MembraneEdge, MembraneProblem
from updating.data.measurements import Measurements, add_noise

__all__ = ["ROOT", "CASES", "STEEL", "TWO_PLATES", "E", "NU", "RHO", "H", "ETA", "D", "LY",
           "LENGTHS", "FREQUENCY", "OMEGA", "MATERIAL", "grid", "chain_description",
           "levy_chain_experiment", "exact_measurements", "exact_joint", "dense_interface",
           "field_difference", "mixed_chain", "folded_description", "folded_reference",
           "STRIP_H", "STRIP_A", "membrane_strip", "membrane_strip_fields",
           "membrane_strip_problem"]

ROOT = Path(__file__).resolve().parents[1]
"""The repository."""
CASES = ROOT / "cases"
"""The example descriptions (``cases/*.toml``)."""


STEEL = """\
[materials.steel]
young_modulus = 210e9
poisson_ratio = 0.3
density = 7800.0
loss_factor = 0.01
"""
"""The steel of the test descriptions: ``[materials.steel]``, 1 % loss factor."""

# Two plates side by side, one coplanar joint, a point force, a measurement grid: the
# description the input checks and the library-call tests vary one field of
TWO_PLATES = ('''\
name = "two"
frequency = 155.0

''' + STEEL + '''
[plates.P1]
material = "steel"
thickness = 0.001
size = [0.5, 0.4]

[plates.P2]
material = "steel"
thickness = 0.001
size = [0.5, 0.4]

[joints.G1]
kind = "coplanar"
between = ["P1.right", "P2.left"]
log10_stiffness = 2.0

[[boundaries]]
edge = "P2.right"
condition = "simply_supported"

[[loads]]
kind = "point_force"
plate = "P1"
at = [0.17, 0.13]
amplitude = 1.0

[measurement]
spacing = 0.1
''')

E, NU, RHO, H, ETA = 210e9, 0.3, 7800.0, 1e-3, 0.01
D = complex_rigidity(E, H, NU, ETA)
LY = 0.5
LENGTHS = (0.5, 0.45, 0.55)
FREQUENCY = 450.0
OMEGA = 2 * np.pi * FREQUENCY
MATERIAL = {"young_modulus": E, "poisson_ratio": NU, "density": RHO, "loss_factor": ETA}


def inner_grid(length: float, width: float, n: int = 15) -> np.ndarray:
    """``n`` x ``n`` points, shape (n * n, 2), on the plate ``[0, length] x [0, width]``, 2 % in
    from its edges: where the folded-plate checks compare fields."""
    x, y = np.meshgrid(np.linspace(0.02, 0.98, n) * length, np.linspace(0.02, 0.98, n) * width)
    return np.column_stack([x.ravel(), y.ravel()])


def folded_w(solution, plates: FoldedPlates, width: float) -> dict[str, np.ndarray]:
    """``w`` of each plate of a folded plate (``plates`` as :func:`folded_description`'s) on
    its :func:`inner_grid`."""
    return {name: solution.plates[name].field(inner_grid(length, width))["w"]
            for name, (length, *_) in plates.items()}


def grid(lx, ly, n=10):
    return np.array([(x, y) for x in np.linspace(0.04 * lx, 0.96 * lx, n)
                     for y in np.linspace(0.04 * ly, 0.96 * ly, n)])


def chain_description(joints, resolution=1.0, left="simply_supported", right="clamped",
                      force=(0, 0.12, 0.31), lengths=LENGTHS, edge_loads=(), frequency=FREQUENCY,
                      ly=LY):
    """A chain P1-P2-... along x; ``joints`` are dicts with kind/log10_stiffness/..."""
    n = len(joints) + 1
    plates = {f"P{i + 1}": {"material": "steel", "thickness": H, "size": [lengths[i], ly],
                            "origin": [sum(lengths[:i]), 0.0]} for i in range(n)}
    boundaries = [{"edge": f"P{i + 1}.{e}", "condition": "simply_supported"}
                  for i in range(n) for e in ("bottom", "top")]
    for edge, condition in (("P1.left", left), (f"P{n}.right", right)):
        if condition != "free":
            boundaries.append({"edge": edge, "condition": condition})
    loads = list(edge_loads)
    if force is not None:
        plate, x, y = force
        loads.append({"kind": "point_force", "plate": f"P{plate + 1}", "at": [x, y],
                      "amplitude": 1.0})
    return {
        "name": "chain", "frequency": frequency, "materials": {"steel": MATERIAL},
        "plates": plates,
        "joints": {f"G{i + 1}": {"between": [f"P{i + 1}.right", f"P{i + 2}.left"], **joint}
                   for i, joint in enumerate(joints)},
        "boundaries": boundaries, "loads": loads,
        "discretisation": {"resolution": resolution},
    }


def levy_chain_experiment(truths, lengths=LENGTHS[:2], model_log_k=2.5, noise=0.1):
    """A chain (simply supported left, clamped right, 1 N at (0.12, 0.31) on the first plate),
    one coplanar joint per pair (loss factor 0.05) at ``model_log_k`` in the model, updating
    bounds [-1, 6]: ``(case, exact)``, ``exact`` the Levy series of the chain whose joints have
    the log10 k ``truths`` (the measured field vtcr did not compute)."""
    joints = [{"kind": "coplanar", "log10_stiffness": model_log_k, "loss_factor": 0.05}
              for _ in truths]
    description = chain_description(joints, 1.0, force=(0, 0.12, 0.31), lengths=lengths)
    description["measurement"] = {"spacing": 0.08, "noise": noise}
    description["updating"] = {"bounds": [-1.0, 6.0]}
    description["truth"] = {"joints": {f"G{i + 1}": {"log10_stiffness": t}
                                       for i, t in enumerate(truths)}}
    case = parse_case(description)
    exact = levy_chain([Section(lx, D, NU, RHO * H) for lx in lengths], LY,
                       2 * np.pi * case.frequencies[0],
                       joints=[coplanar(10.0**t, 0.05) for t in truths],
                       left="simply_supported", right="clamped",
                       point_forces=[(0, 0.12, 0.31, 1.0)])
    return case, exact


def exact_measurements(case, exact, noise=0.0, rng=None):
    """Measurements at the case's grid from a Levy chain solution (plate ``Pi`` is section
    ``i - 1``), times ``1 + U(-noise, noise)``."""
    layout = {}
    for plate, x, y in case.measurement_points():
        layout.setdefault(plate, []).append((x, y))
    data = {}
    for plate, points in sorted(layout.items()):
        points = np.array(points)
        values = exact.w(points[:, 0], points[:, 1], plate=int(plate[1:]) - 1)
        data[plate] = (points, add_noise(values, noise, rng) if noise else values)
    return Measurements({case.frequencies[0]: data})


def exact_joint(joint):
    k = 10.0 ** joint["log10_stiffness"]
    if joint["kind"] == "hinge":
        return hinge(k, joint.get("loss_factor", 0.0))
    return coplanar(k, joint.get("loss_factor", 0.0), joint.get("mass", 0.0))


def dense_interface(system, blocks):
    """Minimiser of sum ||A_b S_I + a_b||^2 s.t. G S = g, from the dense normal equations."""
    n = system.n_s
    h, rhs = np.zeros((n, n), dtype=complex), np.zeros(n, dtype=complex)
    for b in blocks:
        h[np.ix_(b.index, b.index)] += b.matrix.conj().T @ b.matrix
        rhs[b.index] -= b.matrix.conj().T @ b.offset
    g_mat, g = system.constraints
    g_mat = g_mat.toarray()
    m = g_mat.shape[0]
    kkt = np.block([[h, g_mat.conj().T], [g_mat, np.zeros((m, m))]])
    scale = 1.0 / np.sqrt(np.abs(kkt).max(axis=1))
    x = scipy.linalg.solve(kkt * scale[:, None] * scale[None, :], np.concatenate([rhs, g]) * scale)
    return (x * scale)[:n]


def field_difference(system, s, t):
    """Relative L2 difference of the plate fields of interface unknowns ``s`` and ``t``."""
    from solver.plate import evaluate_field

    a, b = system.plate_amplitudes(s), system.plate_amplitudes(t)
    num = den = 0.0
    for pid, problem in system.problems.items():
        points = grid(*problem.size)
        wa = evaluate_field(problem, system.bases[pid], a[pid], points)["w"]
        wb = evaluate_field(problem, system.bases[pid], b[pid], points)["w"]
        num += np.sum(np.abs(wa - wb) ** 2)
        den += np.sum(np.abs(wb) ** 2)
    return float(np.sqrt(num / den))


def mixed_chain():
    """Three plates: damped coplanar joint with a line mass (two shear unknowns), then a hinge;
    free outer edges, so that junction corner forces appear at the joint ends."""
    joints = [{"kind": "coplanar", "log10_stiffness": 1.5, "loss_factor": 0.1, "mass": 0.05},
              {"kind": "hinge", "log10_stiffness": 3.5}]
    return parse_case(chain_description(joints, left="free", force=(1, 0.2, 0.17)))


# ---------------------------------------------------------------------------------------------
# Folded plates with shear-diaphragm ends: descriptions and their exact prismatic solution
# ---------------------------------------------------------------------------------------------
FoldedPlates = Mapping[str, tuple[float, tuple[float, float, float], tuple[float, float, float],
                                  float, str]]
"""``{plate: (length, origin, x_axis, thickness, right edge's condition)}``: steel plates of
width ``ly`` along +y, placed in 3D; the left edge is on a line or simply supported."""
FoldLines = Mapping[str, Mapping[str, tuple[str, complex]]]
"""``{joint: {plate: (edge, log10 k)}}``: junction lines, ``inf`` a rigid member (for the
reference, a complex log10 gives a lossy spring: ``log10(k (1 + j zeta))``)."""


FOLD_ENDS = {"diaphragm": ("simply_supported", "diaphragm"), "symmetric": ("symmetric", "roller"),
             "roller": ("simply_supported", "roller"), "fixed": ("simply_supported", "fixed")}
"""The ends y = 0 and y = ``ly`` of a prismatic folded plate: shear diaphragms, or planes of
symmetry (the exact reference's ``ends``), or mixed ends, simply supported in bending and
in-plane rollers (their line's loads log-singular there; no exact reference), or simply
supported and fixed in plane (no exact reference either); their bending and in-plane
conditions."""


def folded_description(plates: FoldedPlates, lines: FoldLines, load: tuple[str, float, float],
                       frequencies: float | list[float], held: bool | None, ly: float,
                       resolution: float = 1.5, ends: str = "diaphragm") -> dict:
    """The vtcr description of a prismatic folded plate: every plate's ends y = 0 and y =
    ``ly`` as ``ends`` says (:data:`FOLD_ENDS`: shear diaphragms, simply supported with
    ``in_plane = "diaphragm"``, or planes of symmetry), its other outer edges simply supported
    (fixed in-plane) or as ``plates`` says, 1 N at ``load``."""
    joined = {f"{p}.{edge}" for members in lines.values() for p, (edge, _) in members.items()}
    boundaries = []
    end_condition, end_in_plane = FOLD_ENDS[ends]
    for name, (_, _, _, _, right) in plates.items():
        for edge, condition, in_plane in (("bottom", end_condition, end_in_plane),
                                          ("top", end_condition, end_in_plane),
                                          ("left", "simply_supported", None),
                                          ("right", right, None)):
            if f"{name}.{edge}" not in joined:
                boundaries.append({"edge": f"{name}.{edge}", "condition": condition}
                                  | ({"in_plane": in_plane} if in_plane else {}))
    return {
        "name": "fold",
        **({"frequencies": frequencies} if isinstance(frequencies, list)
           else {"frequency": frequencies}),
        "materials": {"steel": MATERIAL},
        "plates": {name: {"material": "steel", "thickness": h, "size": [length, ly],
                          "frame": {"origin": list(origin), "x_axis": list(x_axis),
                                    "y_axis": [0.0, 1.0, 0.0]}}
                   for name, (length, origin, x_axis, h, _) in plates.items()},
        "joints": {jid: {"kind": "junction",
                         "between": [f"{p}.{edge}" for p, (edge, _) in members.items()],
                         "log10_stiffness": {p: k for p, (_, k) in members.items()}}
                        | ({"held": held} if held is not None else {})
                   for jid, members in lines.items()},
        "boundaries": boundaries,
        "discretisation": {"resolution": resolution},
        "loads": [{"kind": "point_force", "plate": load[0], "at": list(load[1:]),
                   "amplitude": 1.0}],
    }


def folded_reference(plates: FoldedPlates, lines: FoldLines, load: tuple[str, float, float],
                     frequency: float, held: bool, ly: float, n_terms: int = 600,
                     translational: Mapping[str, Mapping[str, complex]] | None = None,
                     ends: str = "diaphragm"):
    """The exact prismatic solution (``tests/exact_prismatic.py``) of
    :func:`folded_description`'s structure, lines moving or ``held``, its ends as ``ends``
    says (:data:`FOLD_ENDS`).

    ``translational``: ``{joint: {plate: k_t*}}``, the complex stiffness (N/m^2, ``k_t (1 + j
    zeta_t)``) of a translational spring between that member's edge and the line
    (``PrismaticLine.translational``: ``F_i = k_t* (U_J - X_i)``); members not listed are tied
    rigidly in translation.  (Reference only: :func:`folded_description` has no such spring.)
    """
    translational = translational or {}
    unknown = set(translational) - set(lines)
    if unknown:
        raise ValueError(f"translational springs on unknown joints {sorted(unknown)}")
    strips = {name: FoldedPlate(length, complex_rigidity(E, h, NU, ETA),
                                membrane_stiffness(E, h, NU, ETA), NU, RHO * h, origin, x_axis,
                                (0.0, 1.0, 0.0), right=right)
              for name, (length, origin, x_axis, h, right) in plates.items()}
    prismatic = [PrismaticLine({p: (edge, math.inf if k == math.inf else 10.0**k)
                                for p, (edge, k) in members.items()}, held=held,
                                translational=dict(translational.get(jid, {})))
                 for jid, members in lines.items()]
    return prismatic_levy(strips, prismatic, ly, 2.0 * math.pi * frequency,
                          forces=[(*load, 1.0)], n_terms=n_terms, ends=ends)


# The exact in-plane strip: one 2 mm steel plate 0.5 x 0.4 m of tests/exact_prismatic.py,
# shear diaphragms on y = 0 and y = 0.4, clamped (in-plane fixed) on x = 0 and free on
# x = 0.5, driven by an in-plane force along x at (0.08, 0.17); rectangles cut from it, their
# edges given its exact data, are solved by the membrane VTCR and compared with it
STRIP_H = 0.002
"""The strip's thickness (m)."""
STRIP_A = membrane_stiffness(E, STRIP_H, NU, ETA)
"""The strip's membrane stiffness :math:`A^*` (N/m)."""
_STRIP_SIZE = (0.5, 0.4)
_STRIP_FORCE = ("P", 0.08, 0.17, 1.0)


def membrane_strip(frequency: float):
    """The exact strip's in-plane field at ``frequency`` and the circular frequency."""
    plate = FoldedPlate(_STRIP_SIZE[0], complex_rigidity(E, STRIP_H, NU, ETA), STRIP_A, NU,
                        RHO * STRIP_H, (0, 0, 0), (1, 0, 0), (0, 1, 0), left="clamped",
                        right="free")
    omega = 2.0 * math.pi * frequency
    return prismatic_levy({"P": plate}, [], _STRIP_SIZE[1], omega,
                          inplane_forces=[_STRIP_FORCE], n_terms=200).membranes["P"], omega


def membrane_strip_fields(field, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``u`` (n, 2) and ``N`` (n, 2, 2) of the exact strip's in-plane ``field``."""
    d = {(c, i, j): field.derivative(c, x, y, nx=i, ny=j)
         for c in "uv" for i, j in ((0, 0), (1, 0), (0, 1))}
    n_xx = STRIP_A * (d["u", 1, 0] + NU * d["v", 0, 1])
    n_yy = STRIP_A * (d["v", 0, 1] + NU * d["u", 1, 0])
    n_xy = 0.5 * STRIP_A * (1.0 - NU) * (d["u", 0, 1] + d["v", 1, 0])
    resultants = np.array([[n_xx, n_xy], [n_xy, n_yy]]).transpose(2, 0, 1)
    return np.stack([d["u", 0, 0], d["v", 0, 0]], axis=-1), resultants


def membrane_strip_problem(field, omega: float, corner: np.ndarray, size: tuple[float, float],
                           conditions: Mapping[str, str]) -> MembraneProblem:
    """The rectangle ``corner + [0, size]`` of the exact strip, each edge given the exact data
    of its in-plane condition (``conditions``, by edge name)."""
    edges = {}
    for edge in plate_edges(size):
        def data(s: np.ndarray, edge=edge) -> dict[str, np.ndarray]:
            points = corner + edge.start + s[:, None] * edge.tangent
            u, resultants = membrane_strip_fields(field, points[:, 0], points[:, 1])
            traction = resultants @ edge.normal
            return {"u_n": u @ edge.normal, "u_t": u @ edge.tangent,
                    "N_nn": traction @ edge.normal, "N_nt": traction @ edge.tangent}

        edges[edge.name] = MembraneEdge(
            conditions[edge.name],
            {key: (lambda s, key=key, data=data: data(s)[key])
             for key in ("u_n", "u_t", "N_nn", "N_nt")})
    return MembraneProblem(size, STRIP_A, NU, RHO * STRIP_H, omega, edges)
