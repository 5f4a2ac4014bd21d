/* Banded factorizations in C for contin.numerics.linalg (built by setup.py as contin.numerics._banded; optional:
   contin.numerics.linalg uses LAPACK and numpy where it is not built).

   factor, solve: LU with partial pivoting of a tridiagonal matrix and its solves
   (contin.numerics.linalg.TridiagonalLU).  The factorization is LAPACK's gttrf (the same pivoting, the
   same factors: A = P L U with U upper triangular with two superdiagonals).  The solves run LAPACK's
   gtts2 algorithm with one change: they multiply by the pivots' reciprocals, stored by the factorization, instead of dividing
   by the pivots.  A back substitution is a chain of dependent operations, and a division's latency
   is several times a multiplication's: at n = 2000 a solve takes 10 us against scipy's dgttrs 27 us.
   The results differ from LAPACK's by rounding only.

   inf_norm, residual: the tridiagonal matrix's infinity norm and f - A x from its three diagonals
   (the bordered solver's residual test), from a copy kept before factor overwrites them; max_abs:
   an array's largest modulus (the same test's sizes).

   ldlt_negative: the pivot-free L D L^T of a symmetric band matrix, counting its negative pivots
   (contin.numerics.linalg.SymmetricBand.negative_pivots), in one pass where the Python version alternates
   LAPACK's banded Cholesky with eliminations of the negative pivots by hand; cholesky_solve: a solve
   with the Cholesky factor it leaves when the matrix is positive definite (LAPACK's pbtrs). */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

/* A writable (or read-only when `writable` is 0) C-contiguous buffer of `size` float64 or int64 values. */
static int get(PyObject *obj, Py_buffer *view, int writable, const char *format, Py_ssize_t size,
               const char *what) {
    int flags = PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | (writable ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(obj, view, flags) < 0) return -1;
    const char *f = view->format;
    if (f != NULL && (f[0] == '<' || f[0] == '=' || f[0] == '@')) f++;
    if (f == NULL || view->itemsize != 8 || (strcmp(f, format) != 0 && !(format[0] == 'q' && strcmp(f, "l") == 0))
        || (size >= 0 && view->len / 8 != size)) {
        PyErr_Format(PyExc_TypeError, "%s: expected %zd values of format '%s'", what, size, format);
        PyBuffer_Release(view);
        return -1;
    }
    return 0;
}

/* The buffers args[k] for k < count, each with its writability, format, size and name; on failure
   those acquired are released and -1 returned. */
static int get_all(PyObject *const *args, int count, const int *writable, const char *const *formats,
                   const Py_ssize_t *sizes, const char *const *names, Py_buffer *views) {
    for (int k = 0; k < count; k++) {
        if (get(args[k], &views[k], writable[k], formats[k], sizes[k], names[k]) < 0) {
            for (int j = 0; j < k; j++) PyBuffer_Release(&views[j]);
            return -1;
        }
    }
    return 0;
}

static void release_all(Py_buffer *views, int count) {
    for (int k = 0; k < count; k++) PyBuffer_Release(&views[k]);
}

/* factor(dl, d, du, du2, piv, rd) -> info.  In place: dl (n-1), d (n), du (n-1) hold the matrix and
   receive the factors; du2 (n-2), piv (n, int64, 0-based rows) and rd (n, the reciprocals of U's
   diagonal) are outputs.  info: 0, or k + 1 where U[k, k] is exactly zero (rd then holds inf there). */
static PyObject *factor(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 6) {
        PyErr_SetString(PyExc_TypeError, "factor(dl, d, du, du2, piv, rd)");
        return NULL;
    }
    Py_ssize_t n = PyObject_Length(args[1]);
    if (n < 2) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "factor: n must be at least 2");
        return NULL;
    }
    static const int writable[6] = {1, 1, 1, 1, 1, 1};
    static const char *const formats[6] = {"d", "d", "d", "d", "q", "d"};
    static const char *const names[6] = {"dl", "d", "du", "du2", "piv", "rd"};
    const Py_ssize_t sizes[6] = {n - 1, n, n - 1, n - 2, n, n};
    Py_buffer v[6];
    if (get_all(args, 6, writable, formats, sizes, names, v) < 0) return NULL;
    double *dl = v[0].buf, *d = v[1].buf, *du = v[2].buf, *du2 = v[3].buf, *rd = v[5].buf;
    long long *piv = v[4].buf;
    for (Py_ssize_t i = 0; i < n - 2; i++) du2[i] = 0.0;
    for (Py_ssize_t i = 0; i < n - 1; i++) {
        if (fabs(d[i]) >= fabs(dl[i])) {  /* no interchange */
            piv[i] = i;
            if (d[i] != 0.0) {
                double fact = dl[i] / d[i];
                dl[i] = fact;
                d[i + 1] -= fact * du[i];
            }
        } else {  /* interchange rows i and i + 1 */
            piv[i] = i + 1;
            double fact = d[i] / dl[i];
            d[i] = dl[i];
            dl[i] = fact;
            double temp = du[i];
            du[i] = d[i + 1];
            d[i + 1] = temp - fact * d[i + 1];
            if (i < n - 2) {
                du2[i] = du[i + 1];
                du[i + 1] = -fact * du[i + 1];
            }
        }
    }
    piv[n - 1] = n - 1;
    Py_ssize_t info = 0;
    for (Py_ssize_t i = 0; i < n; i++) {
        if (d[i] == 0.0 && info == 0) info = i + 1;
        rd[i] = 1.0 / d[i];
    }
    release_all(v, 6);
    return PyLong_FromSsize_t(info);
}

/* inf_norm(dl, d, du) -> the largest row sum of |A| for the tridiagonal A with these sub-, main and
   superdiagonals (NaN when an entry is NaN): the scale of the bordered solver's residual test, read
   from the diagonals the factorization copies anyway. */
static PyObject *inf_norm(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "inf_norm(dl, d, du)");
        return NULL;
    }
    Py_ssize_t n = PyObject_Length(args[1]);
    if (n < 2) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "inf_norm: n must be at least 2");
        return NULL;
    }
    static const int writable[3] = {0, 0, 0};
    static const char *const formats[3] = {"d", "d", "d"};
    static const char *const names[3] = {"dl", "d", "du"};
    const Py_ssize_t sizes[3] = {n - 1, n, n - 1};
    Py_buffer v[3];
    if (get_all(args, 3, writable, formats, sizes, names, v) < 0) return NULL;
    const double *dl = v[0].buf, *d = v[1].buf, *du = v[2].buf;
    /* row i holds dl[i - 1], d[i], du[i]; a NaN row sum fails every comparison and stays */
    double largest = fabs(d[0]) + fabs(du[0]);
    for (Py_ssize_t i = 1; i < n - 1; i++) {
        double s = fabs(dl[i - 1]) + fabs(d[i]) + fabs(du[i]);
        if (!(s <= largest) && largest == largest) largest = s;
    }
    double last = fabs(dl[n - 2]) + fabs(d[n - 1]);
    if (!(last <= largest) && largest == largest) largest = last;
    release_all(v, 3);
    return PyFloat_FromDouble(largest);
}

/* residual(dl, d, du, x, f, out, trans) -> None: out = f - A x (A^T x when trans) for the tridiagonal A
   with these sub-, main and superdiagonals; the bordered solver's residual test in one pass instead
   of scipy's product and a numpy subtraction. */
static PyObject *residual(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 7) {
        PyErr_SetString(PyExc_TypeError, "residual(dl, d, du, x, f, out, trans)");
        return NULL;
    }
    Py_ssize_t n = PyObject_Length(args[1]);
    if (n < 2) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "residual: n must be at least 2");
        return NULL;
    }
    int trans = PyObject_IsTrue(args[6]);
    if (trans < 0) return NULL;
    static const int writable[6] = {0, 0, 0, 0, 0, 1};
    static const char *const formats[6] = {"d", "d", "d", "d", "d", "d"};
    static const char *const names[6] = {"dl", "d", "du", "x", "f", "out"};
    const Py_ssize_t sizes[6] = {n - 1, n, n - 1, n, n, n};
    Py_buffer v[6];
    if (get_all(args, 6, writable, formats, sizes, names, v) < 0) return NULL;
    const double *d = v[1].buf, *x = v[3].buf, *f = v[4].buf;
    /* A^T has the superdiagonal below and the subdiagonal above */
    const double *below = trans ? v[2].buf : v[0].buf, *above = trans ? v[0].buf : v[2].buf;
    double *out = v[5].buf;
    out[0] = f[0] - (d[0] * x[0] + above[0] * x[1]);
    for (Py_ssize_t i = 1; i < n - 1; i++)
        out[i] = f[i] - (below[i - 1] * x[i - 1] + d[i] * x[i] + above[i] * x[i + 1]);
    out[n - 1] = f[n - 1] - (below[n - 2] * x[n - 2] + d[n - 1] * x[n - 1]);
    release_all(v, 6);
    Py_RETURN_NONE;
}

/* max_abs(a) -> the largest modulus of the float64 values of the C-contiguous array a (0 when empty,
   NaN when any is NaN): the sizes in the bordered solver's residual test, in one pass where numpy
   makes |a| first. */
static PyObject *max_abs(PyObject *self, PyObject *arg) {
    Py_buffer v;
    if (get(arg, &v, 0, "d", -1, "max_abs: a") < 0) return NULL;
    const double *a = v.buf;
    Py_ssize_t n = v.len / 8;
    double largest = 0.0;
    for (Py_ssize_t i = 0; i < n; i++) {
        double m = fabs(a[i]);
        if (!(m <= largest)) {  /* larger, or NaN: a NaN ends the search */
            largest = m;
            if (m != m) break;
        }
    }
    PyBuffer_Release(&v);
    return PyFloat_FromDouble(largest);
}

/* One right-hand side x (length n, stride 1) overwritten by the solution.  The values the next
   row needs are carried in registers: reading back a value just stored costs the store's latency on
   every row of these dependent chains. */
static void solve_one(Py_ssize_t n, const double *dl, const double *rd, const double *du, const double *du2,
                      const long long *piv, double *x, int trans) {
    if (!trans) {
        /* L: the row interchanges and eliminations of the factorization, in order; cur is x[i] */
        double cur = x[0];
        for (Py_ssize_t i = 0; i < n - 1; i++) {
            double next = x[i + 1];
            if (piv[i] == i) {
                x[i] = cur;
                cur = next - dl[i] * cur;
            } else {
                x[i] = next;
                cur = cur - dl[i] * next;
            }
        }
        x[n - 1] = cur;
        /* U: back substitution; x1 is x[i + 1], x2 is x[i + 2] */
        double x2 = x[n - 1] * rd[n - 1];
        double x1 = (x[n - 2] - du[n - 2] * x2) * rd[n - 2];
        x[n - 1] = x2;
        x[n - 2] = x1;
        for (Py_ssize_t i = n - 3; i >= 0; i--) {
            double xi = (x[i] - du[i] * x1 - du2[i] * x2) * rd[i];
            x[i] = xi;
            x2 = x1;
            x1 = xi;
        }
    } else {
        /* U^T: forward substitution; x1 is x[i - 1], x2 is x[i - 2] */
        double x2 = x[0] * rd[0];
        double x1 = (x[1] - du[0] * x2) * rd[1];
        x[0] = x2;
        x[1] = x1;
        for (Py_ssize_t i = 2; i < n; i++) {
            double xi = (x[i] - du[i - 1] * x1 - du2[i - 2] * x2) * rd[i];
            x[i] = xi;
            x2 = x1;
            x1 = xi;
        }
        /* L^T with the interchanges, in reverse; cur is x[i + 1] */
        double cur = x[n - 1];
        for (Py_ssize_t i = n - 2; i >= 0; i--) {
            double xi = x[i];
            if (piv[i] == i) {
                x[i + 1] = cur;
                cur = xi - dl[i] * cur;
            } else {
                x[i + 1] = xi - dl[i] * cur;
            }
        }
        x[0] = cur;
    }
}

/* solve(dl, rd, du, du2, piv, x, trans) -> None: x (n, or n x k C-contiguous) overwritten by the
   solution of A x = b (A^T x = b when trans is true). */
static PyObject *solve(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 7) {
        PyErr_SetString(PyExc_TypeError, "solve(dl, rd, du, du2, piv, x, trans)");
        return NULL;
    }
    int trans = PyObject_IsTrue(args[6]);
    if (trans < 0) return NULL;
    Py_ssize_t n = PyObject_Length(args[1]);
    if (n < 2) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "solve: n must be at least 2");
        return NULL;
    }
    static const int writable[6] = {0, 0, 0, 0, 0, 1};
    static const char *const formats[6] = {"d", "d", "d", "d", "q", "d"};
    static const char *const names[6] = {"dl", "rd", "du", "du2", "piv", "x"};
    const Py_ssize_t sizes[6] = {n - 1, n, n - 1, n - 2, n, -1};
    Py_buffer v[6];
    if (get_all(args, 6, writable, formats, sizes, names, v) < 0) return NULL;
    const double *dl = v[0].buf, *rd = v[1].buf, *du = v[2].buf, *du2 = v[3].buf;
    const long long *piv = v[4].buf;
    Py_buffer *vx = &v[5];
    Py_ssize_t total = vx->len / 8;
    if (total % n != 0 || (vx->ndim == 2 && vx->shape[0] != n) || vx->ndim > 2) {
        PyErr_Format(PyExc_TypeError, "solve: x must have %zd rows", n);
        release_all(v, 6);
        return NULL;
    }
    Py_ssize_t k = total / n;
    double *x = vx->buf;
    if (k == 1) {
        solve_one(n, dl, rd, du, du2, piv, x, trans);
    } else if (k > 1) {
        /* columns of a C-ordered n x k array: gather each, solve, scatter back */
        double *column = PyMem_Malloc(n * sizeof(double));
        if (column == NULL) {
            release_all(v, 6);
            return PyErr_NoMemory();
        }
        for (Py_ssize_t c = 0; c < k; c++) {
            for (Py_ssize_t i = 0; i < n; i++) column[i] = x[i * k + c];
            solve_one(n, dl, rd, du, du2, piv, column, trans);
            for (Py_ssize_t i = 0; i < n; i++) x[i * k + c] = column[i];
        }
        PyMem_Free(column);
    }
    release_all(v, 6);
    Py_RETURN_NONE;
}

/* ldlt_negative(work, growth_limit, max_negative, zero_tol) -> list of columns, or None.

   work: the upper band (kd + 1) x n in Fortran order (column j holds A[j - kd .. j, j] in rows
   0 .. kd), overwritten.  The pivot-free L D L^T runs column by column; each pivot d_j is
   positive, or negative (its column is listed), or the factorization cannot be trusted and None is
   returned: a pivot that is not a number, zero, or negative with |d_j| <= zero_tol; a multiplier
   |A[j, k]| / |d_j| above growth_limit; more than max_negative negative pivots.  When no pivot is
   negative, work holds the Cholesky factor U (A = U^T U) in LAPACK's upper band storage, ready for
   dpbtrs. */
static PyObject *ldlt_negative(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError, "ldlt_negative(work, growth_limit, max_negative, zero_tol)");
        return NULL;
    }
    double growth_limit = PyFloat_AsDouble(args[1]);
    Py_ssize_t max_negative = PyLong_AsSsize_t(args[2]);
    double zero_tol = PyFloat_AsDouble(args[3]);
    if (PyErr_Occurred()) return NULL;
    Py_buffer view;
    if (PyObject_GetBuffer(args[0], &view, PyBUF_F_CONTIGUOUS | PyBUF_FORMAT | PyBUF_WRITABLE) < 0) return NULL;
    const char *f = view.format;
    if (f != NULL && (f[0] == '<' || f[0] == '=' || f[0] == '@')) f++;
    if (view.ndim != 2 || view.itemsize != 8 || f == NULL || strcmp(f, "d") != 0 || view.shape[0] < 1) {
        PyErr_SetString(PyExc_TypeError, "ldlt_negative: work must be a 2-D Fortran-ordered float64 array");
        PyBuffer_Release(&view);
        return NULL;
    }
    Py_ssize_t kd = view.shape[0] - 1, n = view.shape[1], ld = kd + 1;
    double *w = view.buf;  /* A[i, j] (i <= j <= i + kd) at w[(kd + i - j) + j * ld] */
    PyObject *columns = PyList_New(0);
    if (columns == NULL) {
        PyBuffer_Release(&view);
        return NULL;
    }
    double *row = PyMem_Malloc((kd + 1) * sizeof(double));
    if (row == NULL) {
        Py_DECREF(columns);
        PyBuffer_Release(&view);
        return PyErr_NoMemory();
    }
    int trusted = 1;
    for (Py_ssize_t j = 0; j < n && trusted; j++) {
        double d = w[kd + j * ld];
        if (!(d > 0.0) && !(d < 0.0 && fabs(d) > zero_tol)) {
            trusted = 0;  /* not a number, zero, or negative at the round-off level */
            break;
        }
        Py_ssize_t k = kd < n - 1 - j ? kd : n - 1 - j;
        double largest = 0.0;
        for (Py_ssize_t t = 1; t <= k; t++) {
            row[t] = w[(kd - t) + (j + t) * ld];  /* A[j, j + t] */
            if (fabs(row[t]) > largest) largest = fabs(row[t]);
        }
        if (!(largest / fabs(d) <= growth_limit)) {
            trusted = 0;
            break;
        }
        if (d < 0.0) {
            PyObject *column = PyLong_FromSsize_t(j);
            if (column == NULL || PyList_Append(columns, column) < 0) {
                Py_XDECREF(column);
                PyMem_Free(row);
                Py_DECREF(columns);
                PyBuffer_Release(&view);
                return NULL;
            }
            Py_DECREF(column);
            if (PyList_GET_SIZE(columns) > max_negative) {
                trusted = 0;
                break;
            }
        }
        /* the Schur complement on the next k rows: A[j + t, j + s] -= A[j, j + t] A[j, j + s] / d */
        for (Py_ssize_t s = 1; s <= k; s++) {
            double factor = row[s] / d;
            double *column_s = w + (j + s) * ld;
            for (Py_ssize_t t = 1; t <= s; t++) column_s[kd - (s - t)] -= row[t] * factor;
        }
        if (d > 0.0) {  /* Cholesky's row: u_jj = sqrt(d), u_j,j+t = A[j, j + t] / u_jj */
            double u = sqrt(d);
            w[kd + j * ld] = u;
            for (Py_ssize_t t = 1; t <= k; t++) w[(kd - t) + (j + t) * ld] = row[t] / u;
        }
    }
    PyMem_Free(row);
    PyBuffer_Release(&view);
    if (!trusted) {
        Py_DECREF(columns);
        Py_RETURN_NONE;
    }
    return columns;
}

/* sturm_count(d, e, growth_limit, zero_tol) -> int: the negative pivots of the pivot-free L D L^T of
   the symmetric tridiagonal matrix with diagonal d (n) and off-diagonal e (n - 1), read-only; -1 when
   that factorization cannot be trusted (the checks of ldlt_negative: a pivot that is not a number,
   zero, or negative with |pivot| <= zero_tol, or a multiplier |e_j| / |pivot| above growth_limit).
   What ldlt_negative counts for a band of width one, without the Cholesky factor it also leaves. */
static PyObject *sturm_count(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 4) {
        PyErr_SetString(PyExc_TypeError, "sturm_count(d, e, growth_limit, zero_tol)");
        return NULL;
    }
    Py_ssize_t n = PyObject_Length(args[0]);
    if (n < 1) {
        if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "sturm_count: n must be at least 1");
        return NULL;
    }
    double growth_limit = PyFloat_AsDouble(args[2]);
    double zero_tol = PyFloat_AsDouble(args[3]);
    if (PyErr_Occurred()) return NULL;
    static const int writable[2] = {0, 0};
    static const char *const formats[2] = {"d", "d"};
    static const char *const names[2] = {"sturm_count: d", "sturm_count: e"};
    const Py_ssize_t sizes[2] = {n, n - 1};
    Py_buffer v[2];
    if (get_all(args, 2, writable, formats, sizes, names, v) < 0) return NULL;
    const double *d = v[0].buf, *e = v[1].buf;
    long negative = 0;
    double pivot = d[0];
    for (Py_ssize_t j = 0; j < n; j++) {
        if (!(pivot > 0.0) && !(pivot < 0.0 && fabs(pivot) > zero_tol)) {
            negative = -1;
            break;
        }
        if (pivot < 0.0) negative++;
        if (j + 1 < n) {
            if (!(fabs(e[j]) / fabs(pivot) <= growth_limit)) {
                negative = -1;
                break;
            }
            pivot = d[j + 1] - e[j] * (e[j] / pivot);
        }
    }
    release_all(v, 2);
    return PyLong_FromLong(negative);
}

/* cholesky_solve(u, rdiag, x) -> None: x (n, C-contiguous) overwritten by the solution of U^T U x = x,
   with U the upper band Cholesky factor that ldlt_negative (or LAPACK's pbtrf) leaves in u ((kd + 1, n),
   Fortran-ordered, U[i, j] at u[kd + i - j, j]) and rdiag (n) the reciprocals of its diagonal.  LAPACK's
   pbtrs for one right-hand side, with two changes that shorten the chain of dependent operations
   from one row to the next: both substitutions are column sweeps (each row's value, once known, is
   subtracted from the kd rows after it, where a row's sum over the kd before it is a chain of kd
   multiply-adds), and they multiply by the diagonal's reciprocals instead of dividing. */
static PyObject *cholesky_solve(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "cholesky_solve(u, rdiag, x)");
        return NULL;
    }
    Py_buffer view;
    if (PyObject_GetBuffer(args[0], &view, PyBUF_F_CONTIGUOUS | PyBUF_FORMAT) < 0) return NULL;
    const char *f = view.format;
    if (f != NULL && (f[0] == '<' || f[0] == '=' || f[0] == '@')) f++;
    if (view.ndim != 2 || view.itemsize != 8 || f == NULL || strcmp(f, "d") != 0 || view.shape[0] < 1) {
        PyErr_SetString(PyExc_TypeError, "cholesky_solve: u must be a 2-D Fortran-ordered float64 array");
        PyBuffer_Release(&view);
        return NULL;
    }
    Py_ssize_t kd = view.shape[0] - 1, n = view.shape[1], ld = kd + 1;
    static const int writable[2] = {0, 1};
    static const char *const formats[2] = {"d", "d"};
    static const char *const names[2] = {"cholesky_solve: rdiag", "cholesky_solve: x"};
    const Py_ssize_t sizes[2] = {n, n};
    Py_buffer v[2];
    if (get_all(args + 1, 2, writable, formats, sizes, names, v) < 0) {
        PyBuffer_Release(&view);
        return NULL;
    }
    const double *u = view.buf, *rdiag = v[0].buf;
    double *x = v[1].buf;
    /* U^T z = x: z_j known, U[j, j + t] z_j leaves row j + t (U[j, j + t] at u[kd - t, j + t]) */
    for (Py_ssize_t j = 0; j < n; j++) {
        double zj = x[j] * rdiag[j];
        x[j] = zj;
        Py_ssize_t k = kd < n - 1 - j ? kd : n - 1 - j;
        for (Py_ssize_t t = 1; t <= k; t++) x[j + t] -= u[(kd - t) + (j + t) * ld] * zj;
    }
    /* U x = z from the last row: x_j known, U[j - t, j] x_j leaves row j - t (column j, contiguous) */
    for (Py_ssize_t j = n - 1; j >= 0; j--) {
        const double *col = u + j * ld;
        double xj = x[j] * rdiag[j];
        x[j] = xj;
        Py_ssize_t k = kd < j ? kd : j;
        for (Py_ssize_t t = 1; t <= k; t++) x[j - t] -= col[kd - t] * xj;
    }
    release_all(v, 2);
    PyBuffer_Release(&view);
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"factor", (PyCFunction)(void (*)(void))factor, METH_FASTCALL, "factor(dl, d, du, du2, piv, rd) -> info"},
    {"inf_norm", (PyCFunction)(void (*)(void))inf_norm, METH_FASTCALL, "inf_norm(dl, d, du) -> float"},
    {"residual", (PyCFunction)(void (*)(void))residual, METH_FASTCALL,
     "residual(dl, d, du, x, f, out, trans) -> None"},
    {"max_abs", (PyCFunction)max_abs, METH_O, "max_abs(a) -> float"},
    {"solve", (PyCFunction)(void (*)(void))solve, METH_FASTCALL, "solve(dl, rd, du, du2, piv, x, trans) -> None"},
    {"cholesky_solve", (PyCFunction)(void (*)(void))cholesky_solve, METH_FASTCALL, "cholesky_solve(u, rdiag, x) -> None"},
    {"sturm_count", (PyCFunction)(void (*)(void))sturm_count, METH_FASTCALL,
     "sturm_count(d, e, growth_limit, zero_tol) -> int (-1: not trusted)"},
    {"ldlt_negative", (PyCFunction)(void (*)(void))ldlt_negative, METH_FASTCALL,
     "ldlt_negative(work, growth_limit, max_negative, zero_tol) -> columns or None"},
    {NULL, NULL, 0, NULL}
};

static struct PyModuleDef moduledef = {PyModuleDef_HEAD_INIT, "_banded", NULL, -1, methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__banded(void) { return PyModule_Create(&moduledef); }
