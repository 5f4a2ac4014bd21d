/* The contact barrier's per-state work in C for contin_models.contact.barrier (built by setup.py as
   contin_models.contact._cbarrier; optional: the barrier runs the same steps in numpy where it is
   not built, and tests/test_contact_compiled.py checks that the two agree).

   support: the fixed sample points of every cell (their distances checked and reduced to each cell's
   gap) and the points of the barrier integral on the pieces of the cells within dhat of the
   indenter, as ContactBarrier._checked_samples, ._integration_points and ._points_within compute
   them (the module docstring of barrier.py, "Contact on the barrier's support").  The steps are the
   numpy code's, element by element in the same order: the gap polynomial of each cell, its monotone
   pieces between the critical points, the roots that end the support refined by Newton's method
   inside their brackets, Gauss-Legendre points on each piece.  One difference: numpy stops the
   Newton iteration of all roots together when the largest update falls to 1e-14, C each root when
   its own does (the roots agree to that tolerance; an error eps in a root moves the energy by
   O(eps^4)).

   assemble: the chain rule from the point kernels' derivatives to the cells' energies, forces,
   gradient, 6x6 Hessian blocks and the d2E/dx dc border, as ContactBarrier.evaluate sums them.

   safe_fraction: the step filter of ContactBarrier.max_safe_fraction over every fixed sample.

   A cell i >= 1 is the quadratic B-spline piece on the nodes i-1, i, i+1; the pole's (i = N-1) third
   node is the mirror image (-r_{N-2}, z_{N-2}); the base cell 0 is the node itself.  Indenters:
   plate != 0 is a plate at height c (d = c - z), otherwise a sphere of radius rho centred at (0, c)
   (d = sqrt(r^2 + (z - c)^2) - rho). */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

/* ---- arguments -------------------------------------------------------------------------------- */

/* A C-contiguous buffer of float64 ('d') or int64 ('q') values, writable or not, of `size` values
   (any size when size < 0); TypeError otherwise. */
static int buffer_of(PyObject *obj, Py_buffer *view, int writable, char format, Py_ssize_t size, const char *what) {
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s: not a C-contiguous%s array", what, writable ? " writable" : "");
        return -1;
    }
    const char *f = view->format;
    if (f != NULL && (f[0] == '<' || f[0] == '=' || f[0] == '@')) f++;
    int format_ok = f != NULL && view->itemsize == 8 &&
                    (f[0] == format || (format == 'q' && f[0] == 'l')) && f[1] == '\0';
    if (!format_ok || (size >= 0 && view->len / 8 != size)) {
        PyErr_Format(PyExc_TypeError, "%s: expected %zd values of format '%c'", what, size, format);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

typedef struct {
    PyObject *object;
    int writable;
    char format;
    Py_ssize_t size;
    const char *name;
} Want;

/* The buffers of `wants` into `views`; on failure those acquired are released and -1 returned. */
static int buffers(const Want *wants, int count, Py_buffer *views) {
    for (int k = 0; k < count; k++) {
        if (buffer_of(wants[k].object, &views[k], wants[k].writable, wants[k].format, wants[k].size,
                      wants[k].name) < 0) {
            for (int j = 0; j < k; j++) PyBuffer_Release(&views[j]);
            return -1;
        }
    }
    return 0;
}

static void release(Py_buffer *views, int count) {
    for (int k = 0; k < count; k++) PyBuffer_Release(&views[k]);
}

static int numbers(PyObject *const *args, int count, double *out) {
    for (int k = 0; k < count; k++) {
        out[k] = PyFloat_AsDouble(args[k]);
        if (out[k] == -1.0 && PyErr_Occurred()) return -1;
    }
    return 0;
}

/* ---- geometry ---------------------------------------------------------------------------------- */

/* numpy.sign of a float: -1, 0 or 1, and NaN for NaN */
static inline double sign_of(double x) {
    return x > 0.0 ? 1.0 : x < 0.0 ? -1.0 : x == 0.0 ? 0.0 : x;
}

/* A measure of (r, z)'s distance from the indenter that grows with it: the squared distance from the
   sphere's centre, the distance itself from a plate.  Cheaper than the distance, and as good to compare
   or to take the smallest of: distance_from(reach) is the distance exactly as the generated distance
   kernels compute it, and it is a monotone function of reach (sqrt and the subtraction round monotonically). */
static inline double reach(double r, double z, double c, int plate) {
    if (plate) return -z + c;
    double dz = z - c;
    return dz * dz + r * r;
}

static inline double distance_from(double reach, double rho, int plate) {
    return plate ? reach : sqrt(reach) - rho;
}

static inline double distance(double r, double z, double c, double rho, int plate) {
    return distance_from(reach(r, z, c, plate), rho, plate);
}

/* The three nodes of cell i >= 1 of an n-node meridian and the sign of the third one's r. */
static inline void stencil(Py_ssize_t i, Py_ssize_t n, Py_ssize_t *a, Py_ssize_t *b, Py_ssize_t *c, double *sign) {
    *a = i - 1;
    *b = i;
    if (i == n - 1) {
        *c = n - 2;
        *sign = -1.0;
    } else {
        *c = i + 1;
        *sign = 1.0;
    }
}

/* Ascending coefficients c[0..k) at t (Horner, as barrier._polyval). */
static inline double polyval(const double *c, int k, double t) {
    double out = c[k - 1];
    for (int j = k - 2; j >= 0; j--) out = out * t + c[j];
    return out;
}

static inline void derivative(const double *c, int k, double *out) {
    for (int j = 1; j < k; j++) out[j - 1] = c[j] * (double)j;
}

/* A root of the polynomial c[0..k) in [lo, hi], whose ends differ in sign (barrier._roots_in_brackets). */
static double bracketed_root(const double *c, int k, double lo, double hi) {
    double slope[4];
    derivative(c, k, slope);
    double f_lo = polyval(c, k, lo), a = lo, b = hi, t = 0.5 * (a + b);
    for (int it = 0; it < 60; it++) {
        double f = polyval(c, k, t);
        if (sign_of(f) == sign_of(f_lo)) a = t;
        else b = t;
        double step = t - f / polyval(slope, k - 1, t);
        double next = (step >= a && step <= b) ? step : 0.5 * (a + b);
        int done = fabs(next - t) <= 1e-14;
        t = next;
        if (done) break;
    }
    return t;
}

static void sort(double *v, int n) {
    for (int i = 1; i < n; i++) {
        double x = v[i];
        int j = i - 1;
        while (j >= 0 && v[j] > x) {
            v[j + 1] = v[j];
            j--;
        }
        v[j + 1] = x;
    }
}

/* The ends and critical points of the quartic g in [-1/2, 1/2], sorted (barrier._monotone_breaks). */
static void monotone_breaks(const double *g, double *breaks) {
    double A = 12.0 * g[4], B = 6.0 * g[3], C = 2.0 * g[2];
    double inflect[2] = {0.5, 0.5};
    double disc = B * B - 4.0 * A * C;
    if (A != 0 && disc > 0) {
        double q = -0.5 * (B + copysign(sqrt(disc), B));
        inflect[0] = q / A;
        inflect[1] = q != 0 ? C / q : 0.5;
    } else if (A == 0 && B != 0) {
        inflect[0] = -C / B;
    }
    double convex[4] = {-0.5, 0.5, 0.5, 0.5};
    for (int k = 0; k < 2; k++) convex[k + 1] = (inflect[k] > -0.5 && inflect[k] < 0.5) ? inflect[k] : 0.5;
    sort(convex, 4);
    double slope[4];
    derivative(g, 5, slope);
    breaks[0] = -0.5;
    breaks[4] = 0.5;
    for (int k = 0; k < 3; k++) {
        double lo = convex[k], hi = convex[k + 1];
        int change = sign_of(polyval(slope, 4, lo)) * sign_of(polyval(slope, 4, hi)) < 0 && hi > lo;
        breaks[k + 1] = change ? bracketed_root(slope, 4, lo, hi) : 0.5;
    }
    sort(breaks, 5);
}

/* The polynomial in t negative exactly where the cell's curve is within dhat (ContactBarrier._gap_polynomial);
   p and q are the curve's r and z in monomials of t. */
static void gap_polynomial(const double *p, const double *zq, double c, double rho, double dhat, int plate,
                           double *g) {
    if (plate) {
        g[0] = c - dhat - zq[0];
        g[1] = -zq[1];
        g[2] = -zq[2];
        g[3] = g[4] = 0.0;
        return;
    }
    double q[3] = {zq[0] - c, zq[1], zq[2]}, reach = rho + dhat;
    g[0] = p[0] * p[0] + q[0] * q[0] - reach * reach;
    g[1] = 2.0 * (p[0] * p[1] + q[0] * q[1]);
    g[2] = p[1] * p[1] + q[1] * q[1] + 2.0 * (p[0] * p[2] + q[0] * q[2]);
    g[3] = 2.0 * (p[1] * p[2] + q[1] * q[2]);
    g[4] = p[2] * p[2] + q[2] * q[2];
}

/* The cell's curve in monomials of t (ContactCells.curve): rows of barrier._MONOMIAL times the nodes. */
static inline void monomials(double x0, double x1, double x2, double *out) {
    out[0] = 0.125 * x0 + 0.75 * x1 + 0.125 * x2;
    out[1] = -0.5 * x0 + 0.0 * x1 + 0.5 * x2;
    out[2] = 0.5 * x0 + -1.0 * x1 + 0.5 * x2;
}

/* support(x, c, rho, plate, dhat, basis, cell_weight, xi, wq, gaps, cell, cr, cz, weight, r, z) -> P

   x: the interleaved state (2N); basis: the fixed rule's cell basis (3 x q, row j the weights of the
   stencil's node j at the q points); cell_weight (N); xi, wq: the support rule on [-1, 1].  Fills
   gaps (N: each cell's smallest fixed-sample distance) and the first P entries of the points' cell
   (int64), cr, cz (3 each), weight, r and z (room for 1 + 4 len(xi) (N - 1) points).  Returns P, or
   -1 when a fixed sample is not strictly outside the indenter, -2 when a point of the integral is not
   (the numpy code then raises the error that names it). */
static PyObject *support(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 16) {
        PyErr_SetString(PyExc_TypeError,
                        "support(x, c, rho, plate, dhat, basis, cell_weight, xi, wq, gaps, cell, cr, cz, weight, r, z)");
        return NULL;
    }
    double num[3];
    if (numbers(args + 1, 2, num) < 0 || numbers(args + 4, 1, num + 2) < 0) return NULL;
    double c = num[0], rho = num[1], dhat = num[2];
    int plate = PyObject_IsTrue(args[3]);
    if (plate < 0) return NULL;
    Py_ssize_t two_n = PyObject_Length(args[0]), nq = PyObject_Length(args[7]);
    if (two_n < 2 || two_n % 2 || nq < 1) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "support: bad sizes of x or xi");
        return NULL;
    }
    Py_ssize_t n = two_n / 2, room = 1 + 4 * nq * (n - 1);
    const Want wants[12] = {{args[0], 0, 'd', two_n, "x"}, {args[5], 0, 'd', -1, "basis"},
                            {args[6], 0, 'd', n, "cell_weight"}, {args[7], 0, 'd', nq, "xi"},
                            {args[8], 0, 'd', nq, "wq"}, {args[9], 1, 'd', n, "gaps"},
                            {args[10], 1, 'q', room, "cell"}, {args[11], 1, 'd', 3 * room, "cr"},
                            {args[12], 1, 'd', 3 * room, "cz"}, {args[13], 1, 'd', room, "weight"},
                            {args[14], 1, 'd', room, "r"}, {args[15], 1, 'd', room, "z"}};
    Py_buffer v[12];
    if (buffers(wants, 12, v) < 0) return NULL;
    const double *x = v[0].buf, *basis = v[1].buf, *cw = v[2].buf, *xi = v[3].buf, *wq = v[4].buf;
    double *gaps = v[5].buf, *cr = v[7].buf, *cz = v[8].buf, *weight = v[9].buf, *rp = v[10].buf, *zp = v[11].buf;
    long long *cell = v[6].buf;
    Py_ssize_t q = v[1].len / 24;
    if (q < 1 || v[1].len != 24 * q) {
        release(v, 12);
        PyErr_SetString(PyExc_TypeError, "support: basis must hold 3 rows of the fixed points' weights");
        return NULL;
    }
    Py_ssize_t P = 0;
    int status = 0;
    /* the fixed samples: every one strictly outside, each cell's smallest distance */
    double d0 = distance(x[0], x[1], c, rho, plate);
    if (!(d0 > 0)) status = -1;
    gaps[0] = d0;
    for (Py_ssize_t i = 1; i < n && status == 0; i++) {
        Py_ssize_t a, b, e;
        double sign;
        stencil(i, n, &a, &b, &e, &sign);
        double r0 = x[2 * a], r1 = x[2 * b], r2 = x[2 * e] * sign, z0 = x[2 * a + 1], z1 = x[2 * b + 1], z2 = x[2 * e + 1];
        double nearest = INFINITY;
        for (Py_ssize_t j = 0; j < q; j++) {
            double rs = r0 * basis[j] + r1 * basis[q + j] + r2 * basis[2 * q + j];
            double zs = z0 * basis[j] + z1 * basis[q + j] + z2 * basis[2 * q + j];
            double k = reach(rs, zs, c, plate);
            if (k < nearest) nearest = k;
        }
        gaps[i] = distance_from(nearest, rho, plate);
        if (!(gaps[i] > 0)) status = -1;
    }
    /* the base node's own term, then the support of every cell whose samples come within 2 dhat */
    if (status == 0 && d0 < dhat) {
        cell[0] = 0;
        cr[0] = cz[0] = cr[2] = cz[2] = 0.0;
        cr[1] = cz[1] = 1.0;
        weight[0] = cw[0];
        rp[0] = x[0];
        zp[0] = x[1];
        P = 1;
    }
    for (Py_ssize_t i = 1; i < n && status == 0; i++) {
        if (!(gaps[i] < 2.0 * dhat)) continue;
        Py_ssize_t a, b, e;
        double sign;
        stencil(i, n, &a, &b, &e, &sign);
        double R[3], Z[3], g[5], breaks[5];
        monomials(x[2 * a], x[2 * b], x[2 * e] * sign, R);
        monomials(x[2 * a + 1], x[2 * b + 1], x[2 * e + 1], Z);
        gap_polynomial(R, Z, c, rho, dhat, plate, g);
        monotone_breaks(g, breaks);
        for (int k = 0; k < 4 && status == 0; k++) {
            double lo = breaks[k], hi = breaks[k + 1];
            int in_lo = polyval(g, 5, lo) < 0, in_hi = polyval(g, 5, hi) < 0;
            double root = (in_lo != in_hi && hi > lo) ? bracketed_root(g, 5, lo, hi) : 0.0;
            double s = in_lo ? lo : root, f = in_hi ? hi : root;
            if (!((in_lo || in_hi) && f > s)) continue;
            for (Py_ssize_t j = 0; j < nq; j++) {
                double t = 0.5 * (s + f) + 0.5 * (f - s) * xi[j], tt = t * t;
                double B0 = 0.5 * tt - 0.5 * t + 0.125, B1 = 0.75 - tt, B2 = 0.5 * tt + 0.5 * t + 0.125;
                double *pr = cr + 3 * P, *pz = cz + 3 * P;
                pr[0] = B0;
                pr[1] = B1;
                pr[2] = B2 * sign;
                pz[0] = B0;
                pz[1] = B1;
                pz[2] = B2;
                double r = pr[0] * x[2 * a] + pr[1] * x[2 * b] + pr[2] * x[2 * e];
                double z = pz[0] * x[2 * a + 1] + pz[1] * x[2 * b + 1] + pz[2] * x[2 * e + 1];
                double d = distance(r, z, c, rho, plate);
                if (!(d > 0)) {
                    status = -2;
                    break;
                }
                if (!(d < dhat)) continue;  /* the ends of a piece sit at dhat up to rounding */
                cell[P] = i;
                weight[P] = 0.5 * (f - s) * wq[j] * cw[i];
                rp[P] = r;
                zp[P] = z;
                P++;
            }
        }
    }
    release(v, 12);
    return PyLong_FromSsize_t(status ? status : P);
}

/* assemble(n, cell, cr, cz, weight, e, g, gradient, active, cell_e, cell_f, h, blocks, xc) -> m or -1

   The P points of support (their cells non-decreasing), the point kernels' energies e (P), gradients
   g (3 x P, rows d/dr, d/dz, d/dc) and packed Hessians h (6 x P; h, blocks and xc all None for no
   Hessian).  Adds each cell's share to gradient (2N) and, with h, to xc (2N: d2E/dx dc); fills the
   first m entries of active (int64: the cells with a point, increasing), cell_e, cell_f (-dE_i/dc)
   and blocks (36 each, row-major in the stencil's (r_0, z_0, r_1, z_1, r_2, z_2)).  Returns m, or -1
   when a derivative is not finite. */
static PyObject *assemble(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 14) {
        PyErr_SetString(PyExc_TypeError,
                        "assemble(n, cell, cr, cz, weight, e, g, gradient, active, cell_e, cell_f, h, blocks, xc)");
        return NULL;
    }
    Py_ssize_t n = PyLong_AsSsize_t(args[0]), P = PyObject_Length(args[1]);
    if (n < 1 || P < 0) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "assemble: n must be positive");
        return NULL;
    }
    int hessian = args[11] != Py_None;
    const Want wants[13] = {{args[1], 0, 'q', P, "cell"}, {args[2], 0, 'd', 3 * P, "cr"},
                            {args[3], 0, 'd', 3 * P, "cz"}, {args[4], 0, 'd', P, "weight"},
                            {args[5], 0, 'd', P, "e"}, {args[6], 0, 'd', 3 * P, "g"},
                            {args[7], 1, 'd', 2 * n, "gradient"}, {args[8], 1, 'q', P, "active"},
                            {args[9], 1, 'd', P, "cell_e"}, {args[10], 1, 'd', P, "cell_f"},
                            {args[11], 0, 'd', 6 * P, "h"}, {args[12], 1, 'd', 36 * P, "blocks"},
                            {args[13], 1, 'd', 2 * n, "xc"}};
    Py_buffer v[13];
    int count = hessian ? 13 : 10;
    if (buffers(wants, count, v) < 0) return NULL;
    const long long *cell = v[0].buf;
    const double *cr = v[1].buf, *cz = v[2].buf, *w = v[3].buf, *e = v[4].buf, *g = v[5].buf;
    double *grad = v[6].buf, *cell_e = v[8].buf, *cell_f = v[9].buf;
    long long *active = v[7].buf;
    const double *h = hessian ? v[10].buf : NULL;
    double *blocks = hessian ? v[11].buf : NULL, *xc = hessian ? v[12].buf : NULL;
    for (Py_ssize_t p = 0; p < P; p++) {
        int finite = isfinite(g[p]) && isfinite(g[P + p]) && isfinite(g[2 * P + p]);
        for (int k = 0; hessian && k < 6; k++) finite = finite && isfinite(h[k * P + p]);
        if (!finite) {
            release(v, count);
            return PyLong_FromLong(-1);
        }
    }
    /* each cell's sums first, then added at its nodes (the pole's mirrored neighbour twice) */
    Py_ssize_t m = 0;
    for (Py_ssize_t p = 0; p < P; m++) {
        Py_ssize_t i = cell[p], dof[3];
        if (i == 0) {
            dof[0] = dof[1] = dof[2] = 0;
        } else {
            double sign;
            stencil(i, n, &dof[0], &dof[1], &dof[2], &sign);
        }
        double node[6] = {0.0}, border[6] = {0.0}, energy = 0.0, force = 0.0;
        double *blk = hessian ? blocks + 36 * m : NULL;
        if (hessian) memset(blk, 0, 36 * sizeof(double));
        for (; p < P && cell[p] == i; p++) {
            const double *a = cr + 3 * p, *b = cz + 3 * p;
            double wp = w[p];
            energy += wp * e[p];
            force -= wp * g[2 * P + p];
            for (int j = 0; j < 3; j++) {
                node[2 * j] += a[j] * wp * g[p];
                node[2 * j + 1] += b[j] * wp * g[P + p];
            }
            if (!hessian) continue;
            /* the coefficients' outer product first: (c_i c_j) s is exactly symmetric in i, j */
            double hrr = wp * h[p], hrz = wp * h[P + p], hzz = wp * h[3 * P + p];
            for (int j = 0; j < 3; j++) {
                for (int k = 0; k < 3; k++) {
                    blk[6 * (2 * j) + 2 * k] += hrr * (a[j] * a[k]);
                    blk[6 * (2 * j) + 2 * k + 1] += hrz * (a[j] * b[k]);
                    blk[6 * (2 * j + 1) + 2 * k] += hrz * (a[k] * b[j]);
                    blk[6 * (2 * j + 1) + 2 * k + 1] += hzz * (b[j] * b[k]);
                }
                border[2 * j] += a[j] * wp * h[2 * P + p];
                border[2 * j + 1] += b[j] * wp * h[4 * P + p];
            }
        }
        active[m] = i;
        cell_e[m] = energy;
        cell_f[m] = force;
        for (int j = 0; j < 6; j++) {
            grad[2 * dof[j / 2] + j % 2] += node[j];
            if (hessian) xc[2 * dof[j / 2] + j % 2] += border[j];
        }
    }
    release(v, count);
    return PyLong_FromSsize_t(m);
}

/* safe_fraction(x, dx, c, dc, rho, plate, basis) -> t, or -1.0 when a fixed sample of x is not strictly
   outside the indenter

   The first s in (0, 1] at which a fixed sample of x + s dx reaches the indenter at c + s dc (each
   moves on a straight segment), or a number > 1 when none does in [0, 1]: the root of
   ContactBarrier.max_safe_fraction before its safety factor. */
static PyObject *safe_fraction(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 7) {
        PyErr_SetString(PyExc_TypeError, "safe_fraction(x, dx, c, dc, rho, plate, basis)");
        return NULL;
    }
    double num[3];
    if (numbers(args + 2, 3, num) < 0) return NULL;
    double c = num[0], dc = num[1], rho = num[2];
    int plate = PyObject_IsTrue(args[5]);
    if (plate < 0) return NULL;
    Py_ssize_t two_n = PyObject_Length(args[0]);
    if (two_n < 2 || two_n % 2) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "safe_fraction: bad size of x");
        return NULL;
    }
    Py_ssize_t n = two_n / 2;
    const Want wants[3] = {{args[0], 0, 'd', two_n, "x"}, {args[1], 0, 'd', two_n, "dx"},
                           {args[6], 0, 'd', -1, "basis"}};
    Py_buffer v[3];
    if (buffers(wants, 3, v) < 0) return NULL;
    const double *x = v[0].buf, *dx = v[1].buf, *basis = v[2].buf;
    Py_ssize_t q = v[2].len / 24;
    if (q < 1 || v[2].len != 24 * q) {
        release(v, 3);
        PyErr_SetString(PyExc_TypeError, "safe_fraction: basis must hold 3 rows of the fixed points' weights");
        return NULL;
    }
    double first = INFINITY, nearest = INFINITY;
    for (Py_ssize_t i = 0; i < n; i++) {
        Py_ssize_t a = 0, b = 0, e = 0;
        double sign = 1.0;
        if (i > 0) stencil(i, n, &a, &b, &e, &sign);
        Py_ssize_t samples = i == 0 ? 1 : q;
        for (Py_ssize_t j = 0; j < samples; j++) {
            double r, z, vr, vz;
            if (i == 0) {
                r = x[0], z = x[1], vr = dx[0], vz = dx[1];
            } else {
                double B0 = basis[j], B1 = basis[q + j], B2 = basis[2 * q + j];
                r = x[2 * a] * B0 + x[2 * b] * B1 + x[2 * e] * sign * B2;
                z = x[2 * a + 1] * B0 + x[2 * b + 1] * B1 + x[2 * e + 1] * B2;
                vr = dx[2 * a] * B0 + dx[2 * b] * B1 + dx[2 * e] * sign * B2;
                vz = dx[2 * a + 1] * B0 + dx[2 * b + 1] * B1 + dx[2 * e + 1] * B2;
            }
            double k = reach(r, z, c, plate), root;
            if (k < nearest) nearest = k;
            if (plate) {
                double rate = vz - dc;  /* d(s) = d - s rate */
                if (!(rate > 0)) continue;
                root = k / rate;
            } else {
                double uz = z - c, wz = vz - dc;
                double A = vr * vr + wz * wz, B = r * vr + uz * wz;
                if (!(B < 0)) continue;  /* moving away from the centre */
                /* a sample that moves by less than half its distance d stays outside the whole step:
                   d >= (k - rho^2) / (2 sqrt(k)) outside, so 16 A k < (k - rho^2)^2 means |v| < d / 2 */
                double excess = k - rho * rho;
                if (excess > 0 && 16.0 * A * k < excess * excess) continue;
                double d = distance_from(k, rho, plate);
                double C = d * (hypot(r, uz) + rho);  /* |u|^2 - rho^2 > 0, without cancellation */
                double disc = B * B - A * C;
                if (!(disc >= 0)) continue;
                root = C / (-B + sqrt(disc));
            }
            if (root < first) first = root;
        }
    }
    int outside = distance_from(nearest, rho, plate) > 0;
    release(v, 3);
    return PyFloat_FromDouble(outside ? first : -1.0);
}

static PyMethodDef methods[] = {
    {"support", (PyCFunction)(void (*)(void))support, METH_FASTCALL,
     "support(x, c, rho, plate, dhat, basis, cell_weight, xi, wq, gaps, cell, cr, cz, weight, r, z) -> P"},
    {"assemble", (PyCFunction)(void (*)(void))assemble, METH_FASTCALL,
     "assemble(n, cell, cr, cz, weight, e, g, gradient, active, cell_e, cell_f, h, blocks, xc) -> m"},
    {"safe_fraction", (PyCFunction)(void (*)(void))safe_fraction, METH_FASTCALL,
     "safe_fraction(x, dx, c, dc, rho, plate, basis) -> t"},
    {NULL, NULL, 0, NULL}
};

static struct PyModuleDef moduledef = {PyModuleDef_HEAD_INIT, "_cbarrier", NULL, -1, methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__cbarrier(void) { return PyModule_Create(&moduledef); }
