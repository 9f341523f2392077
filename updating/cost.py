r"""The modified constitutive-relation error and its reduced cost function p -> E_mod^2(p).

For each measured frequency (``vtcr-formulation.md`` sections 6.3 and 7):

.. math::
    E_{mod}^2(p) = \min_{S:\ GS = g}\ (1 - r)\sum_\Gamma\alpha_\Gamma E_\Gamma^2(S; p)
                   + r\,E_{mes}^2(S),\qquad
    E_{mes}^2 = \frac{\sum_n|\Pi_n u(S) - \tilde u_n|^2}{\sum_n|\tilde u_n|^2},

where the plate fields are :math:`u_i = \Phi_i(U_i^0 + T_iS) + w_{p,i}` (admissibility holds
exactly for every S). Both terms are quadratic in :math:`z = [S; 1]`; the measurement term has
the linear part that the paper's printed eq. 30 omits. With several frequencies the costs are
summed, each with its own fixed normalisation (its :math:`E_{ref}` and :math:`\|\tilde u\|^2`).

Everything that does not depend on p — plate factorisations, transfer operators, residual Gram
matrices, the measurement operator and :math:`E_{ref}` (fixed at the initial parameters) — is
built once in :class:`ModifiedProblem`; one evaluation assembles
:math:`Q(p) = \frac{1-r}{E_{ref}}\sum\alpha_\Gamma Q_\Gamma(p) + rQ_{mes}` with a few scalar
multiplications and solves the small KKT system of :func:`solver.substructure.solve_reduced`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from solver.plate import evaluate_field
from solver.rays import ray_field
from solver.substructure import (
    build_assembly_system,
    joint_energy_matrices,
    solve_assembly,
    solve_reduced,
)

__all__ = ["ModifiedProblem", "Evaluation", "channel_parameters", "PARAMETER_NAMES"]

PARAMETER_NAMES = ("log10_stiffness", "loss_factor", "mass")


def channel_parameters(parameters, omega):
    """``{(joint, channel): c}`` from ``{joint: {log10_stiffness, loss_factor, mass}}``."""
    out = {}
    for jid, p in parameters.items():
        out[jid, "rotation"] = 10.0 ** p["log10_stiffness"] * (1.0 + 1j * p["loss_factor"])
        out[jid, "mass"] = omega**2 * p["mass"] + 0j
    return out


@dataclass(frozen=True)
class Evaluation:
    """E_mod^2 and its parts at one parameter set (dimensionless; sums over frequencies)."""

    e_mod: float
    e_int: float
    e_mes: float
    residuals: dict  # joint -> E_Gamma^2
    interface: dict  # frequency -> S


@dataclass
class _Frequency:
    system: object
    operator: np.ndarray  # (n_meas, n_s): measured w per unit S
    offset: np.ndarray  # (n_meas,): measured w at S = 0
    measured: np.ndarray  # (n_meas,)
    gram: np.ndarray  # (n_s + 1, n_s + 1): E_mes^2 = z^H gram z


def _measurement_gram(operator, offset, measured):
    x = np.column_stack([operator, offset - measured])
    return x.conj().T @ x / float(np.vdot(measured, measured).real)


class ModifiedProblem:
    """The parameter-independent part of the updating problem, built once.

    Parameters
    ----------
    case : assembly.Case
        The model; its joints give the initial parameters p0 that fix :math:`E_{ref}`.
    measurements : updating.measurements.Measurements
    r : float, optional
        Weight of the measurement term (default ``[updating] r``).
    resolution : float, optional
        Discretisation resolution (default ``[discretisation] resolution``).
    """

    def __init__(self, case, measurements, r=None, resolution=None):
        self.case = case
        self.r = case.updating.r if r is None else r
        self.alpha = dict(case.updating.alpha)
        self.joints = tuple(case.joints)
        self.frequencies = {}
        for frequency in measurements.frequencies:
            system = build_assembly_system(case, frequency, resolution)
            solve_assembly(case, frequency, system=system)  # fixes E_ref at p0
            rows, offsets, values = [], [], []
            for pid, (points, measured) in measurements.data[frequency].items():
                problem, basis = system.problems[pid], system.bases[pid]
                rays = ray_field(basis, points)["w"]
                particular = evaluate_field(problem, basis, np.zeros(basis.n_dof), points)["w"]
                op, off = system.affine_plate_operator(pid, rays, particular)
                rows.append(op)
                offsets.append(off)
                values.append(measured)
            operator, offset = np.vstack(rows), np.concatenate(offsets)
            measured = np.concatenate(values)
            self.frequencies[frequency] = _Frequency(
                system, operator, offset, measured, _measurement_gram(operator, offset, measured))

    def initial_parameters(self):
        """``{joint: {log10_stiffness, loss_factor, mass}}`` of the model."""
        return {jid: {"log10_stiffness": j.log10_stiffness, "loss_factor": j.loss_factor,
                      "mass": j.mass} for jid, j in self.case.joints.items()}

    def _solve(self, data, parameters, gram):
        system = data.system
        energies = joint_energy_matrices(system, channel_parameters(parameters, system.omega))
        interface = sum(self.alpha[jid] * q for jid, q in energies.items()) / system.e_ref
        cost = (1.0 - self.r) * interface + self.r * gram
        s = solve_reduced(system, cost)
        z = np.append(s, 1.0)
        residuals = {jid: float((z.conj() @ q @ z).real) / system.e_ref
                     for jid, q in energies.items()}
        return s, residuals, float((z.conj() @ gram @ z).real)

    def evaluate(self, parameters) -> Evaluation:
        """:math:`E_{mod}^2`, :math:`E_{int}^2`, :math:`E_{mes}^2` and every :math:`E_\\Gamma^2`."""
        residuals = dict.fromkeys(self.joints, 0.0)
        e_mes, interfaces = 0.0, {}
        for frequency, data in self.frequencies.items():
            s, res, mes = self._solve(data, parameters, data.gram)
            interfaces[frequency] = s
            e_mes += mes
            for jid, value in res.items():
                residuals[jid] += value
        e_int = sum(self.alpha[jid] * value for jid, value in residuals.items())
        e_mod = (1.0 - self.r) * e_int + self.r * e_mes
        return Evaluation(e_mod, e_int, e_mes, residuals, interfaces)

    def cost(self, parameters) -> float:
        """:math:`E_{mod}^2(p)` (the reduced cost function)."""
        return self.evaluate(parameters).e_mod

    def noise_floor(self, parameters, noise, seed=0, realisations=4):
        r"""Residuals a correct model would show under measurement noise alone.

        The measured values are replaced by the model's own prediction at ``parameters`` times
        :math:`1 + e`, :math:`e\sim U[-noise, noise]`; the mean of the resulting
        :math:`E_\Gamma^2` over a few realisations is the level below which a joint's residual
        cannot be told from noise and discretisation error.
        """
        rng = np.random.default_rng(seed)
        floors = dict.fromkeys(self.joints, 0.0)
        for frequency, data in self.frequencies.items():
            energies = joint_energy_matrices(
                data.system, channel_parameters(parameters, data.system.omega))
            cost0 = sum(self.alpha[jid] * q for jid, q in energies.items())
            s0 = solve_reduced(data.system, cost0)
            prediction = data.operator @ s0 + data.offset
            for _ in range(realisations):
                noisy = prediction * (1.0 + rng.uniform(-noise, noise, prediction.shape))
                gram = _measurement_gram(data.operator, data.offset, noisy)
                _, res, _ = self._solve(data, parameters, gram)
                for jid, value in res.items():
                    floors[jid] += value / realisations
        return floors

    def field(self, frequency, interface):
        """Plate amplitudes for interface unknowns S (to plot or export the updated field)."""
        return self.frequencies[frequency].system.plate_amplitudes(interface)

    @property
    def reference_energies(self):
        return {f: d.system.e_ref for f, d in self.frequencies.items()}

    @property
    def size(self):
        """``(ray unknowns, interface unknowns, constraints)`` at the first frequency."""
        data = next(iter(self.frequencies.values()))
        n_rays = sum(b.n_dof for b in data.system.bases.values())
        return n_rays, data.system.n_s, data.system.constraints[0].shape[0]


def log_grid(bounds, n):
    """``n`` equally spaced values of log10 k over ``bounds``."""
    lo, hi = bounds
    return np.linspace(lo, hi, n) if n > 1 else np.array([0.5 * (lo + hi)])


def cost_curve(problem, parameters, joint, values):
    """E_mod^2, E_int^2, E_mes^2 and E_Gamma^2 of ``joint`` against its log10 k."""
    rows = []
    for value in values:
        trial = {jid: dict(p) for jid, p in parameters.items()}
        trial[joint]["log10_stiffness"] = float(value)
        ev = problem.evaluate(trial)
        rows.append((float(value), ev.e_mod, ev.e_int, ev.e_mes, ev.residuals[joint]))
    return rows

