"""Record every number the shell's views compute at one deformed state per case (``tests/data/shell_views.npz``).

The shell's energy is computed by several views of one definition: the traced axisymmetric energy
(:class:`contin_models.shell.ShellPointLoad`, :class:`contin_models.shell.structure.ShellStructure`), the
harmonic blocks per wave number (:class:`contin_models.shell.harmonic.HarmonicShell`) and the ring mesh
(:func:`contin_models.shell.harmonic.ring_mesh_block`).  A refactoring of how they are built must not move
any of their numbers; ``tests/test_shell_views_unchanged.py`` recomputes :func:`shell_views` and compares
it with the file: bit for bit with the numpy kernels (``CONTIN_COMPILED=0``), to roundoff with the C ones.

``CONTIN_COMPILED=0 python -m tests.regression.capture_shell_views`` writes the file.  It was written
before the refactoring of the shell's modules began, and is not to be regenerated to make a test pass.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

#: The file the numbers are kept in.
DATA = Path(__file__).resolve().parents[1] / "data" / "shell_views.npz"
#: Nodes of every mesh (small: the file stays small and the test fast).
N = 30
#: Wave numbers of the harmonic blocks.
WAVE_NUMBERS = (0, 1, 2, 7)
#: Nodes and sectors of the ring mesh (its Hessian is dense in the ``3 N`` mode amplitudes: a smaller mesh).
RING_NODES, RING_SECTORS = 8, 6


def deformed(x_ref: np.ndarray) -> np.ndarray:
    """A fixed non-reference axisymmetric state near ``x_ref``: radii scaled by a few per mille (a pole
    stays on the axis), heights lowered most at the top (a dimple of 3 % of the height)."""
    x = np.array(x_ref, dtype=float)
    s = np.linspace(0.0, 1.0, x.size // 2)
    x[0::2] *= 1.0 + 0.004 * np.sin(3.0 * np.pi * s)
    z = x[1::2]
    x[1::2] = z - 0.03 * (z - z.min()) * s ** 2
    return x


def _sparse(out: dict, key: str, H) -> None:
    H = H.tocsr()
    out[f"{key}/data"], out[f"{key}/indices"], out[f"{key}/indptr"] = H.data, H.indices, H.indptr


def _point_load(out: dict, name: str, pole: str) -> None:
    """The paper's model: the cap under a point force at the pole, with its own pole treatment."""
    from contin_models.shell import ShellPointLoad

    prob = ShellPointLoad(N=N, pole=pole)
    x = deformed(prob.cap.x)
    out[f"{name}/energy"] = np.array([prob.elastic_energy(x)])
    out[f"{name}/gradient"] = prob.elastic_gradient(x)
    _sparse(out, f"{name}/hessian", prob.elastic_hessian(x))


def _structure(out: dict, name: str, st, pressure: float = 0.0, jets: bool = False, ring: bool = False) -> None:
    """A structure's traced energy, gradient, Hessian, its harmonic blocks and (``ring``) the ring mesh's."""
    from contin_models.shell.harmonic import HarmonicShell
    from contin_models.shell.ring_mesh import ring_mesh_block
    from contin_models.shell.volume import enclosed_volume, volume_gradient, volume_hessian

    x = deformed(st.meridian.x)
    out[f"{name}/energy"] = np.array([st.energy(x)])
    out[f"{name}/gradient"] = st.gradient(x)
    _sparse(out, f"{name}/hessian", st.hessian(x))
    hs = HarmonicShell(st)
    if pressure:
        out[f"{name}/volume"] = np.array([enclosed_volume(x, hs.z_ref)])
        out[f"{name}/volume_gradient"] = volume_gradient(x, hs.z_ref)
        _sparse(out, f"{name}/volume_hessian", volume_hessian(x, hs.z_ref))
    for n in WAVE_NUMBERS:
        out[f"{name}/band_{n}"] = hs.band_block(x, n).ab
        if pressure:
            out[f"{name}/band_{n}_pressure"] = hs.band_block(x, n, pressure=pressure).ab
    _sparse(out, f"{name}/full_2_reference", hs.full_block(x, 2, pressure, reference=True))
    if jets:
        hj = HarmonicShell(st, method="jets")
        for n in (0, 2):
            out[f"{name}/band_{n}_jets"] = hj.band_block(x, n, pressure=pressure).ab
    if ring:
        out[f"{name}/ring_2"] = ring_mesh_block(hs, x, 2, RING_SECTORS, pressure=pressure)


def shell_views() -> dict[str, np.ndarray]:
    """Every recorded number, by ``case/quantity`` (a sparse matrix as its CSR ``data``, ``indices``, ``indptr``).

    Cases: the paper's point-load model with the mirror pole (its default) and with the pole skipped; the
    paper's structure (sliding base, no edge element); a clamped cap (blocks under pressure too, and by
    the jets); a pinned cap (its moment-free edge element), and a coarse one under pressure with the ring
    mesh; a complete sphere under pressure (two poles, free, the enclosed volume); a cap whose thickness
    varies along the meridian, with the reference length in ``kappa11``.
    """
    from contin_models.shell.geometry import spherical_cap
    from contin_models.shell.meridian import complete_sphere_meridian
    from contin_models.shell.structure import ShellStructure

    E, nu, h = 1e6, 0.5, 0.02
    cap = spherical_cap(1.0, 0.8, N)
    out: dict[str, np.ndarray] = {}
    _point_load(out, "paper_mirror", "mirror")
    _point_load(out, "paper_skip", "skip")
    _structure(out, "paper_structure", ShellStructure(cap, E, nu, h, boundary="sliding", edge_bending="none"))
    _structure(out, "clamped", ShellStructure(cap, E, 0.3, h, boundary="clamped"), pressure=0.7, jets=True)
    _structure(out, "pinned", ShellStructure(cap, E, nu, h, boundary="pinned"))
    _structure(out, "pinned_ring", ShellStructure(spherical_cap(1.0, 0.8, RING_NODES), E, nu, h, boundary="pinned"),
               pressure=0.7, ring=True)
    _structure(out, "sphere", ShellStructure(complete_sphere_meridian(1.0, N), E, 0.3, h, boundary="free"),
               pressure=0.7)
    thickness = h * (1.0 + 0.5 * np.linspace(0.0, 1.0, N))
    _structure(out, "variable_h", ShellStructure(cap, E, nu, thickness, boundary="sliding",
                                                 kappa11_length="reference"))
    return out


def differences(views: dict[str, np.ndarray], reference, rtol: float = 0.0) -> list[str]:
    """The quantities of ``views`` that differ from ``reference``, one line each (empty: none differs).

    Parameters
    ----------
    views : dict of str to ndarray
        :func:`shell_views` as computed now.
    reference : mapping of str to ndarray
        The recorded numbers (:data:`DATA` loaded).
    rtol : float
        0: every array must be bitwise equal.  Otherwise a float array may differ by ``rtol`` times its
        largest entry (the C kernels round differently from numpy in the last bits); integer arrays
        (sparsity patterns) and shapes must still be equal.
    """
    out = [f"{key}: missing" for key in sorted(set(reference) - set(views))]
    out += [f"{key}: not recorded" for key in sorted(set(views) - set(reference))]
    for key in sorted(set(views) & set(reference)):
        got, want = np.asarray(views[key]), np.asarray(reference[key])
        if got.shape != want.shape or got.dtype.kind != want.dtype.kind:
            out.append(f"{key}: shape {got.shape} {got.dtype}, recorded {want.shape} {want.dtype}")
        elif rtol == 0.0 or want.dtype.kind != "f":
            if not np.array_equal(got, want):
                out.append(f"{key}: {np.count_nonzero(got != want)} of {want.size} entries differ")
        else:
            scale = np.max(np.abs(want), initial=0.0)
            err = np.max(np.abs(got - want), initial=0.0)
            if not err <= rtol * scale:
                out.append(f"{key}: differs by {err:.3e}, {err / scale if scale else np.inf:.3e} of its largest entry")
    return out


def main() -> int:
    from contin.numerics.compiled import compiled_enabled

    if compiled_enabled():
        print("run with CONTIN_COMPILED=0: the file holds the numpy kernels' numbers", file=sys.stderr)
        return 2
    views = shell_views()
    np.savez_compressed(DATA, **views)
    print(f"wrote {DATA} ({len(views)} arrays, {DATA.stat().st_size} bytes)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
