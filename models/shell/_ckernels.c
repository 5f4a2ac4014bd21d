/* Fast element kernels of the discrete axisymmetric shell (contin_models.shell._ckernels).
   Generated from the numpy kernels by contin.modelkit.codegen.c_extension_text: do not edit. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <string.h>

/* An input of a kernel: a float64 buffer (1-D with any whole stride, or C-contiguous) or a number
   (stride 0). */
typedef struct {
    Py_buffer view;
    int held;
    const double *data;
    Py_ssize_t stride;
    double scalar;
} Input;

/* An output: a writable C-contiguous float64 buffer of rows x m values (row r of element i at r m + i). */
typedef struct {
    Py_buffer view;
    int held;
    double *data;
} Output;

static void release(Input *in, Py_ssize_t nin, Output *out, Py_ssize_t nout) {
    for (Py_ssize_t k = 0; k < nin; k++) {
        if (in[k].held) PyBuffer_Release(&in[k].view);
    }
    for (Py_ssize_t k = 0; k < nout; k++) {
        if (out[k].held) PyBuffer_Release(&out[k].view);
    }
}

/* numpy.sign of a float: -1, 0 (for either zero) or 1, and NaN for NaN */
static inline double sign_of(double x) {
    return x > 0.0 ? 1.0 : x < 0.0 ? -1.0 : x == 0.0 ? 0.0 : x;
}

static int is_float64(const Py_buffer *view) {
    const char *f = view->format;
    if (f == NULL) return 0;
    if (f[0] == '<' || f[0] == '=' || f[0] == '@') f++;
    return view->itemsize == 8 && strcmp(f, "d") == 0;
}

/* A buffer the kernel cannot use (strided in two dimensions, read-only output, ...) raises
   ValueError or BufferError in CPython and numpy: the wrapper answers TypeError only. */
static int as_type_error(void) {
    PyObject *type, *value, *traceback;
    PyErr_Fetch(&type, &value, &traceback);
    PyErr_Format(PyExc_TypeError, "buffer not usable by the compiled kernel (%S)", value ? value : Py_None);
    Py_XDECREF(type);
    Py_XDECREF(value);
    Py_XDECREF(traceback);
    return -1;
}

/* Reads the inputs args[0..nin) and the outputs args[nin..nin+nout) (rows[k] x m values each); 0, or
   -1 with TypeError set (the Python wrapper then calls the numpy kernel, which takes any array-like). */
static int prepare(const char *name, PyObject *const *args, Py_ssize_t nargs, Input *in, Py_ssize_t nin,
                   Output *out, Py_ssize_t nout, const Py_ssize_t *rows, Py_ssize_t *m) {
    *m = 1;
    for (Py_ssize_t k = 0; k < nin; k++) in[k].held = 0;
    for (Py_ssize_t k = 0; k < nout; k++) out[k].held = 0;
    if (nargs != nin + nout) {
        PyErr_Format(PyExc_TypeError, "%s takes %zd arguments (the inputs, then the outputs), got %zd", name,
                     nin + nout, nargs);
        return -1;
    }
    for (Py_ssize_t k = 0; k < nin; k++) {
        if (PyObject_CheckBuffer(args[k])) {
            if (PyObject_GetBuffer(args[k], &in[k].view, PyBUF_RECORDS_RO) < 0) return as_type_error();
            in[k].held = 1;
            const Py_buffer *v = &in[k].view;
            if (!is_float64(v)) {
                PyErr_Format(PyExc_TypeError, "%s: argument %zd is not float64", name, k);
                return -1;
            }
            Py_ssize_t size = v->len / 8, stride = 1;
            if (v->ndim == 1 && v->strides != NULL) {
                stride = v->strides[0] / 8;
                if (stride * 8 != v->strides[0]) {
                    PyErr_Format(PyExc_TypeError, "%s: argument %zd has a stride of %zd bytes", name, k,
                                 v->strides[0]);
                    return -1;
                }
            } else if (v->ndim > 1 && !PyBuffer_IsContiguous(v, 'C')) {
                PyErr_Format(PyExc_TypeError, "%s: argument %zd is neither 1-D nor C-contiguous", name, k);
                return -1;
            }
            if (size == 1) {
                in[k].scalar = *(const double *)v->buf;
                in[k].data = &in[k].scalar;
                in[k].stride = 0;
                continue;
            }
            if (*m != 1 && size != *m) {
                PyErr_Format(PyExc_TypeError, "%s: argument %zd has %zd elements, expected %zd", name, k, size, *m);
                return -1;
            }
            *m = size;
            in[k].data = (const double *)v->buf;
            in[k].stride = stride;
        } else {
            in[k].scalar = PyFloat_AsDouble(args[k]);
            if (in[k].scalar == -1.0 && PyErr_Occurred()) {
                PyErr_Clear();
                PyErr_Format(PyExc_TypeError, "%s: argument %zd is neither a float64 array nor a number", name, k);
                return -1;
            }
            in[k].data = &in[k].scalar;
            in[k].stride = 0;
        }
    }
    for (Py_ssize_t k = 0; k < nout; k++) {
        if (PyObject_GetBuffer(args[nin + k], &out[k].view, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT | PyBUF_WRITABLE) < 0) {
            return as_type_error();
        }
        out[k].held = 1;
        if (!is_float64(&out[k].view) || out[k].view.len / 8 != rows[k] * *m) {
            PyErr_Format(PyExc_TypeError, "%s: output %zd must be a float64 array of %zd x %zd values", name, k,
                         rows[k], *m);
            return -1;
        }
        out[k].data = (double *)out[k].view.buf;
    }
    return 0;
}

static PyObject *c_bend_fast_gradient(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {6};
    Input in[11];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("bend_fast_gradient", args, nargs, in, 11, outputs, 1, rows, &_m) < 0) {
        release(in, 11, outputs, 1);
        return NULL;
    }
    double *out = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double ar = in[0].data[_i * in[0].stride];
        const double az = in[1].data[_i * in[1].stride];
        const double br = in[2].data[_i * in[2].stride];
        const double bz = in[3].data[_i * in[3].stride];
        const double r1 = in[4].data[_i * in[4].stride];
        const double lbar = in[5].data[_i * in[5].stride];
        const double rbar = in[6].data[_i * in[6].stride];
        const double k11bar = in[7].data[_i * in[7].stride];
        const double k22bar = in[8].data[_i * in[8].stride];
        const double kb = in[9].data[_i * in[9].stride];
        const double nu = in[10].data[_i * in[10].stride];
        double la = sqrt(((ar * ar) + (az * az)));
        double lb = sqrt(((br * br) + (bz * bz)));
        double ila = (1.0 / la);
        double ilb = (1.0 / lb);
        double ca = (ar * ila);
        double sa = (az * ila);
        double cb = (br * ilb);
        double sb = (bz * ilb);
        double lab = (la * lb);
        double den = (((ar * br) + (az * bz)) + lab);
        double tn = (((ar * bz) - (az * br)) / den);
        double it2 = (((1.0 / 2.0) * lab) / den);
        double it = sqrt(it2);
        double sphi = (it * (sa + sb));
        double cphi = (it * (ca + cb));
        double ir = (1.0 / r1);
        double k22 = (ir * sphi);
        double k11 = ((2.0 * tn) / lbar);
        double kq = ((((2.0 * 3.141592653589793) * kb) * lbar) * rbar);
        double kqnu = (kq * nu);
        double _c0 = (k11 - k11bar);
        double _c1 = (k22 - k22bar);
        double _c2 = (1.0 / lbar);
        double _c3 = ((tn * tn) + 1.0);
        double _c4 = (((1.0 / 2.0) * cphi) * ir);
        double _c5 = ((_c0 * kq) + (_c1 * kqnu));
        double _c6 = ((_c0 * kqnu) + (_c1 * kq));
        double _c7 = (_c2 * _c3);
        double _c8 = (ir * k22);
        double _c9 = (_c4 * _c6);
        double _c10 = (_c5 * _c7);
        double _c11 = ((-_c10) + _c9);
        double _c12 = (_c10 + _c9);
        double _c13 = (_c6 * _c8);
        double _c14 = (_c11 * ila);
        double _c15 = (_c12 * ilb);
        double _c16 = (_c14 * sa);
        double _c17 = (_c14 * ca);
        double _c18 = (_c15 * sb);
        double _c19 = (_c15 * cb);
        out[0 * _m + _i] = _c16;
        out[1 * _m + _i] = (-_c17);
        out[2 * _m + _i] = (((-_c13) - _c16) + _c18);
        out[3 * _m + _i] = (_c17 - _c19);
        out[4 * _m + _i] = (-_c18);
        out[5 * _m + _i] = _c19;
    }
    release(in, 11, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_bend_fast_hessian(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {21};
    Input in[11];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("bend_fast_hessian", args, nargs, in, 11, outputs, 1, rows, &_m) < 0) {
        release(in, 11, outputs, 1);
        return NULL;
    }
    double *out = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double ar = in[0].data[_i * in[0].stride];
        const double az = in[1].data[_i * in[1].stride];
        const double br = in[2].data[_i * in[2].stride];
        const double bz = in[3].data[_i * in[3].stride];
        const double r1 = in[4].data[_i * in[4].stride];
        const double lbar = in[5].data[_i * in[5].stride];
        const double rbar = in[6].data[_i * in[6].stride];
        const double k11bar = in[7].data[_i * in[7].stride];
        const double k22bar = in[8].data[_i * in[8].stride];
        const double kb = in[9].data[_i * in[9].stride];
        const double nu = in[10].data[_i * in[10].stride];
        double la = sqrt(((ar * ar) + (az * az)));
        double lb = sqrt(((br * br) + (bz * bz)));
        double ila = (1.0 / la);
        double ilb = (1.0 / lb);
        double ca = (ar * ila);
        double sa = (az * ila);
        double cb = (br * ilb);
        double sb = (bz * ilb);
        double lab = (la * lb);
        double den = (((ar * br) + (az * bz)) + lab);
        double tn = (((ar * bz) - (az * br)) / den);
        double it2 = (((1.0 / 2.0) * lab) / den);
        double it = sqrt(it2);
        double sphi = (it * (sa + sb));
        double cphi = (it * (ca + cb));
        double ir = (1.0 / r1);
        double k22 = (ir * sphi);
        double k11 = ((2.0 * tn) / lbar);
        double kq = ((((2.0 * 3.141592653589793) * kb) * lbar) * rbar);
        double kqnu = (kq * nu);
        double _c0 = (k11 - k11bar);
        double _c1 = (k22 - k22bar);
        double _c2 = (1.0 / lbar);
        double _c3 = ((tn * tn) + 1.0);
        double _c4 = ((-_c2) * _c3);
        double _c6 = ((1.0 / 2.0) * cphi);
        double _c7 = (_c6 * ir);
        double _c8 = ((-_c4) * tn);
        double _c9 = (((-1.0) / 4.0) * k22);
        double _c10 = (ir * ir);
        double _c11 = ((-_c10) * _c6);
        double _c12 = ((_c0 * kq) + (_c1 * kqnu));
        double _c13 = ((_c0 * kqnu) + (_c1 * kq));
        double _c14 = (ir * k22);
        double _c15 = ((2.0 * _c10) * k22);
        double _c16 = (_c4 * kq);
        double _c17 = (_c4 * kqnu);
        double _c18 = (_c16 + (_c7 * kqnu));
        double _c19 = ((-_c16) + (_c7 * kqnu));
        double _c21 = (_c17 + (_c7 * kq));
        double _c22 = ((-_c17) + (_c7 * kq));
        double _c23 = (_c14 * kq);
        double _c24 = (_c12 * _c4);
        double _c25 = (_c13 * _c9);
        double _c26 = (_c12 * _c8);
        double _c27 = ((_c18 * _c4) + _c26);
        double _c28 = (_c11 * _c13);
        double _c29 = ((_c13 * _c7) + _c24);
        double _c30 = ((_c13 * _c7) - _c24);
        double _c32 = (((_c21 * _c7) + _c25) + _c27);
        double _c33 = (((_c13 * _c9) + (_c21 * _c7)) - _c27);
        double _c34 = (((-_c14) * _c21) + _c28);
        double _c35 = (((((-_c19) * _c4) + (_c22 * _c7)) + _c25) + _c26);
        double _c36 = (((-_c14) * _c22) + _c28);
        double _c37 = ((_c13 * _c15) + (_c14 * _c23));
        double _c38 = (_c29 * ila);
        double _c39 = (_c30 * ilb);
        double _c40 = (_c32 * (ila * ila));
        double _c41 = ((_c33 * ila) * ilb);
        double _c42 = (_c34 * ila);
        double _c43 = (_c35 * (ilb * ilb));
        double _c44 = (_c36 * ilb);
        double _c45 = (_c38 * sa);
        double _c46 = (_c39 * sb);
        double _c47 = (sa * sa);
        double _c48 = (((2.0 * _c45) * ca) * ila);
        double _c49 = (ca * ca);
        double _c50 = (_c41 * sa);
        double _c51 = (_c41 * ca);
        double _c52 = (sb * sb);
        double _c53 = (((2.0 * _c46) * cb) * ilb);
        double _c54 = (cb * cb);
        double _c57 = ((_c40 * _c47) + _c48);
        double _c58 = (((_c38 * ila) * (_c47 - _c49)) - ((_c40 * ca) * sa));
        double _c59 = (_c50 * sb);
        double _c60 = (_c50 * cb);
        double _c61 = (_c42 * sa);
        double _c62 = ((_c40 * _c49) - _c48);
        double _c63 = (_c51 * sb);
        double _c64 = (_c51 * cb);
        double _c65 = (_c42 * ca);
        double _c66 = ((_c43 * _c52) + _c53);
        double _c67 = (((_c39 * ilb) * (_c52 - _c54)) - ((_c43 * cb) * sb));
        double _c68 = (_c44 * sb);
        double _c69 = ((_c43 * _c54) - _c53);
        double _c70 = (_c44 * cb);
        double _c71 = (_c58 + _c60);
        double _c75 = (_c63 + _c67);
        out[0 * _m + _i] = _c57;
        out[1 * _m + _i] = _c58;
        out[2 * _m + _i] = (((-_c57) + _c59) + _c61);
        out[3 * _m + _i] = (-_c71);
        out[4 * _m + _i] = (-_c59);
        out[5 * _m + _i] = _c60;
        out[6 * _m + _i] = _c62;
        out[7 * _m + _i] = (((-_c58) - _c63) - _c65);
        out[8 * _m + _i] = ((-_c62) + _c64);
        out[9 * _m + _i] = _c63;
        out[10 * _m + _i] = (-_c64);
        out[11 * _m + _i] = (((((_c37 + _c57) - (2.0 * _c59)) - (2.0 * _c61)) + _c66) + (2.0 * _c68));
        out[12 * _m + _i] = (((_c65 - _c70) + _c71) + _c75);
        out[13 * _m + _i] = ((_c59 - _c66) - _c68);
        out[14 * _m + _i] = (((-_c60) - _c67) + _c70);
        out[15 * _m + _i] = ((_c62 - (2.0 * _c64)) + _c69);
        out[16 * _m + _i] = (-_c75);
        out[17 * _m + _i] = (_c64 - _c69);
        out[18 * _m + _i] = _c66;
        out[19 * _m + _i] = _c67;
        out[20 * _m + _i] = _c69;
    }
    release(in, 11, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_bend_fast_gradient_hessian(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {27};
    Input in[11];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("bend_fast_gradient_hessian", args, nargs, in, 11, outputs, 1, rows, &_m) < 0) {
        release(in, 11, outputs, 1);
        return NULL;
    }
    double *out = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double ar = in[0].data[_i * in[0].stride];
        const double az = in[1].data[_i * in[1].stride];
        const double br = in[2].data[_i * in[2].stride];
        const double bz = in[3].data[_i * in[3].stride];
        const double r1 = in[4].data[_i * in[4].stride];
        const double lbar = in[5].data[_i * in[5].stride];
        const double rbar = in[6].data[_i * in[6].stride];
        const double k11bar = in[7].data[_i * in[7].stride];
        const double k22bar = in[8].data[_i * in[8].stride];
        const double kb = in[9].data[_i * in[9].stride];
        const double nu = in[10].data[_i * in[10].stride];
        double la = sqrt(((ar * ar) + (az * az)));
        double lb = sqrt(((br * br) + (bz * bz)));
        double ila = (1.0 / la);
        double ilb = (1.0 / lb);
        double ca = (ar * ila);
        double sa = (az * ila);
        double cb = (br * ilb);
        double sb = (bz * ilb);
        double lab = (la * lb);
        double den = (((ar * br) + (az * bz)) + lab);
        double tn = (((ar * bz) - (az * br)) / den);
        double it2 = (((1.0 / 2.0) * lab) / den);
        double it = sqrt(it2);
        double sphi = (it * (sa + sb));
        double cphi = (it * (ca + cb));
        double ir = (1.0 / r1);
        double k22 = (ir * sphi);
        double k11 = ((2.0 * tn) / lbar);
        double kq = ((((2.0 * 3.141592653589793) * kb) * lbar) * rbar);
        double kqnu = (kq * nu);
        double _c0 = (k11 - k11bar);
        double _c1 = (k22 - k22bar);
        double _c2 = (1.0 / lbar);
        double _c3 = ((tn * tn) + 1.0);
        double _c4 = ((-_c2) * _c3);
        double _c6 = ((1.0 / 2.0) * cphi);
        double _c7 = (_c6 * ir);
        double _c8 = ((-_c4) * tn);
        double _c9 = (((-1.0) / 4.0) * k22);
        double _c10 = (ir * ir);
        double _c11 = ((-_c10) * _c6);
        double _c12 = ((_c0 * kq) + (_c1 * kqnu));
        double _c13 = ((_c0 * kqnu) + (_c1 * kq));
        double _c14 = (ir * k22);
        double _c15 = ((2.0 * _c10) * k22);
        double _c16 = (_c4 * kq);
        double _c17 = (_c4 * kqnu);
        double _c18 = (_c16 + (_c7 * kqnu));
        double _c19 = ((-_c16) + (_c7 * kqnu));
        double _c21 = (_c17 + (_c7 * kq));
        double _c22 = ((-_c17) + (_c7 * kq));
        double _c23 = (_c14 * kq);
        double _c24 = (_c12 * _c4);
        double _c25 = (_c13 * _c9);
        double _c26 = (_c12 * _c8);
        double _c27 = ((_c18 * _c4) + _c26);
        double _c28 = (_c11 * _c13);
        double _c29 = ((_c13 * _c7) + _c24);
        double _c30 = ((_c13 * _c7) - _c24);
        double _c31 = (_c13 * _c14);
        double _c32 = (((_c21 * _c7) + _c25) + _c27);
        double _c33 = (((_c13 * _c9) + (_c21 * _c7)) - _c27);
        double _c34 = (((-_c14) * _c21) + _c28);
        double _c35 = (((((-_c19) * _c4) + (_c22 * _c7)) + _c25) + _c26);
        double _c36 = (((-_c14) * _c22) + _c28);
        double _c37 = ((_c13 * _c15) + (_c14 * _c23));
        double _c38 = (_c29 * ila);
        double _c39 = (_c30 * ilb);
        double _c40 = (_c32 * (ila * ila));
        double _c41 = ((_c33 * ila) * ilb);
        double _c42 = (_c34 * ila);
        double _c43 = (_c35 * (ilb * ilb));
        double _c44 = (_c36 * ilb);
        double _c45 = (_c38 * sa);
        double _c46 = (_c39 * sb);
        double _c47 = (sa * sa);
        double _c48 = (((2.0 * _c45) * ca) * ila);
        double _c49 = (ca * ca);
        double _c50 = (_c41 * sa);
        double _c51 = (_c41 * ca);
        double _c52 = (sb * sb);
        double _c53 = (((2.0 * _c46) * cb) * ilb);
        double _c54 = (cb * cb);
        double _c55 = (_c38 * ca);
        double _c56 = (_c39 * cb);
        double _c57 = ((_c40 * _c47) + _c48);
        double _c58 = (((_c38 * ila) * (_c47 - _c49)) - ((_c40 * ca) * sa));
        double _c59 = (_c50 * sb);
        double _c60 = (_c50 * cb);
        double _c61 = (_c42 * sa);
        double _c62 = ((_c40 * _c49) - _c48);
        double _c63 = (_c51 * sb);
        double _c64 = (_c51 * cb);
        double _c65 = (_c42 * ca);
        double _c66 = ((_c43 * _c52) + _c53);
        double _c67 = (((_c39 * ilb) * (_c52 - _c54)) - ((_c43 * cb) * sb));
        double _c68 = (_c44 * sb);
        double _c69 = ((_c43 * _c54) - _c53);
        double _c70 = (_c44 * cb);
        double _c72 = (_c58 + _c60);
        double _c76 = (_c63 + _c67);
        out[0 * _m + _i] = _c45;
        out[1 * _m + _i] = (-_c55);
        out[2 * _m + _i] = (((-_c31) - _c45) + _c46);
        out[3 * _m + _i] = (_c55 - _c56);
        out[4 * _m + _i] = (-_c46);
        out[5 * _m + _i] = _c56;
        out[6 * _m + _i] = _c57;
        out[7 * _m + _i] = _c58;
        out[8 * _m + _i] = (((-_c57) + _c59) + _c61);
        out[9 * _m + _i] = (-_c72);
        out[10 * _m + _i] = (-_c59);
        out[11 * _m + _i] = _c60;
        out[12 * _m + _i] = _c62;
        out[13 * _m + _i] = (((-_c58) - _c63) - _c65);
        out[14 * _m + _i] = ((-_c62) + _c64);
        out[15 * _m + _i] = _c63;
        out[16 * _m + _i] = (-_c64);
        out[17 * _m + _i] = (((((_c37 + _c57) - (2.0 * _c59)) - (2.0 * _c61)) + _c66) + (2.0 * _c68));
        out[18 * _m + _i] = (((_c65 - _c70) + _c72) + _c76);
        out[19 * _m + _i] = ((_c59 - _c66) - _c68);
        out[20 * _m + _i] = (((-_c60) - _c67) + _c70);
        out[21 * _m + _i] = ((_c62 - (2.0 * _c64)) + _c69);
        out[22 * _m + _i] = (-_c76);
        out[23 * _m + _i] = (_c64 - _c69);
        out[24 * _m + _i] = _c66;
        out[25 * _m + _i] = _c67;
        out[26 * _m + _i] = _c69;
    }
    release(in, 11, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_bend_cur_fast_gradient(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {6};
    Input in[11];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("bend_cur_fast_gradient", args, nargs, in, 11, outputs, 1, rows, &_m) < 0) {
        release(in, 11, outputs, 1);
        return NULL;
    }
    double *out = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double ar = in[0].data[_i * in[0].stride];
        const double az = in[1].data[_i * in[1].stride];
        const double br = in[2].data[_i * in[2].stride];
        const double bz = in[3].data[_i * in[3].stride];
        const double r1 = in[4].data[_i * in[4].stride];
        const double lbar = in[5].data[_i * in[5].stride];
        const double rbar = in[6].data[_i * in[6].stride];
        const double k11bar = in[7].data[_i * in[7].stride];
        const double k22bar = in[8].data[_i * in[8].stride];
        const double kb = in[9].data[_i * in[9].stride];
        const double nu = in[10].data[_i * in[10].stride];
        double la = sqrt(((ar * ar) + (az * az)));
        double lb = sqrt(((br * br) + (bz * bz)));
        double ila = (1.0 / la);
        double ilb = (1.0 / lb);
        double ca = (ar * ila);
        double sa = (az * ila);
        double cb = (br * ilb);
        double sb = (bz * ilb);
        double lab = (la * lb);
        double den = (((ar * br) + (az * bz)) + lab);
        double tn = (((ar * bz) - (az * br)) / den);
        double it2 = (((1.0 / 2.0) * lab) / den);
        double it = sqrt(it2);
        double sphi = (it * (sa + sb));
        double cphi = (it * (ca + cb));
        double ir = (1.0 / r1);
        double k22 = (ir * sphi);
        double isum = (1.0 / (la + lb));
        double k11 = ((4.0 * isum) * tn);
        double kq = ((((2.0 * 3.141592653589793) * kb) * lbar) * rbar);
        double kqnu = (kq * nu);
        double _c0 = (k11 - k11bar);
        double _c1 = (k22 - k22bar);
        double _c2 = ((-isum) * k11);
        double _c3 = (((1.0 / 2.0) * (tn * tn)) + (1.0 / 2.0));
        double _c4 = (4.0 * isum);
        double _c5 = (((1.0 / 2.0) * cphi) * ir);
        double _c6 = ((_c0 * kq) + (_c1 * kqnu));
        double _c7 = ((_c0 * kqnu) + (_c1 * kq));
        double _c8 = (_c3 * _c4);
        double _c9 = (ir * k22);
        double _c10 = (_c2 * _c6);
        double _c11 = (_c5 * _c7);
        double _c12 = (_c6 * _c8);
        double _c13 = (_c11 - _c12);
        double _c14 = (_c11 + _c12);
        double _c15 = (_c7 * _c9);
        double _c16 = (_c13 * ila);
        double _c17 = (_c14 * ilb);
        double _c18 = ((_c10 * ca) - (_c16 * sa));
        double _c19 = ((_c10 * sa) + (_c16 * ca));
        double _c20 = ((_c10 * cb) - (_c17 * sb));
        double _c21 = ((_c10 * sb) + (_c17 * cb));
        out[0 * _m + _i] = (-_c18);
        out[1 * _m + _i] = (-_c19);
        out[2 * _m + _i] = (((-_c15) + _c18) - _c20);
        out[3 * _m + _i] = (_c19 - _c21);
        out[4 * _m + _i] = _c20;
        out[5 * _m + _i] = _c21;
    }
    release(in, 11, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_bend_cur_fast_hessian(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {21};
    Input in[11];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("bend_cur_fast_hessian", args, nargs, in, 11, outputs, 1, rows, &_m) < 0) {
        release(in, 11, outputs, 1);
        return NULL;
    }
    double *out = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double ar = in[0].data[_i * in[0].stride];
        const double az = in[1].data[_i * in[1].stride];
        const double br = in[2].data[_i * in[2].stride];
        const double bz = in[3].data[_i * in[3].stride];
        const double r1 = in[4].data[_i * in[4].stride];
        const double lbar = in[5].data[_i * in[5].stride];
        const double rbar = in[6].data[_i * in[6].stride];
        const double k11bar = in[7].data[_i * in[7].stride];
        const double k22bar = in[8].data[_i * in[8].stride];
        const double kb = in[9].data[_i * in[9].stride];
        const double nu = in[10].data[_i * in[10].stride];
        double la = sqrt(((ar * ar) + (az * az)));
        double lb = sqrt(((br * br) + (bz * bz)));
        double ila = (1.0 / la);
        double ilb = (1.0 / lb);
        double ca = (ar * ila);
        double sa = (az * ila);
        double cb = (br * ilb);
        double sb = (bz * ilb);
        double lab = (la * lb);
        double den = (((ar * br) + (az * bz)) + lab);
        double tn = (((ar * bz) - (az * br)) / den);
        double it2 = (((1.0 / 2.0) * lab) / den);
        double it = sqrt(it2);
        double sphi = (it * (sa + sb));
        double cphi = (it * (ca + cb));
        double ir = (1.0 / r1);
        double k22 = (ir * sphi);
        double isum = (1.0 / (la + lb));
        double k11 = ((4.0 * isum) * tn);
        double kq = ((((2.0 * 3.141592653589793) * kb) * lbar) * rbar);
        double kqnu = (kq * nu);
        double _c0 = (k11 - k11bar);
        double _c1 = (k22 - k22bar);
        double _c2 = ((-isum) * k11);
        double _c3 = (tn * tn);
        double _c4 = (((1.0 / 2.0) * _c3) + (1.0 / 2.0));
        double _c6 = (4.0 * isum);
        double _c7 = ((1.0 / 2.0) * cphi);
        double _c8 = (_c7 * ir);
        double _c9 = (isum * isum);
        double _c10 = ((2.0 * _c9) * k11);
        double _c11 = (4.0 * _c9);
        double _c12 = (_c11 * _c4);
        double _c14 = (_c3 + 1.0);
        double _c15 = ((2.0 * isum) * tn);
        double _c16 = (_c14 * _c15);
        double _c17 = (((-1.0) / 4.0) * k22);
        double _c18 = (ir * ir);
        double _c19 = ((-_c18) * _c7);
        double _c20 = ((_c0 * kq) + (_c1 * kqnu));
        double _c21 = ((_c0 * kqnu) + (_c1 * kq));
        double _c22 = (_c4 * _c6);
        double _c23 = (ir * k22);
        double _c24 = ((2.0 * _c18) * k22);
        double _c25 = (_c2 * kq);
        double _c26 = (_c22 * kq);
        double _c27 = (_c2 * kqnu);
        double _c28 = (_c22 * kqnu);
        double _c29 = ((-_c26) + (_c8 * kqnu));
        double _c30 = (_c26 + (_c8 * kqnu));
        double _c32 = ((-_c28) + (_c8 * kq));
        double _c33 = (_c28 + (_c8 * kq));
        double _c34 = (_c23 * kq);
        double _c35 = (_c2 * _c20);
        double _c36 = (_c20 * _c22);
        double _c37 = ((_c10 * _c20) + (_c2 * _c25));
        double _c38 = (_c12 * _c20);
        double _c39 = (_c27 * _c8);
        double _c40 = (_c22 * _c25);
        double _c41 = (((-_c38) + _c39) + _c40);
        double _c42 = ((-_c23) * _c27);
        double _c43 = (_c16 * _c20);
        double _c44 = (_c22 * _c29);
        double _c45 = (_c17 * _c21);
        double _c46 = ((_c32 * _c8) + _c45);
        double _c47 = (_c19 * _c21);
        double _c48 = ((_c21 * _c8) - _c36);
        double _c49 = ((_c21 * _c8) + _c36);
        double _c51 = ((_c38 + _c39) - _c40);
        double _c52 = ((_c43 - _c44) + _c46);
        double _c53 = ((_c2 * _c29) + _c38);
        double _c54 = (((-_c43) + _c44) + _c46);
        double _c55 = (((-_c23) * _c32) + _c47);
        double _c56 = ((((_c22 * _c30) + (_c33 * _c8)) + _c43) + _c45);
        double _c57 = (((-_c23) * _c33) + _c47);
        double _c58 = ((_c21 * _c24) + (_c23 * _c34));
        double _c59 = (_c41 * ilb);
        double _c60 = (_c48 * ila);
        double _c61 = (_c49 * ilb);
        double _c62 = (_c51 * ila);
        double _c63 = (_c52 * (ila * ila));
        double _c64 = (_c53 * ila);
        double _c65 = ((_c54 * ila) * ilb);
        double _c66 = (_c55 * ila);
        double _c67 = (_c56 * (ilb * ilb));
        double _c68 = (_c57 * ilb);
        double _c69 = ((ca * ca) - (sa * sa));
        double _c70 = ((2.0 * ca) * sa);
        double _c71 = ((((1.0 / 2.0) * _c35) * ila) + ((1.0 / 2.0) * _c63));
        double _c72 = (((1.0 / 2.0) * _c37) + _c71);
        double _c73 = (((1.0 / 2.0) * _c37) - _c71);
        double _c74 = ((_c60 * ila) - _c62);
        double _c75 = ((_c69 * _c73) + (_c70 * _c74));
        double _c76 = ((cb * cb) - (sb * sb));
        double _c77 = ((2.0 * cb) * sb);
        double _c78 = ((((1.0 / 2.0) * _c35) * ilb) + ((1.0 / 2.0) * _c67));
        double _c79 = (((1.0 / 2.0) * _c37) + _c78);
        double _c80 = (((1.0 / 2.0) * _c37) - _c78);
        double _c81 = ((-_c59) + (_c61 * ilb));
        double _c82 = ((_c76 * _c80) + (_c77 * _c81));
        double _c83 = ((_c37 * cb) - (_c59 * sb));
        double _c84 = ((_c37 * sb) + (_c59 * cb));
        double _c85 = ((_c64 * cb) - (_c65 * sb));
        double _c86 = ((_c64 * sb) + (_c65 * cb));
        double _c91 = (_c72 + _c75);
        double _c92 = (((-_c69) * _c74) + (_c70 * _c73));
        double _c93 = ((_c83 * ca) - (_c85 * sa));
        double _c94 = ((_c84 * ca) - (_c86 * sa));
        double _c95 = ((_c42 * ca) - (_c66 * sa));
        double _c96 = (_c72 - _c75);
        double _c97 = ((_c83 * sa) + (_c85 * ca));
        double _c98 = ((_c84 * sa) + (_c86 * ca));
        double _c99 = ((_c42 * sa) + (_c66 * ca));
        double _c100 = (_c79 + _c82);
        double _c101 = (((-_c76) * _c81) + (_c77 * _c80));
        double _c102 = ((_c42 * cb) - (_c68 * sb));
        double _c103 = (_c79 - _c82);
        double _c104 = ((_c42 * sb) + (_c68 * cb));
        double _c107 = (_c92 - _c94);
        double _c110 = (_c101 - _c97);
        out[0 * _m + _i] = _c91;
        out[1 * _m + _i] = _c92;
        out[2 * _m + _i] = (((-_c91) + _c93) - _c95);
        out[3 * _m + _i] = (-_c107);
        out[4 * _m + _i] = (-_c93);
        out[5 * _m + _i] = (-_c94);
        out[6 * _m + _i] = _c96;
        out[7 * _m + _i] = (((-_c92) + _c97) - _c99);
        out[8 * _m + _i] = ((-_c96) + _c98);
        out[9 * _m + _i] = (-_c97);
        out[10 * _m + _i] = (-_c98);
        out[11 * _m + _i] = (((((_c100 - (2.0 * _c102)) + _c58) + _c91) - (2.0 * _c93)) + (2.0 * _c95));
        out[12 * _m + _i] = ((((-_c104) + _c107) + _c110) + _c99);
        out[13 * _m + _i] = (((-_c100) + _c102) + _c93);
        out[14 * _m + _i] = (((-_c101) + _c104) + _c94);
        out[15 * _m + _i] = ((_c103 + _c96) - (2.0 * _c98));
        out[16 * _m + _i] = (-_c110);
        out[17 * _m + _i] = ((-_c103) + _c98);
        out[18 * _m + _i] = _c100;
        out[19 * _m + _i] = _c101;
        out[20 * _m + _i] = _c103;
    }
    release(in, 11, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_bend_cur_fast_gradient_hessian(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {27};
    Input in[11];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("bend_cur_fast_gradient_hessian", args, nargs, in, 11, outputs, 1, rows, &_m) < 0) {
        release(in, 11, outputs, 1);
        return NULL;
    }
    double *out = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double ar = in[0].data[_i * in[0].stride];
        const double az = in[1].data[_i * in[1].stride];
        const double br = in[2].data[_i * in[2].stride];
        const double bz = in[3].data[_i * in[3].stride];
        const double r1 = in[4].data[_i * in[4].stride];
        const double lbar = in[5].data[_i * in[5].stride];
        const double rbar = in[6].data[_i * in[6].stride];
        const double k11bar = in[7].data[_i * in[7].stride];
        const double k22bar = in[8].data[_i * in[8].stride];
        const double kb = in[9].data[_i * in[9].stride];
        const double nu = in[10].data[_i * in[10].stride];
        double la = sqrt(((ar * ar) + (az * az)));
        double lb = sqrt(((br * br) + (bz * bz)));
        double ila = (1.0 / la);
        double ilb = (1.0 / lb);
        double ca = (ar * ila);
        double sa = (az * ila);
        double cb = (br * ilb);
        double sb = (bz * ilb);
        double lab = (la * lb);
        double den = (((ar * br) + (az * bz)) + lab);
        double tn = (((ar * bz) - (az * br)) / den);
        double it2 = (((1.0 / 2.0) * lab) / den);
        double it = sqrt(it2);
        double sphi = (it * (sa + sb));
        double cphi = (it * (ca + cb));
        double ir = (1.0 / r1);
        double k22 = (ir * sphi);
        double isum = (1.0 / (la + lb));
        double k11 = ((4.0 * isum) * tn);
        double kq = ((((2.0 * 3.141592653589793) * kb) * lbar) * rbar);
        double kqnu = (kq * nu);
        double _c0 = (k11 - k11bar);
        double _c1 = (k22 - k22bar);
        double _c2 = ((-isum) * k11);
        double _c3 = (tn * tn);
        double _c4 = (((1.0 / 2.0) * _c3) + (1.0 / 2.0));
        double _c6 = (4.0 * isum);
        double _c7 = ((1.0 / 2.0) * cphi);
        double _c8 = (_c7 * ir);
        double _c9 = (isum * isum);
        double _c10 = ((2.0 * _c9) * k11);
        double _c11 = (4.0 * _c9);
        double _c12 = (_c11 * _c4);
        double _c14 = (_c3 + 1.0);
        double _c15 = ((2.0 * isum) * tn);
        double _c16 = (_c14 * _c15);
        double _c17 = (((-1.0) / 4.0) * k22);
        double _c18 = (ir * ir);
        double _c19 = ((-_c18) * _c7);
        double _c20 = ((_c0 * kq) + (_c1 * kqnu));
        double _c21 = ((_c0 * kqnu) + (_c1 * kq));
        double _c22 = (_c4 * _c6);
        double _c23 = (ir * k22);
        double _c24 = ((2.0 * _c18) * k22);
        double _c25 = (_c2 * kq);
        double _c26 = (_c22 * kq);
        double _c27 = (_c2 * kqnu);
        double _c28 = (_c22 * kqnu);
        double _c29 = ((-_c26) + (_c8 * kqnu));
        double _c30 = (_c26 + (_c8 * kqnu));
        double _c32 = ((-_c28) + (_c8 * kq));
        double _c33 = (_c28 + (_c8 * kq));
        double _c34 = (_c23 * kq);
        double _c35 = (_c2 * _c20);
        double _c36 = (_c20 * _c22);
        double _c37 = ((_c10 * _c20) + (_c2 * _c25));
        double _c38 = (_c12 * _c20);
        double _c39 = (_c27 * _c8);
        double _c40 = (_c22 * _c25);
        double _c41 = (((-_c38) + _c39) + _c40);
        double _c42 = ((-_c23) * _c27);
        double _c43 = (_c16 * _c20);
        double _c44 = (_c22 * _c29);
        double _c45 = (_c17 * _c21);
        double _c46 = ((_c32 * _c8) + _c45);
        double _c47 = (_c19 * _c21);
        double _c48 = ((_c21 * _c8) - _c36);
        double _c49 = ((_c21 * _c8) + _c36);
        double _c50 = (_c21 * _c23);
        double _c51 = ((_c38 + _c39) - _c40);
        double _c52 = ((_c43 - _c44) + _c46);
        double _c53 = ((_c2 * _c29) + _c38);
        double _c54 = (((-_c43) + _c44) + _c46);
        double _c55 = (((-_c23) * _c32) + _c47);
        double _c56 = ((((_c22 * _c30) + (_c33 * _c8)) + _c43) + _c45);
        double _c57 = (((-_c23) * _c33) + _c47);
        double _c58 = ((_c21 * _c24) + (_c23 * _c34));
        double _c59 = (_c41 * ilb);
        double _c60 = (_c48 * ila);
        double _c61 = (_c49 * ilb);
        double _c62 = (_c51 * ila);
        double _c63 = (_c52 * (ila * ila));
        double _c64 = (_c53 * ila);
        double _c65 = ((_c54 * ila) * ilb);
        double _c66 = (_c55 * ila);
        double _c67 = (_c56 * (ilb * ilb));
        double _c68 = (_c57 * ilb);
        double _c69 = ((ca * ca) - (sa * sa));
        double _c70 = ((2.0 * ca) * sa);
        double _c71 = ((((1.0 / 2.0) * _c35) * ila) + ((1.0 / 2.0) * _c63));
        double _c72 = (((1.0 / 2.0) * _c37) + _c71);
        double _c73 = (((1.0 / 2.0) * _c37) - _c71);
        double _c74 = ((_c60 * ila) - _c62);
        double _c75 = ((_c69 * _c73) + (_c70 * _c74));
        double _c76 = ((cb * cb) - (sb * sb));
        double _c77 = ((2.0 * cb) * sb);
        double _c78 = ((((1.0 / 2.0) * _c35) * ilb) + ((1.0 / 2.0) * _c67));
        double _c79 = (((1.0 / 2.0) * _c37) + _c78);
        double _c80 = (((1.0 / 2.0) * _c37) - _c78);
        double _c81 = ((-_c59) + (_c61 * ilb));
        double _c82 = ((_c76 * _c80) + (_c77 * _c81));
        double _c83 = ((_c37 * cb) - (_c59 * sb));
        double _c84 = ((_c37 * sb) + (_c59 * cb));
        double _c85 = ((_c64 * cb) - (_c65 * sb));
        double _c86 = ((_c64 * sb) + (_c65 * cb));
        double _c87 = ((_c35 * ca) - (_c60 * sa));
        double _c88 = ((_c35 * sa) + (_c60 * ca));
        double _c89 = ((_c35 * cb) - (_c61 * sb));
        double _c90 = ((_c35 * sb) + (_c61 * cb));
        double _c91 = (_c72 + _c75);
        double _c92 = (((-_c69) * _c74) + (_c70 * _c73));
        double _c93 = ((_c83 * ca) - (_c85 * sa));
        double _c94 = ((_c84 * ca) - (_c86 * sa));
        double _c95 = ((_c42 * ca) - (_c66 * sa));
        double _c96 = (_c72 - _c75);
        double _c97 = ((_c83 * sa) + (_c85 * ca));
        double _c98 = ((_c84 * sa) + (_c86 * ca));
        double _c99 = ((_c42 * sa) + (_c66 * ca));
        double _c100 = (_c79 + _c82);
        double _c101 = (((-_c76) * _c81) + (_c77 * _c80));
        double _c102 = ((_c42 * cb) - (_c68 * sb));
        double _c103 = (_c79 - _c82);
        double _c104 = ((_c42 * sb) + (_c68 * cb));
        double _c108 = (_c92 - _c94);
        double _c111 = (_c101 - _c97);
        out[0 * _m + _i] = (-_c87);
        out[1 * _m + _i] = (-_c88);
        out[2 * _m + _i] = (((-_c50) + _c87) - _c89);
        out[3 * _m + _i] = (_c88 - _c90);
        out[4 * _m + _i] = _c89;
        out[5 * _m + _i] = _c90;
        out[6 * _m + _i] = _c91;
        out[7 * _m + _i] = _c92;
        out[8 * _m + _i] = (((-_c91) + _c93) - _c95);
        out[9 * _m + _i] = (-_c108);
        out[10 * _m + _i] = (-_c93);
        out[11 * _m + _i] = (-_c94);
        out[12 * _m + _i] = _c96;
        out[13 * _m + _i] = (((-_c92) + _c97) - _c99);
        out[14 * _m + _i] = ((-_c96) + _c98);
        out[15 * _m + _i] = (-_c97);
        out[16 * _m + _i] = (-_c98);
        out[17 * _m + _i] = (((((_c100 - (2.0 * _c102)) + _c58) + _c91) - (2.0 * _c93)) + (2.0 * _c95));
        out[18 * _m + _i] = ((((-_c104) + _c108) + _c111) + _c99);
        out[19 * _m + _i] = (((-_c100) + _c102) + _c93);
        out[20 * _m + _i] = (((-_c101) + _c104) + _c94);
        out[21 * _m + _i] = ((_c103 + _c96) - (2.0 * _c98));
        out[22 * _m + _i] = (-_c111);
        out[23 * _m + _i] = ((-_c103) + _c98);
        out[24 * _m + _i] = _c100;
        out[25 * _m + _i] = _c101;
        out[26 * _m + _i] = _c103;
    }
    release(in, 11, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_stretch_fast_gradient(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {4};
    Input in[7];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("stretch_fast_gradient", args, nargs, in, 7, outputs, 1, rows, &_m) < 0) {
        release(in, 7, outputs, 1);
        return NULL;
    }
    double *out = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double er = in[0].data[_i * in[0].stride];
        const double ez = in[1].data[_i * in[1].stride];
        const double rs = in[2].data[_i * in[2].stride];
        const double lbar = in[3].data[_i * in[3].stride];
        const double rbar = in[4].data[_i * in[4].stride];
        const double ks = in[5].data[_i * in[5].stride];
        const double nu = in[6].data[_i * in[6].stride];
        double l = sqrt(((er * er) + (ez * ez)));
        double il = (1.0 / l);
        double c = (er * il);
        double s = (ez * il);
        double eps11 = ((l / lbar) - 1.0);
        double eps22 = ((-1.0) + (((1.0 / 2.0) * rs) / rbar));
        double kq = ((((2.0 * 3.141592653589793) * ks) * lbar) * rbar);
        double kqnu = (kq * nu);
        double _c0 = ((eps11 * kq) + (eps22 * kqnu));
        double _c1 = ((eps11 * kqnu) + (eps22 * kq));
        double _c2 = (1.0 / lbar);
        double _c3 = ((1.0 / 2.0) / rbar);
        double _c4 = (_c0 * _c2);
        double _c5 = (_c1 * _c3);
        double _c6 = (_c4 * c);
        double _c7 = (_c4 * s);
        out[0 * _m + _i] = (_c5 - _c6);
        out[1 * _m + _i] = (-_c7);
        out[2 * _m + _i] = (_c5 + _c6);
        out[3 * _m + _i] = _c7;
    }
    release(in, 7, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_stretch_fast_hessian(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {10};
    Input in[7];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("stretch_fast_hessian", args, nargs, in, 7, outputs, 1, rows, &_m) < 0) {
        release(in, 7, outputs, 1);
        return NULL;
    }
    double *out = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double er = in[0].data[_i * in[0].stride];
        const double ez = in[1].data[_i * in[1].stride];
        const double rs = in[2].data[_i * in[2].stride];
        const double lbar = in[3].data[_i * in[3].stride];
        const double rbar = in[4].data[_i * in[4].stride];
        const double ks = in[5].data[_i * in[5].stride];
        const double nu = in[6].data[_i * in[6].stride];
        double l = sqrt(((er * er) + (ez * ez)));
        double il = (1.0 / l);
        double c = (er * il);
        double s = (ez * il);
        double eps11 = ((l / lbar) - 1.0);
        double eps22 = ((-1.0) + (((1.0 / 2.0) * rs) / rbar));
        double kq = ((((2.0 * 3.141592653589793) * ks) * lbar) * rbar);
        double kqnu = (kq * nu);
        double _c0 = ((eps11 * kq) + (eps22 * kqnu));
        double _c2 = (1.0 / lbar);
        double _c3 = ((1.0 / 2.0) / rbar);
        double _c4 = (_c2 * kq);
        double _c6 = (_c2 * kqnu);
        double _c7 = (_c3 * kq);
        double _c8 = (_c0 * _c2);
        double _c10 = (_c2 * _c4);
        double _c11 = (_c3 * _c6);
        double _c12 = (_c3 * _c7);
        double _c13 = ((c * c) - (s * s));
        double _c14 = ((2.0 * c) * s);
        double _c15 = ((1.0 / 2.0) * _c10);
        double _c16 = (((1.0 / 2.0) * _c8) * il);
        double _c17 = (_c15 + _c16);
        double _c18 = (_c15 - _c16);
        double _c19 = (_c13 * _c18);
        double _c22 = (_c17 + _c19);
        double _c23 = (_c14 * _c18);
        double _c24 = (_c11 * c);
        double _c25 = (_c17 - _c19);
        double _c26 = (_c11 * s);
        double _c27 = (2.0 * _c24);
        double _c28 = (_c12 + _c22);
        double _c29 = (_c23 - _c26);
        double _c30 = (_c23 + _c26);
        out[0 * _m + _i] = ((-_c27) + _c28);
        out[1 * _m + _i] = _c29;
        out[2 * _m + _i] = (_c12 - _c22);
        out[3 * _m + _i] = (-_c29);
        out[4 * _m + _i] = _c25;
        out[5 * _m + _i] = (-_c30);
        out[6 * _m + _i] = (-_c25);
        out[7 * _m + _i] = (_c27 + _c28);
        out[8 * _m + _i] = _c30;
        out[9 * _m + _i] = _c25;
    }
    release(in, 7, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_stretch_fast_gradient_hessian(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {14};
    Input in[7];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("stretch_fast_gradient_hessian", args, nargs, in, 7, outputs, 1, rows, &_m) < 0) {
        release(in, 7, outputs, 1);
        return NULL;
    }
    double *out = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double er = in[0].data[_i * in[0].stride];
        const double ez = in[1].data[_i * in[1].stride];
        const double rs = in[2].data[_i * in[2].stride];
        const double lbar = in[3].data[_i * in[3].stride];
        const double rbar = in[4].data[_i * in[4].stride];
        const double ks = in[5].data[_i * in[5].stride];
        const double nu = in[6].data[_i * in[6].stride];
        double l = sqrt(((er * er) + (ez * ez)));
        double il = (1.0 / l);
        double c = (er * il);
        double s = (ez * il);
        double eps11 = ((l / lbar) - 1.0);
        double eps22 = ((-1.0) + (((1.0 / 2.0) * rs) / rbar));
        double kq = ((((2.0 * 3.141592653589793) * ks) * lbar) * rbar);
        double kqnu = (kq * nu);
        double _c0 = ((eps11 * kq) + (eps22 * kqnu));
        double _c1 = ((eps11 * kqnu) + (eps22 * kq));
        double _c2 = (1.0 / lbar);
        double _c3 = ((1.0 / 2.0) / rbar);
        double _c4 = (_c2 * kq);
        double _c6 = (_c2 * kqnu);
        double _c7 = (_c3 * kq);
        double _c8 = (_c0 * _c2);
        double _c9 = (_c1 * _c3);
        double _c10 = (_c2 * _c4);
        double _c11 = (_c3 * _c6);
        double _c12 = (_c3 * _c7);
        double _c13 = ((c * c) - (s * s));
        double _c14 = ((2.0 * c) * s);
        double _c15 = ((1.0 / 2.0) * _c10);
        double _c16 = (((1.0 / 2.0) * _c8) * il);
        double _c17 = (_c15 + _c16);
        double _c18 = (_c15 - _c16);
        double _c19 = (_c13 * _c18);
        double _c20 = (_c8 * c);
        double _c21 = (_c8 * s);
        double _c22 = (_c17 + _c19);
        double _c23 = (_c14 * _c18);
        double _c24 = (_c11 * c);
        double _c25 = (_c17 - _c19);
        double _c26 = (_c11 * s);
        double _c27 = (2.0 * _c24);
        double _c28 = (_c12 + _c22);
        double _c29 = (_c23 - _c26);
        double _c30 = (_c23 + _c26);
        out[0 * _m + _i] = ((-_c20) + _c9);
        out[1 * _m + _i] = (-_c21);
        out[2 * _m + _i] = (_c20 + _c9);
        out[3 * _m + _i] = _c21;
        out[4 * _m + _i] = ((-_c27) + _c28);
        out[5 * _m + _i] = _c29;
        out[6 * _m + _i] = (_c12 - _c22);
        out[7 * _m + _i] = (-_c29);
        out[8 * _m + _i] = _c25;
        out[9 * _m + _i] = (-_c30);
        out[10 * _m + _i] = (-_c25);
        out[11 * _m + _i] = (_c27 + _c28);
        out[12 * _m + _i] = _c30;
        out[13 * _m + _i] = _c25;
    }
    release(in, 7, outputs, 1);
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"bend_fast_gradient", (PyCFunction)(void (*)(void))c_bend_fast_gradient, METH_FASTCALL, "bend_fast_gradient(*inputs, out)"},
    {"bend_fast_hessian", (PyCFunction)(void (*)(void))c_bend_fast_hessian, METH_FASTCALL, "bend_fast_hessian(*inputs, out)"},
    {"bend_fast_gradient_hessian", (PyCFunction)(void (*)(void))c_bend_fast_gradient_hessian, METH_FASTCALL, "bend_fast_gradient_hessian(*inputs, out)"},
    {"bend_cur_fast_gradient", (PyCFunction)(void (*)(void))c_bend_cur_fast_gradient, METH_FASTCALL, "bend_cur_fast_gradient(*inputs, out)"},
    {"bend_cur_fast_hessian", (PyCFunction)(void (*)(void))c_bend_cur_fast_hessian, METH_FASTCALL, "bend_cur_fast_hessian(*inputs, out)"},
    {"bend_cur_fast_gradient_hessian", (PyCFunction)(void (*)(void))c_bend_cur_fast_gradient_hessian, METH_FASTCALL, "bend_cur_fast_gradient_hessian(*inputs, out)"},
    {"stretch_fast_gradient", (PyCFunction)(void (*)(void))c_stretch_fast_gradient, METH_FASTCALL, "stretch_fast_gradient(*inputs, out)"},
    {"stretch_fast_hessian", (PyCFunction)(void (*)(void))c_stretch_fast_hessian, METH_FASTCALL, "stretch_fast_hessian(*inputs, out)"},
    {"stretch_fast_gradient_hessian", (PyCFunction)(void (*)(void))c_stretch_fast_gradient_hessian, METH_FASTCALL, "stretch_fast_gradient_hessian(*inputs, out)"},
    {NULL, NULL, 0, NULL}
};

static struct PyModuleDef moduledef = {PyModuleDef_HEAD_INIT, "_ckernels", NULL, -1, methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__ckernels(void) {
    PyObject *module = PyModule_Create(&moduledef);
    return module;
}
