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

import math
import time
from dataclasses import dataclass

import numpy as np

from solver.plate import evaluate_field
from solver.vtcr import NumericalError
from solver.rays import ray_field
from solver.substructure import (
    build_assembly_system,
    joint_energy_matrices,
    solve_assembly,
    solve_reduced,
)

__all__ = ["ModifiedProblem", "Evaluation", "channel_parameters", "case_parameters",
           "with_joint", "direct_interface", "joint_energies", "PARAMETER_NAMES"]

PARAMETER_NAMES = ("log10_stiffness", "loss_factor", "mass")


def case_parameters(case):
    """``{joint: {log10_stiffness, loss_factor, mass}}`` of a description's joints."""
    return {jid: {"log10_stiffness": j.log10_stiffness, "loss_factor": j.loss_factor,
                  "mass": j.mass} for jid, j in case.joints.items()}


def with_joint(parameters, joint, **values):
    """A copy of ``parameters`` with ``values`` set on ``joint`` (the others untouched)."""
    trial = {jid: dict(p) for jid, p in parameters.items()}
    trial[joint].update(values)
    return trial


def direct_interface(system, energies, alpha):
    r"""Interface unknowns S of the model response (r = 0): minimise the weighted joint error
    :math:`\sum\alpha_\Gamma z^HQ_\Gamma z` under admissibility, as
    :func:`solver.substructure.solve_assembly` does, on an already built system."""
    return solve_reduced(system, sum(alpha[jid] * q for jid, q in energies.items()))


def joint_energies(system, parameters):
    """``{joint: Q_Gamma}`` of one frequency's system at ``parameters``."""
    return joint_energy_matrices(system, channel_parameters(parameters, system.omega))


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
        return case_parameters(self.case)

    def _energies(self, parameters):
        """``{frequency: {joint: Q_Gamma}}`` at ``parameters``."""
        return {f: joint_energies(d.system, parameters) for f, d in self.frequencies.items()}

    def _solve(self, data, energies, gram):
        system = data.system
        interface = sum(self.alpha[jid] * q for jid, q in energies.items()) / system.e_ref
        cost = (1.0 - self.r) * interface + self.r * gram
        s = solve_reduced(system, cost)
        z = np.append(s, 1.0)
        residuals = {jid: float((z.conj() @ q @ z).real) / system.e_ref
                     for jid, q in energies.items()}
        return s, residuals, float((z.conj() @ gram @ z).real)

    def evaluate(self, parameters, grams=None) -> Evaluation:
        """:math:`E_{mod}^2`, :math:`E_{int}^2`, :math:`E_{mes}^2` and every :math:`E_\\Gamma^2`.

        ``grams`` (``{frequency: gram}``, see :meth:`synthetic_grams`) replaces the measured
        data by other data on the same points.
        """
        return self._evaluate(parameters, self._energies(parameters), grams)

    def _evaluate(self, parameters, energies, grams=None):
        residuals = dict.fromkeys(self.joints, 0.0)
        e_mes, interfaces = 0.0, {}
        for frequency, data in self.frequencies.items():
            gram = data.gram if grams is None else grams[frequency]
            s, res, mes = self._solve(data, energies[frequency], gram)
            interfaces[frequency] = s
            e_mes += mes
            for jid, value in res.items():
                residuals[jid] += value
        e_int = sum(self.alpha[jid] * value for jid, value in residuals.items())
        e_mod = (1.0 - self.r) * e_int + self.r * e_mes
        if not math.isfinite(e_mod):  # an optimiser fed NaN would wander silently
            raise NumericalError(
                "E_mod^2 is not finite at " + ", ".join(
                    f"{j} log10 k {p['log10_stiffness']:.3g}" for j, p in parameters.items())
                + f" (residuals {residuals}, E_mes^2 {e_mes})")
        return Evaluation(e_mod, e_int, e_mes, residuals, interfaces)

    def cost(self, parameters, grams=None) -> float:
        """:math:`E_{mod}^2(p)` (the reduced cost function)."""
        return self.evaluate(parameters, grams).e_mod

    def synthetic_grams(self, parameters, noise, seed=0, realisations=4):
        r"""Measurement Gram matrices of synthetic experiments on the measured points.

        The data are the model's own prediction at ``parameters`` (the interface solution of
        :math:`E_{int}^2` alone) times :math:`1 + e`, :math:`e\sim U[-noise, noise]`: what the
        measurements would be if the model were right and only the stated noise were at work.
        Returns ``realisations`` dicts ``{frequency: gram}``.
        """
        return self._synthetic_grams(self._energies(parameters), noise, seed, realisations)

    def _synthetic_grams(self, energies, noise, seed, realisations):
        rng = np.random.default_rng(seed)
        predictions = {
            f: d.operator @ direct_interface(d.system, energies[f], self.alpha) + d.offset
            for f, d in self.frequencies.items()}
        return [{f: _measurement_gram(self.frequencies[f].operator, self.frequencies[f].offset,
                                      w * (1.0 + rng.uniform(-noise, noise, w.shape)))
                 for f, w in predictions.items()}
                for _ in range(realisations)]

    def noise_floor(self, parameters, noise, seed=0, realisations=4):
        """What a correct model would show under measurement noise alone.

        Means over :meth:`synthetic_grams` realisations: ``({joint: E_Gamma^2}, E_mod^2)``, the
        levels below which a joint's residual, and the cost, cannot be told from noise and
        discretisation error. The joint energies at ``parameters`` are built once and serve
        every realisation.
        """
        energies = self._energies(parameters)
        floors, e_mod = dict.fromkeys(self.joints, 0.0), 0.0
        for grams in self._synthetic_grams(energies, noise, seed, realisations):
            evaluation = self._evaluate(parameters, energies, grams)
            e_mod += evaluation.e_mod / realisations
            for jid, value in evaluation.residuals.items():
                floors[jid] += value / realisations
        return floors, e_mod

    def field(self, frequency, interface):
        """Plate amplitudes for interface unknowns S (to plot or export the updated field)."""
        return self.frequencies[frequency].system.plate_amplitudes(interface)

    def evaluation_seconds(self, parameters, repeats=5):
        """Best wall time of one :meth:`cost` evaluation at ``parameters`` (all frequencies)."""
        best = math.inf
        for _ in range(repeats):
            t0 = time.perf_counter()
            self.cost(parameters)
            best = min(best, time.perf_counter() - t0)
        return best

    @property
    def factorisation_seconds(self):
        """Per frequency: the time to assemble and factorise the full admissibility system (plate
        blocks and their transfer operators, interface layout), done once in the set-up."""
        return {f: sum(d.system.timings.values()) for f, d in self.frequencies.items()}

    @property
    def reference_energies(self):
        return {f: d.system.e_ref for f, d in self.frequencies.items()}

    @property
    def warnings(self):
        """Condition warnings of the plate solves, one line each (as ``CaseSolution.warnings``)."""
        from solver.vtcr import condition_warnings

        return tuple(line for f, d in self.frequencies.items()
                     for line in condition_warnings(d.system.rcond, f))

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


def cost_curve(problem, parameters, joint, values, on_point=None):
    """E_mod^2, E_int^2, E_mes^2 and E_Gamma^2 of ``joint`` against its log10 k.

    ``on_point()`` is called after each value (progress display).
    """
    rows = []
    for value in values:
        ev = problem.evaluate(with_joint(parameters, joint, log10_stiffness=float(value)))
        rows.append((float(value), ev.e_mod, ev.e_int, ev.e_mes, ev.residuals[joint]))
        if on_point:
            on_point()
    return rows

