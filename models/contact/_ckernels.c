/* Contact barrier kernels (contin_models.contact._ckernels).
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

static PyObject *c_sphere_distance(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {1};
    Input in[6];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("sphere_distance", args, nargs, in, 6, outputs, 1, rows, &_m) < 0) {
        release(in, 6, outputs, 1);
        return NULL;
    }
    double *out_d = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double r = in[0].data[_i * in[0].stride];
        const double z = in[1].data[_i * in[1].stride];
        const double zc = in[2].data[_i * in[2].stride];
        const double rho = in[3].data[_i * in[3].stride];
        double dz = (z - zc);
        double q = sqrt(((dz * dz) + (r * r)));
        double d = (q - rho);
        double _d = d;
        out_d[_i] = _d;
    }
    release(in, 6, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_sphere_energy(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {1};
    Input in[6];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("sphere_energy", args, nargs, in, 6, outputs, 1, rows, &_m) < 0) {
        release(in, 6, outputs, 1);
        return NULL;
    }
    double *out_e = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double r = in[0].data[_i * in[0].stride];
        const double z = in[1].data[_i * in[1].stride];
        const double zc = in[2].data[_i * in[2].stride];
        const double rho = in[3].data[_i * in[3].stride];
        const double K = in[4].data[_i * in[4].stride];
        const double dhat = in[5].data[_i * in[5].stride];
        double dz = (z - zc);
        double q = sqrt(((dz * dz) + (r * r)));
        double d = (q - rho);
        double s = (d - dhat);
        double logt = log((d / dhat));
        double w0 = (((-K) * logt) * (s * s));
        double _e = w0;
        out_e[_i] = _e;
    }
    release(in, 6, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_sphere_gradient(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {3};
    Input in[6];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("sphere_gradient", args, nargs, in, 6, outputs, 1, rows, &_m) < 0) {
        release(in, 6, outputs, 1);
        return NULL;
    }
    double *out_g = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double r = in[0].data[_i * in[0].stride];
        const double z = in[1].data[_i * in[1].stride];
        const double zc = in[2].data[_i * in[2].stride];
        const double rho = in[3].data[_i * in[3].stride];
        const double K = in[4].data[_i * in[4].stride];
        const double dhat = in[5].data[_i * in[5].stride];
        double dz = (z - zc);
        double q = sqrt(((dz * dz) + (r * r)));
        double iq = (1.0 / q);
        double nr = (iq * r);
        double nz = (dz * iq);
        double d = (q - rho);
        double s = (d - dhat);
        double logt = log((d / dhat));
        double u = (s / d);
        double w1 = (((-K) * s) * ((2.0 * logt) + u));
        double _c0 = (nz * w1);
        out_g[0 * _m + _i] = (nr * w1);
        out_g[1 * _m + _i] = _c0;
        out_g[2 * _m + _i] = (-_c0);
    }
    release(in, 6, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_sphere_hessian(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {6};
    Input in[6];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("sphere_hessian", args, nargs, in, 6, outputs, 1, rows, &_m) < 0) {
        release(in, 6, outputs, 1);
        return NULL;
    }
    double *out_h = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double r = in[0].data[_i * in[0].stride];
        const double z = in[1].data[_i * in[1].stride];
        const double zc = in[2].data[_i * in[2].stride];
        const double rho = in[3].data[_i * in[3].stride];
        const double K = in[4].data[_i * in[4].stride];
        const double dhat = in[5].data[_i * in[5].stride];
        double dz = (z - zc);
        double q = sqrt(((dz * dz) + (r * r)));
        double iq = (1.0 / q);
        double nr = (iq * r);
        double nz = (dz * iq);
        double d = (q - rho);
        double s = (d - dhat);
        double logt = log((d / dhat));
        double u = (s / d);
        double w1 = (((-K) * s) * ((2.0 * logt) + u));
        double w2 = ((-K) * ((2.0 * logt) + (u * (4.0 - u))));
        double _c0 = (nr * nr);
        double _c1 = (nz * nz);
        double _c2 = (iq * w1);
        double _c3 = (((_c2 * nr) * nz) - ((nr * nz) * w2));
        double _c4 = ((_c0 * _c2) + (_c1 * w2));
        out_h[0 * _m + _i] = ((_c0 * w2) + (_c1 * _c2));
        out_h[1 * _m + _i] = (-_c3);
        out_h[2 * _m + _i] = _c3;
        out_h[3 * _m + _i] = _c4;
        out_h[4 * _m + _i] = (-_c4);
        out_h[5 * _m + _i] = _c4;
    }
    release(in, 6, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_sphere_derivatives(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[3] = {1, 3, 6};
    Input in[6];
    Output outputs[3];
    Py_ssize_t _m;
    if (prepare("sphere_derivatives", args, nargs, in, 6, outputs, 3, rows, &_m) < 0) {
        release(in, 6, outputs, 3);
        return NULL;
    }
    double *out_e = outputs[0].data;
    double *out_g = outputs[1].data;
    double *out_h = outputs[2].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double r = in[0].data[_i * in[0].stride];
        const double z = in[1].data[_i * in[1].stride];
        const double zc = in[2].data[_i * in[2].stride];
        const double rho = in[3].data[_i * in[3].stride];
        const double K = in[4].data[_i * in[4].stride];
        const double dhat = in[5].data[_i * in[5].stride];
        double dz = (z - zc);
        double q = sqrt(((dz * dz) + (r * r)));
        double iq = (1.0 / q);
        double nr = (iq * r);
        double nz = (dz * iq);
        double d = (q - rho);
        double s = (d - dhat);
        double logt = log((d / dhat));
        double u = (s / d);
        double w0 = (((-K) * logt) * (s * s));
        double w1 = (((-K) * s) * ((2.0 * logt) + u));
        double w2 = ((-K) * ((2.0 * logt) + (u * (4.0 - u))));
        double _c0 = (nr * w1);
        double _c1 = (nz * w1);
        double _c2 = (nr * nr);
        double _c3 = (nz * nz);
        double _c4 = (iq * w1);
        double _c5 = (((_c0 * iq) * nz) - ((nr * nz) * w2));
        double _c6 = ((_c2 * _c4) + (_c3 * w2));
        double _e = w0;
        out_g[0 * _m + _i] = _c0;
        out_g[1 * _m + _i] = _c1;
        out_g[2 * _m + _i] = (-_c1);
        out_h[0 * _m + _i] = ((_c2 * w2) + (_c3 * _c4));
        out_h[1 * _m + _i] = (-_c5);
        out_h[2 * _m + _i] = _c5;
        out_h[3 * _m + _i] = _c6;
        out_h[4 * _m + _i] = (-_c6);
        out_h[5 * _m + _i] = _c6;
        out_e[_i] = _e;
    }
    release(in, 6, outputs, 3);
    Py_RETURN_NONE;
}

static PyObject *c_plate_distance(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {1};
    Input in[5];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("plate_distance", args, nargs, in, 5, outputs, 1, rows, &_m) < 0) {
        release(in, 5, outputs, 1);
        return NULL;
    }
    double *out_d = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double z = in[1].data[_i * in[1].stride];
        const double zp = in[2].data[_i * in[2].stride];
        double d = ((-z) + zp);
        double _d = d;
        out_d[_i] = _d;
    }
    release(in, 5, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_plate_energy(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {1};
    Input in[5];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("plate_energy", args, nargs, in, 5, outputs, 1, rows, &_m) < 0) {
        release(in, 5, outputs, 1);
        return NULL;
    }
    double *out_e = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double z = in[1].data[_i * in[1].stride];
        const double zp = in[2].data[_i * in[2].stride];
        const double K = in[3].data[_i * in[3].stride];
        const double dhat = in[4].data[_i * in[4].stride];
        double d = ((-z) + zp);
        double s = (d - dhat);
        double logt = log((d / dhat));
        double w0 = (((-K) * logt) * (s * s));
        double _e = w0;
        out_e[_i] = _e;
    }
    release(in, 5, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_plate_gradient(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {3};
    Input in[5];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("plate_gradient", args, nargs, in, 5, outputs, 1, rows, &_m) < 0) {
        release(in, 5, outputs, 1);
        return NULL;
    }
    double *out_g = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double z = in[1].data[_i * in[1].stride];
        const double zp = in[2].data[_i * in[2].stride];
        const double K = in[3].data[_i * in[3].stride];
        const double dhat = in[4].data[_i * in[4].stride];
        double d = ((-z) + zp);
        double s = (d - dhat);
        double logt = log((d / dhat));
        double u = (s / d);
        double w1 = (((-K) * s) * ((2.0 * logt) + u));
        out_g[0 * _m + _i] = 0.0;
        out_g[1 * _m + _i] = (-w1);
        out_g[2 * _m + _i] = w1;
    }
    release(in, 5, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_plate_hessian(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[1] = {6};
    Input in[5];
    Output outputs[1];
    Py_ssize_t _m;
    if (prepare("plate_hessian", args, nargs, in, 5, outputs, 1, rows, &_m) < 0) {
        release(in, 5, outputs, 1);
        return NULL;
    }
    double *out_h = outputs[0].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double z = in[1].data[_i * in[1].stride];
        const double zp = in[2].data[_i * in[2].stride];
        const double K = in[3].data[_i * in[3].stride];
        const double dhat = in[4].data[_i * in[4].stride];
        double d = ((-z) + zp);
        double s = (d - dhat);
        double logt = log((d / dhat));
        double u = (s / d);
        double w2 = ((-K) * ((2.0 * logt) + (u * (4.0 - u))));
        out_h[0 * _m + _i] = 0.0;
        out_h[1 * _m + _i] = 0.0;
        out_h[2 * _m + _i] = 0.0;
        out_h[3 * _m + _i] = w2;
        out_h[4 * _m + _i] = (-w2);
        out_h[5 * _m + _i] = w2;
    }
    release(in, 5, outputs, 1);
    Py_RETURN_NONE;
}

static PyObject *c_plate_derivatives(PyObject *self, PyObject *const *args, Py_ssize_t nargs) {
    static const Py_ssize_t rows[3] = {1, 3, 6};
    Input in[5];
    Output outputs[3];
    Py_ssize_t _m;
    if (prepare("plate_derivatives", args, nargs, in, 5, outputs, 3, rows, &_m) < 0) {
        release(in, 5, outputs, 3);
        return NULL;
    }
    double *out_e = outputs[0].data;
    double *out_g = outputs[1].data;
    double *out_h = outputs[2].data;
    for (Py_ssize_t _i = 0; _i < _m; _i++) {
        const double z = in[1].data[_i * in[1].stride];
        const double zp = in[2].data[_i * in[2].stride];
        const double K = in[3].data[_i * in[3].stride];
        const double dhat = in[4].data[_i * in[4].stride];
        double d = ((-z) + zp);
        double s = (d - dhat);
        double logt = log((d / dhat));
        double u = (s / d);
        double w0 = (((-K) * logt) * (s * s));
        double w1 = (((-K) * s) * ((2.0 * logt) + u));
        double w2 = ((-K) * ((2.0 * logt) + (u * (4.0 - u))));
        double _e = w0;
        out_g[0 * _m + _i] = 0.0;
        out_g[1 * _m + _i] = (-w1);
        out_g[2 * _m + _i] = w1;
        out_h[0 * _m + _i] = 0.0;
        out_h[1 * _m + _i] = 0.0;
        out_h[2 * _m + _i] = 0.0;
        out_h[3 * _m + _i] = w2;
        out_h[4 * _m + _i] = (-w2);
        out_h[5 * _m + _i] = w2;
        out_e[_i] = _e;
    }
    release(in, 5, outputs, 3);
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"sphere_distance", (PyCFunction)(void (*)(void))c_sphere_distance, METH_FASTCALL, "sphere_distance(*inputs, *outputs)"},
    {"sphere_energy", (PyCFunction)(void (*)(void))c_sphere_energy, METH_FASTCALL, "sphere_energy(*inputs, *outputs)"},
    {"sphere_gradient", (PyCFunction)(void (*)(void))c_sphere_gradient, METH_FASTCALL, "sphere_gradient(*inputs, *outputs)"},
    {"sphere_hessian", (PyCFunction)(void (*)(void))c_sphere_hessian, METH_FASTCALL, "sphere_hessian(*inputs, *outputs)"},
    {"sphere_derivatives", (PyCFunction)(void (*)(void))c_sphere_derivatives, METH_FASTCALL, "sphere_derivatives(*inputs, *outputs)"},
    {"plate_distance", (PyCFunction)(void (*)(void))c_plate_distance, METH_FASTCALL, "plate_distance(*inputs, *outputs)"},
    {"plate_energy", (PyCFunction)(void (*)(void))c_plate_energy, METH_FASTCALL, "plate_energy(*inputs, *outputs)"},
    {"plate_gradient", (PyCFunction)(void (*)(void))c_plate_gradient, METH_FASTCALL, "plate_gradient(*inputs, *outputs)"},
    {"plate_hessian", (PyCFunction)(void (*)(void))c_plate_hessian, METH_FASTCALL, "plate_hessian(*inputs, *outputs)"},
    {"plate_derivatives", (PyCFunction)(void (*)(void))c_plate_derivatives, METH_FASTCALL, "plate_derivatives(*inputs, *outputs)"},
    {NULL, NULL, 0, NULL}
};

static struct PyModuleDef moduledef = {PyModuleDef_HEAD_INIT, "_ckernels", NULL, -1, methods, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__ckernels(void) {
    PyObject *module = PyModule_Create(&moduledef);
    if (module != NULL && PyModule_AddStringConstant(module, "RETURNS", "{'sphere_distance': (True, [()]), 'sphere_energy': (True, [()]), 'sphere_gradient': (True, [(3,)]), 'sphere_hessian': (True, [(6,)]), 'sphere_derivatives': (True, [(), (3,), (6,)]), 'plate_distance': (True, [()]), 'plate_energy': (True, [()]), 'plate_gradient': (True, [(3,)]), 'plate_hessian': (True, [(6,)]), 'plate_derivatives': (True, [(), (3,), (6,)])}") < 0) {
        Py_DECREF(module);
        return NULL;
    }
    return module;
}
