"""Finite-element reference for ``bench_clamped_corners.py``: a Kirchhoff plate clamped on one
edge by Argyris triangles (scikit-fem), written apart from the VTCR solver.

The problem: ``[0, 0.3] x [0, 0.4]`` m, 2 mm steel, loss factor 0.01, clamped on x = 0, free
elsewhere, a line force of 1 N/m on x = 0.3; time factor ``exp(+j omega t)``. Weak form
(bilinear, no conjugation), for every admissible ``v``:

    int D*[(1 - nu) w_ij v_ij + nu lap w lap v] dA - omega^2 rho h int w v dA = int T v ds.

Why not ``bench/fem_argyris.py``'s element: scikit-fem's Argyris basis is built from global
monomials, which meet a round-off floor of about 1e-5 on the small elements this problem
needs; here each triangle's basis is written in its own centred, scaled coordinates. The
clamped-free corners (0, 0) and (0, 0.4) are singular (w ~ r^2.07), so the mesh is refined
towards them until an element's size is about max(r / 4, 1e-6), and towards the loaded corners
(0.3, 0), (0.3, 0.4) to max(r / 4, 1e-3) (finer there, the vertices' absolute coordinates
cost round-off). Self-checks made when it was written (against exact solutions at the
bench's 285 points): a cantilever strip (nu = 0) converges like h^6 to 3.7e-10 at 300 Hz and
9.9e-9 at 1 kHz; a Levy strip (clamped, simply supported, free with a half-sine load,
nu = 0.3) to 4.8e-10 and 1.2e-8. On the corner-refined family, base meshes 24 x 32, 48 x 64,
96 x 128 cells change ``w`` by 1.1e-7, 3.5e-9, 1.3e-9 at 300 Hz and 3.8e-6, 8.5e-8, 1.4e-9 at
1 kHz; round-off is about 1e-9.
"""
from __future__ import annotations

import itertools
import math
import time

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.linalg import splu
from fem_argyris import bending_form, mass_form
from skfem import Basis, ElementTriArgyris, MeshTri, asm


class ArgyrisLocal(ElementTriArgyris):
    """Argyris element with a per-triangle local scaled monomial basis."""

    _xc = None
    _s = None

    def _geom(self, mesh):
        if self._xc is None:
            P = mesh.p[:, mesh.t]  # (2, 3, nel)
            self._xc = P.mean(axis=1)  # (2, nel)
            e = np.stack([P[:, 0] - P[:, 1], P[:, 1] - P[:, 2], P[:, 2] - P[:, 0]])
            self._s = np.sqrt((e ** 2).sum(axis=1)).max(axis=0)  # (nel,)
        return self._xc, self._s

    def gbasis(self, mapping, X, i, tind=None):
        from skfem.element.discrete_field import DiscreteField
        if tind is None:
            tind = np.arange(mapping.mesh.t.shape[1])
        xc, s = self._geom(mapping.mesh)
        if self.V is None:
            self._pbasis_init(self.maxdeg, self.dim, self.derivatives,
                              self.tensorial_basis)
            self.V = np.linalg.inv(self._eval_dofs(mapping.mesh))
        V = self.V[tind]
        x = mapping.F(X, tind=tind)  # (2, nsel, npts)
        sc = s[tind][:, None]
        xi = (x[0] - xc[0, tind][:, None]) / sc
        eta = (x[1] - xc[1, tind][:, None]) / sc
        U = [np.zeros((self.dim,) * k + x[0].shape)
             for k in range(self.derivatives + 1)]
        N = len(self._pbasis[()])
        for k in range(self.derivatives + 1):
            diffs = list(itertools.product(*((list(range(self.dim)),) * k)))
            fac = 1.0 / sc ** k
            for itr in range(N):
                coef = V[:, itr, i][:, None]
                for diff in diffs:
                    U[k][diff] += coef * self._pbasis[diff][itr](xi, eta) * fac
        return (DiscreteField(value=U[0], grad=U[1], hess=U[2]),)

    def _eval_dofs(self, mesh, tind=None):
        if tind is None:
            tind = np.arange(mesh.t.shape[1])
        xc, s = self._geom(mesh)
        xc = xc[:, tind]
        s = s[tind]
        N = len(self._pbasis[()])
        V = np.zeros((len(tind), N, N))
        w = {'v': np.array([mesh.p[:, mesh.t[itr, tind]]
                            for itr in range(mesh.t.shape[0])])}
        w['e'] = np.array([.5 * (w['v'][itr] + w['v'][(itr + 1) % 3])
                           for itr in range(3)])
        w['n'] = np.array([w['v'][itr] - w['v'][(itr + 1) % 3]
                           for itr in range(3)])
        w['n'][2] = -w['n'][2]
        for itr in range(3):
            w['n'][itr] = np.array([w['n'][itr, 1, :], -w['n'][itr, 0, :]])
            w['n'][itr] /= np.linalg.norm(w['n'][itr], axis=0)
        # boundary normal sign swap exactly as in scikit-fem (needs full mesh)
        assert len(tind) == mesh.t.shape[1]
        from skfem.assembly import FacetBasis
        fb = FacetBasis(mesh, mesh.elem(), intorder=0)
        ix = np.isin(mesh.t2f, mesh.boundary_facets())
        sortix = np.argsort(mesh.t2f[ix])
        norms1 = np.vstack((w['n'][:, 0, :][ix][sortix],
                            w['n'][:, 1, :][ix][sortix]))
        norms2 = fb.normals[:, :, 0]
        signs = np.sum(norms1 * norms2, axis=0)
        signs1 = signs.copy()
        signs1[sortix] = signs
        w['n'][:, 0, :][ix] *= signs1
        w['n'][:, 1, :][ix] *= signs1

        def wrap(f, order):
            return lambda x, y: f((x - xc[0]) / s, (y - xc[1]) / s) / s ** order

        for itr in range(N):
            F = {k: wrap(self._pbasis[k][itr], len(k)) for k in self._pbasis}
            for jtr in range(N):
                V[:, jtr, itr] = self.gdof(F, w, jtr)
        return V


class PlateFE:
    """Argyris discretisation on a tensor mesh with unit-stiffness matrices."""

    def __init__(self, xs, ys, nu, chunk=4000, intorder=10, mesh=None):
        t0 = time.perf_counter()
        if mesh is None:
            mesh = MeshTri.init_tensor(np.asarray(xs, float), np.asarray(ys, float))
        self.mesh = mesh
        self.elem = ArgyrisLocal()
        self.nu = nu
        nel = self.mesh.t.shape[1]
        K = None
        M = None
        for start in range(0, nel, chunk):
            els = np.arange(start, min(nel, start + chunk))
            b = Basis(self.mesh, self.elem, elements=els, intorder=intorder)
            Kc = asm(bending_form, b, nu=nu)
            Mc = asm(mass_form, b)
            K = Kc if K is None else K + Kc
            M = Mc if M is None else M + Mc
        self.basis = Basis(self.mesh, self.elem, intorder=1)
        self.K = K.tocsr()
        self.M = M.tocsr()
        self.N = self.K.shape[0]
        self.t_asm = time.perf_counter() - t0

    # ---- pointwise evaluation -------------------------------------------
    def eval_matrix(self, pts, cells=None, what="value"):
        """Sparse matrix mapping the dof vector to value / dx / dy at pts (2, n)."""
        pts = np.asarray(pts, float)
        b = self.basis
        if cells is None:
            cells = self.mesh.element_finder(mapping=b.mapping)(*pts)
        X = b.mapping.invF(pts[:, :, None], tind=cells)
        vals = []
        for k in range(b.Nbfun):
            f = self.elem.gbasis(b.mapping, X, k, tind=cells)[0]
            if what == "value":
                vals.append(f.value[:, 0])
            elif what == "dx":
                vals.append(f.grad[0][:, 0])
            elif what == "dy":
                vals.append(f.grad[1][:, 0])
        vals = np.array(vals)  # (Nbfun, n)
        n = pts.shape[1]
        rows = np.tile(np.arange(n), b.Nbfun)
        cols = b.element_dofs[:, cells].flatten()
        return coo_matrix((vals.flatten(), (rows, cols)), shape=(n, self.N)).tocsr()

    def edge_points(self, facets, ngauss=5):
        """Gauss points (2, n), weights (n,), owning cells (n,) on facets."""
        gx, gw = np.polynomial.legendre.leggauss(ngauss)
        p0 = self.mesh.p[:, self.mesh.facets[0, facets]]
        p1 = self.mesh.p[:, self.mesh.facets[1, facets]]
        L = np.linalg.norm(p1 - p0, axis=0)
        t = 0.5 * (gx + 1.0)
        pts = p0[:, :, None] + (p1 - p0)[:, :, None] * t[None, None, :]
        wts = L[:, None] * 0.5 * gw[None, :]
        cells = np.repeat(self.mesh.f2t[0, facets], ngauss)
        return pts.reshape(2, -1), wts.reshape(-1), cells

    def line_load(self, facets, g):
        """Vector of int_facets g(x, y) v ds (exact for polynomial g of low degree)."""
        pts, wts, cells = self.edge_points(facets)
        E = self.eval_matrix(pts, cells)
        return E.T @ (wts * g(pts[0], pts[1]))

    def facets(self, fun):
        return self.mesh.facets_satisfying(fun, boundaries_only=True)

    # ---- solve ----------------------------------------------------------
    def solve(self, Dc, rhoh, omega, load, fixed):
        free = np.setdiff1d(np.arange(self.N), fixed)
        A = (Dc * self.K - omega ** 2 * rhoh * self.M)[free][:, free].tocsc()
        t0 = time.perf_counter()
        lu = splu(A)
        b = np.asarray(load[free], complex)
        uf = lu.solve(b)
        # iterative refinement (LU round-off is ~1e-9 relative otherwise)
        self.refine_corr = []
        for _ in range(3):
            du = lu.solve(b - A @ uf)
            uf = uf + du
            self.refine_corr.append(np.linalg.norm(du) / np.linalg.norm(uf))
        self.t_solve = time.perf_counter() - t0
        u = np.zeros(self.N, complex)
        u[free] = uf
        self.nfree = free.size
        return u


def material(E=210e9, rho=7800.0, h=0.002, nu=0.3, eta=0.01):
    D = E * h ** 3 / (12 * (1 - nu ** 2))
    return D * (1 + 1j * eta), rho * h


CLAMP_NAMES = ["u", "u_x", "u_y", "u_xy", "u_yy", "u_n"]  # on an edge x = const


def corner_refined_mesh(nx, ny, Lx, Ly, corners, c, hmin, max_iter=200):
    """corners: list of (x, y) or (x, y, hmin_corner)."""
    corners = [tuple(cc) + (hmin,) if len(cc) == 2 else tuple(cc) for cc in corners]
    return _corner_refined_mesh(nx, ny, Lx, Ly, corners, c)


def _corner_refined_mesh(nx, ny, Lx, Ly, corners, c, max_iter=200):
    """Uniform init_tensor mesh (nx x ny) refined (scikit-fem red-green-blue)
    around the given corner points until every triangle satisfies
        diameter <= sqrt(2) * max(r / c, hmin),
    r = distance from the triangle (its nearest vertex) to the nearest corner.
    Element size thus grows linearly with the distance to the corners."""
    m = MeshTri.init_tensor(np.linspace(0, Lx, nx + 1), np.linspace(0, Ly, ny + 1))
    corners = np.asarray(corners, float)
    for _ in range(max_iter):
        P = m.p[:, m.t]  # (2, 3, nel)
        e = np.stack([P[:, 0] - P[:, 1], P[:, 1] - P[:, 2], P[:, 2] - P[:, 0]])
        diam = np.sqrt((e ** 2).sum(axis=1)).max(axis=0)
        target = np.full(m.t.shape[1], np.inf)
        for cx, cy, hm in corners:
            r = np.sqrt((P[0] - cx) ** 2 + (P[1] - cy) ** 2).min(axis=0)
            target = np.minimum(target, np.maximum(r / c, hm))
        marked = np.nonzero(diam > np.sqrt(2) * target * (1 + 1e-9))[0]
        if marked.size == 0:
            break
        m = m.refined(marked)
    return MeshTri(m.p, m.t)


LX, LY, LINE_FORCE = 0.3, 0.4, 1.0


def clamped_plate_reference(frequency: float, points: np.ndarray,
                            base: int = 16) -> tuple[np.ndarray, str]:
    """``w`` at ``points`` (n, 2) of the plate of the module docstring at ``frequency`` (Hz),
    on the corner-refined mesh of ``3 base x 4 base`` cells, and a description of the run."""
    corners = [(0.0, 0.0), (0.0, LY), (LX, 0.0, 1e-3), (LX, LY, 1e-3)]
    mesh = corner_refined_mesh(3 * base, 4 * base, LX, LY, corners, 4, 1e-6)
    fe = PlateFE(None, None, 0.3, mesh=mesh)
    left = fe.facets(lambda x: np.isclose(x[0], 0.0, rtol=0, atol=1e-12))
    right = fe.facets(lambda x: np.isclose(x[0], LX, rtol=0, atol=1e-12))
    fixed = fe.basis.get_dofs(facets=left).all(CLAMP_NAMES)
    load = fe.line_load(right, lambda x, y: LINE_FORCE + 0 * y)
    bending_stiffness, mass = material()
    u = fe.solve(bending_stiffness, mass, 2 * math.pi * frequency, load, fixed)
    w = fe.eval_matrix(np.asarray(points, float).T) @ u
    return w, f"{fe.nfree} unknowns, {fe.t_asm + fe.t_solve:.0f} s"
