"""Symmetry groups of the benchmark models, given as generators acting linearly on the state.

A model with a symmetry group ``G`` exposes ``symmetry_generators``: a tuple of sparse ``n x n``
matrices ``g`` with ``E(g u, p) = E(u, p)`` for every state ``u`` and load ``p``.  Then
``g^T f(g u, p) = f(u, p)`` and ``g^T J(g u, p) g = J(u, p)``; every generator here is orthogonal
(a permutation of the unknowns, some of them with a change of sign, or a rotation), so that ``J``
commutes with ``g`` at every state that ``g`` fixes, and ``g`` maps equilibria to equilibria.  The
engine does not read them yet; they are data for the tests and for a later symmetry-aware engine.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

__all__ = ["signed_permutation", "group_closure_size"]


def signed_permutation(source: Sequence[int] | np.ndarray, signs: Sequence[float] | np.ndarray | None = None
                       ) -> sp.csr_matrix:
    """The matrix ``g`` with ``(g u)[i] = signs[i] * u[source[i]]``.

    Parameters
    ----------
    source : sequence of int
        A permutation of ``0 .. n-1``: entry ``i`` of the image is taken from entry ``source[i]``.
    signs : sequence of float, optional
        ``+1`` or ``-1`` per entry of the image (default all ``+1``).

    Returns
    -------
    scipy.sparse.csr_matrix
        The orthogonal ``n x n`` matrix.
    """
    source = np.asarray(source, dtype=np.int64)
    n = source.size
    if not np.array_equal(np.sort(source), np.arange(n)):
        raise ValueError("signed_permutation: source must be a permutation of 0 .. n-1")
    values = np.ones(n) if signs is None else np.asarray(signs, dtype=float)
    if values.shape != (n,) or not np.all(np.abs(values) == 1.0):
        raise ValueError("signed_permutation: signs must be n values, each +1 or -1")
    return sp.csr_matrix((values, (np.arange(n), source)), shape=(n, n))


def group_closure_size(generators: Sequence[sp.spmatrix | np.ndarray], limit: int = 10_000) -> int:
    """The order of the group the generators generate (by closure on dense copies; small groups only).

    Parameters
    ----------
    generators : sequence of matrices
        Orthogonal generators.
    limit : int
        Stop and raise once the group has more elements than this.

    Returns
    -------
    int
        The number of distinct group elements, the identity included.
    """
    dense = [np.asarray(g.toarray() if sp.issparse(g) else g, dtype=float) for g in generators]
    n = dense[0].shape[0]

    def key(m: np.ndarray) -> bytes:
        return (np.round(m, 8) + 0.0).tobytes()  # + 0.0: -0.0 and 0.0 are one entry

    elements = {key(np.eye(n)): np.eye(n)}
    frontier = [np.eye(n)]
    while frontier:
        fresh = []
        for m in frontier:
            for g in dense:
                product = g @ m
                k = key(product)
                if k not in elements:
                    elements[k] = product
                    fresh.append(product)
                    if len(elements) > limit:
                        raise ValueError(f"group_closure_size: more than {limit} elements")
        frontier = fresh
    return len(elements)
