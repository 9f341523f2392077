r"""Exact Levy series reference for plates meeting on junction lines (T, L, X, coplanar joints).

Like ``tests/exact.py`` (whose conventions, Levy basis and strip Green function it reuses),
this module is independent of the ``solver``, ``assembly`` and ``updating`` packages.

Plates
------
Plate ``i`` occupies its local rectangle ``[0, Lx_i] x [0, Ly]`` (the same ``Ly`` for all),
is simply supported on ``y = 0`` and ``y = Ly`` and obeys, with time dependence
``exp(+j omega t)``, ``D* Lap^2 w - rho_h omega^2 w = f``.  It is placed in space by a frame:
the local point ``(x, y)`` is at ``o + x x_axis + y y_axis`` and ``w`` is along
``e_z = x_axis \times y_axis``.  The small rotation of its normal is

    phi = (dw/dy) x_axis - (dw/dx) y_axis = grad(w) \times e_z.

On an edge ``x = 0`` ('left', outward ``n_x = -1``) or ``x = Lx`` ('right', ``n_x = +1``),
as in ``tests/exact.py``, ``theta = dw/dn = n_x w_x``, ``M_n = -D* (w_xx + nu w_yy)`` and the
virtual work of the edge forces is ``int (K_n dw - M_n d(theta)) ds``.

Junction lines
--------------
A line of direction ``e`` and length ``Ly`` carries the edges of its members.  It is held in
translation (``w = 0`` on each member's edge) and has its own rotation ``Theta_J(s)`` about
``e``, ``s`` the arc length from the line's start.  Member ``i`` (``sigma_i = y_axis . e``
``= +1`` or ``-1``) rotates about ``e`` by

    Theta_i = phi_i . e = -sigma_i w_x,

and the line exerts on it the moment ``m_i e`` per length, ``m_i = k_i (Theta_J - Theta_i)``
(``k_i = inf``: ``Theta_i = Theta_J``); the massless line balances ``sum_i m_i = 0``.

*Edge condition.*  The virtual work of ``m_i e`` is ``m_i e . d(phi) = m_i d(Theta_i)
= -sigma_i n_x m_i d(theta)`` and must equal the edge term ``-M_n d(theta)``, hence

    M_n = sigma_i n_x m_i      (right edge: M_n = sigma m;  left edge: M_n = -sigma m).

Equivalently the edge couple of a Kirchhoff plate is the vector ``M_n (e_z \times n)``
(right edge: ``M_n y_axis``, left edge: ``-M_n y_axis``) and its component along ``e`` is
``m_i``.  With ``m_i = k_i (Theta_J - Theta_i)`` this reads
``M_n = k_i (theta + sigma_i n_x Theta_J)``: a spring of stiffness ``k_i`` between the normal
slope and the line.  Two coplanar members (right edge of A, left edge of B, same frame) with
``k_A = k_B = 2k`` give ``Theta_J = (Theta_A + Theta_B) / 2`` and
``M_n^A = M_n^B = k (w_x^A - w_x^B)``: the ``hinge(k)`` joint of ``tests/exact.py``.

*Harmonics.*  Every field is a sine series ``sum_m (.)_m sin(alpha_m y)``,
``alpha_m = m pi / Ly``, in its plate's local ``y``; ``Theta_J(s) = sum_m T_m sin(alpha_m s)``
along the line.  A member with ``sigma = +1`` has ``y = s``; one with ``sigma = -1`` has
``y = Ly - s`` and ``sin(alpha_m s) = (-1)^(m+1) sin(alpha_m y)``, so in its local series
``Theta_J`` has the coefficients ``c_m T_m`` with ``c_m = 1`` or ``(-1)^(m+1)``, and its
``m_i`` enters the line balance with the same factor.

Public API
----------
StripPlate, JunctionLine, junction_levy, JunctionSolution, default_junction_n_terms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from exact import BOUNDARY_CONDITIONS, EDGES, LevyPlateField, Section, default_n_terms

__all__ = [
    "StripPlate",
    "JunctionLine",
    "junction_levy",
    "JunctionSolution",
    "default_junction_n_terms",
]

# Tolerance (relative to 1 for the axes, to Ly for positions) of the geometric checks.
_GEOMETRY_TOL = 1e-9


@dataclass(frozen=True)
class StripPlate:
    r"""One plate, simply supported on its local edges ``y = 0`` and ``y = Ly``.

    Attributes
    ----------
    length : float
        ``Lx`` (m); the plate occupies its local ``[0, Lx] x [0, Ly]``.
    D : complex
        Complex rigidity ``D*`` (``exact.complex_rigidity``).
    nu : float
        Poisson ratio.
    rho_h : float
        Mass per area (kg/m^2).
    origin, x_axis, y_axis : tuple of 3 float
        Frame: ``(x, y)`` is at ``origin + x x_axis + y y_axis``; the axes are orthonormal and
        ``w`` is along ``x_axis \times y_axis``.
    left, right : {'simply_supported', 'clamped', 'free'}
        Conditions on ``x = 0`` and ``x = Lx``; ignored for an edge on a junction line.
    """

    length: float
    D: complex
    nu: float
    rho_h: float
    origin: tuple
    x_axis: tuple
    y_axis: tuple
    left: str = "simply_supported"
    right: str = "simply_supported"

    def __post_init__(self):
        if not self.length > 0:
            raise ValueError(f"plate length must be > 0, got {self.length}")
        for bc in (self.left, self.right):
            if bc not in BOUNDARY_CONDITIONS:
                raise ValueError(f"unknown boundary condition {bc!r}")
        gram = np.array([[np.dot(a, b) for b in (self.x_axis, self.y_axis)]
                         for a in (self.x_axis, self.y_axis)])
        if np.max(np.abs(gram - np.eye(2))) > _GEOMETRY_TOL:
            raise ValueError("x_axis and y_axis must be orthonormal")

    def edge_start(self, end):
        """3D point of the local ``(x_edge, 0)`` of ``end`` ('left': ``x = 0``, 'right': ``Lx``)."""
        x_edge = 0.0 if end == "left" else self.length
        return np.asarray(self.origin, float) + x_edge * np.asarray(self.x_axis, float)


@dataclass(frozen=True)
class JunctionLine:
    """Junction line: ``members`` maps a plate name to ``(end, k)``.

    ``end`` is 'left' or 'right' (the plate edge on the line) and ``k`` the complex stiffness
    ``k (1 + j zeta)`` (N m/rad per m) of the rotational spring tying that edge to the line,
    or ``math.inf`` for a rigid tie.  The line's direction ``e`` is the first member's
    ``y_axis`` and its arc length ``s`` starts at that member's local ``y = 0``.
    """

    members: dict

    def __post_init__(self):
        if len(self.members) < 2:
            raise ValueError("a junction line needs at least 2 members")
        for name, (end, k) in self.members.items():
            if end not in EDGES:
                raise ValueError(f"member {name!r}: end must be 'left' or 'right', not {end!r}")
            if np.isnan(k) or (not np.isinf(k) and np.real(k) < 0):
                raise ValueError(f"member {name!r}: stiffness must be >= 0 or inf, got {k}")


def default_junction_n_terms(Ly, kappa):
    """Number of harmonics used by ``junction_levy`` when ``n_terms`` is not given.

    ``exact.default_n_terms`` for a point force, ``max(1000, 20 |kappa| Ly / pi)``, doubled:
    ``max(2000, 40 |kappa| Ly / pi)``.  Beyond ``alpha ~ |kappa|`` the force harmonics seen
    at a distance ``d`` (in ``x``, or through a junction) decay like ``exp(-alpha d)`` and,
    on the force's own line ``x = x0``, like ``alpha^-3 sin(alpha y0) sin(alpha y)``: the
    oscillating tail is ``~ N^-3 / |sin(pi (y - y0) / Ly)|`` relative, below ``1e-8`` at
    ``N = 2000`` as soon as ``|y - y0| >= Ly / 100``.  At the force itself the tail is
    ``~ N^-2`` (``~1e-7`` relative).

    Parameters
    ----------
    Ly : float
        Width of the plates (m).
    kappa : float
        Largest ``|kappa|`` of the plates, ``kappa^4 = rho_h omega^2 / D*``.
    """
    return 2 * default_n_terms(Ly, kappa, True)


def _harmonic_signs(sigma, m):
    """Factor ``c_m`` with ``sin(alpha_m s) = c_m sin(alpha_m y)``: 1, or ``(-1)^(m+1)``."""
    return np.ones(m.size) if sigma > 0 else (-1.0) ** (m + 1)


def _line_orientations(plates, line, Ly):
    """Start, direction ``e`` and ``sigma_i = y_axis_i . e`` of a junction line.

    Raises ``ValueError`` unless every member's ``y_axis`` is ``+e`` or ``-e`` and its edge
    covers the same segment ``[p0, p0 + Ly e]``, ``p0`` the first member's edge start.
    """
    names = list(line.members)
    first = plates[names[0]]
    start = first.edge_start(line.members[names[0]][0])
    direction = np.asarray(first.y_axis, float)
    sigmas = {}
    for name in names:
        plate = plates[name]
        sigma = float(np.dot(plate.y_axis, direction))
        if abs(abs(sigma) - 1.0) > _GEOMETRY_TOL:
            raise ValueError(f"member {name!r}: y_axis is not parallel to the line")
        sigma = math.copysign(1.0, sigma)
        expected = start if sigma > 0 else start + Ly * direction
        gap = np.linalg.norm(plate.edge_start(line.members[name][0]) - expected)
        if gap > _GEOMETRY_TOL * Ly:
            raise ValueError(f"member {name!r}: its edge is not on the line (gap {gap:g} m)")
        sigmas[name] = sigma
    return start, direction, sigmas


class JunctionSolution:
    r"""Levy solution returned by ``junction_levy``.

    Attributes
    ----------
    fields : dict of str -> exact.LevyPlateField
        Per-plate fields in local coordinates (``.derivative(x, y, nx, ny)`` etc.).
    plates : dict of str -> StripPlate
    lines : list of JunctionLine
    line_frames : list of (numpy.ndarray, numpy.ndarray)
        ``(p0, e)``: start and unit direction of each line.
    sigmas : list of dict
        ``sigma_i = y_axis_i . e`` of each line's members.
    line_coefficients : numpy.ndarray
        ``(n_lines, n_terms)`` sine coefficients ``T_m`` of ``Theta_J(s)``.
    load : (str, float, float, complex)
    n_terms : int
    """

    def __init__(self, fields, plates, lines, line_frames, sigmas, line_coefficients, load):
        self.fields = fields
        self.plates = plates
        self.lines = lines
        self.line_frames = line_frames
        self.sigmas = sigmas
        self.line_coefficients = line_coefficients
        self.load = load
        self.alpha = next(iter(fields.values())).alpha
        self.n_terms = self.alpha.size
        self.omega = next(iter(fields.values())).omega
        self.Ly = next(iter(fields.values())).Ly

    def w(self, plate, x, y):
        """Deflection of ``plate`` at its local points ``(x, y)`` (broadcast together)."""
        return self.fields[plate].w(x, y)

    def line_rotation(self, line, s):
        r"""Rotation of line ``line`` about ``e``: ``Theta_J(s) = sum_m T_m sin(alpha_m s)``."""
        s = np.asarray(s, float)
        return np.sin(s[..., None] * self.alpha) @ self.line_coefficients[line]

    def member_rotation_harmonics(self, line, plate):
        """Local sine coefficients of ``Theta_i = -sigma_i w_x`` on ``plate``'s edge."""
        end = self.lines[line].members[plate][0]
        x_edge = 0.0 if end == "left" else self.plates[plate].length
        slope = self.fields[plate].harmonic_derivative([x_edge], 1)[0]
        return -self.sigmas[line][plate] * slope

    def spring_dissipated_power(self, line, plate):
        """Time-averaged power dissipated by the spring tying ``plate`` to ``line``.

        ``0.5 omega Im(k) int_0^Ly |Theta_J - Theta_i|^2 ds
        = 0.5 omega Im(k) Ly/2 sum_m |c_m T_m - Theta_{i,m}|^2``; 0 for a rigid tie.
        """
        k = self.lines[line].members[plate][1]
        if np.isinf(k):
            return 0.0
        signs = _harmonic_signs(self.sigmas[line][plate], np.arange(1, self.n_terms + 1))
        jump = signs * self.line_coefficients[line] - self.member_rotation_harmonics(line, plate)
        return 0.25 * self.omega * np.imag(k) * self.Ly * np.sum(np.abs(jump) ** 2)

    def plate_dissipated_power(self, plate):
        """``0.5 omega Im(D*) a(w, w*)/D*`` from the bending energy integral of ``plate``."""
        return self.fields[plate].dissipated_power()

    def dissipated_power(self):
        """Total time-averaged power dissipated by the plates and the springs."""
        plates = sum(self.plate_dissipated_power(name) for name in self.fields)
        springs = sum(self.spring_dissipated_power(j, name)
                      for j, line in enumerate(self.lines) for name in line.members)
        return plates + springs

    def input_power(self):
        """Time-averaged power of the point force, ``0.5 Re(conj(F) j omega w(x0, y0))``.

        Evaluated with the same truncated series, so it balances ``dissipated_power``
        harmonic by harmonic whatever ``n_terms``.
        """
        plate, x0, y0, F = self.load
        return 0.5 * np.real(np.conj(F) * 1j * self.omega * self.w(plate, x0, y0))


def junction_levy(plates, lines, Ly, omega, load, n_terms=None):
    r"""Levy solution of plates joined on junction lines, under one point force.

    Each harmonic ``m`` of each plate is, as in ``exact.LevyPlateField``,

        W_m(x) = a_1 phi_1(x) + a_2 phi_2(x) + b_1 phi_1(Lx - x) + b_2 phi_2(Lx - x)
                 + q_m G_m(|x - x0|),      q_m = 2 F sin(alpha_m y0) / Ly,

    with ``phi_1, phi_2`` the exponentials decaying away from the left/right edge (no
    overflow on long plates) and ``G_m`` the Green function of the infinite strip for the
    force harmonic.  ``G_m`` solves the harmonic's ODE with the delta at ``x0`` exactly and
    decays away from it, so the force adds no unknown and no jump condition: the ``4``
    coefficients per plate only fix the edge conditions.

    Per harmonic, the unknowns are the ``4`` coefficients of each plate and ``T_m`` of each
    line; the equations are two per plate edge and one per line (see the module docstring;
    ``n_x = -1`` on a left edge, ``+1`` on a right one, ``c_m`` the member's harmonic sign):

    * outer edge: ``w = theta = 0`` (clamped), ``w = M_n = 0`` (simply supported),
      ``M_n = K_n = 0`` (free);
    * member edge: ``w = 0`` and ``M_n = k (theta + sigma n_x c_m T_m)``, or
      ``Theta_i = -sigma n_x theta = c_m T_m`` if rigid;
    * line: ``sum_i c_m m_i = sum_i c_m sigma_i n_x M_n^i = 0``.

    The ``n_terms`` small systems are solved at once after scaling each row to a unit
    largest entry.

    Parameters
    ----------
    plates : dict of str -> StripPlate
    lines : sequence of JunctionLine
        Each plate edge lies on at most one line.
    Ly : float
        Common width (m).
    omega : float
        Angular frequency (rad/s), > 0.
    load : (str, float, float, complex)
        ``(plate, x0, y0, F)``: force ``F`` (N, along the plate's ``+w``) at the local point
        ``(x0, y0)``, ``0 < x0 < Lx``, ``0 <= y0 <= Ly``.
    n_terms : int, optional
        Number of harmonics; ``default_junction_n_terms`` when omitted.

    Returns
    -------
    JunctionSolution

    Notes
    -----
    With damping (``Im D* > 0``) no harmonic sits exactly on a strip cut-on, where ``G_m``
    is singular.  A line whose members all have ``k = 0`` leaves ``T_m`` undetermined.
    """
    lines = list(lines)
    names = list(plates)
    load_plate, x0, y0, F = load
    if load_plate not in plates:
        raise ValueError(f"load on unknown plate {load_plate!r}")
    if not (0.0 < x0 < plates[load_plate].length and 0.0 <= y0 <= Ly):
        raise ValueError(f"point force ({x0}, {y0}) not inside plate {load_plate!r}")
    on_line = {}
    for j, line in enumerate(lines):
        for name, (end, _) in line.members.items():
            if name not in plates:
                raise ValueError(f"line {j}: unknown plate {name!r}")
            if (name, end) in on_line:
                raise ValueError(f"edge {end!r} of plate {name!r} is on two junction lines")
            on_line[(name, end)] = j
    orientations = [_line_orientations(plates, line, Ly) for line in lines]

    if n_terms is None:
        kappa = max(abs(p.rho_h * omega**2 / p.D) ** 0.25 for p in plates.values())
        n_terms = default_junction_n_terms(Ly, kappa)
    m = np.arange(1, n_terms + 1)
    alpha = m * np.pi / Ly
    fields = {}
    for name, p in plates.items():
        forces = [(x0, 2.0 * F * np.sin(alpha * y0) / Ly)] if name == load_plate else []
        fields[name] = LevyPlateField(Section(p.length, p.D, p.nu, p.rho_h), Ly, omega,
                                      alpha, forces)

    maps = {(name, end): fields[name].edge_maps(end) for name in names for end in EDGES}
    n_unknowns = 4 * len(names) + len(lines)
    column = {name: 4 * i for i, name in enumerate(names)}
    rows, rhs = [], []

    def add_equation(terms, line_terms=()):
        """Append ``sum coef * quantity(plate, end) + sum coef_T * T_line = 0``.

        ``terms``: ``(coef, plate, end, quantity)`` with ``quantity`` a key of
        ``LevyPlateField.edge_maps``; ``line_terms``: ``(coef, line)``; coefficients are
        scalars or ``(n_terms,)`` arrays.
        """
        row = np.zeros((n_terms, n_unknowns), complex)
        value = np.zeros(n_terms, complex)
        for coef, name, end, quantity in terms:
            q = maps[(name, end)][quantity]
            row[:, column[name]:column[name] + 4] += np.asarray(coef)[..., None] * q[:, :4]
            value -= coef * q[:, 4]
        for coef, j in line_terms:
            row[:, 4 * len(names) + j] += coef
        rows.append(row)
        rhs.append(value)

    for name in names:
        for end in EDGES:
            if (name, end) not in on_line:
                conditions = {"clamped": ("w", "theta"), "simply_supported": ("w", "M"),
                              "free": ("M", "K")}[getattr(plates[name], end)]
                for quantity in conditions:
                    add_equation([(1.0, name, end, quantity)])
                continue
            j = on_line[(name, end)]
            k = lines[j].members[name][1]
            sigma_nx = orientations[j][2][name] * (1.0 if end == "right" else -1.0)
            signs = _harmonic_signs(orientations[j][2][name], m)
            add_equation([(1.0, name, end, "w")])
            if np.isinf(k):
                add_equation([(-sigma_nx, name, end, "theta")], [(-signs, j)])
            else:
                add_equation([(1.0, name, end, "M"), (-k, name, end, "theta")],
                             [(-k * sigma_nx * signs, j)])
    for j, line in enumerate(lines):
        sigmas = orientations[j][2]
        add_equation([(_harmonic_signs(sigmas[name], m) * sigmas[name]
                       * (1.0 if end == "right" else -1.0), name, end, "M")
                      for name, (end, _) in line.members.items()])

    matrix = np.stack(rows, axis=1)
    vector = np.stack(rhs, axis=1)
    scale = np.max(np.abs(matrix), axis=2)
    solution = np.linalg.solve(matrix / scale[:, :, None], (vector / scale)[:, :, None])[..., 0]
    for name in names:
        fields[name].coefficients = solution[:, column[name]:column[name] + 4]
    line_coefficients = solution[:, 4 * len(names):].T.copy()
    return JunctionSolution(fields, dict(plates), lines,
                            [(start, e) for start, e, _ in orientations],
                            [sigmas for _, _, sigmas in orientations],
                            line_coefficients, (load_plate, float(x0), float(y0), F))
