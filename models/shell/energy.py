"""Elastic energy of the discrete axisymmetric shell: global energy, gradient and banded Hessian.

The state is the interleaved vector ``x = [r_0, z_0, r_1, z_1, ..., r_{N-1}, z_{N-1}]`` of all node
coordinates, so every element touches a contiguous block of dofs and the Hessian is banded with
half-bandwidth 5 (a bending element couples nodes ``i-1 .. i+1``).  The energy is eq. (3.12) of the
paper (``docs/physics.md`` section 2):

* stretching: every edge ``i = 0 .. N-2``,
  ``pi rbar^i lbar^i ks (eps11^2 + 2 nu eps11 eps22 + eps22^2)``, ``ks = E h / (1 - nu^2)``;
* bending: every interior node ``i = 1 .. N-2``,
  ``pi rbar_i lbar_i kb (B11^2 + 2 nu B11 B22 + B22^2)``, ``B = kappa - kappabar``,
  ``kb = E h^3 / (12 (1 - nu^2))``.

The element formulas, their exact gradients and Hessians live in the generated module
:mod:`models.shell._generated` (see :mod:`models.shell.codegen` for the definitions: ``kappa11`` is
``2 tan(xi/2) / L``, ``kappa22 = n_r / r_i`` with the node normal the unit bisector of the two edge
normals).  ``kappa11_length`` selects ``L``: ``"current"`` (the deformed Voronoi length; the
default) or ``"reference"`` (the reference one, as physics.md section 2 writes the formula).  Only
``"current"`` passes the pure-dilation check of physics.md section 7 (``kappa11 = 1/((1+e) R)``);
both reach Reissner's stiffness as ``h/R -> 0`` (they differ by 3e-4 there) but differ by 0.3 % in
F at ``w/R = 0.1`` for the default scene (``python -m studies.shell_mesh_convergence``), so the choice
matters in the nonlinear range.

Not decided here
----------------
Boundary conditions and the pole.  No dof is fixed.  The bending element is skipped at the base
node (it has one edge) and at the pole node (``r = 0``, where ``n_r / r`` is 0/0), which is only
what is needed to avoid a division by zero: it is *not* a pole treatment.  The symmetric pole
treatment of physics.md section 2 (mirror node across the axis, ``kappa22 = kappa11`` at the pole,
vanishing area weight; to be shown second-order convergent in ``1/N``) and the sliding base are
decided in the next step.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
import scipy.sparse as sp

from . import _generated as gen
from .geometry import ReferenceCap, split

__all__ = ["ShellEnergy", "HALF_BANDWIDTH"]

HALF_BANDWIDTH = 5
"""Half-bandwidth of the Hessian in the interleaved dof ordering."""

_PARTS = ("stretch", "bend")


class _Term:
    """One family of elements: generated kernels, local-to-global dof map, fixed arguments."""

    def __init__(self, kernels: str, dofs: np.ndarray, params: tuple) -> None:
        self.energy_fn = getattr(gen, f"{kernels}_energy")
        self.gradient_fn = getattr(gen, f"{kernels}_gradient")
        self.hessian_fn = getattr(gen, f"{kernels}_hessian")
        self.dofs = dofs  # (m, ndof) global indices
        self.params = params
        self.hess_slot: np.ndarray | None = None  # (m * ndof * ndof,) index into the CSR data

    def local(self, x: np.ndarray) -> list[np.ndarray]:
        return [x[self.dofs[:, k]] for k in range(self.dofs.shape[1])]

    def energy(self, x: np.ndarray) -> np.ndarray:
        return self.energy_fn(*self.local(x), *self.params)

    def gradient(self, x: np.ndarray) -> np.ndarray:
        return self.gradient_fn(*self.local(x), *self.params)

    def hessian(self, x: np.ndarray) -> np.ndarray:
        return self.hessian_fn(*self.local(x), *self.params)


class ShellEnergy:
    """Stretching plus bending energy of a discrete axisymmetric shell about a reference cap.

    Parameters
    ----------
    cap : ReferenceCap
        The reference (stress-free) configuration, from :func:`models.shell.spherical_cap`.
    E : float
        Young's modulus, ``> 0``.
    h : float
        Thickness, ``> 0``.
    nu : float
        Poisson's ratio, in ``(-1, 1)`` (``nu = 1/2`` is allowed: the plane-stress constants stay
        finite).
    kappa11_length : {"reference", "current"}
        Length in ``kappa11 = 2 tan(xi/2) / L``: the reference Voronoi length (default, physics.md
        section 2) or the current one.  At the reference state both give the same curvature; they
        differ by terms of order (membrane strain) x (curvature).

    Notes
    -----
    Energies are in units of ``E R^3`` times a length ratio; gradients and Hessians are with
    respect to the interleaved state ``[r_0, z_0, r_1, z_1, ...]``.  No boundary conditions and no
    pole treatment (see the module docstring).
    """

    def __init__(self, cap: ReferenceCap, E: float, h: float, nu: float,
                 kappa11_length: Literal["reference", "current"] = "current") -> None:
        E, h, nu = float(E), float(h), float(nu)
        if not (E > 0 and math.isfinite(E)):
            raise ValueError(f"ShellEnergy: E must be a positive number, got {E!r}")
        if not (h > 0 and math.isfinite(h)):
            raise ValueError(f"ShellEnergy: h must be a positive number, got {h!r}")
        if not (-1.0 < nu < 1.0):
            raise ValueError(f"ShellEnergy: nu must be in (-1, 1), got {nu!r}")
        if kappa11_length not in ("reference", "current"):
            raise ValueError(f"ShellEnergy: kappa11_length must be 'reference' or 'current', "
                             f"got {kappa11_length!r}")
        self.cap = cap
        self.E, self.h, self.nu = E, h, nu
        self.kappa11_length = kappa11_length
        self.ks = E * h / (1.0 - nu**2)
        self.kb = E * h**3 / (12.0 * (1.0 - nu**2))
        N = cap.N
        self.n = 2 * N

        edges = np.arange(N - 1)
        s_dofs = np.stack([2 * edges, 2 * edges + 1, 2 * edges + 2, 2 * edges + 3], axis=1)
        stretch = _Term("stretch", s_dofs, (cap.edge_length, cap.edge_radius, self.ks, nu))

        self.bend_nodes = np.arange(1, N - 1)  # base and pole skipped (see module docstring)
        b_dofs = 2 * (self.bend_nodes[:, None] - 1) + np.arange(6)[None, :]
        kernels = "bend" if kappa11_length == "reference" else "bend_cur"
        curv_fn = getattr(gen, f"{kernels}_curvatures")
        i = self.bend_nodes
        lbar, rbar = cap.voronoi_length[i], cap.node_radius[i]
        # Reference curvatures from the very same kernel, so the reference state is exactly flat.
        k11bar, k22bar = curv_fn(cap.r[i - 1], cap.z[i - 1], cap.r[i], cap.z[i], cap.r[i + 1],
                                 cap.z[i + 1], lbar, rbar, 0.0, 0.0, 1.0, 0.0)
        self.kappa11_bar, self.kappa22_bar = k11bar, k22bar
        self._curv_fn = curv_fn
        bend = _Term(kernels, b_dofs, (lbar, rbar, k11bar, k22bar, self.kb, nu))
        self._terms = {"stretch": stretch, "bend": bend}
        self._build_pattern()

    # ---- sparsity pattern ------------------------------------------------------------------------
    def _build_pattern(self) -> None:
        n = self.n
        keys = []
        for term in self._terms.values():
            d = term.dofs
            rows = np.broadcast_to(d[:, :, None], d.shape + (d.shape[1],))
            cols = np.broadcast_to(d[:, None, :], d.shape + (d.shape[1],))
            keys.append((rows * n + cols).ravel())
        unique = np.unique(np.concatenate(keys))
        for term, k in zip(self._terms.values(), keys):
            term.hess_slot = np.searchsorted(unique, k)
        rows, cols = np.divmod(unique, n)
        self._indices = cols.astype(np.int32)
        self._indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n))]).astype(np.int32)
        self._nnz = unique.size

    # ---- public interface ------------------------------------------------------------------------
    @property
    def reference_state(self) -> np.ndarray:
        """The reference state vector (a new array)."""
        return self.cap.x

    def _check(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.shape != (self.n,):
            raise ValueError(f"state vector must have shape ({self.n},), got {x.shape}")
        return x

    def _selected(self, part: str | None) -> list[_Term]:
        if part is None:
            return list(self._terms.values())
        if part not in _PARTS:
            raise ValueError(f"part must be one of {_PARTS} or None, got {part!r}")
        return [self._terms[part]]

    def element_energies(self, x: np.ndarray, part: Literal["stretch", "bend"]) -> np.ndarray:
        """Energies of the individual elements of one part.

        Parameters
        ----------
        x : ndarray, shape ``(2 N,)``
            State vector.
        part : {"stretch", "bend"}
            Edges (``N-1`` values) or interior nodes (``N-2`` values, nodes ``1 .. N-2``).

        Returns
        -------
        ndarray
        """
        (term,) = self._selected(part)
        return term.energy(self._check(x))

    def energy(self, x: np.ndarray, part: Literal["stretch", "bend"] | None = None) -> float:
        """Total elastic energy (or one part of it).

        Parameters
        ----------
        x : ndarray, shape ``(2 N,)``
            State vector ``[r_0, z_0, r_1, z_1, ...]``.
        part : {"stretch", "bend"} or None
            Restrict to the stretching or the bending sum; ``None`` for both.

        Returns
        -------
        float
        """
        x = self._check(x)
        return float(sum(term.energy(x).sum() for term in self._selected(part)))

    def gradient(self, x: np.ndarray, part: Literal["stretch", "bend"] | None = None) -> np.ndarray:
        """Exact gradient of :meth:`energy`.

        Parameters
        ----------
        x : ndarray, shape ``(2 N,)``
            State vector.
        part : {"stretch", "bend"} or None
            As in :meth:`energy`.

        Returns
        -------
        ndarray, shape ``(2 N,)``
        """
        x = self._check(x)
        g = np.zeros(self.n)
        for term in self._selected(part):
            g += np.bincount(term.dofs.ravel(), weights=term.gradient(x).ravel(), minlength=self.n)
        return g

    def hessian(self, x: np.ndarray, part: Literal["stretch", "bend"] | None = None) -> sp.csr_matrix:
        """Exact Hessian of :meth:`energy`, assembled into a fixed banded CSR pattern.

        Parameters
        ----------
        x : ndarray, shape ``(2 N,)``
            State vector.
        part : {"stretch", "bend"} or None
            As in :meth:`energy`.

        Returns
        -------
        scipy.sparse.csr_matrix, shape ``(2 N, 2 N)``
            Symmetric, banded with half-bandwidth :data:`HALF_BANDWIDTH`; the sparsity pattern is
            the same for every ``x`` and ``part`` (entries of an omitted part are stored zeros).
        """
        x = self._check(x)
        data = np.zeros(self._nnz)
        for term in self._selected(part):
            data += np.bincount(term.hess_slot, weights=term.hessian(x).ravel(), minlength=self._nnz)
        return sp.csr_matrix((data, self._indices.copy(), self._indptr.copy()), shape=(self.n, self.n))

    def strains(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Stretching strains of every edge.

        Parameters
        ----------
        x : ndarray, shape ``(2 N,)``
            State vector.

        Returns
        -------
        eps11, eps22 : ndarray, shape ``(N-1,)``
            Meridional ``l / lbar - 1`` and circumferential ``r_edge / rbar - 1`` strains.
        """
        r, z = split(self._check(x))
        cap = self.cap
        return gen.stretch_strains(r[:-1], z[:-1], r[1:], z[1:], cap.edge_length, cap.edge_radius,
                                   self.ks, self.nu)

    def curvatures(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Discrete curvatures at the bending nodes :attr:`bend_nodes` (``1 .. N-2``).

        Parameters
        ----------
        x : ndarray, shape ``(2 N,)``
            State vector.

        Returns
        -------
        kappa11, kappa22 : ndarray, shape ``(N-2,)``
            Meridional ``2 tan(xi/2) / L`` and circumferential ``n_r / r`` curvatures (not the
            changes: subtract :attr:`kappa11_bar`, :attr:`kappa22_bar` for those).
        """
        r, z = split(self._check(x))
        i = self.bend_nodes
        cap = self.cap
        return self._curv_fn(r[i - 1], z[i - 1], r[i], z[i], r[i + 1], z[i + 1],
                             cap.voronoi_length[i], cap.node_radius[i], 0.0, 0.0, self.kb, self.nu)

    def __repr__(self) -> str:
        c = self.cap
        return (f"ShellEnergy(R={c.R}, phi_hat={c.phi_hat}, N={c.N}, E={self.E}, h={self.h}, "
                f"nu={self.nu}, kappa11_length={self.kappa11_length!r})")
