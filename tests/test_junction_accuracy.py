r"""Junction lines against the exact Levy-strip reference (issue 15).

Every plate is simply supported on its local ``y = 0`` and ``y = Ly``; plates meet on junction
lines (w = 0 on each member, a rotational spring between each member and the line, the
members' moments in balance). ``tests/exact_junction.py`` solves this exactly in ``x`` and by a
sine series in ``y``, independently of the solver (its own checks: ``test_exact_junction.py``).
Here the solver meets it on a T (skin and one stiffener), a skin with two stiffeners welded
with different, lossy springs, and an X (four members, one rigid, stiffeners up and down):
the relative L2 error of ``w`` on a grid of every plate is below 1e-3.

The reference uses 400 harmonics: away from the force's line its series tail is
``~N^-3 / |sin(pi (y - y0) / Ly)|`` relative (``default_junction_n_terms``), below 1e-7 on these
grids, four orders under the tolerance.
"""

import math

import numpy as np
import pytest
from exact import Section, complex_rigidity, hinge, levy_chain
from exact_junction import JunctionLine, StripPlate, junction_levy

from assembly import parse_case
from solver.substructure import solve_assembly
from solver.tolerance import solve_to_tolerance

E, NU, RHO, ETA = 210e9, 0.3, 7800.0, 0.01
LY = 0.4
FREQUENCY = 250.0
N_TERMS = 400
RESOLUTION = 1.5
TOLERANCE = 1e-3

UP, DOWN, ALONG_X, ALONG_Y = (0.0, 0.0, 1.0), (0.0, 0.0, -1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)


def _plate(length, origin, x_axis, thickness=0.001, right="simply_supported"):
    """``(length, origin, x_axis, thickness, right edge)``; y along +y, left edge on a line or
    simply supported."""
    return length, origin, x_axis, thickness, right


def _strip(spec):
    length, origin, x_axis, thickness, right = spec
    return StripPlate(length, complex_rigidity(E, thickness, NU, ETA), NU, RHO * thickness,
                      origin, x_axis, ALONG_Y, right=right)


def _description(plates, lines, load, frequency=FREQUENCY):
    """The vtcr description of the same assembly: ``lines`` ``{joint: {plate: (edge,
    log10 k, loss factor)}}``, ``load`` ``(plate, x0, y0)``."""
    joined = {f"{p}.{edge}" for members in lines.values() for p, (edge, _, _) in members.items()}
    boundaries = []
    for name, (_, _, _, _, right) in plates.items():
        edges = {"bottom": "simply_supported", "top": "simply_supported",
                 "left": "simply_supported", "right": right}
        boundaries += [{"edge": f"{name}.{edge}", "condition": condition}
                       for edge, condition in edges.items() if f"{name}.{edge}" not in joined]
    return {
        "name": "levy-junctions", "frequency": frequency,
        "materials": {"steel": {"young_modulus": E, "poisson_ratio": NU, "density": RHO,
                                "loss_factor": ETA}},
        "plates": {name: {"material": "steel", "thickness": thickness, "size": [length, LY],
                          "frame": {"origin": list(origin), "x_axis": list(x_axis),
                                    "y_axis": list(ALONG_Y)}}
                   for name, (length, origin, x_axis, thickness, _) in plates.items()},
        "joints": {jid: {"kind": "junction",
                         "between": [f"{p}.{edge}" for p, (edge, _, _) in members.items()],
                         "log10_stiffness": {p: k for p, (_, k, _) in members.items()},
                         "loss_factor": {p: zeta for p, (_, _, zeta) in members.items()},
                         "held": True}  # the reference's lines are held
                   for jid, members in lines.items()},
        "boundaries": boundaries,
        "loads": [{"kind": "point_force", "plate": load[0], "at": list(load[1:]),
                   "amplitude": 1.0}],
    }


def _reference(plates, lines, load, frequency=FREQUENCY):
    junctions = [JunctionLine({p: (edge, math.inf if math.isinf(k) else
                                   10.0**k * (1.0 + 1j * zeta))
                               for p, (edge, k, zeta) in members.items()})
                 for members in lines.values()]
    return junction_levy({name: _strip(spec) for name, spec in plates.items()}, junctions, LY,
                         2.0 * math.pi * frequency, (*load, 1.0), N_TERMS)


def tee():
    """Skin S1 | S2, stiffener T1 (2 mm, 0.3 m, free top) standing on their line, lossy."""
    plates = {"S1": _plate(0.5, (0.0, 0.0, 0.0), ALONG_X),
              "S2": _plate(0.4, (0.5, 0.0, 0.0), ALONG_X),
              "T1": _plate(0.3, (0.5, 0.0, 0.0), UP, 0.002, "free")}
    lines = {"W1": {"S1": ("right", math.inf, 0.0), "S2": ("left", math.inf, 0.0),
                    "T1": ("left", 2.3, 0.05)}}
    return plates, lines, ("S1", 0.17, 0.13)


def two_stiffeners():
    """Skin B1 | B2 | B3 with stiffeners T1, T2 of different heights, springs 10^2.5 (lossy)
    and 10^1.5; the force in the middle bay."""
    plates = {"B1": _plate(0.5, (0.0, 0.0, 0.0), ALONG_X),
              "B2": _plate(0.45, (0.5, 0.0, 0.0), ALONG_X),
              "B3": _plate(0.4, (0.95, 0.0, 0.0), ALONG_X),
              "T1": _plate(0.15, (0.5, 0.0, 0.0), UP, 0.002, "free"),
              "T2": _plate(0.2, (0.95, 0.0, 0.0), UP, 0.002, "free")}
    lines = {"W1": {"B1": ("right", math.inf, 0.0), "B2": ("left", math.inf, 0.0),
                    "T1": ("left", 2.5, 0.1)},
             "W2": {"B2": ("right", math.inf, 0.0), "B3": ("left", math.inf, 0.0),
                    "T2": ("left", 1.5, 0.0)}}
    return plates, lines, ("B2", 0.21, 0.17)


def cross():
    """An X: skin S1 | S2 and stiffeners T1 (up) and T2 (down), every member but S1 on a
    spring of its own."""
    plates = {"S1": _plate(0.5, (0.0, 0.0, 0.0), ALONG_X),
              "S2": _plate(0.45, (0.5, 0.0, 0.0), ALONG_X),
              "T1": _plate(0.3, (0.5, 0.0, 0.0), UP, 0.002, "free"),
              "T2": _plate(0.25, (0.5, 0.0, 0.0), DOWN, 0.0015, "free")}
    lines = {"X1": {"S1": ("right", math.inf, 0.0), "S2": ("left", 3.0, 0.02),
                    "T1": ("left", 2.0, 0.0), "T2": ("left", 2.5, 0.05)}}
    return plates, lines, ("S2", 0.29, 0.13)


def _grid(length):
    """A 9 x 7 grid of a plate's interior, local coordinates, ``(x, y)`` flattened."""
    x, y = np.meshgrid(np.linspace(0.05, 0.95, 9) * length, np.linspace(0.05, 0.95, 7) * LY)
    return x.ravel(), y.ravel()


@pytest.mark.parametrize("build", [tee, two_stiffeners, cross])
def test_junction_fields_match_the_levy_reference(build):
    """Relative L2 error of w below 1e-3 on every plate (the issue's target), on a 9 x 7 grid
    of each plate. Measured at resolution 1.5: at most 2.3e-7 (T), 1.9e-7 (two stiffeners),
    7.4e-8 (X); at the default resolution 1: 4.3e-4, 4.4e-4, 2.7e-4. A wrong sign, spring law
    or member orientation costs O(1)."""
    plates, lines, load = build()
    reference = _reference(plates, lines, load)
    solution = solve_assembly(parse_case(_description(plates, lines, load)), FREQUENCY,
                              RESOLUTION)
    for name, (length, *_rest) in plates.items():
        x, y = _grid(length)
        exact = reference.w(name, x, y)
        error = np.linalg.norm(solution.w(name, np.c_[x, y]) - exact)
        assert error < TOLERANCE * np.linalg.norm(exact), (name, error / np.linalg.norm(exact))


def test_a_vanishing_stiffener_spring_leaves_the_skin_on_a_rigid_hinge_line():
    """T1's spring at 1e-8 N m/rad/m: the skin is S1 | S2 on a line held in translation with
    a continuous slope, which ``exact.levy_chain`` gives as a hinge of 1e14 (slope defect
    < 1e-9); and T1 barely moves. The skin within 1e-3 (the issue's accuracy target; T1's
    spring perturbs it by ~k / (D kappa) ~ 1e-11); T1's field below 1e-6 of the skin's
    (driven by a moment ~1e-8 times the line's rotation)."""
    plates, lines, load = tee()
    lines["W1"]["T1"] = ("left", -8.0, 0.0)
    solution = solve_assembly(parse_case(_description(plates, lines, load)), FREQUENCY,
                              RESOLUTION)
    skin = [Section(plates[p][0], complex_rigidity(E, 0.001, NU, ETA), NU, RHO * 0.001)
            for p in ("S1", "S2")]
    chain = levy_chain(skin, LY, 2.0 * math.pi * FREQUENCY, [hinge(1e14)],
                       point_forces=[(0, *load[1:], 1.0)], n_terms=N_TERMS)
    largest = 0.0
    for i, name in enumerate(("S1", "S2")):
        x, y = _grid(plates[name][0])
        exact = chain.w(x, y, i)
        assert np.linalg.norm(solution.w(name, np.c_[x, y]) - exact) \
            < TOLERANCE * np.linalg.norm(exact)
        largest = max(largest, float(np.max(np.abs(exact))))
    x, y = _grid(plates["T1"][0])
    assert np.max(np.abs(solution.w("T1", np.c_[x, y]))) < 1e-6 * largest


def test_a_stiffener_at_2500_hz_meets_the_tolerance():
    """The stall of the issue: skin bays of 0.4 m, a 10 cm, 2 mm stiffener (1.1 bending
    wavelengths high at 2500 Hz, the skin 6 across) welded at log10 k = 3.5, its top free.
    With LU plate solves each load function's transfer carried coefficients far larger than
    the field's, their sum lost digits as rays were added, and so did the enriched solve of
    the estimate: the tolerance 1e-3 stopped at "the round-off floor" (S2 estimated 2.4e-3 at
    resolution 1, 5.4e-3 at 1.5, while the field at 1.5 was within 3.5e-6). With the
    truncated rank-revealing plate solves it is met at 1.5 (estimate 8.5e-9, error 5.5e-10)."""
    plates = {"S1": _plate(0.4, (0.0, 0.0, 0.0), ALONG_X),
              "S2": _plate(0.4, (0.4, 0.0, 0.0), ALONG_X),
              "T1": _plate(0.1, (0.4, 0.0, 0.0), UP, 0.002, "free")}
    lines = {"W1": {"S1": ("right", math.inf, 0.0), "S2": ("left", math.inf, 0.0),
                    "T1": ("left", 3.5, 0.0)}}
    load = ("S1", 0.17, 0.13)
    solution, estimate = solve_to_tolerance(parse_case(_description(plates, lines, load, 2500.0)),
                                            2500.0, TOLERANCE)
    reference = _reference(plates, lines, load, 2500.0)
    assert estimate.total <= TOLERANCE
    for name, (length, *_rest) in plates.items():
        x, y = _grid(length)
        exact = reference.w(name, x, y)
        error = np.linalg.norm(solution.w(name, np.c_[x, y]) - exact) / np.linalg.norm(exact)
        assert error < 2 * TOLERANCE, (name, error)
