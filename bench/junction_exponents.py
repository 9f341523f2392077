"""The exponents of the in-plane field where a moving line ends on edges fixed in their plane
(:mod:`solver.junction_exponents`, ``docs/method.md`` section 10.4, *Ends held in their
plane*) for a few shapes, and which of them load the line (those the solver gives load
functions :math:`t^{\\lambda - 1}` and corner functions of their own).

Run: ``python bench/junction_exponents.py`` (a second). Measured: ``bench/README.md``.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import scipy.optimize

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from solver.junction_exponents import (  # noqa: E402
    EndMember,
    junction_exponents,
    line_loading_exponents,
)

POISSON = 0.3
SHEAR_MODULUS = 210e9 / (2.0 * (1.0 + POISSON))


def member(thickness: float, partner: int | None = None) -> EndMember:
    return EndMember(thickness, SHEAR_MODULUS, POISSON, partner)


SHAPES = {
    "one quadrant, line edge free (the fixed-free corner)": (member(1.0),),
    "L fold, equal plates": (member(2.0), member(2.0)),
    "L fold, 1 mm and 2 mm": (member(1.0), member(2.0)),
    "T, stiffener 1e-3 of the skin": (member(1.0, 1), member(1.0, 0), member(1e-3)),
    "T, skin 1 mm, stiffener 1.5 mm (tests/test_moving_lines.py's T1 of the panels)":
        (member(1.0, 1), member(1.0, 0), member(1.5)),
    "T, skin 1 mm, stiffener 2 mm (tests/test_held_ends.py, cases/stiffened_panel.toml)":
        (member(1.0, 1), member(1.0, 0), member(2.0)),
    "T, stiffener as thick as the skin": (member(1.0, 1), member(1.0, 0), member(1.0)),
    "cross of two 1 mm skins": (member(1.0, 1), member(1.0, 0), member(1.0, 3),
                                member(1.0, 2)),
}


def main() -> None:
    kappa = (3.0 - POISSON) / (1.0 + POISSON)
    williams = scipy.optimize.brentq(
        lambda lam: 1.0 + kappa**2 + 2.0 * kappa * math.cos(math.pi * lam) - 4.0 * lam**2,
        0.5, 1.0, xtol=1e-14)
    print(f"check: the Williams equation's fixed-free root {williams:.6f}")
    for name, members in SHAPES.items():
        roots = junction_exponents(members)
        loading = line_loading_exponents(members)
        print(f"{name}: " + (", ".join(f"{r:.4f}" for r in roots) or "none")
              + " in (0, 2); loading the line: "
              + (", ".join(f"{r:.4f}" for r in loading) or "none"))


if __name__ == "__main__":
    main()
