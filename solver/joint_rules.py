r"""Joint lines: their Gauss rules, the Legendre functions that carry their loads, and the
channel parameters of the joint laws (``docs/method.md`` sections 6.2 and 7.3).

A leaf of the assembly solve: :mod:`solver.substructure` builds its channels on these rules,
and :mod:`solver.power` integrates the power through the joints on the same ones.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike

from assembly.case import Case
from assembly.joints import JunctionJoint
from solver.rays import gauss_legendre

__all__ = ["interface_function_count", "load_function_projection", "legendre_values",
           "joint_gauss", "channel_parameters", "joint_parameters", "translational_stiffness"]


def interface_function_count(kappa0: float, length: float, resolution: float = 1.0,
                             tau: float = 2.5, kappa_answered: float | None = None) -> int:
    r"""Legendre functions per interface unknown:
    :math:`M = \lceil\min(0.75\,s\,\kappa_0,\ \tfrac{\tau}{2}\kappa_a)\,L\rceil + 2`, with
    :math:`\kappa_a = \kappa_0` (``kappa_answered``) unless given.

    A Legendre series resolves :math:`e^{j\beta\sigma}` on :math:`[0, L]` once
    :math:`M > \beta L/2`; the joint loads carry wavenumbers up to about :math:`1.5\kappa_0`
    (propagating waves plus the slower part of the edge boundary layers). More functions than
    the plates' rays can answer make the loads' system ill-posed: against the Levy series of a
    three-plate chain from 60 to 600 Hz and log10 k = 2 to 8, ``+ 2`` was near the best count
    everywhere, and ``+ 8`` up to ten times less accurate at stiff joints and low
    :math:`\kappa_0L` (``bench/README.md``). For the same reason the count stops growing with
    the resolution :math:`s` where the functions pass the rays' largest edge wavenumber
    :math:`\tau\kappa_a` (``tau``, the ``edge_wavenumber_ratio``), at :math:`s = 2\tau/3`:
    on a stiffened panel at 2500 Hz (rays at resolution 2.25) 59, 65 and 87 functions gave
    7e-9, 7e-9 and 2e-8, the 129 of resolution 3.375 6e-3.

    A moving line (``docs/method.md`` section 10.4) takes for :math:`\kappa_a` the smallest
    :math:`\kappa_0` of its members, the largest edge wavenumber *every* member's rays answer.
    A member's :math:`K_n`, :math:`N_{nn}`, :math:`N_{nt}` enter only the line's force
    balance and translation continuity; on a function its bending rays cannot answer, its
    :math:`K_n` is balanced by the other members' in-plane tractions, whose response, of
    compliance about :math:`1/(A^*\beta)`, is 1e3 to 1e4 times smaller than a bending one:
    a near-null direction of the interface problem per such function. On a three-bay panel
    at 2500 Hz (1 mm skin, 2 mm stiffeners, :math:`\kappa_0` 100 and 71 /m) the 53 functions
    of :math:`\kappa_0 = 100` left 72 singular values below 1e-8 of the largest, interface
    loads of 1e5 to 1e7 N/m for a 1 N force and, through the grouped factorisation of the
    interface problem, fields wrong by order 1; the 38 of :math:`\kappa_a = 71` converge
    (2e-5 to 2e-4 between resolutions 1.5 and 2.25).
    """
    answered = kappa0 if kappa_answered is None else kappa_answered
    return math.ceil(min(0.75 * resolution * kappa0, 0.5 * tau * answered) * length) + 2


def load_function_projection(root_w: np.ndarray, psi: np.ndarray) -> np.ndarray:
    r""":math:`Q^HW^{1/2}`, shape (n_f, Gauss points): the coordinates, on an orthonormal basis
    :math:`Q` of the joint's weighted load functions :math:`W^{1/2}\psi`, of a quantity sampled
    at the joint's Gauss points. A channel's load and kinematic samples are taken through it.

    The residual :math:`r = (LS + l) - c(RS + \rho)` then counts through its :math:`L^2`
    projection on the functions that carry the loads, :math:`\|Q^HW^{1/2}r\|^2`: the joint law
    is imposed as far as the loads can carry it. The part of the plates' traces outside those
    functions, which no load of the discretisation can balance, is not counted; measuring it
    made each channel's rows as many as its Gauss points (instead of its functions) and, with
    the functions a plate's rays can answer, left a floor of that part in every residual
    (``bench/README.md``)."""
    return scipy.linalg.orth(root_w[:, None] * psi).conj().T * root_w


def legendre_values(sigma: ArrayLike, length: float, n: int) -> np.ndarray:
    """``P_m(2 sigma / L - 1)`` for ``m < n``, shape ``(len(sigma), n)``."""
    x = 2.0 * np.asarray(sigma) / length - 1.0
    return np.polynomial.legendre.legvander(x, n - 1)


def joint_gauss(length: float, k_max: float) -> tuple[np.ndarray, np.ndarray]:
    r"""Gauss points and weights on a joint line of ``length`` (m): :math:`\lceil k_{max}L\rceil + 16`
    points, where :math:`k_{max}` is the largest ray wavenumber of the two plates."""
    x, w = gauss_legendre(math.ceil(k_max * length) + 16)
    return 0.5 * length * (x + 1.0), 0.5 * length * w


def channel_parameters(parameters: Mapping[str, Mapping[str, float]],
                       omega: float) -> dict[tuple[str, str], complex]:
    r"""``{(channel name, kind): c}`` from ``{name: {log10_stiffness, loss_factor, mass}}``
    (:meth:`assembly.Case.updatable_parameters`): the rotation channel's
    :math:`k(1 + j\zeta)` and the mass channel's :math:`\omega^2\mu`."""
    out = {}
    for name, p in parameters.items():
        out[name, "rotation"] = 10.0 ** p["log10_stiffness"] * (1.0 + 1j * p["loss_factor"])
        out[name, "mass"] = omega**2 * p["mass"] + 0j
    return out


def joint_parameters(case: Case, omega: float) -> dict[tuple[str, str], complex]:
    """Channel parameters ``{(channel name, kind): c}`` of the description's joints."""
    return channel_parameters(case.updatable_parameters(), omega)


def translational_stiffness(joint: JunctionJoint, plate: str) -> complex:
    r""":math:`k_{t,i}^* = 10^{\log_{10}k_{t,i}}(1 + j\zeta_{t,i})` (N/m²) of a junction
    member's translational spring."""
    return (10.0 ** joint.member_log10_translational_stiffness(plate)
            * (1.0 + 1j * joint.member_translational_loss_factor(plate)))
