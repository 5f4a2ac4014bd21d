"""General reference meridians (contin_models.shell.meridian): geometry of every segment type, node
placement, the stress-free reference state, volumes, imperfections and input validation."""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.special import ellipeinc

from contin_models.shell import (Cone, EllipseArc, ReferenceMeridian, ShellEnergy, SphericalArc, TableProfile,
                                 TorusArc, annulus_meridian, complete_sphere_meridian, cone_meridian,
                                 ellipsoid_cap_meridian, meridian, plate_meridian, spherical_cap,
                                 spherical_cap_meridian, table_meridian, torus_meridian, with_dimple, with_mode)
from contin_models.shell.meridian import dimple_width
from contin_models.shell.volume import enclosed_volume

CAP_FIELDS = ("r", "z", "theta", "edge_length", "edge_radius", "voronoi_length", "node_radius", "kappa11", "kappa22")


def cone_on_cap(N=41, pole_ratio=1.0, **kw):
    """A cone (r 1.3 -> cos 0.7) meeting a unit spherical cap at a corner."""
    phi = 0.7
    return meridian([Cone(1.3, 0.4, math.cos(phi), math.sin(phi)), SphericalArc(1.0, phi, math.pi / 2)], N,
                    pole_ratio, **kw)


def smooth_chain(N=61):
    """Cone, torus arc and spherical cap joined with continuous tangents (no corner)."""
    R, phi, a = 1.0, 0.9, 0.2
    # spherical cap from phi to the pole; a torus arc of radius a tangent to it at phi, centred on
    # the sphere's radius through the junction; a cone tangent to the torus at angle phi - 0.4
    c = (R - a) * math.cos(phi), (R - a) * math.sin(phi)
    t0 = phi - 0.4
    p0 = (c[0] + a * math.cos(t0), c[1] + a * math.sin(t0))
    tan = (math.sin(t0), -math.cos(t0))  # backwards along the torus at t0
    start = (p0[0] + 0.3 * tan[0], p0[1] + 0.3 * tan[1])
    return meridian([Cone(*start, *p0), TorusArc(c[0], c[1], a, t0, phi), SphericalArc(R, phi, math.pi / 2)], N)


# ---- the spherical cap ---------------------------------------------------------------------------
@pytest.mark.parametrize("R, phi_hat, N, q", [(1.0, 0.8, 200, 0.5), (2.7, 0.3, 17, 1.0), (1e-3, 1.4, 50, 1 / 3)])
def test_spherical_cap_meridian_is_spherical_cap(R, phi_hat, N, q):
    cap, m = spherical_cap(R, phi_hat, N, q), spherical_cap_meridian(R, phi_hat, N, q)
    for name in CAP_FIELDS:
        np.testing.assert_array_equal(getattr(m, name), getattr(cap, name), err_msg=name)
    assert (m.R, m.phi_hat, m.pole_ratio, m.length_scale) == (R, phi_hat, q, R)
    assert m.end_on_axis and not m.start_on_axis and m.r[-1] == 0.0
    np.testing.assert_allclose(m.s, R * (cap.theta - phi_hat), rtol=1e-15, atol=0)
    np.testing.assert_array_equal(m.x, cap.x)
    # the general builder on one spherical arc gives the same mesh to round-off
    g = meridian([SphericalArc(R, phi_hat, math.pi / 2)], N, q)
    np.testing.assert_allclose(g.r, cap.r, rtol=0, atol=1e-15 * R)
    np.testing.assert_allclose(g.z, cap.z, rtol=0, atol=1e-15 * R)
    assert g.r[-1] == 0.0 and g.z[-1] == R
    # arrays are read-only
    with pytest.raises(ValueError):
        m.r[0] = 1.0


def test_hemisphere_and_beyond():
    m = spherical_cap_meridian(1.0, 0.0, 21, 1.0)
    assert (m.r[0], m.z[0]) == (1.0, 0.0) and m.s[-1] == pytest.approx(math.pi / 2, rel=1e-15)
    deep = spherical_cap_meridian(1.0, -0.5, 21)
    assert deep.z[0] < 0 and np.all(deep.r >= 0)
    with pytest.raises(ValueError, match="phi_hat"):
        spherical_cap(1.0, 0.0, 21)  # unchanged: spherical_cap keeps (0, pi/2)
    with pytest.raises(ValueError, match=r"phi_hat must be in \(-pi/2, pi/2\)"):
        spherical_cap_meridian(1.0, math.pi / 2, 21)


# ---- junctions, corners and arclengths ------------------------------------------------------------
def test_segment_junctions_are_continuous_nodes():
    for m in (cone_on_cap(), smooth_chain()):
        assert m.junction_nodes.size == len(m.segments) - 1
        for k, i in enumerate(m.junction_nodes):
            assert (m.r[i], m.z[i]) == pytest.approx(m.segments[k].end, abs=1e-15)
            assert (m.r[i], m.z[i]) == pytest.approx(m.segments[k + 1].start, abs=1e-12)
            assert m.segment_of_node[i] == k + 1 and m.segment_of_node[i - 1] == k
        # every node on its segment, at its arclength
        S = np.concatenate([[0.0], np.cumsum([sg.length for sg in m.segments])])
        for k, sg in enumerate(m.segments):
            sel = m.segment_of_node == k
            r, z = sg.point(m.s[sel] - S[k])
            np.testing.assert_allclose(r, m.r[sel], atol=1e-14)
            np.testing.assert_allclose(z, m.z[sel], atol=1e-14)
        assert np.all(np.diff(m.s) > 0) and m.s[-1] == pytest.approx(S[-1], rel=1e-14)
        # each segment gets at least 2 edges and edges in proportion to its length
        counts = np.bincount(m.segment_of_node[:-1])
        assert np.all(counts >= 2)
        np.testing.assert_allclose(counts / (m.N - 1), np.diff(S) / S[-1], atol=1.0 / (m.N - 1) + 1e-12)
    assert smooth_chain().corner_nodes.size == 0  # tangent junctions are not corners


def test_cone_on_plate_has_a_corner_node():
    m = meridian([Cone(1.0, 0.0, 0.5, 0.3), Cone(0.5, 0.3, 0.0, 0.3)], 21)
    (i,) = m.corner_nodes
    assert (m.r[i], m.z[i]) == (0.5, 0.3) and i in m.junction_nodes
    # the normal angle: the cone's on its nodes, the plate's (pi/2) after, the bisector at the corner
    cone_theta = math.atan2(0.5, 0.3)
    np.testing.assert_allclose(m.theta[:i], cone_theta, rtol=1e-15)
    np.testing.assert_allclose(m.theta[i + 1:], math.pi / 2, rtol=1e-15)
    assert m.theta[i] == pytest.approx(0.5 * (cone_theta + math.pi / 2), rel=1e-14)
    assert cone_on_cap().corner_nodes.size == 1


def test_arclengths_are_exact_curve_lengths():
    phi = 0.6
    assert spherical_cap_meridian(1.5, phi, 30).s[-1] == pytest.approx(1.5 * (math.pi / 2 - phi), rel=1e-15)
    assert meridian([SphericalArc(1.5, phi, math.pi / 2)], 30, 0.5).s[-1] == pytest.approx(1.5 * (math.pi / 2 - phi), rel=1e-15)
    assert cone_meridian(2.0, 20, height=0.5).s[-1] == pytest.approx(math.hypot(2.0, 0.5), rel=1e-15)
    assert cone_meridian(2.0, 20, half_angle=math.pi / 3).s[-1] == pytest.approx(2.0 / math.sin(math.pi / 3), rel=1e-15)
    assert torus_meridian(2.0, 0.1, 0.7, -1.0, 2.5, 20).s[-1] == pytest.approx(0.7 * 3.5, rel=1e-15)
    a, b, t0 = 1.0, 0.6, 0.2
    # parametric angle t: speed sqrt(a^2 sin^2 + b^2 cos^2) = a sqrt(1 - (1 - b^2/a^2) cos^2 t)
    m = 1 - (b / a) ** 2
    exact = a * (ellipeinc(math.pi / 2 - t0, m))  # substitute u = pi/2 - t
    e = ellipsoid_cap_meridian(a, b, t0, 31)
    assert e.s[-1] == pytest.approx(exact, rel=1e-14)
    assert EllipseArc(0.5, 2.0, -1.2, 0.9).length == pytest.approx(
        quad(lambda t: math.hypot(0.5 * math.sin(t), 2.0 * math.cos(t)), -1.2, 0.9, epsabs=0, epsrel=1e-13)[0], rel=1e-13)
    # nodes on the ellipse at their arclength
    np.testing.assert_allclose((e.r / a) ** 2 + (e.z / b) ** 2, 1.0, rtol=1e-14)
    arc = np.array([quad(lambda t: math.hypot(a * math.sin(t), b * math.cos(t)), t0, math.atan2(zz / b, rr / a),
                         epsabs=1e-14, epsrel=1e-13)[0] for rr, zz in zip(e.r, e.z)])
    np.testing.assert_allclose(arc, e.s, rtol=0, atol=1e-13)
    assert (e.r[-1], e.z[-1], e.length_scale) == (0.0, b, a * a / b)
    # the chords fall short of the curve at second order
    gaps = [spherical_cap_meridian(1.0, phi, n, 1.0).s[-1] - spherical_cap_meridian(1.0, phi, n, 1.0).edge_length.sum()
            for n in (21, 41)]
    assert gaps[0] / gaps[1] == pytest.approx(4.0, rel=0.01)


def test_complete_sphere_is_symmetric_with_both_poles_on_the_axis():
    for N, q in ((81, 0.5), (40, 1.0), (101, 1 / 3)):
        m = complete_sphere_meridian(2.0, N, q)
        assert m.start_on_axis and m.end_on_axis
        assert (m.r[0], m.z[0], m.r[-1], m.z[-1]) == (0.0, -2.0, 0.0, 2.0)
        np.testing.assert_array_equal(m.r, m.r[::-1])
        np.testing.assert_array_equal(m.z, -m.z[::-1])
        np.testing.assert_allclose(np.hypot(m.r, m.z), 2.0, rtol=1e-15)
        np.testing.assert_allclose(m.s + m.s[::-1], 2.0 * math.pi, rtol=1e-15)
        d = m.edge_length
        assert d[0] == pytest.approx(d[-1], rel=1e-14)
        if q < 1:
            assert d[0] / d[N // 2] == pytest.approx(q, rel=0.05)  # graded at both poles
        assert (m.theta[0], m.theta[-1]) == pytest.approx((-math.pi / 2, math.pi / 2), abs=1e-15)


def test_table_meridian_reproduces_a_circle():
    # the table's interpolant is accurate (cubic spline: the error falls faster than 4x per halving)
    def table(n):
        t = np.linspace(0.3, math.pi / 2, n)
        return np.cos(t), np.sin(t)

    pos_err = []
    for n in (10, 20):
        m = table_meridian(*table(n), 41)
        assert m.end_on_axis and (m.r[-1], m.z[-1]) == (0.0, 1.0)
        pos_err.append(np.max(np.abs(np.hypot(m.r, m.z) - 1)))
    assert pos_err[0] < 1e-4 and pos_err[0] / pos_err[1] > 4
    # and the discrete reference curvatures on it are the circle's to O(spacing^2): ratio ~4 when N doubles
    k_err = []
    for N in (21, 41):
        m = table_meridian(*table(200), N)
        k_err.append(np.max(np.abs(m.kappa11[1:-1] - 1)))
        assert np.max(np.abs(m.kappa22[1:-1] - 1)) < 1e-6
    assert k_err[0] / k_err[1] == pytest.approx(4.0, rel=0.05)
    assert m.s[-1] == pytest.approx(math.pi / 2 - 0.3, rel=1e-10)


def test_ring_node_and_refinement():
    ring = 0.5
    m = meridian([SphericalArc(1.0, 0.3, math.pi / 2)], 61, 0.5, ring=ring, ring_ratio=0.4)
    i = m.ring_node
    assert m.s[i] == ring
    r, z = m.segments[0].point(np.array([ring]))
    assert (m.r[i], m.z[i]) == pytest.approx((r[0], z[0]), abs=1e-15)
    d = np.diff(m.s)
    assert d[i - 1] / d[2] == pytest.approx(0.4, rel=0.1) and d[i] / d[2] == pytest.approx(0.4, rel=0.1)
    assert d[-1] / d[2] == pytest.approx(0.5, rel=0.1)


# ---- the reference state is stress free ----------------------------------------------------------
def all_meridians():
    phi = 0.7
    out = {
        "spherical_cap": spherical_cap_meridian(1.0, 0.8, 40),
        "hemisphere": spherical_cap_meridian(1.0, 0.0, 40),
        "complete_sphere": complete_sphere_meridian(1.0, 41),
        "plate": plate_meridian(1.0, 30),
        "annulus": annulus_meridian(1.0, 0.3, 30),
        "cone": cone_meridian(1.0, 30, height=0.4),
        "torus": torus_meridian(1.5, 0.0, 0.5, -1.0, 2.0, 30),
        "ellipsoid": ellipsoid_cap_meridian(1.0, 0.5, 0.1, 40),
        "table": table_meridian(np.cos(np.linspace(0.5, math.pi / 2, 12)), 1.2 * np.sin(np.linspace(0.5, math.pi / 2, 12)), 30),
        "smooth_chain": smooth_chain(),
        "variable_thickness": cone_on_cap(41, 0.5, thickness=lambda s: 0.02 * (1 + 0.5 * np.cos(2 * s))),
        "per_segment_thickness": meridian([Cone(1.3, 0.4, math.cos(phi), math.sin(phi), thickness=0.03),
                                           SphericalArc(1.0, phi, math.pi / 2, thickness=0.01)], 41),
    }
    out["dimpled"] = with_dimple(out["spherical_cap"], 0.02, 0.2)
    return out


@pytest.mark.parametrize("variant", ["reference", "current"])
def test_reference_state_is_stress_free_for_every_meridian(variant):
    E, h, nu = 3.0, 0.02, 0.3
    for name, m in all_meridians().items():
        hh = h if m.thickness is None else m.thickness
        s = ShellEnergy(m, E, hh, nu, kappa11_length=variant)
        x = m.x
        assert abs(s.energy(x)) <= 1e-26 * E * h * m.length_scale**2, name
        assert np.max(np.abs(s.gradient(x))) <= 1e-13 * E * h * m.length_scale, name
        k11, k22 = s.curvatures(x)
        np.testing.assert_allclose(k11, m.kappa11[1:-1], rtol=1e-13, err_msg=name)
        np.testing.assert_allclose(k22, m.kappa22[1:-1], rtol=1e-13, err_msg=name)
        assert np.isnan(m.kappa11[[0, -1]]).all(), name


def test_thickness_per_node():
    ms = all_meridians()
    m = ms["per_segment_thickness"]
    (i,) = m.junction_nodes
    assert np.all(m.thickness[:i] == 0.03) and np.all(m.thickness[i + 1:] == 0.01) and m.thickness[i] == 0.02
    m = ms["variable_thickness"]
    np.testing.assert_allclose(m.thickness, 0.02 * (1 + 0.5 * np.cos(2 * m.s)), rtol=1e-15)
    assert spherical_cap_meridian(1.0, 0.8, 20).thickness is None
    np.testing.assert_array_equal(spherical_cap_meridian(1.0, 0.8, 20, thickness=0.01).thickness, 0.01)
    with pytest.raises(ValueError, match="carry no thickness"):
        meridian([Cone(1.0, 0.0, 0.5, 0.3, thickness=0.01), Cone(0.5, 0.3, 0.0, 0.3)], 21)
    with pytest.raises(ValueError, match="thickness must be positive"):
        plate_meridian(1.0, 21, thickness=lambda s: 0.5 - s)


def test_theta_is_the_normal_angle_of_the_smooth_curve():
    # the unit tangent from base to pole is (-sin theta, cos theta): along the chords of a cone, the
    # polar angle on a spherical cap (checked above), the ellipse's analytic tangent
    m = cone_meridian(1.0, 20, height=0.6)
    t = np.column_stack([-np.sin(m.theta), np.cos(m.theta)])
    chord = np.array([-1.0, 0.6]) / math.hypot(1.0, 0.6)
    np.testing.assert_allclose(t, np.broadcast_to(chord, t.shape), atol=1e-15)
    a, b = 1.0, 0.6
    e = ellipsoid_cap_meridian(a, b, 0.2, 31)
    tp = np.arctan2(e.z / b, e.r / a)  # parametric angle
    ref = np.column_stack([-a * np.sin(tp), b * np.cos(tp)])
    ref /= np.linalg.norm(ref, axis=1)[:, None]
    np.testing.assert_allclose(np.column_stack([-np.sin(e.theta), np.cos(e.theta)]), ref, atol=1e-14)
    nr, nz = e.normals()
    assert (nr[-1], nz[-1]) == pytest.approx((0.0, 1.0), abs=1e-14)


# ---- volumes -------------------------------------------------------------------------------------
def test_enclosed_volumes():
    a, H = 1.3, 0.7
    m = cone_meridian(a, 17, height=H, z_base=0.2)
    assert enclosed_volume(m.x, 0.2) == pytest.approx(math.pi * a * a * H / 3, rel=1e-14)
    R, phi = 1.0, 0.6
    Hc = R * (1 - math.sin(phi))
    exact = math.pi * Hc**2 * (3 * R - Hc) / 3
    err = [exact - enclosed_volume(spherical_cap_meridian(R, phi, n).x, R * math.sin(phi)) for n in (20, 40, 80)]
    assert err[0] > 0 and err[0] < 1e-2 * exact
    np.testing.assert_allclose(np.log2(np.array(err[:-1]) / err[1:]), 2.0, atol=0.1)
    # the complete sphere from pole to pole (z_ref at the south pole: no skirt)
    err = [4 / 3 * math.pi - enclosed_volume(complete_sphere_meridian(1.0, n, 1.0).x, -1.0) for n in (21, 41)]
    assert err[0] / err[1] == pytest.approx(4.0, rel=0.1)


# ---- imperfections -------------------------------------------------------------------------------
def test_dimple():
    m = spherical_cap_meridian(1.0, 0.8, 60)
    d0 = with_dimple(m, 0.0, 0.2)
    for name in CAP_FIELDS + ("s",):
        np.testing.assert_array_equal(getattr(d0, name), getattr(m, name), err_msg=name)
    delta = 0.01
    d = with_dimple(m, delta, lambda_I=2.0, h=0.005, nu=0.3)
    assert isinstance(d, ReferenceMeridian) and d.kind == "spherical_cap+dimple"
    assert d.r[-1] == 0.0 and m.z[-1] - d.z[-1] == pytest.approx(delta, rel=1e-13)
    assert (d.r[0], d.z[0]) == (m.r[0], m.z[0])
    # normal to the sphere: the nodes move radially, by the Gaussian in the polar angle from the pole
    beta0 = dimple_width(2.0, 1.0, 0.005, 0.3)
    beta = math.pi / 2 - m.theta
    w = np.hypot(d.r, d.z) - 1.0
    np.testing.assert_allclose(w[1:], -delta * np.exp(-(beta[1:] / beta0) ** 2), atol=1e-15)
    np.testing.assert_allclose(np.arctan2(d.z[1:-1], d.r[1:-1]), m.theta[1:-1], atol=1e-15)
    assert with_dimple(m, delta, beta0).z[-1] == d.z[-1]
    # recomputed reference quantities: the dimpled shape is the new stress-free state
    assert not np.allclose(d.kappa11, m.kappa11, equal_nan=True)
    s = ShellEnergy(d, 1.0, 0.005, 0.3)
    assert np.max(np.abs(s.gradient(d.x))) == 0.0
    assert with_dimple(m, -delta, beta0).z[-1] == pytest.approx(m.z[-1] + delta, rel=1e-15)
    with pytest.raises(ValueError, match="exactly one of beta0 and lambda_I"):
        with_dimple(m, delta)
    with pytest.raises(ValueError, match="end on the axis"):
        with_dimple(annulus_meridian(1.0, 0.5, 20), delta, 0.2)


def test_mode_imperfection():
    m = spherical_cap_meridian(1.0, 0.8, 40)
    rng = np.random.default_rng(0)
    mode = rng.standard_normal(2 * m.N)
    mode[-2] = 0.0
    out = with_mode(m, mode, 0.01)
    nr, nz = m.normals()
    wn = (out.r - m.r) * nr + (out.z - m.z) * nz
    k = int(np.argmax(np.abs(wn)))
    assert wn[k] == pytest.approx(-0.01, rel=1e-12)
    np.testing.assert_allclose(np.column_stack([out.r - m.r, out.z - m.z]).ravel(), mode * (-0.01 / (mode[2 * k] * nr[k] + mode[2 * k + 1] * nz[k])), atol=1e-15)
    pole = with_mode(m, mode, 0.01, normalize="pole")
    assert m.z[-1] - pole.z[-1] == pytest.approx(0.01, rel=1e-12) and pole.r[-1] == 0.0
    assert with_mode(m, mode, 0.0).z.tobytes() == m.z.tobytes()
    mode[-2] = 1e-3
    with pytest.raises(ValueError, match=r"mode\[78\]"):
        with_mode(m, mode, 0.01)
    with pytest.raises(ValueError, match="shape"):
        with_mode(m, mode[:-2], 0.01)


# ---- validation ----------------------------------------------------------------------------------
def test_bad_input():
    with pytest.raises(ValueError, match="R must be a positive number"):
        SphericalArc(-1.0, 0.2, 1.0)
    with pytest.raises(ValueError, match=r"theta1 must be in \["):
        SphericalArc(1.0, 0.2, 2.0)
    with pytest.raises(ValueError, match="r0 must be >= 0"):
        Cone(-0.1, 0.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="zero-length"):
        Cone(1.0, 0.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="zero-length"):
        SphericalArc(1.0, 0.3, 0.3)
    with pytest.raises(ValueError, match="half plane r >= 0"):
        TorusArc(0.5, 0.0, 1.0, 0.0, math.pi)
    with pytest.raises(ValueError, match="a must be a positive number"):
        EllipseArc(-1.0, 1.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="not monotone"):
        TableProfile([1.0, 0.8, 0.9, 0.5, 0.0], [0.0, 0.1, 0.2, 0.3, 0.4])
    with pytest.raises(ValueError, match="coincide"):
        TableProfile([1.0, 0.8, 0.8, 0.5, 0.0], [0.0, 0.1, 0.1, 0.3, 0.4])
    with pytest.raises(ValueError, match="r must be >= 0"):
        TableProfile([1.0, 0.5, 0.0, -0.5], [0.0, 0.1, 0.2, 0.3])
    with pytest.raises(ValueError, match="segment 1 .* gap"):
        meridian([Cone(1.0, 0.0, 0.5, 0.3), Cone(0.5, 0.31, 0.0, 0.3)], 21)
    with pytest.raises(ValueError, match="N must be an integer >= 5"):
        meridian([Cone(1.0, 0.0, 0.5, 0.3), Cone(0.5, 0.3, 0.0, 0.3)], 4)
    with pytest.raises(ValueError, match="reverse the segments"):
        meridian([Cone(0.0, 0.0, 1.0, 0.0)], 10)
    with pytest.raises(ValueError, match="pole_ratio must be in"):
        plate_meridian(1.0, 10, 0.0)
    with pytest.raises(ValueError, match="a must be a positive number"):
        plate_meridian(-1.0, 10)
    with pytest.raises(ValueError, match="ring must be an arclength"):
        meridian([Cone(1.0, 0.0, 0.0, 0.0)], 10, ring=2.0)
    with pytest.raises(ValueError, match="exactly one of height and half_angle"):
        cone_meridian(1.0, 10)
    with pytest.raises(ValueError, match="a_inner"):
        annulus_meridian(1.0, 1.5, 10)
