r"""Exact Levy series reference for prismatic folded plates: bending and membrane motion of
every plate, plates meeting on lines that are free in translation.

Like ``tests/exact.py`` and ``tests/exact_junction.py`` (whose conventions, bending basis, strip
Green function and line bookkeeping it reuses), this module is independent of the ``solver``,
``assembly`` and ``updating`` packages.

Plates
------
Plate ``i`` occupies its local rectangle ``[0, Lx_i] x [0, Ly]`` (the same ``Ly`` for all) and
is placed in space by a frame, as in ``exact_junction``: the local point ``(x, y)`` is at
``o + x x_axis + y y_axis`` and ``e_z = x_axis \times y_axis``.  Its displacement is the vector
``u x_axis + v y_axis + w e_z``.  Time dependence ``exp(+j omega t)``; complex moduli
``E* = E (1 + j eta)``, ``D* = E* h^3 / (12 (1 - nu^2))``, ``A* = E* h / (1 - nu^2)``,
``rho_h = rho h``.

*Bending* (``tests/exact.py``): ``D* Lap^2 w - rho_h omega^2 w = f``.  On an edge ``x = 0``
('left', outward normal ``n_x x_axis`` with ``n_x = -1``) or ``x = Lx`` ('right', ``n_x = +1``)

    theta = n_x w_x,   M_n = -D* (w_xx + nu w_yy),   K_n = -n_x D* (w_xxx + (2 - nu) w_xyy).

*Membrane* (plane stress):

    N_xx = A* (u_x + nu v_y),  N_yy = A* (v_y + nu u_x),  N_xy = A* (1 - nu) / 2 (u_y + v_x),
    N_xx,x + N_xy,y + rho_h omega^2 u + f_x = 0,   N_xy,x + N_yy,y + rho_h omega^2 v = 0,

with the wavenumbers ``k_L^2 = rho_h omega^2 / A*`` and ``k_S^2 = 2 k_L^2 / (1 - nu)``.

*Edge forces.*  Integrating the internal virtual work of a plate by parts leaves, on an edge
``x = const``, ``int [n_x (N_xx du + N_xy dv) + K_n dw - M_n d(theta)] dy``.  Hence the force
per length that the outside applies to an edge is the vector

    F = n_x (N_xx x_axis + N_xy y_axis) + K_n e_z,

and its couple is ``M_n (e_z \times n)`` (``exact_junction``; it has no drilling part).

Harmonics
---------
``prismatic_levy(..., ends=...)`` chooses the conditions on the ends ``y = 0`` and ``y = Ly``
of every plate: shear diaphragms (``ends="diaphragm"``, the default, below) or planes of
symmetry (``ends="symmetric"``, *Symmetric ends* further down).  Either way every field is a
series in ``alpha_m = m pi / Ly`` whose ``y`` shapes are ``P`` for ``w`` and ``u`` and ``Q``
for ``v`` (``P, Q = sin, cos`` or ``cos, sin``); ``theta``, ``M_n``, ``K_n``, ``N_xx`` and the
normal strains go with ``P``, ``N_xy`` and ``w_xy`` with ``Q``.

*Shear diaphragms*: ``w = M_yy = 0`` and ``u = N_yy = 0``.  Every field is a series

    w = sum_m W_m(x) sin(alpha_m y),  u = sum_m U_m(x) sin(alpha_m y),
    v = sum_m V_m(x) cos(alpha_m y),     m = 1, 2, ...

which meets the four end conditions term by term.  A normal force ``F`` at ``(x0, y0)`` has the
harmonics ``2 F sin(alpha_m y0) / Ly delta(x - x0)``; an in-plane force ``F_x`` along
``x_axis`` the same harmonics in the first membrane equation.  (A force along ``y_axis`` would
also load the ``m = 0`` term ``cos(0 y)``; it is not supported.)  Per harmonic (``' = d/dx``,
``alpha = alpha_m``)

    U'' - (1 - nu)/2 alpha^2 U - (1 + nu)/2 alpha V' + k_L^2 U = -f_m / A*,
    (1 - nu)/2 V'' - alpha^2 V + (1 + nu)/2 alpha U' + k_L^2 V = 0,
    N_xx = A* (U' - nu alpha V) sin(alpha y),   N_xy = A* (1 - nu)/2 (alpha U + V') cos(alpha y).

*Membrane basis.*  The potentials ``u = phi_x + psi_y``, ``v = phi_y - psi_x`` with
``phi = Phi(x) sin(alpha y)``, ``psi = Psi(x) cos(alpha y)`` give ``U = Phi' - alpha Psi``,
``V = alpha Phi - Psi'``, ``Phi'' = lambda_L^2 Phi``, ``Psi'' = lambda_S^2 Psi`` with
``lambda_L^2 = alpha^2 - k_L^2`` and ``lambda_S^2 = alpha^2 - k_S^2`` (principal roots,
``Re >= 0``).  The pair decaying away from ``x = 0`` is

    L = (-lambda_L, alpha) e_L,   S = (-alpha, lambda_S) e_S,   e_L, e_S = exp(-lambda_L,S x).

When ``k_S << alpha`` (low frequency, or high harmonics: in-plane wavelengths many times the
plate) ``lambda_L, lambda_S -> alpha`` and both tend to ``(-alpha, alpha) exp(-alpha x)``:
they become dependent (their difference is ``O(k^2 / alpha^2)``).  The basis used instead is

    a = S / alpha = (-1, lambda_S / alpha) e_S,
    b = (L - S) / d = (-lambda_L h - r_L e_S,  alpha h + r_S e_S),

with ``d = lambda_L - lambda_S = (k_S^2 - k_L^2) / (lambda_L + lambda_S)``, the divided
difference ``h = (e_L - e_S) / d`` (evaluated with ``expm1``, ``-> -x e_S`` as ``d -> 0``) and

    r_L = (lambda_L - alpha) / d = -(1 - nu)/(1 + nu) (lambda_L + lambda_S)/(lambda_L + alpha),
    r_S = (alpha - lambda_S) / d = 2/(1 + nu) (lambda_L + lambda_S)/(alpha + lambda_S),

all free of cancellation.  As ``k -> 0``, ``b -> (alpha x + (1 - nu)/(1 + nu),
-alpha x + 2/(1 + nu)) exp(-alpha x)``, the static plane-stress family: ``a`` and ``b`` stay
``O(1)`` and independent at every ``alpha`` and ``omega``.  Modes decaying away from
``x = Lx`` follow from the mirror symmetry of the equations,
``(U(x), V(x)) -> (-U(Lx - x), V(Lx - x))``.

*In-plane force.*  The strip Green function of ``f_m = q delta(x - x0)`` is
``U = sum_j g_j U_j(|r|)``, ``V = sign(r) sum_j g_j V_j(|r|)``, ``r = x - x0``, in the pair
``(a, b)`` decaying from ``r = 0``: ``V`` continuous (``V(0) = 0``) and
``[N_xx] = 2 A* U'(0+) = -q``; ``U`` and ``N_xy`` are then continuous.

*Symmetric ends* (``ends="symmetric"``): the planes ``y = 0`` and ``y = Ly`` are planes of
symmetry, ``w_y = 0`` and ``K_y = -D* (w_yyy + (2 - nu) w_xxy) = 0`` in bending, ``v = 0`` and
``N_xy = 0`` in plane (a roller).  Then

    w = sum_{m>=0} W_m(x) cos(alpha_m y),  u = sum_{m>=0} U_m(x) cos(alpha_m y),
    v = sum_{m>=1} V_m(x) sin(alpha_m y),

and ``w_y``, ``w_yyy``, ``w_xxy``, ``v`` and ``N_xy = A* (1 - nu)/2 (V' - alpha U)
sin(alpha y)`` vanish term by term on both ends.  ``n_terms`` harmonics are then
``m = 0 .. n_terms - 1``.  A normal force ``F`` at ``(x0, y0)`` has the harmonics
``eps_m F cos(alpha_m y0) / Ly delta(x - x0)``, ``eps_0 = 1``, ``eps_m = 2`` (``m >= 1``); an
in-plane force along ``x_axis`` the same in the first membrane equation.

*Bending* keeps its harmonic equation and its edge expressions (``theta = n_x W'``,
``M_n = -D* (W'' - nu alpha^2 W)``, ``K_n = -n_x D* (W''' - (2 - nu) alpha^2 W')``, now
amplitudes of ``cos``): ``exact.LevyPlateField`` serves unchanged, evaluated in ``cos``.

*Membrane*: ``N_xx = A* (U' + nu alpha V) cos(alpha y)`` and the harmonic equations

    U'' - (1 - nu)/2 alpha^2 U + (1 + nu)/2 alpha V' + k_L^2 U = -f_m / A*,
    (1 - nu)/2 V'' - alpha^2 V - (1 + nu)/2 alpha U' + k_L^2 V = 0

are the diaphragm ones for ``(U, V~)``, ``V~ = -V``.  ``MembraneField`` solves for
``(U, V~)`` with the diaphragm basis and Green function and returns ``V = -V~``; in
``(U, V~)`` the edge amplitudes are ``N_xx = A* (U' - nu alpha V~)`` (as for the diaphragms),
``v = -V~`` and ``N_xy = -A* (1 - nu)/2 (alpha U + V~')`` (both with the opposite sign), and
the membrane energy density is the diaphragm one.

*The harmonic m = 0* (``alpha = 0``) is the motion uniform in ``y``.  In bending it is
cylindrical: ``D* W'''' - rho_h omega^2 W = f_0``, whose roots ``s_1 = kappa``,
``s_2 = sqrt(-kappa^2)`` (``~ j kappa``) and strip Green function ``exact.LevyPlateField``
already takes at ``alpha = 0``.  In plane the equations decouple, ``U'' + k_L^2 U = -f_0/A*``
and ``(1 - nu)/2 V~'' + k_L^2 V~ = 0``, and the pair ``a``, ``b`` does not exist (``a``
divides by ``alpha``); ``m = 0`` uses

    a_0 = (e_L, 0),   b_0 = (0, e_S),   lambda_L,S = sqrt(-k_L,S^2)  (~ j k_L, j k_S),

the outgoing longitudinal and shear waves, with the Green function
``U = q / (2 A* lambda_L) e_L(|r|)``.  ``V_0`` multiplies ``sin(0 y) = 0``: it is no motion,
and ``b_0`` is kept only so that ``m = 0`` has the same system as the other harmonics.  The
rows it enters (``v`` or ``N_xy`` on each edge, the axial line unknown ``E_0`` and its
balance) are homogeneous and, at ``alpha = 0``, decoupled from ``U_0``, ``W_0`` and the other
line unknowns; they are the damped shear-wave problem above, so ``V_0 = 0`` and ``E_0 = 0``
(exactly: elimination never mixes the decoupled blocks).

Lines
-----
A line of direction ``e`` and arc length ``s`` (``exact_junction``: ``e`` is its first
member's ``y_axis``; member ``i`` has ``sigma_i = y_axis . e = +/-1``) carries the edges of its
members.  It moves as a rigid line: translation ``U_J(s)`` (3D) and rotation ``Theta_J(s)``
about ``e``.  On the line ``sin(alpha_m y) = c_m sin(alpha_m s)`` and, as ``y_axis = sigma e``,
``sigma cos(alpha_m y) = c_m cos(alpha_m s)`` with ``c_m = 1`` (``sigma = +1``, ``y = s``) or
``(-1)^(m+1)`` (``sigma = -1``, ``y = Ly - s``).  So, with ``(t_1, t_2)`` an orthonormal pair
normal to ``e`` (``t_1`` the first member's ``x_axis``, ``t_2 = e \times t_1``),

    U_J(s) = sum_m [(T1_m t_1 + T2_m t_2) sin(alpha_m s) + E_m e cos(alpha_m s)],
    Theta_J(s) = sum_m T_m sin(alpha_m s),

and every member equation below is its local harmonic times ``c_m``:

* translation, rigid tie: ``c_m (U_m x_axis + W_m e_z) . t_k = Tk_m`` (``k = 1, 2``;
  ``x_axis`` and ``e_z`` are normal to ``e``) and ``c_m V_m = E_m``;
* translation, spring (``translational[i] = k_t*``, N/m^2): the line applies to the edge
  ``F_i = k_t* (U_J - X_i)``, ``X_i = u x_axis + v y_axis + w e_z`` the edge's displacement.
  On the line ``X_i = sum_m [c_m (U_m x_axis + W_m e_z) sin(alpha_m s) + c_m V_m e
  cos(alpha_m s)]`` and ``F_i = sum_m [c_m (n_x N_xx,m x_axis + K_n,m e_z) sin(alpha_m s) +
  c_m n_x N_xy,m e cos(alpha_m s)]`` (the ``cos`` parts through ``sigma y_axis = e``), so

      c_m (n_x N_xx,m x_axis + K_n,m e_z) . t_k = k_t* (Tk_m - c_m (U_m x_axis + W_m e_z) . t_k),
      c_m n_x N_xy,m = k_t* (E_m - c_m V_m);

  ``k_t* -> inf`` gives the rigid tie back; ``k_t* = 0`` frees the edge in translation;
* rotation (``exact_junction``): ``Theta_i = -sigma w_x``; ``M_n = k (theta + sigma n_x c_m
  T_m)`` on a spring ``k``, ``-sigma n_x theta = c_m T_m`` on a rigid tie;
* balance of the massless line, which receives ``-F_i`` and the couple ``-m_i e`` from
  member ``i``: ``sum_i F_i = 0`` and ``sum_i m_i = 0``, i.e. ``sum_i c_m F_i . t_k = 0``
  with ``F_i . t_k = (n_x N_xx x_axis + K_n e_z) . t_k`` (amplitudes of ``sin``),
  ``sum_i c_m n_x N_xy^i = 0`` (the ``e`` part of ``F_i`` is
  ``n_x N_xy sigma cos(alpha y) = n_x N_xy c_m cos(alpha s)``) and
  ``sum_i c_m sigma_i n_x M_n^i = 0`` (``m_i = sigma_i n_x M_n``, ``exact_junction``).

At the ends ``s = 0, Ly`` the line's transverse translation and rotation vanish (``sin``) and
its axial one is free (``cos``), as the diaphragms ask; the Kirchhoff corner forces act there
along ``e_z``, on the supports.

*Symmetric ends.*  With ``P, Q = cos, sin``: ``cos(alpha_m (Ly - s)) = (-1)^m cos(alpha_m s)``
and ``sigma sin(alpha_m (Ly - s)) = -(-1)^(m+1) sin(alpha_m s) = (-1)^m sin(alpha_m s)``, so
``P(alpha_m y) = c_m P(alpha_m s)`` and ``sigma Q(alpha_m y) = c_m Q(alpha_m s)`` with
``c_m = 1`` or ``(-1)^m`` (``m >= 0``), and

    U_J(s) = sum_m [(T1_m t_1 + T2_m t_2) cos(alpha_m s) + E_m e sin(alpha_m s)],
    Theta_J(s) = sum_m T_m cos(alpha_m s).

Every law above holds as written with these ``c_m`` (read ``sin, cos`` as ``P, Q``: the
``t_k`` parts and the rotation go with ``P``, the ``e`` parts with ``Q``), on the physical
amplitudes ``V``, ``N_xy`` (*Symmetric ends* above).  At the ends the line's transverse
translation and rotation are free and its axial translation vanishes, as the planes of
symmetry ask; there are no corner forces (``w_xy``, ``Q``-shaped, vanishes there).

The force balance is the same whether a member is tied rigidly or on a translational spring
(``F_i`` is its edge force either way), and the spring acts on the line itself, so it adds
nothing to the moment balance.  If every member has a spring, ``U_J`` is a free node fixed
by the balance.

``held=True`` replaces the three force balances by ``U_J = 0``: ``w = u = v = 0`` on every
rigidly tied member's edge (a member on a translational spring is then on a spring to the
fixed line).  Without in-plane loads and translational springs the membrane fields then
vanish and, with diaphragm ends, the bending fields are those of
``exact_junction.junction_levy``.

Power
-----
Input ``0.5 Re(conj(F) j omega w(x0, y0))`` per normal force (``u`` for an in-plane one);
dissipation ``0.5 omega Im(D*) a(w, w*)/D*`` (``exact.LevyPlateField``),
``0.5 omega Im(A*) Ly/2 sum_m int [|U'|^2 + alpha^2 |V|^2 - 2 nu alpha Re(U' conj V)
+ (1 - nu)/2 |alpha U + V'|^2] dx``, ``0.5 omega Im(k) int |Theta_J - Theta_i|^2 ds`` per
rotational spring and ``0.5 omega Im(k_t*) int |U_J - X_i|^2 ds
= 0.5 omega Im(k_t*) Ly/2 sum_m [sum_k |Tk_m - c_m (U_m x_axis + W_m e_z) . t_k|^2
+ |E_m - c_m V_m|^2]`` per translational spring (``sin^2`` and ``cos^2`` both average to
``1/2`` over ``[0, Ly]`` for ``m >= 1``).  The lines do no work (``sum_i F_i . U_J = 0``), so
the two balance harmonic by harmonic.

With symmetric ends the same sums hold with the weights of ``P = cos`` and ``Q = sin``:
``int_0^Ly cos^2 = Ly`` and ``int_0^Ly sin^2 = 0`` for ``m = 0`` (``Ly/2`` both for
``m >= 1``).  Each term goes with the shape of its strains: ``|U'|^2``, ``alpha^2 |V|^2``,
``Re(U' conj V)``, ``|W''|^2``, ``alpha^4 |W|^2``, ``|Theta|^2`` and the ``t_k`` parts with
``P``; ``|alpha U + V'|^2``, ``alpha^2 |W'|^2`` and ``|E - c V|^2`` with ``Q`` (written in
``(U, V~)`` as for the diaphragms, *Symmetric ends* above).

Public API
----------
membrane_stiffness, FoldedPlate, PrismaticLine, MembraneField, prismatic_levy,
PrismaticSolution, CosineLevyField, default_prismatic_n_terms, INPLANE_CONDITIONS, ENDS.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field

import numpy as np
from exact import EDGES, LevyPlateField, Section, _graded_breakpoints
from exact_junction import (
    JunctionLine,
    JunctionSolution,
    StripPlate,
    _harmonic_signs,
    _line_orientations,
    default_junction_n_terms,
)

__all__ = [
    "ENDS",
    "INPLANE_CONDITIONS",
    "CosineLevyField",
    "FoldedPlate",
    "MembraneField",
    "PrismaticLine",
    "PrismaticSolution",
    "default_prismatic_n_terms",
    "membrane_stiffness",
    "prismatic_levy",
]

# The two membrane quantities an outer edge prescribes to zero, by in-plane condition.
INPLANE_CONDITIONS = {"fixed": ("u", "v"), "free": ("Nx", "Nxy"), "diaphragm": ("v", "Nx"),
                      "roller": ("u", "Nxy")}
_BENDING_CONDITIONS = {"clamped": ("w", "theta"), "simply_supported": ("w", "M"),
                       "free": ("M", "K")}
# Conditions on the ends y = 0 and y = Ly of every plate (module docstring, Harmonics).
ENDS = ("diaphragm", "symmetric")
# Number of points x harmonics evaluated at once (complex arrays stay ~ 30 MB).
_CHUNK_ENTRIES = 2_000_000
_GAUSS_NODES = 16


def membrane_stiffness(E, h, nu, eta):
    """Complex membrane stiffness ``A* = E h (1 + j eta) / (1 - nu^2)`` (N/m)."""
    return E * h * (1.0 + 1j * eta) / (1.0 - nu**2)


@dataclass(frozen=True)
class FoldedPlate:
    """One plate of a prismatic structure; its local ends ``y = 0, Ly`` are those chosen by
    ``prismatic_levy(..., ends=...)`` (shear diaphragms or planes of symmetry).

    Attributes
    ----------
    length : float
        ``Lx`` (m); the plate occupies its local ``[0, Lx] x [0, Ly]``.
    D, A : complex
        Bending and membrane stiffnesses ``D*`` (``exact.complex_rigidity``) and ``A*``
        (``membrane_stiffness``); they are independent parameters (a stiff-membrane limit
        scales ``A`` alone).
    nu : float
        Poisson ratio.
    rho_h : float
        Mass per area (kg/m^2).
    origin, x_axis, y_axis : tuple of 3 float
        Frame, as ``exact_junction.StripPlate``.
    left, right : {'simply_supported', 'clamped', 'free'}
        Bending conditions on ``x = 0`` and ``x = Lx``; ignored for an edge on a line.
    left_inplane, right_inplane : {'fixed', 'free', 'diaphragm', 'roller'}, optional
        In-plane conditions (``INPLANE_CONDITIONS``): ``u = v = 0``, ``N_xx = N_xy = 0``,
        ``v = N_xx = 0``, ``u = N_xy = 0``.  Default: 'free' on a free edge, else 'fixed'.
    """

    length: float
    D: complex
    A: complex
    nu: float
    rho_h: float
    origin: tuple
    x_axis: tuple
    y_axis: tuple
    left: str = "simply_supported"
    right: str = "simply_supported"
    left_inplane: str | None = None
    right_inplane: str | None = None

    def __post_init__(self):
        self.strip()  # checks the length, the bending conditions and the frame
        for end in EDGES:
            condition = self.inplane_condition(end)
            if condition not in INPLANE_CONDITIONS:
                raise ValueError(f"unknown in-plane condition {condition!r}")

    def strip(self):
        """The bending-only ``exact_junction.StripPlate`` of this plate."""
        return StripPlate(self.length, self.D, self.nu, self.rho_h, self.origin, self.x_axis,
                          self.y_axis, self.left, self.right)

    def inplane_condition(self, end):
        """In-plane condition of the outer edge ``end`` ('left' or 'right')."""
        given = self.left_inplane if end == "left" else self.right_inplane
        if given is not None:
            return given
        return "free" if getattr(self, end) == "free" else "fixed"

    def edge_start(self, end):
        """3D point of the local ``(x_edge, 0)`` of ``end``."""
        return self.strip().edge_start(end)

    def axes(self):
        """``(x_axis, y_axis, e_z)`` as arrays."""
        x_axis, y_axis = np.asarray(self.x_axis, float), np.asarray(self.y_axis, float)
        return x_axis, y_axis, np.cross(x_axis, y_axis)

    def wavenumbers(self, omega):
        """``(|kappa|, |k_S|)``: bending ``kappa^4 = rho_h omega^2 / D*``, in-plane shear."""
        k_shear2 = 2.0 * self.rho_h * omega**2 / (self.A * (1.0 - self.nu))
        return abs(self.rho_h * omega**2 / self.D) ** 0.25, abs(k_shear2) ** 0.5


@dataclass(frozen=True)
class PrismaticLine(JunctionLine):
    """Line shared by plate edges: ``members`` maps a plate name to ``(end, k)`` as
    ``exact_junction.JunctionLine``; ``held=True`` fixes its translation (``U_J = 0``).

    ``translational`` maps a member's name to the complex stiffness ``k_t* = k_t (1 + j
    zeta_t)`` (N/m^2: force per length per displacement) of an isotropic translational spring
    between its edge and the line, ``F_i = k_t* (U_J - X_i)`` (module docstring, Lines); a
    member not in it (or with ``math.inf``) is tied rigidly in translation, ``X_i = U_J``.
    """

    held: bool = False
    translational: dict = field(default_factory=dict)

    def __post_init__(self):
        super().__post_init__()
        for name, k_t in self.translational.items():
            if name not in self.members:
                raise ValueError(f"translational spring on {name!r}, not a member of the line")
            if np.isnan(k_t) or (not np.isinf(k_t) and np.real(k_t) < 0):
                raise ValueError(f"member {name!r}: translational stiffness must be >= 0 or inf,"
                                 f" got {k_t}")

    def translational_stiffness(self, name):
        """``k_t*`` of member ``name``, ``math.inf`` for a rigid tie."""
        return self.translational.get(name, math.inf)


def default_prismatic_n_terms(plates, Ly, omega):
    """Number of harmonics used by ``prismatic_levy`` when ``n_terms`` is not given.

    ``exact_junction.default_junction_n_terms`` with the largest wavenumber of the plates,
    bending ``|kappa|`` or in-plane ``|k_S|`` (for thin plates ``|kappa|`` always):
    ``max(2000, 40 kappa Ly / pi)``.  Beyond ``alpha ~ kappa`` every harmonic is evanescent.
    A normal force's harmonics behave as in ``exact_junction`` (tail ``~N^-3 / |sin(pi (y -
    y0) / Ly)|`` on the force's line ``x = x0``, ``exp(-alpha d)`` at a distance ``d``); the
    membrane fields it drives are excited on the lines, so their harmonics carry at least the
    factor ``exp(-alpha d)`` of the force's distance ``d`` to the nearest line.  An in-plane
    force's own harmonics decay only like ``alpha^-1`` on ``x = x0`` (its field is logarithmic
    at the force): there the tail is ``~N^-1 / |sin(pi (y - y0) / Ly)|``; off that line they
    decay like ``exp(-alpha |x - x0|)``.  The power balance holds for any truncation.

    The same holds with symmetric ends: a harmonic's ``x`` dependence is the same and the
    ``y`` factors ``cos(alpha_m y0) cos(alpha_m y)`` oscillate like the ``sin`` ones.

    Parameters
    ----------
    plates : iterable of FoldedPlate
    Ly, omega : float
    """
    kappa = max(max(p.wavenumbers(omega)) for p in plates)
    return default_junction_n_terms(Ly, kappa)


# --------------------------------------------------------------------------------------
# End conditions: harmonics, y shapes, line signs and energy weights
# --------------------------------------------------------------------------------------


def _checked_ends(ends):
    """``ends`` if it is one of ``ENDS``, else ``ValueError``."""
    if ends not in ENDS:
        raise ValueError(f"ends must be one of {ENDS}, got {ends!r}")
    return ends


def _harmonic_indices(ends, n_terms):
    """``m = 1 .. n_terms`` (diaphragms) or ``0 .. n_terms - 1`` (symmetric: ``cos(0 y)``)."""
    return np.arange(1, n_terms + 1) if ends == "diaphragm" else np.arange(n_terms)


def _end_shapes(ends):
    """``(P, Q)``: ``y`` shape of ``w``, ``u`` and of ``v`` (``sin, cos`` or ``cos, sin``)."""
    return (np.sin, np.cos) if ends == "diaphragm" else (np.cos, np.sin)


def _end_signs(sigma, m, ends):
    """Line factor ``c_m``: ``P(alpha_m y) = c_m P(alpha_m s)``, ``sigma Q(alpha_m y) = c_m
    Q(alpha_m s)``; 1 for ``sigma = +1``, else ``(-1)^(m+1)`` (diaphragms, as
    ``exact_junction``) or ``(-1)^m`` (symmetric: ``cos(m pi - x) = (-1)^m cos x``)."""
    if ends == "diaphragm":
        return _harmonic_signs(sigma, m)
    return np.ones(m.size) if sigma > 0 else (-1.0) ** m


def _energy_factors(alpha, ends):
    """``(f_P, f_Q)``: ``int_0^Ly P^2 dy`` and ``int_0^Ly Q^2 dy`` in units of ``Ly / 2``.

    All 1 for ``alpha > 0``; for the symmetric ``m = 0`` (``alpha = 0``) ``cos^2 = 1`` gives 2
    and ``sin^2 = 0`` gives 0.  (Multiplying by an exact 1.0 leaves the diaphragm sums
    bit for bit as they were.)
    """
    ones = np.ones(alpha.size)
    if ends == "diaphragm":
        return ones, ones
    uniform = alpha == 0
    return np.where(uniform, 2.0, 1.0), np.where(uniform, 0.0, 1.0)


# --------------------------------------------------------------------------------------
# Membrane field of one plate
# --------------------------------------------------------------------------------------


def _decaying_pair(lam_long, lam_shear, d, xi, k):
    """k-th ``xi``-derivative of ``e_S = exp(-lambda_S xi)`` and ``h = (e_L - e_S) / d``.

    ``d = lambda_L - lambda_S`` is given (computed without cancellation).  For ``|d xi| < 1``,
    ``h = -xi e_S expm1(z) / z`` with ``z = -d xi`` (``-> -xi e_S`` as ``d -> 0``), else the
    difference itself.  ``h^(k) = (-lambda_L)^k h + g_k e_S`` with
    ``g_k = ((-lambda_L)^k - (-lambda_S)^k) / d``: ``0, -1, lambda_L + lambda_S``.

    Parameters
    ----------
    lam_long, lam_shear, d : numpy.ndarray
        Per-harmonic roots and their difference, shape ``(n_terms,)``.
    xi : numpy.ndarray
        Distances ``>= 0``, shape ``(P, 1)``.
    k : int
        Derivative order, 0..2.
    """
    e_s = np.exp(-lam_shear * xi)
    z = -d * xi
    small = np.abs(z) < 1.0
    z_safe = np.where(small & (z != 0), z, 1.0)
    ratio = np.where(small & (z != 0), np.expm1(z_safe) / z_safe, 1.0)
    h = np.where(small, -xi * e_s * ratio,
                 (np.exp(-lam_long * xi) - e_s) / np.where(small, 1.0, d))
    g = (0.0, -1.0, lam_long + lam_shear)[k]
    return (-lam_shear) ** k * e_s, (-lam_long) ** k * h + g * e_s


def _parity(sign, order):
    """``sign^order`` of an even (1) or odd (``sign``, 0 at ``r = 0``: the mean) function."""
    return sign if order % 2 else 1.0


def _quadrature(length, cuts, h0, hcap):
    """Gauss-Legendre nodes and weights on ``[0, length]``, graded towards the ends and cuts.

    Panels of ``_GAUSS_NODES`` points from ``h0`` next to ``0``, ``length`` and each cut,
    doubling up to ``hcap`` (``exact.LevyPlateField.bending_form``'s rule).
    """
    ends = np.unique([0.0, length, *cuts])
    breaks = np.unique(np.concatenate(
        [_graded_breakpoints(a, b, h0, hcap) for a, b in itertools.pairwise(ends)]))
    t, wt = np.polynomial.legendre.leggauss(_GAUSS_NODES)
    mid, half = 0.5 * (breaks[1:] + breaks[:-1]), 0.5 * np.diff(breaks)
    return (mid[:, None] + half[:, None] * t).ravel(), (half[:, None] * wt).ravel()


def _series(harmonics, alpha, x, y, ny, trig, length):
    """``sum_m X_m(x) alpha_m^ny trig(alpha_m y + ny pi / 2)`` at the broadcast ``(x, y)``.

    ``harmonics(x)`` returns ``X_m`` at the points ``x``, shape ``(P, n_terms)``.
    """
    x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
    if np.any(x < -1e-12 * length) or np.any(x > length * (1 + 1e-12)):
        raise ValueError("x outside the plate [0, Lx]")
    xf, yf = x.ravel(), y.ravel()
    out = np.empty(xf.size, complex)
    step = max(1, _CHUNK_ENTRIES // (4 * alpha.size))
    for start in range(0, xf.size, step):
        sl = slice(start, start + step)
        ydep = alpha**ny * trig(np.outer(yf[sl], alpha) + ny * np.pi / 2)
        out[sl] = np.sum(harmonics(xf[sl]) * ydep, axis=1)
    return out.reshape(x.shape)


class MembraneField:
    """In-plane response of one plate, ``u = sum U_m(x) P(alpha_m y)``,
    ``v = sum V_m(x) Q(alpha_m y)`` (``P, Q = sin, cos`` for diaphragm ends, ``cos, sin`` for
    symmetric ones).

    Per harmonic, with the modes ``a``, ``b`` decaying from the left edge (``xi = x``) and
    their mirror images decaying from the right edge (module docstring),

        (U, V~) = c_1 a(x) + c_2 b(x) + c_3 a~(x) + c_4 b~(x) + sum_f (in-plane force f),
        a~(x) = (-a_U(Lx - x), a_V(Lx - x)),

    with ``V = s_v V~``, ``s_v = 1`` (diaphragms) or ``-1`` (symmetric ends, whose equations
    are the diaphragm ones in ``(U, -V)``); ``a``, ``b`` become ``a_0``, ``b_0`` for the
    symmetric ``m = 0`` (``alpha = 0``).  ``harmonic_derivative``, ``derivative`` and
    ``edge_maps`` give the physical ``V``; the internal ``(U, V~)`` is ``reduced_derivative``.

    Attributes
    ----------
    plate : FoldedPlate
    Ly, omega : float
    alpha : numpy.ndarray
        ``m pi / Ly``, ``m = 1..n_terms`` (diaphragms) or ``0..n_terms - 1`` (symmetric).
    ends : {'diaphragm', 'symmetric'}
    lam_long, lam_shear, d, r_long, r_shear : numpy.ndarray
        ``lambda_L``, ``lambda_S``, ``d``, ``r_L``, ``r_S`` of each harmonic (at ``alpha = 0``
        only ``lambda_L``, ``lambda_S`` serve).
    coefficients : numpy.ndarray
        ``(n_terms, 4)`` array of ``c_1..c_4``.
    forces : list of (float, numpy.ndarray)
        ``(x0, q_m)`` of the in-plane forces of this plate, ``q_m = 2 F_x sin(alpha_m y0) / Ly``
        (``eps_m F_x cos(alpha_m y0) / Ly`` for symmetric ends).
    """

    def __init__(self, plate, Ly, omega, alpha, forces, ends="diaphragm"):
        self.plate = plate
        self.Ly = Ly
        self.omega = omega
        self.alpha = alpha
        self.ends = _checked_ends(ends)
        self.shapes = _end_shapes(ends)
        self.v_sign = 1.0 if ends == "diaphragm" else -1.0
        self.energy_factors = _energy_factors(alpha, ends)
        # The harmonic m = 0 (symmetric ends only) has its own modes a_0, b_0.
        self.uniform = alpha == 0
        nu = plate.nu
        k_long2 = plate.rho_h * omega**2 / plate.A
        k_shear2 = 2.0 * k_long2 / (1.0 - nu)
        self.lam_long = np.sqrt(alpha**2 - k_long2 + 0j)
        self.lam_shear = np.sqrt(alpha**2 - k_shear2 + 0j)
        total = self.lam_long + self.lam_shear
        self.d = (k_shear2 - k_long2) / total
        self.r_long = -(1.0 - nu) / (1.0 + nu) * total / (self.lam_long + alpha)
        self.r_shear = 2.0 / (1.0 + nu) * total / (alpha + self.lam_shear)
        self.forces = forces
        self.coefficients = np.zeros((alpha.size, 4), complex)
        self._green = [(x0, self._green_coefficients(q)) for x0, q in forces]

    def decaying_modes(self, xi, k):
        """k-th ``xi``-derivative of the modes ``a``, ``b`` at distances ``xi`` (``(P, 1)``).

        Returns ``(U, V~)``, each ``(P, n_terms, 2)``:
        ``a = (-e_S, lambda_S / alpha e_S)``, ``b = (-lambda_L h - r_L e_S, alpha h + r_S e_S)``;
        at ``alpha = 0`` ``a_0 = (e_L, 0)``, ``b_0 = (0, e_S)`` (module docstring).
        """
        e_s, h = _decaying_pair(self.lam_long, self.lam_shear, self.d, xi, k)
        # a is not defined at alpha = 0 (replaced below): divide by 1 there, not by 0.
        alpha_safe = np.where(self.uniform, 1.0, self.alpha)
        U = np.stack([-e_s, -self.lam_long * h - self.r_long * e_s], axis=-1)
        V = np.stack([self.lam_shear / alpha_safe * e_s, self.alpha * h + self.r_shear * e_s],
                     axis=-1)
        if np.any(self.uniform):
            lam_long = self.lam_long[self.uniform]
            U[:, self.uniform, 0] = (-lam_long) ** k * np.exp(-lam_long * xi)
            V[:, self.uniform, 1] = e_s[:, self.uniform]
            U[:, self.uniform, 1] = V[:, self.uniform, 0] = 0.0
        return U, V

    def _green_coefficients(self, q):
        """``(g_a, g_b)`` of the force harmonics ``q``: ``V(0) = 0``, ``U'(0+) = -q / (2 A*)``.

        ``[[V_a, V_b], [U_a', U_b']] g = [0, c]`` gives ``g = c (-V_b, V_a) / det``; at
        ``alpha = 0`` (``V_a = 0``, ``V_b = 1``, ``U_a' = -lambda_L``) ``g = (q / (2 A*
        lambda_L), 0)``.
        """
        zero = np.zeros((1, 1))
        _, V0 = self.decaying_modes(zero, 0)
        U1, _ = self.decaying_modes(zero, 1)
        V0, U1 = V0[0], U1[0]
        det = V0[:, 0] * U1[:, 1] - V0[:, 1] * U1[:, 0]
        c = -q / (2.0 * self.plate.A)
        return (c / det)[:, None] * np.stack([-V0[:, 1], V0[:, 0]], axis=-1)

    def homogeneous_basis(self, x, k):
        """k-th x-derivative of ``U`` and ``V~`` of the four modes, each ``(P, n_terms, 4)``."""
        x = np.asarray(x, float)[:, None]
        u_left, v_left = self.decaying_modes(x, k)
        u_right, v_right = self.decaying_modes(self.plate.length - x, k)
        sign = (-1.0) ** k
        return (np.concatenate([u_left, -sign * u_right], axis=-1),
                np.concatenate([v_left, sign * v_right], axis=-1))

    def particular(self, x, k):
        """k-th x-derivative of the in-plane force part, ``(U, V~)`` each ``(P, n_terms)``."""
        x = np.asarray(x, float)[:, None]
        U = np.zeros((x.shape[0], self.alpha.size), complex)
        V = np.zeros_like(U)
        for x0, g in self._green:
            r = x - x0
            u_modes, v_modes = self.decaying_modes(np.abs(r), k)
            U += _parity(np.sign(r), k) * np.sum(u_modes * g, axis=-1)
            V += _parity(np.sign(r), k + 1) * np.sum(v_modes * g, axis=-1)
        return U, V

    def reduced_derivative(self, x, k):
        """``(U_m^(k), V~_m^(k))`` (``k = 0..2``) at the points ``x``, each ``(P, n_terms)``."""
        basis_u, basis_v = self.homogeneous_basis(x, k)
        part_u, part_v = self.particular(x, k)
        return (np.einsum("pmj,mj->pm", basis_u, self.coefficients) + part_u,
                np.einsum("pmj,mj->pm", basis_v, self.coefficients) + part_v)

    def harmonic_derivative(self, x, k):
        """``(U_m^(k), V_m^(k))`` (``k = 0..2``) at the points ``x``, each ``(P, n_terms)``:
        the amplitudes of ``P(alpha_m y)`` and ``Q(alpha_m y)``, ``V = s_v V~``."""
        U, V = self.reduced_derivative(x, k)
        return U, self.v_sign * V

    def derivative(self, component, x, y, nx=0, ny=0):
        """``d^(nx+ny)/dx^nx dy^ny`` of ``u`` (``component='u'``) or ``v`` (``'v'``).

        ``sum_m U_m^(nx) alpha_m^ny P(alpha_m y + ny pi/2)``, or ``V`` with ``Q``.
        """
        index, trig = {"u": (0, self.shapes[0]), "v": (1, self.shapes[1])}[component]
        return _series(lambda xs: self.harmonic_derivative(xs, nx)[index], self.alpha, x, y,
                       ny, trig, self.plate.length)

    def u(self, x, y):
        """In-plane displacement ``u`` along ``x_axis``."""
        return self.derivative("u", x, y)

    def v(self, x, y):
        """In-plane displacement ``v`` along ``y_axis``."""
        return self.derivative("v", x, y)

    def edge_maps(self, end):
        """Affine maps from ``c_1..c_4`` to the edge quantities of each harmonic.

        Returns ``{'u', 'v', 'Nx', 'Nxy'} -> (n_terms, 5)`` arrays (column 4: the in-plane
        forces), the amplitudes of ``P`` (``u``, ``Nx``) and ``Q`` (``v``, ``Nxy``); in
        ``(U, V~)``: ``u = U``, ``v = s_v V~``, ``Nx = A* (U' - nu alpha V~)``,
        ``Nxy = s_v A* (1 - nu)/2 (alpha U + V~')`` (module docstring, *Symmetric ends*).
        """
        x = [0.0 if end == "left" else self.plate.length]
        orders = []
        for k in range(2):
            pairs = zip(self.homogeneous_basis(x, k), self.particular(x, k))
            orders.append([np.concatenate([basis[0], part[0][:, None]], axis=1)
                           for basis, part in pairs])
        (U, V), (U1, V1) = orders
        a = self.alpha[:, None]
        A, nu = self.plate.A, self.plate.nu
        return {"u": U, "v": self.v_sign * V, "Nx": A * (U1 - nu * a * V),
                "Nxy": self.v_sign * (0.5 * A * (1 - nu) * (a * U + V1))}

    def membrane_form(self):
        """Real membrane form ``a_m(u, u*) / A*`` of the plate.

        ``int [|e_xx|^2 + |e_yy|^2 + 2 nu Re(e_xx conj e_yy) + (1 - nu)/2 |g_xy|^2] dA``
        ``= Ly/2 sum_m int_0^Lx [f_P (|U'|^2 + alpha^2 |V~|^2 - 2 nu alpha Re(U' conj V~))
        + f_Q (1 - nu)/2 |alpha U + V~'|^2] dx`` (the normal strains go with ``P``, the shear
        with ``Q``; ``f_P, f_Q`` of ``_energy_factors``), by Gauss quadrature on panels graded
        from ``1/(4 max |lambda|)`` at the edges and forces up to ``2 / |k_S|``.
        """
        nu, alpha = self.plate.nu, self.alpha
        f_p, f_q = self.energy_factors
        h0 = 0.25 / np.max(np.abs(np.concatenate([self.lam_long, self.lam_shear])))
        hcap = min(2.0 / self.plate.wavenumbers(self.omega)[1], self.plate.length)
        nodes, weights = _quadrature(self.plate.length, [x0 for x0, _ in self.forces], h0, hcap)
        total = 0.0
        step = max(1, _CHUNK_ENTRIES // (4 * alpha.size))
        for start in range(0, nodes.size, step):
            sl = slice(start, start + step)
            (U, V), (U1, V1) = (self.reduced_derivative(nodes[sl], k) for k in range(2))
            density = (f_p * (np.abs(U1) ** 2 + alpha**2 * np.abs(V) ** 2
                              - 2 * nu * alpha * np.real(U1 * np.conj(V)))
                       + f_q * (0.5 * (1 - nu) * np.abs(alpha * U + V1) ** 2))
            total += weights[sl] @ density.sum(axis=1)
        return 0.5 * self.Ly * total

    def dissipated_power(self):
        """Time-averaged membrane dissipation ``0.5 omega Im(A*) a_m(u, u*) / A*``."""
        return 0.5 * self.omega * np.imag(self.plate.A) * self.membrane_form()


# --------------------------------------------------------------------------------------
# Bending field of one plate with symmetric ends
# --------------------------------------------------------------------------------------


class CosineLevyField(LevyPlateField):
    """``exact.LevyPlateField`` for symmetric ends: ``w = sum_{m>=0} W_m(x) cos(alpha_m y)``.

    The harmonics ``W_m``, their basis, Green function and ``edge_maps`` are the parent's (the
    harmonic equation and the edge expressions do not depend on the ``y`` shape; at
    ``alpha_0 = 0`` the roots are ``kappa`` and ``sqrt(-kappa^2)``).  Only what sees ``y``
    changes: the series is in ``cos`` (so ``w``, ``edge_slope``, ``edge_moment``,
    ``edge_shear`` follow) and the energy weighs ``m = 0`` by ``int cos^2 = Ly`` instead of
    ``Ly / 2``.  ``forces`` carry ``q_m = eps_m F cos(alpha_m y0) / Ly``.
    """

    def derivative(self, x, y, nx=0, ny=0):
        """``d^(nx+ny) w / dx^nx dy^ny = sum_m W_m^(nx) alpha_m^ny cos(alpha_m y + ny pi/2)``
        (``nx <= 3``, any ``ny``)."""
        return _series(lambda xs: self.harmonic_derivative(xs, nx), self.alpha, x, y, ny,
                       np.cos, self.section.Lx)

    def bending_form(self):
        """Real bending form ``a(w, w*) / D*``: the parent's ``Ly/2 sum_m`` (``w_xx``, ``w_yy``
        in ``cos``, ``w_xy`` in ``sin``) plus ``Ly/2 int |W_0''|^2 dx`` for the rest of
        ``int_0^Ly cos^2(0) = Ly`` (``alpha_0 = 0``: ``w_yy = w_xy = 0``), that term computed
        by the parent on the ``m = 0`` harmonic alone."""
        total = super().bending_form()
        if self.alpha[0] != 0:
            return total
        uniform = LevyPlateField(self.section, self.Ly, self.omega, self.alpha[:1],
                                 [(x0, q[:1]) for x0, q in self.forces])
        uniform.coefficients = self.coefficients[:1]
        return total + uniform.bending_form()


# --------------------------------------------------------------------------------------
# Solution
# --------------------------------------------------------------------------------------


class PrismaticSolution(JunctionSolution):
    r"""Levy solution returned by ``prismatic_levy``: a ``JunctionSolution`` (whose bending
    fields and member rotations it shares) with the in-plane fields, the lines' translations
    and the translational springs' dissipation (``translational_spring_dissipated_power``,
    included in ``dissipated_power``).  The line rotation and the rotational springs'
    dissipation are the parent's written for either ends: ``y`` shapes ``P, Q`` and line
    factors ``c_m`` of ``ends`` (module docstring).

    Attributes
    ----------
    ends : {'diaphragm', 'symmetric'}
    harmonics : numpy.ndarray
        The ``m`` of the harmonics: ``1..n_terms`` or ``0..n_terms - 1``.
    bending : dict of str -> exact.LevyPlateField
        Per-plate bending fields (``fields`` of ``JunctionSolution``; ``CosineLevyField`` for
        symmetric ends).
    membranes : dict of str -> MembraneField
        Per-plate in-plane fields.
    plates : dict of str -> FoldedPlate
    lines : list of PrismaticLine
    line_frames : list of (p0, e, t1, t2)
        Start, direction and transverse pair of each line (numpy arrays).
    sigmas : list of dict
        ``sigma_i = y_axis_i . e`` of each line's members.
    translation_coefficients : numpy.ndarray
        ``(n_lines, n_terms, 3)``: ``T1_m, T2_m, E_m`` of ``U_J(s)`` (amplitudes of ``P``,
        ``P`` and ``Q``; the symmetric ``E_0`` is 0).
    rotation_coefficients : numpy.ndarray
        ``(n_lines, n_terms)``: ``T_m`` of ``Theta_J(s)`` (``line_coefficients``, of ``P``).
    forces, inplane_forces : list of (str, float, float, complex)
    n_terms : int
    """

    def __init__(self, bending, membranes, plates, lines, line_frames, sigmas,
                 translation_coefficients, rotation_coefficients, forces, inplane_forces,
                 ends="diaphragm"):
        super().__init__(bending, plates, lines, line_frames, sigmas, rotation_coefficients,
                         None)
        self.ends = _checked_ends(ends)
        self.harmonics = _harmonic_indices(ends, self.n_terms)
        self.shapes = _end_shapes(ends)
        self.energy_factors = _energy_factors(self.alpha, ends)
        self.bending = bending
        self.membranes = membranes
        self.translation_coefficients = translation_coefficients
        self.rotation_coefficients = rotation_coefficients
        self.forces = forces
        self.inplane_forces = inplane_forces

    def u(self, plate, x, y):
        """In-plane displacement along ``x_axis`` of ``plate`` at ``(x, y)``."""
        return self.membranes[plate].u(x, y)

    def v(self, plate, x, y):
        """In-plane displacement along ``y_axis`` of ``plate`` at ``(x, y)``."""
        return self.membranes[plate].v(x, y)

    def displacement(self, plate, x, y):
        """3D displacement ``u x_axis + v y_axis + w e_z``, shape ``broadcast(x, y) + (3,)``."""
        x_axis, y_axis, e_z = self.plates[plate].axes()
        return (self.u(plate, x, y)[..., None] * x_axis + self.v(plate, x, y)[..., None] * y_axis
                + self.w(plate, x, y)[..., None] * e_z)

    def line_signs(self, line, plate):
        """Factors ``c_m`` of ``plate`` on ``line`` (``_end_signs``)."""
        return _end_signs(self.sigmas[line][plate], self.harmonics, self.ends)

    def line_rotation(self, line, s):
        r"""Rotation of line ``line`` about ``e``: ``Theta_J(s) = sum_m T_m P(alpha_m s)``."""
        s = np.asarray(s, float)
        return self.shapes[0](s[..., None] * self.alpha) @ self.line_coefficients[line]

    def spring_dissipated_power(self, line, plate):
        """Time-averaged power dissipated by the rotational spring tying ``plate`` to ``line``.

        ``0.5 omega Im(k) int_0^Ly |Theta_J - Theta_i|^2 ds
        = 0.5 omega Im(k) Ly/2 sum_m f_P |c_m T_m - Theta_{i,m}|^2``; 0 for a rigid tie.
        """
        k = self.lines[line].members[plate][1]
        if np.isinf(k):
            return 0.0
        jump = (self.line_signs(line, plate) * self.line_coefficients[line]
                - self.member_rotation_harmonics(line, plate))
        return (0.25 * self.omega * np.imag(k) * self.Ly
                * np.sum(self.energy_factors[0] * np.abs(jump) ** 2))

    def line_translation(self, line, s):
        """``U_J(s) = sum_m (T1 t1 + T2 t2) P(alpha s) + E e Q(alpha s)``, ``(..., 3)``."""
        s = np.asarray(s, float)[..., None]
        _, e, t1, t2 = self.line_frames[line]
        T1, T2, E = self.translation_coefficients[line].T
        sines, cosines = (shape(s * self.alpha) for shape in self.shapes)
        return ((sines @ T1)[..., None] * t1 + (sines @ T2)[..., None] * t2
                + (cosines @ E)[..., None] * e)

    def member_translation_harmonics(self, line, plate):
        """Harmonics of ``plate``'s edge displacement ``X_i`` on ``line``, in the line's frame.

        ``(n_terms, 3)``: ``c_m (U_m x_axis + W_m e_z) . t_k`` (``k = 1, 2``, amplitudes of
        ``P(alpha_m s)``) and ``c_m V_m`` (of ``Q(alpha_m s)``), comparable with
        ``translation_coefficients[line]``.
        """
        end = self.lines[line].members[plate][0]
        x_edge = [0.0 if end == "left" else self.plates[plate].length]
        W = self.bending[plate].harmonic_derivative(x_edge, 0)[0]
        U, V = (c[0] for c in self.membranes[plate].harmonic_derivative(x_edge, 0))
        x_axis, _, e_z = self.plates[plate].axes()
        _, _, t1, t2 = self.line_frames[line]
        signs = self.line_signs(line, plate)
        return signs[:, None] * np.stack([U * (x_axis @ t1) + W * (e_z @ t1),
                                          U * (x_axis @ t2) + W * (e_z @ t2), V], axis=-1)

    def translational_spring_dissipated_power(self, line, plate):
        """Time-averaged power dissipated by the translational spring of ``plate`` on ``line``.

        ``0.5 omega Im(k_t*) int_0^Ly |U_J - X_i|^2 ds
        = 0.5 omega Im(k_t*) Ly/2 sum_m (f_P, f_P, f_Q) . |(T1, T2, E)_m - X_i,m|^2``
        (``sin^2`` and ``cos^2`` both average to 1/2 for ``m >= 1``; ``_energy_factors``);
        0 for a rigid tie.
        """
        k_t = self.lines[line].translational_stiffness(plate)
        if np.isinf(k_t):
            return 0.0
        jump = self.translation_coefficients[line] - self.member_translation_harmonics(line,
                                                                                        plate)
        f_p, f_q = self.energy_factors
        weights = np.stack([f_p, f_p, f_q], axis=-1)
        return 0.25 * self.omega * np.imag(k_t) * self.Ly * np.sum(weights * np.abs(jump) ** 2)

    def dissipated_power(self):
        """Total time-averaged dissipation: plates (bending and membrane), rotational springs
        (``JunctionSolution.dissipated_power``) and translational springs."""
        translational = sum(self.translational_spring_dissipated_power(j, name)
                            for j, line in enumerate(self.lines) for name in line.translational)
        return super().dissipated_power() + translational

    def bending_dissipated_power(self, plate):
        """``0.5 omega Im(D*) a(w, w*) / D*`` of ``plate``."""
        return self.bending[plate].dissipated_power()

    def membrane_dissipated_power(self, plate):
        """``0.5 omega Im(A*) a_m(u, u*) / A*`` of ``plate``."""
        return self.membranes[plate].dissipated_power()

    def plate_dissipated_power(self, plate):
        """Bending plus membrane dissipation of ``plate``."""
        return self.bending_dissipated_power(plate) + self.membrane_dissipated_power(plate)

    def input_power(self):
        """``0.5 Re(conj(F) j omega w(x0, y0))`` per normal force, ``u`` per in-plane one.

        Evaluated with the same truncated series, so it balances ``dissipated_power``
        whatever ``n_terms``.
        """
        total = 0.0
        for fields, displacement in ((self.forces, self.w), (self.inplane_forces, self.u)):
            for plate, x0, y0, F in fields:
                total += 0.5 * np.real(np.conj(F) * 1j * self.omega * displacement(plate, x0, y0))
        return total


# --------------------------------------------------------------------------------------
# Solver
# --------------------------------------------------------------------------------------


class _Equations:
    """Per-harmonic linear system: 8 unknowns per plate (4 bending, 4 membrane), then
    ``T1, T2, E, T`` per line."""

    def __init__(self, names, n_lines, maps, n_terms):
        self.column = {name: 8 * i for i, name in enumerate(names)}
        self.line_base = 8 * len(names)
        self.n_unknowns = self.line_base + 4 * n_lines
        self.maps = maps
        self.n_terms = n_terms
        self.rows, self.rhs = [], []

    def add(self, terms, line_terms=()):
        """Append ``sum coef * quantity(plate, end) + sum coef * unknown(line, k) = 0``.

        ``terms``: ``(coef, plate, end, quantity)``; ``line_terms``: ``(coef, line, k)`` with
        ``k`` 0, 1, 2 for ``T1, T2, E`` and 3 for ``T``; coefficients are scalars or
        ``(n_terms,)`` arrays.
        """
        row = np.zeros((self.n_terms, self.n_unknowns), complex)
        value = np.zeros(self.n_terms, complex)
        for coef, name, end, quantity in terms:
            q = self.maps[(name, end)][quantity]
            start = self.column[name]
            row[:, start:start + 8] += np.asarray(coef)[..., None] * q[:, :8]
            value -= coef * q[:, 8]
        for coef, line, k in line_terms:
            row[:, self.line_base + 4 * line + k] += coef
        self.rows.append(row)
        self.rhs.append(value)

    def solve(self):
        """Solution ``(n_terms, n_unknowns)`` of the row-equilibrated systems."""
        matrix = np.stack(self.rows, axis=1)
        vector = np.stack(self.rhs, axis=1)
        scale = np.max(np.abs(matrix), axis=2)
        return np.linalg.solve(matrix / scale[:, :, None], (vector / scale)[:, :, None])[..., 0]


def _edge_maps(bending, membrane, end):
    """``quantity -> (n_terms, 9)`` maps of one edge: 4 bending, 4 membrane, load columns."""
    out = {}
    maps = bending.edge_maps(end)
    zeros = np.zeros((maps["w"].shape[0], 4))
    for quantity, q in maps.items():
        out[quantity] = np.concatenate([q[:, :4], zeros, q[:, 4:]], axis=1)
    for quantity, q in membrane.edge_maps(end).items():
        out[quantity] = np.concatenate([zeros, q[:, :4], q[:, 4:]], axis=1)
    return out


def _outer_edge_equations(eqs, name, plate, end):
    """Two bending and two in-plane conditions of an edge on no line."""
    for quantity in (_BENDING_CONDITIONS[getattr(plate, end)]
                     + INPLANE_CONDITIONS[plate.inplane_condition(end)]):
        eqs.add([(1.0, name, end, quantity)])


def _member_equations(eqs, name, plate, end, line, stiffness, frame, sigma, signs,
                      translational=math.inf):
    """Translation law (3 rows) and rotation law (1 row) of a member on ``line``.

    Rigid tie in translation: ``c_m (U x_axis + W e_z) . t_k = Tk``, ``c_m V = E``.  On a
    translational spring ``k_t*`` (``F_i = k_t* (U_J - X_i)``):
    ``c_m (n_x N_xx x_axis + K_n e_z) . t_k + k_t* c_m (U x_axis + W e_z) . t_k - k_t* Tk = 0``
    and ``c_m n_x N_xy + k_t* c_m V - k_t* E = 0`` (the rows are equilibrated by
    ``_Equations.solve``, so a stiff ``k_t*`` approaches the rigid rows).
    Rotation: ``M_n = k (theta + sigma n_x c_m T)`` on a spring, ``-sigma n_x theta = c_m T``
    on a rigid tie (``exact_junction``).
    """
    x_axis, _, e_z = plate.axes()
    _, _, t1, t2 = frame
    n_x = 1.0 if end == "right" else -1.0
    if np.isinf(translational):
        for k, t in enumerate((t1, t2)):
            eqs.add([(signs * (x_axis @ t), name, end, "u"),
                     (signs * (e_z @ t), name, end, "w")], [(-1.0, line, k)])
        eqs.add([(signs, name, end, "v")], [(-1.0, line, 2)])
    else:
        k_t = translational
        for k, t in enumerate((t1, t2)):
            eqs.add([(signs * n_x * (x_axis @ t), name, end, "Nx"),
                     (signs * (e_z @ t), name, end, "K"),
                     (k_t * signs * (x_axis @ t), name, end, "u"),
                     (k_t * signs * (e_z @ t), name, end, "w")], [(-k_t, line, k)])
        eqs.add([(signs * n_x, name, end, "Nxy"), (k_t * signs, name, end, "v")],
                [(-k_t, line, 2)])
    sigma_nx = sigma * n_x
    if np.isinf(stiffness):
        eqs.add([(-sigma_nx, name, end, "theta")], [(-signs, line, 3)])
    else:
        eqs.add([(1.0, name, end, "M"), (-stiffness, name, end, "theta")],
                [(-stiffness * sigma_nx * signs, line, 3)])


def _line_equations(eqs, j, line, plates, frame, sigmas, m, ends):
    """Balance of the massless line ``j``: moments, then forces (or ``U_J = 0`` if held).

    ``sum_i c_m sigma_i n_x M_n = 0``; ``sum_i c_m [n_x N_xx x_axis + K_n e_z] . t_k = 0``;
    ``sum_i c_m n_x N_xy = 0`` (``c_m`` of ``ends``, ``_end_signs``).
    """
    _, _, t1, t2 = frame
    members = []
    for name, (end, _) in line.members.items():
        n_x = 1.0 if end == "right" else -1.0
        x_axis, _, e_z = plates[name].axes()
        members.append((name, end, n_x, _end_signs(sigmas[name], m, ends), x_axis, e_z))
    eqs.add([(signs * sigmas[name] * n_x, name, end, "M")
             for name, end, n_x, signs, _, _ in members])
    if line.held:
        for k in range(3):
            eqs.add([], [(1.0, j, k)])
        return
    for t in (t1, t2):
        eqs.add([term for name, end, n_x, signs, x_axis, e_z in members
                 for term in ((signs * n_x * (x_axis @ t), name, end, "Nx"),
                              (signs * (e_z @ t), name, end, "K"))])
    eqs.add([(signs * n_x, name, end, "Nxy") for name, end, n_x, signs, _, _ in members])


def _checked_forces(plates, Ly, forces, kind):
    """``[(plate, x0, y0, F)]`` with every force strictly inside its plate."""
    out = []
    for plate, x0, y0, F in forces:
        if plate not in plates:
            raise ValueError(f"{kind} force on unknown plate {plate!r}")
        if not (0.0 < x0 < plates[plate].length and 0.0 <= y0 <= Ly):
            raise ValueError(f"{kind} force ({x0}, {y0}) not inside plate {plate!r}")
        out.append((plate, float(x0), float(y0), F))
    return out


def _edges_on_lines(plates, lines):
    """``{(plate, end): line index}``; an edge may lie on one line only."""
    on_line = {}
    for j, line in enumerate(lines):
        for name, (end, _) in line.members.items():
            if name not in plates:
                raise ValueError(f"line {j}: unknown plate {name!r}")
            if (name, end) in on_line:
                raise ValueError(f"edge {end!r} of plate {name!r} is on two lines")
            on_line[(name, end)] = j
    return on_line


def _line_frame(plates, line, Ly):
    """``(p0, e, t1, t2)`` and ``sigmas`` of a line (``exact_junction._line_orientations``)."""
    start, e, sigmas = _line_orientations(plates, line, Ly)
    t1 = plates[next(iter(line.members))].axes()[0]
    return (start, e, t1, np.cross(e, t1)), sigmas


def _harmonic_loads(forces, name, alpha, Ly, ends):
    """``[(x0, q_m)]`` of the forces on plate ``name``: ``q_m = 2 F sin(alpha_m y0) / Ly``
    (diaphragms) or ``eps_m F cos(alpha_m y0) / Ly``, ``eps_0 = 1``, ``eps_m = 2`` (symmetric:
    ``int_0^Ly cos^2 = Ly`` for ``m = 0``, ``Ly / 2`` else)."""
    if ends == "diaphragm":
        return [(x0, 2.0 * F * np.sin(alpha * y0) / Ly) for plate, x0, y0, F in forces
                if plate == name]
    eps = np.where(alpha == 0, 1.0, 2.0)
    return [(x0, eps * F * np.cos(alpha * y0) / Ly) for plate, x0, y0, F in forces
            if plate == name]


def prismatic_levy(plates, lines, Ly, omega, forces=(), inplane_forces=(), n_terms=None,
                   ends="diaphragm"):
    r"""Levy solution of a prismatic folded-plate structure with moving (or held) lines.

    Per harmonic ``m`` each plate has 4 bending coefficients (``exact.LevyPlateField``, or
    ``CosineLevyField`` for symmetric ends, with the strip Green function of its normal
    forces) and 4 membrane ones (``MembraneField``, with the Green function of its in-plane
    forces); each line has ``T1, T2, E`` (translation) and ``T`` (rotation).  Equations
    (module docstring): 4 per outer edge (2 bending, 2 in-plane), 4 per member edge (3
    translation laws: continuity, or the translational spring of
    ``PrismaticLine.translational``; 1 rotation law) and 4 per line (3 force balances or
    ``U_J = 0``, 1 moment balance), the same for either ``ends`` up to the line factors
    ``c_m``.  The ``n_terms`` square systems are solved at once after scaling each row to a
    unit largest entry.

    Parameters
    ----------
    plates : dict of str -> FoldedPlate
    lines : sequence of PrismaticLine
        Each plate edge lies on at most one line.
    Ly : float
        Common width (m).
    omega : float
        Angular frequency (rad/s), > 0.
    forces : sequence of (str, float, float, complex)
        ``(plate, x0, y0, F)``: normal force ``F`` (N, along the plate's ``e_z``) at the local
        point ``(x0, y0)``, ``0 < x0 < Lx``, ``0 <= y0 <= Ly``.
    inplane_forces : sequence of (str, float, float, complex)
        ``(plate, x0, y0, F_x)``: in-plane force along the plate's ``x_axis``.
    n_terms : int, optional
        Number of harmonics; ``default_prismatic_n_terms`` when omitted.  They are
        ``m = 1..n_terms`` with diaphragm ends, ``m = 0..n_terms - 1`` with symmetric ones.
    ends : {'diaphragm', 'symmetric'}
        Conditions on the ends ``y = 0, Ly`` of every plate (module docstring, Harmonics):
        shear diaphragms (``w = M_yy = u = N_yy = 0``, sine series in ``w``, ``u``) or planes
        of symmetry (``w_y = K_y = v = N_xy = 0``, cosine series in ``w``, ``u`` from
        ``m = 0``).

    Returns
    -------
    PrismaticSolution

    Notes
    -----
    With damping (``Im D*, Im A* > 0``) no harmonic sits exactly on a cut-on
    (``alpha_m = kappa``, ``k_L`` or ``k_S``).  A line whose members all have ``k = 0`` leaves
    ``T`` undetermined, one whose members all have ``k_t* = 0`` (and is not held) ``U_J``.
    """
    if not omega > 0:
        raise ValueError(f"omega must be > 0, got {omega}")
    _checked_ends(ends)
    lines = list(lines)
    forces = _checked_forces(plates, Ly, forces, "normal")
    inplane_forces = _checked_forces(plates, Ly, inplane_forces, "in-plane")
    on_line = _edges_on_lines(plates, lines)
    oriented = [_line_frame(plates, line, Ly) for line in lines]
    frames, sigmas = [f for f, _ in oriented], [s for _, s in oriented]
    if n_terms is None:
        n_terms = default_prismatic_n_terms(plates.values(), Ly, omega)
    m = _harmonic_indices(ends, n_terms)
    alpha = m * np.pi / Ly
    # The bending harmonics do not depend on the ends; only their y shape does.
    bending_field = LevyPlateField if ends == "diaphragm" else CosineLevyField
    bending = {name: bending_field(Section(p.length, p.D, p.nu, p.rho_h), Ly, omega, alpha,
                                   _harmonic_loads(forces, name, alpha, Ly, ends))
               for name, p in plates.items()}
    membranes = {name: MembraneField(p, Ly, omega, alpha,
                                     _harmonic_loads(inplane_forces, name, alpha, Ly, ends),
                                     ends)
                 for name, p in plates.items()}
    maps = {(name, end): _edge_maps(bending[name], membranes[name], end)
            for name in plates for end in EDGES}
    eqs = _Equations(list(plates), len(lines), maps, n_terms)
    for name, plate in plates.items():
        for end in EDGES:
            if (name, end) not in on_line:
                _outer_edge_equations(eqs, name, plate, end)
                continue
            j = on_line[(name, end)]
            sigma = sigmas[j][name]
            _member_equations(eqs, name, plate, end, j, lines[j].members[name][1], frames[j],
                              sigma, _end_signs(sigma, m, ends),
                              lines[j].translational_stiffness(name))
    for j, line in enumerate(lines):
        _line_equations(eqs, j, line, plates, frames[j], sigmas[j], m, ends)
    solution = eqs.solve()
    for name in plates:
        start = eqs.column[name]
        bending[name].coefficients = solution[:, start:start + 4]
        membranes[name].coefficients = solution[:, start + 4:start + 8]
    line_part = solution[:, eqs.line_base:].reshape(n_terms, len(lines), 4).transpose(1, 0, 2)
    return PrismaticSolution(bending, membranes, dict(plates), lines, frames, sigmas,
                             line_part[:, :, :3].copy(), line_part[:, :, 3].copy(), forces,
                             inplane_forces, ends)
