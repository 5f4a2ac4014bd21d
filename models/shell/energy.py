"""Elastic energy of the discrete axisymmetric shell: global energy, gradient and banded Hessian.

The state is the interleaved vector ``x = [r_0, z_0, r_1, z_1, ..., r_{N-1}, z_{N-1}]`` of all node
coordinates, so every element touches a contiguous block of dofs and the Hessian is banded with
half-bandwidth 5 (a bending element couples nodes ``i-1 .. i+1``).  The energy is eq. (3.12) of the
paper (``docs/model.md#the-discrete-shell``):

* stretching: every edge ``i = 0 .. N-2``,
  ``pi rbar^i lbar^i ks (eps11^2 + 2 nu eps11 eps22 + eps22^2)``, ``ks = E h / (1 - nu^2)``;
* bending: every interior node ``i = 1 .. N-2``,
  ``pi rbar_i lbar_i kb (B11^2 + 2 nu B11 B22 + B22^2)``, ``B = kappa - kappabar``,
  ``kb = E h^3 / (12 (1 - nu^2))``.

The thickness may vary (``h`` an array of node thicknesses): each edge then takes the mean
thickness of its two nodes in ``ks``, each node its own in ``kb`` (:attr:`ShellEnergy.ks_edges`,
:attr:`ShellEnergy.kb_nodes`).  The reference may be any polyline
(:mod:`contin_models.shell.meridian`), not only the spherical cap.

The element formulas, their exact gradients and Hessians live in the generated module
:mod:`contin_models.shell._generated` (see :mod:`contin_models.shell.codegen` for the definitions: ``kappa11`` is
``2 tan(xi/2) / L``, ``kappa22 = n_r / r_i`` with the node normal the unit bisector of the two edge
normals).  ``kappa11_length`` selects ``L``: ``"current"`` (the deformed Voronoi length; the
default) or ``"reference"`` (the reference one, the paper's eq. 3.9 read with a bar).  Only
``"current"`` passes the pure-dilation check of ``docs/model.md#checks`` (``kappa11 = 1/((1+e) R)``);
both reach Reissner's stiffness as ``h/R -> 0`` (they differ by 3e-4 there) but differ by 0.3 % in
F at ``w/R = 0.1`` for the default scene (``python -m studies.shell_mesh_convergence``), so the choice
matters in the nonlinear range.

Evaluation
----------
The kernels take each element's local variables (edge vectors and radii, computed once per call for
all edges) and return packed outputs: the gradient with respect to the element's dofs and the upper
triangle of its Hessian, one row per entry.  One ``bincount`` per block of elements (all of them up
to ``N ~ 8000``) scatters them into the global gradient or the upper triangle of the global
Hessian, whose fixed CSR data is then gathered from it (exactly symmetric).  The cost is a fixed
number of numpy operations per block, so it is linear in ``N`` (``python -m
studies.bench_shell_assembly``).  The gradient and Hessian kernels run in C where the package's
install built the extension ``contin_models.shell._ckernels`` (:data:`kernels`, :data:`COMPILED`),
with the numpy kernels' numbers.

Not decided here
----------------
Boundary conditions and the pole.  No dof is fixed.  The bending element is skipped at the base
node (it has one edge) and at the pole node (``r = 0``, where ``n_r / r`` is 0/0), which is only
what is needed to avoid a division by zero: it is *not* a pole treatment.  The symmetric pole
treatment of ``docs/model.md#pole-and-edge`` (mirror node across the axis, ``kappa22 = kappa11`` at the pole,
vanishing area weight; to be shown second-order convergent in ``1/N``) and the sliding base are
decided in the next step.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Literal

import numpy as np
import scipy.sparse as sp

from contin.numerics.compiled import prefer_compiled
from contin.numerics.linalg import FixedPattern, same_values

from . import _generated
from .geometry import ReferenceCap

if TYPE_CHECKING:
    from .reference import ShellReference

__all__ = ["ShellEnergy", "HALF_BANDWIDTH", "kernels", "COMPILED", "compiled_rows"]

HALF_BANDWIDTH = 5
"""Half-bandwidth of the Hessian in the interleaved dof ordering."""


def compiled_rows(ndof: dict[str, int]) -> dict[str, int]:
    """Output rows of each kernel the C extension carries: the fast gradient, Hessian and both, per element.

    Parameters
    ----------
    ndof : dict of str to int
        Local dofs of each element (the generated module's ``NDOF``).
    """
    rows = {}
    for name, n in sorted(ndof.items()):
        packed = n * (n + 1) // 2
        rows.update({f"{name}_fast_gradient": n, f"{name}_fast_hessian": packed,
                     f"{name}_fast_gradient_hessian": n + packed})
    return rows


kernels, COMPILED = prefer_compiled(_generated, "contin_models.shell._ckernels", compiled_rows(_generated.NDOF))
"""``kernels``: the element kernels this energy calls: those of :mod:`contin_models.shell._generated`, with
the gradient and Hessian kernels of the C extension ``contin_models.shell._ckernels`` in their place
where it was built (``COMPILED`` is then True; same numbers, about ten times faster at N = 200; see
:mod:`contin.numerics.compiled`).  Public for direct use and for instrumenting them (``studies.bench_floor``
times every call); an energy looks its kernels up here when it is built."""
gen = kernels  # the module's own short name for them

_PARTS = ("stretch", "bend")

_CHUNK = 8192
"""Elements per kernel call.  Longer meshes are processed in blocks of this many elements, each
evaluated and scattered before the next, which bounds the memory of the kernels' temporaries and of
the packed outputs.  (Measured: the time per element is flat for blocks of 4096 elements and more,
up to N = 100000; smaller blocks pay numpy's per-operation overhead more often.)"""


#: Sparsity patterns and scatter slots by mesh size (and block length): they depend on the elements'
#: dofs only (the number of nodes), so a family of shells on one mesh (a fold curve in the thickness or the base
#: angle, a sweep) builds them once.  The slot arrays are shared: nothing writes into them.
_PATTERNS: dict[tuple, tuple] = {}
_PATTERN_CACHE_SIZE = 8


def _edges(x: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Node radii and heights (views) and edge vectors ``x_{i+1} - x_i`` of a state vector."""
    r, z = x[0::2], x[1::2]
    return r, z, r[1:] - r[:-1], z[1:] - z[:-1]


def _read_only(params: tuple) -> tuple:
    """``params`` with every array replaced by a read-only view of it (numbers as they are)."""
    out = []
    for p in params:
        if isinstance(p, np.ndarray):
            p = p.view()
            p.setflags(write=False)
        out.append(p)
    return tuple(out)


def _stretch_local(r, z, er, ez):
    return er, ez, r[:-1] + r[1:]


def _bend_local(r, z, er, ez):
    return er[:-1], ez[:-1], er[1:], ez[1:], r[1:-1]


class _Term:
    """One family of elements: fast kernels, local variables, dof map and fixed arguments.

    The kernels (:mod:`contin_models.shell._generated`, ``<kernels>_fast_*``) take the element's local
    variables, which :attr:`local` computes from the node radii and edge vectors, and return packed
    gradients ``(ndof, m)`` and packed upper-triangle Hessians ``(ndof (ndof + 1) / 2, m)``
    (pairs :attr:`pairs`).
    """

    def __init__(self, kernels: str, dofs: np.ndarray, local, params: tuple) -> None:
        self.energy_fn = getattr(gen, f"{kernels}_fast_energy")
        self.gradient_fn = getattr(gen, f"{kernels}_fast_gradient")
        self.hessian_fn = getattr(gen, f"{kernels}_fast_hessian")
        self.gradient_hessian_fn = getattr(gen, f"{kernels}_fast_gradient_hessian")
        self.dofs = dofs  # (m, ndof) global indices, increasing along each row
        assert np.all(np.diff(dofs, axis=1) > 0)
        self.m, self.ndof = dofs.shape
        self.pairs = np.array(gen.UPPER[kernels])  # (npk, 2) local pairs a <= b of the packed rows
        self.npk = len(self.pairs)
        self.local = local  # (r, z, er, ez) -> tuple of local-variable arrays, each (m,)
        self.params = params


class _Block:
    """A block of consecutive elements of every term, evaluated and scattered together.

    Holds, per term, the element slice and the sliced parameters, and the slots of the packed
    outputs (the terms' outputs one after the other, each ``(rows, elements)`` in C order) in the
    global gradient and in the upper triangle of the global Hessian, relative to the smallest slot
    the block touches (so that each ``bincount`` only spans the block's own range).
    """

    def __init__(self, parts: list[tuple[str, _Term, slice]], slots: tuple[dict, dict, dict]) -> None:
        self.parts = [(name, term, sl, tuple(p[sl] if np.ndim(p) else p for p in term.params))
                      for name, term, sl in parts]
        self.grad, self.hess, self.both = slots

    @classmethod
    def slots(cls, parts: list[tuple[str, _Term, slice]], upper_slot, n: int) -> tuple[dict, dict, dict]:
        """The block's scatter slots of gradients, of Hessians, and of the fused kernels' rows."""
        grad = [(name, t.dofs[sl].T.ravel()) for name, t, sl in parts]
        hess = [(name, upper_slot(t.dofs[sl][:, t.pairs[:, 0]].T.ravel(), t.dofs[sl][:, t.pairs[:, 1]].T.ravel()))
                for name, t, sl in parts]
        # the fused kernels' rows (gradient, then Hessian) into one vector: the gradient, then the
        # Hessian's upper triangle from offset n
        both = [(name, np.concatenate([g, n + h])) for (name, g), (_, h) in zip(grad, hess)]
        return cls._slots(grad), cls._slots(hess), cls._slots(both)

    @staticmethod
    def _slots(per_part: list[tuple[str, np.ndarray]]) -> dict:
        """``{part or None: (slots - lo, lo, hi)}`` for each part alone and for all of them."""
        allslots = np.concatenate([s for _, s in per_part])
        lo, hi = int(allslots.min()), int(allslots.max()) + 1
        out = {name: (s - lo, lo, hi) for name, s in per_part}
        out[None] = (allslots - lo, lo, hi)
        return out

    def arguments(self, local: dict, part: str | None):
        """``(term, local variables, parameters, rows)`` of the block for the selected terms."""
        for name, term, sl, params in self.parts:
            if part is None or part == name:
                yield term, tuple(v[sl] for v in local[name]), params, sl.stop - sl.start


class ShellEnergy:
    """Stretching plus bending energy of a discrete axisymmetric shell about a reference cap.

    Parameters
    ----------
    cap : ReferenceCap or ReferenceMeridian
        The reference (stress-free) configuration, from :func:`contin_models.shell.spherical_cap`
        or any :mod:`contin_models.shell.meridian` constructor (only its ``N``, ``x``,
        ``edge_length``, ``edge_radius``, ``voronoi_length`` and ``node_radius`` are read).
    E : float
        Young's modulus, ``> 0``.
    h : float or array of shape ``(N,)``
        Thickness, ``> 0``: one number, or the thickness of every node (e.g.
        ``ReferenceMeridian.thickness``).  Each edge's stretching stiffness takes the mean of its
        two nodes' thicknesses, each node's bending stiffness its own thickness (``ks ~ h``,
        ``kb ~ h^3``).  A scalar gives exactly the constant-thickness computation (the kernels get
        scalar stiffnesses).
    nu : float
        Poisson's ratio, in ``(-1, 1)`` (``nu = 1/2`` is allowed: the plane-stress constants stay
        finite).
    kappa11_length : {"reference", "current"}
        Length in ``kappa11 = 2 tan(xi/2) / L``: the reference Voronoi length (the paper's
        eq. 3.9 read with a bar) or the current one (the default; see the module docstring).  At the
        reference state both give the same curvature; they differ by terms of order (membrane
        strain) x (curvature).
    reference : ShellReference, optional, keyword only
        The reference data of every element (:class:`contin_models.shell.reference.ShellReference`), in
        place of ``cap``, ``E``, ``h``, ``nu`` and ``kappa11_length``: a structure builds it once with
        its supports and its views share it.  Without it the energy builds its own from the others.

    Attributes
    ----------
    ks, kb : float
        ``E h / (1 - nu^2)`` and ``E h^3 / (12 (1 - nu^2))``.  With a thickness array: the values at
        the pole end, ``ks_edges[-1]`` and ``kb_nodes[-1]`` (what the pole element and the
        point-load normalisation read); elements elsewhere (e.g. a clamped base) should read
        :attr:`kb_nodes` / :attr:`ks_edges` at their own node.
    ks_edges : ndarray, shape ``(N-1,)``
        Stretching stiffness of every edge (constant when ``h`` is a scalar).
    kb_nodes : ndarray, shape ``(N,)``
        Bending stiffness of every node (constant when ``h`` is a scalar).
    h : float or ndarray
        The thickness as given (a read-only copy of an array); :attr:`h_nodes` is always an array.
    reference : ShellReference
        The reference data the energy evaluates against (the same object as the structure's).

    Notes
    -----
    Energies are in units of ``E R^3`` times a length ratio; gradients and Hessians are with
    respect to the interleaved state ``[r_0, z_0, r_1, z_1, ...]``.  No boundary conditions and no
    pole treatment (see the module docstring).
    """

    def __init__(self, cap: ReferenceCap | None = None, E: float | None = None, h: float | np.ndarray | None = None,
                 nu: float | None = None, kappa11_length: Literal["reference", "current"] = "current", *,
                 reference: ShellReference | None = None) -> None:
        if reference is None:
            if cap is None or E is None or h is None or nu is None:
                raise TypeError("ShellEnergy: give cap, E, h and nu, or a reference")
            # the structures build their table with their supports; alone, the energy builds its own
            from .reference import ShellReference
            reference = ShellReference.build(cap, E, nu, h, kappa11_length)
        elif not (cap is None and E is None and h is None and nu is None):
            raise TypeError("ShellEnergy: give either cap, E, h and nu or a reference, not both")
        #: The reference data of every element (:class:`contin_models.shell.reference.ShellReference`).
        self.reference = ref = reference
        self.cap = ref.meridian
        self.E, self.h, self.nu = ref.E, ref.h, ref.nu
        self.kappa11_length = ref.kappa11_length
        N = ref.N
        self.n = 2 * N
        self.bend_nodes = ref.bend.nodes  # base and pole skipped (see module docstring)
        self.ks, self.kb = ref.ks, ref.kb
        self.h_nodes, self.ks_edges, self.kb_nodes = ref.h_nodes, ref.ks_edges, ref.kb_nodes

        edges = np.arange(N - 1)
        s_dofs = 2 * edges[:, None] + np.arange(4)[None, :]
        st = ref.stretch
        stretch = _Term("stretch", s_dofs, _stretch_local, (st.lbar, st.rbar, st.ks, ref.nu))

        b_dofs = 2 * (self.bend_nodes[:, None] - 1) + np.arange(6)[None, :]
        b = ref.bend
        self._curv_fn = getattr(gen, f"{b.kernels}_fast_curvatures")
        self._curv_params = (b.lbar, b.rbar, 0.0, 0.0, b.kb, ref.nu)
        self.kappa11_bar, self.kappa22_bar = b.k11bar, b.k22bar
        bend = _Term(b.kernels, b_dofs, _bend_local, (b.lbar, b.rbar, b.k11bar, b.k22bar, b.kb, ref.nu))
        self._terms = {"stretch": stretch, "bend": bend}  # the order of the packed outputs
        self._build_pattern()
        # gradient and Hessian in one pass (see gradient()): the state of the last full gradient,
        # its Hessian's upper triangle when it was computed with it, and whether a Hessian was
        # asked for at that state
        self._pair_state: np.ndarray | None = None
        self._pair_upper: np.ndarray | None = None
        self._pair_wanted = False

    # ---- sparsity pattern and blocks ------------------------------------------------------------
    def _build_pattern(self) -> None:
        """CSR pattern of the full Hessian, and the element blocks with their scatter slots.

        The element Hessians are scattered into the upper triangle only (one ``bincount`` per
        block over all terms); the full CSR data is a gather of it, so the result is exactly
        symmetric.
        """
        n = self.n
        terms = self._terms
        m = max(t.m for t in terms.values())
        parts = [[(name, t, slice(lo, min(lo + _CHUNK, t.m))) for name, t in terms.items() if lo < t.m]
                 for lo in range(0, m, _CHUNK)]
        key = (n, _CHUNK, tuple((name, t.dofs.shape, t.npk) for name, t in terms.items()))
        if key not in _PATTERNS:
            keys = [t.dofs[:, t.pairs[:, 0]].ravel() * n + t.dofs[:, t.pairs[:, 1]].ravel() for t in terms.values()]
            upper = np.unique(np.concatenate(keys))
            ui, uj = np.divmod(upper, n)
            full = np.unique(np.concatenate([ui * n + uj, uj * n + ui]))
            rows, cols = np.divmod(full, n)
            pattern = FixedPattern(cols.astype(np.int32),
                                   np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n))]).astype(np.int32),
                                   (n, n))

            def upper_slot(i, j):
                return np.searchsorted(upper, i * n + j)

            full_from_upper = np.searchsorted(upper, np.minimum(rows, cols) * n + np.maximum(rows, cols))
            _PATTERNS[key] = (upper.size, full_from_upper, pattern, [_Block.slots(p, upper_slot, n) for p in parts])
            while len(_PATTERNS) > _PATTERN_CACHE_SIZE:
                del _PATTERNS[next(iter(_PATTERNS))]
        self._n_upper, self._full_from_upper, self._pattern, slots = _PATTERNS[key]
        self._nnz = self._pattern.nnz
        self._blocks = [_Block(p, sl) for p, sl in zip(parts, slots, strict=True)]

    def _local(self, x: np.ndarray, part: str | None) -> dict:
        geo = _edges(self._check(x))
        return {name: t.local(*geo) for name, t in self._terms.items() if part is None or part == name}

    def _scatter(self, x: np.ndarray, part: str | None, kind: str, size: int) -> np.ndarray:
        """Evaluate the packed gradients or Hessians block by block and sum them into slots."""
        local = self._local(x, part)
        out = np.zeros(size)
        buf = None
        for block in self._blocks:
            if part not in getattr(block, kind):  # the selected term has no element in this block
                continue
            slots, lo, hi = getattr(block, kind)[part]
            if buf is None or buf.size < slots.size:
                buf = np.empty(slots.size)
            start = 0
            for term, loc, params, k in block.arguments(local, part):
                rows, fn = {"grad": (term.ndof, term.gradient_fn), "hess": (term.npk, term.hessian_fn),
                            "both": (term.ndof + term.npk, term.gradient_hessian_fn)}[kind]
                fn(*loc, *params, out=buf[start:start + rows * k].reshape(rows, k))
                start += rows * k
            if len(self._blocks) == 1 and lo == 0 and hi == size:
                return np.bincount(slots, weights=buf[:start], minlength=size)
            out[lo:hi] += np.bincount(slots, weights=buf[:start], minlength=hi - lo)
        return out

    # ---- public interface ------------------------------------------------------------------------
    @property
    def stretch_parameters(self) -> tuple:
        """The stretching kernels' fixed arguments ``(lbar, rbar, ks, nu)``, the ones the energy uses.

        ``lbar`` and ``rbar`` are the reference length and mid-radius of every edge ``(N-1,)``; ``ks`` is a
        number for a constant thickness, else :attr:`ks_edges`.  The arrays are read-only views.
        """
        return _read_only(self._terms["stretch"].params)

    @property
    def bend_parameters(self) -> tuple:
        """The bending kernels' fixed arguments ``(lbar, rbar, k11bar, k22bar, kb, nu)``, the ones the energy uses.

        Per interior node of :attr:`bend_nodes`: the reference Voronoi length and radius, the reference
        curvatures (:attr:`kappa11_bar`, :attr:`kappa22_bar`, computed by the energy's own kernel), and
        ``kb`` (a number for a constant thickness, else the nodes' :attr:`kb_nodes`).  The arrays are
        read-only views.
        """
        return _read_only(self._terms["bend"].params)

    @property
    def reference_state(self) -> np.ndarray:
        """The reference state vector (a new array)."""
        return self.cap.x

    def _check(self, x: np.ndarray) -> np.ndarray:
        x = np.asarray(x, dtype=float)
        if x.shape != (self.n,):
            raise ValueError(f"state vector must have shape ({self.n},), got {x.shape}")
        return x

    @staticmethod
    def _check_part(part: str | None, optional: bool = True) -> None:
        if not ((optional and part is None) or part in _PARTS):
            allowed = f"{_PARTS} or None" if optional else f"{_PARTS}"
            raise ValueError(f"part must be one of {allowed}, got {part!r}")

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
        self._check_part(part, optional=False)
        local = self._local(x, part)
        out = np.empty(self._terms[part].m)
        lo = 0
        for block in self._blocks:
            for term, loc, params, k in block.arguments(local, part):
                out[lo:lo + k] = term.energy_fn(*loc, *params)
                lo += k
        return out

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
        self._check_part(part)
        local = self._local(x, part)
        return float(sum(term.energy_fn(*loc, *params).sum()
                         for block in self._blocks for term, loc, params, _ in block.arguments(local, part)))

    def gradient(self, x: np.ndarray, part: Literal["stretch", "bend"] | None = None) -> np.ndarray:
        """Exact gradient of :meth:`energy`, with the same parameters ``x`` and ``part``.

        Returns
        -------
        ndarray, shape ``(2 N,)``
        """
        self._check_part(part)
        if part is not None:
            return self._scatter(x, part, "grad", self.n)
        # A solver asks for the Hessian at almost every state whose gradient it asked for (Newton's
        # residual, then its Jacobian); the fused kernels give both for about the Hessian's cost
        # (measured at N = 200, bending and stretching: 0.16 ms against 0.06 + 0.15 ms, plus the
        # geometry and the scatter done twice).
        # They run when the previous full gradient was followed by a Hessian at its state, so that
        # a gradient-only caller (a line search, relaxation) pays for at most one unused Hessian.
        x = self._check(x)
        fuse, self._pair_wanted = self._pair_wanted, False
        self._pair_state = x.copy()
        if not fuse:
            self._pair_upper = None
            return self._scatter(x, None, "grad", self.n)
        both = self._scatter(x, None, "both", self.n + self._n_upper)
        self._pair_upper = both[self.n:]
        return both[:self.n]

    def hessian(self, x: np.ndarray, part: Literal["stretch", "bend"] | None = None) -> sp.csr_matrix:
        """Exact Hessian of :meth:`energy` (same parameters ``x`` and ``part``) in a fixed banded CSR pattern.

        Returns
        -------
        scipy.sparse.csr_matrix, shape ``(2 N, 2 N)``
            Symmetric, banded with half-bandwidth :data:`HALF_BANDWIDTH`; the sparsity pattern is
            the same for every ``x`` and ``part`` (entries of an omitted part are stored zeros).
        """
        self._check_part(part)
        upper = None
        if part is None and self._pair_state is not None and same_values(x, self._pair_state):
            self._pair_wanted = True
            upper = self._pair_upper
        if upper is None:
            upper = self._scatter(x, part, "hess", self._n_upper)
        data = upper.take(self._full_from_upper)
        return self._pattern.matrix(data)

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
        cap = self.cap
        return gen.stretch_fast_strains(*_stretch_local(*_edges(self._check(x))), cap.edge_length,
                                        cap.edge_radius, self.ks, self.nu)

    def curvatures(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Discrete curvatures of the state vector ``x`` (as in :meth:`strains`) at the bending nodes.

        The bending nodes are :attr:`bend_nodes` (``1 .. N-2``).

        Returns
        -------
        kappa11, kappa22 : ndarray, shape ``(N-2,)``
            Meridional ``2 tan(xi/2) / L`` and circumferential ``n_r / r`` curvatures (not the
            changes: subtract :attr:`kappa11_bar`, :attr:`kappa22_bar` for those).
        """
        return self._curv_fn(*_bend_local(*_edges(self._check(x))), *self._curv_params)

    def __repr__(self) -> str:
        c = self.cap
        h = self.h if np.ndim(self.h) == 0 else f"array[{c.N}] in [{self.h.min()}, {self.h.max()}]"
        return (f"ShellEnergy(R={getattr(c, 'R', None)}, phi_hat={getattr(c, 'phi_hat', None)}, N={c.N}, E={self.E}, h={h}, "
                f"nu={self.nu}, kappa11_length={self.kappa11_length!r})")
