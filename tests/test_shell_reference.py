"""The shell's one table of reference data (:mod:`contin_models.shell.reference`).

Every view reads the same :class:`ShellReference`: the structure's energy and harmonic blocks, and the
paper's point-load problem in both controls; its arrays cannot be written; its reference curvatures are
the energy's own at the reference state; and its docstrings name every field it has.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from contin_models.shell import ShellEnergy, ShellPointLoad
from contin_models.shell.geometry import spherical_cap
from contin_models.shell.harmonic import HarmonicShell
from contin_models.shell.meridian import spherical_cap_meridian
from contin_models.shell.reference import (BendReference, EdgeReference, PoleReference, ShellReference,
                                           StretchReference)
from contin_models.shell.structure import ShellStructure

E, NU, H = 1e6, 0.5, 0.02


def _paper_structure(N: int = 40, variant: str = "current") -> ShellStructure:
    return ShellStructure(spherical_cap(1.0, 0.8, N), E, NU, H, "sliding", kappa11_length=variant, edge_bending="none")


def _arrays(ref: ShellReference) -> dict[str, np.ndarray]:
    """Every array of a table, by a dotted name."""
    out = {name: getattr(ref, name) for name in ("h_nodes", "ks_edges", "kb_nodes", "fixed", "free")}
    for part in ("stretch", "bend"):
        table = getattr(ref, part)
        for f in dataclasses.fields(table):
            value = getattr(table, f.name)
            if isinstance(value, np.ndarray):
                out[f"{part}.{f.name}"] = value
    for k, pole in enumerate(ref.poles):
        out[f"poles[{k}].dofs"] = pole.dofs
    return out


@pytest.mark.parametrize("boundary", ["sliding", "clamped", "pinned"])
def test_the_structure_and_its_views_share_one_table(boundary: str) -> None:
    st = ShellStructure(spherical_cap(1.0, 0.8, 30), E, NU, H, boundary)
    ref = st.reference
    assert st.shell.reference is ref
    hs = HarmonicShell(st)
    assert hs.reference is ref
    # the harmonic view's parameters are the table's arrays, not copies of them
    assert hs.s_lbar is ref.stretch.lbar and hs.s_rbar is ref.stretch.rbar and hs.s_ks is ref.ks_edges
    assert hs.b_k11 is ref.bend.k11bar and hs.b_k22 is ref.bend.k22bar and hs.b_nodes is ref.bend.nodes
    assert [element for element, _ in st.pole_elements] == [p.element for p in ref.poles]
    assert st.edge_element is (None if ref.edge is None else ref.edge.element)
    assert ref.edge is not None and ref.edge.kind == ("clamped" if boundary == "clamped" else "moment_free")


def test_the_arrays_are_read_only() -> None:
    for h in (H, np.linspace(0.01, 0.03, 30)):
        ref = ShellStructure(spherical_cap(1.0, 0.8, 30), E, NU, h, "clamped").reference
        arrays = _arrays(ref)
        assert {"stretch.lbar", "stretch.rbar", "bend.k11bar", "bend.k22bar", "poles[0].dofs"} <= set(arrays)
        for name, a in arrays.items():
            with pytest.raises(ValueError, match="read-only"):
                a[0] = a[0]
            assert not a.flags.writeable, name
        with pytest.raises(dataclasses.FrozenInstanceError):
            ref.stretch.lbar = ref.stretch.lbar


@pytest.mark.parametrize("variant", ["current", "reference"])
@pytest.mark.parametrize("control", ["displacement", "force"])
def test_the_paper_models_table_equals_the_structures(variant: str, control: str) -> None:
    paper = ShellPointLoad(1.0, E, NU, H, 0.8, 40, control, kappa11_length=variant)
    ref, expected = paper.reference, _paper_structure(40, variant).reference
    assert paper.shell.reference is ref
    if control == "force":  # the twin lends its table: one table for both problems
        assert ref is paper.twin.reference
    arrays, expected_arrays = _arrays(ref), _arrays(expected)
    assert arrays.keys() == expected_arrays.keys()
    for name in arrays:
        assert np.array_equal(arrays[name], expected_arrays[name]), name
    for name in ("E", "nu", "h", "ks", "kb", "kappa11_length", "boundary", "axis_nodes", "rigid_fix"):
        assert getattr(ref, name) == getattr(expected, name), name
    (pole,), (expected_pole,) = ref.poles, expected.poles
    for name in ("node", "neighbour", "north", "a_bar", "b_bar", "lbar", "kb", "kappa_bar"):
        assert getattr(pole, name) == getattr(expected_pole, name), name
    assert paper.pole_element is pole.element
    assert pole.element.K == expected_pole.element.K
    assert ref.edge is None and expected.edge is None


def test_the_paper_models_skipped_pole_has_no_element() -> None:
    ref = ShellPointLoad(1.0, E, NU, H, 0.8, 40, pole="skip").reference
    assert ref.poles == () and ref.axis_nodes == (39,)


@pytest.mark.parametrize("variant", ["current", "reference"])
def test_the_reference_curvatures_are_the_energys_at_the_reference_state(variant: str) -> None:
    for meridian in (spherical_cap(1.0, 0.8, 37), spherical_cap_meridian(1.0, 0.8, 37)):
        shell = ShellStructure(meridian, E, NU, H, kappa11_length=variant).shell
        k11, k22 = shell.curvatures(meridian.x)
        assert np.array_equal(k11, shell.reference.bend.k11bar)
        assert np.array_equal(k22, shell.reference.bend.k22bar)
        assert shell.reference.bend.kernels == ("bend_cur" if variant == "current" else "bend")


def test_the_stiffnesses_are_numbers_for_a_constant_thickness() -> None:
    cap = spherical_cap(1.0, 0.8, 30)
    ref = ShellStructure(cap, E, NU, H).reference
    assert isinstance(ref.stretch.ks, float) and isinstance(ref.bend.kb, float)
    assert ref.stretch.ks == ref.ks == E * H / (1 - NU**2)
    thick = np.linspace(0.01, 0.03, cap.N)
    ref = ShellStructure(cap, E, NU, thick).reference
    assert ref.stretch.ks.shape == (cap.N - 1,) and ref.bend.kb.shape == (cap.N - 2,)
    assert np.array_equal(ref.bend.kb, ref.kb_nodes[1:-1])


def test_the_energy_alone_builds_a_table_without_supports() -> None:
    cap = spherical_cap(1.0, 0.8, 30)
    ref = ShellEnergy(cap, E, H, NU).reference
    assert ref.boundary is None and ref.poles == () and ref.edge is None and ref.fixed.size == 0
    with pytest.raises(TypeError, match="not both"):
        ShellEnergy(cap, E, H, NU, reference=ref)
    with pytest.raises(TypeError, match="ShellReference.build"):
        ShellReference()


def _documented(doc: str) -> set[str]:
    """The names an ``Attributes`` section of a numpy-style docstring describes."""
    section = doc.split("Attributes\n", 1)[1]
    names = set()
    for line in section.splitlines():
        m = re.match(r"^    (\w+(?:, \w+)*) :", line)
        if m:
            names.update(n.strip() for n in m.group(1).split(","))
    return names


def test_every_field_is_documented() -> None:
    for table in (StretchReference, BendReference, PoleReference, EdgeReference):
        fields = {f.name for f in dataclasses.fields(table)}
        assert fields <= _documented(table.__doc__), table.__name__
    ref = ShellStructure(spherical_cap(1.0, 0.8, 30), E, NU, H, "clamped").reference
    public = {name for name in vars(ref) if not name.startswith("_")}
    assert public <= _documented(ShellReference.__doc__)
