/* python/src/module.c - polarcam._polarcam, the CPython extension over the polarcam library.
 *
 * Conventions kept by every function here:
 *   - images come in as numpy arrays and are used in place (no copy) when their dtype is
 *     uint8, uint16 or float32 in native byte order, aligned, with adjacent pixels along a row
 *     and ascending rows (any row stride: crops of a larger frame work); anything else is a
 *     TypeError (dtype) or ValueError (layout in memory) naming the explicit copy to make;
 *   - outputs are new arrays or written into the caller's out= arrays (checked first);
 *   - the GIL is released around every call into the library that touches pixels, so Python
 *     threads run the pipeline on several cores at once;
 *   - a library error becomes ValueError (bad input), OSError and its subclasses (I/O,
 *     devices, timeouts), MemoryError, NotImplementedError or RuntimeError, carrying the
 *     library's detail message and its code name as the errname attribute.
 * Every library call goes through adapter.h.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <structmember.h>

#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "adapter.h"
#include "polarcam/error.h"

PyMODINIT_FUNC PyInit__polarcam(void);

/* A METH_VARARGS | METH_KEYWORDS function in a PyMethodDef. */
#define KW(f) ((PyCFunction)(void (*)(void))(f))

/* ------------------------------------------------------------------------------------------
 * errors
 */

static PyObject *exc_type(int rc)
{
	switch (rc) {
	case PC_EINVAL:
	case PC_ERANGE:
	case PC_EFORMAT:
	case PC_ENUMERIC:
	case PC_EOVERFLOW:
		return PyExc_ValueError;
	case PC_ENOENT:
		return PyExc_FileNotFoundError;
	case PC_EPERM:
		return PyExc_PermissionError;
	case PC_ETIMEDOUT:
		return PyExc_TimeoutError;
	case PC_EDISCONNECTED:
		return PyExc_ConnectionError;
	case PC_EAGAIN:
		return PyExc_BlockingIOError;
	case PC_EIO:
	case PC_EBUSY:
		return PyExc_OSError;
	case PC_ENOMEM:
		return PyExc_MemoryError;
	case PC_ENOTSUP:
		return PyExc_NotImplementedError;
	default:
		return PyExc_RuntimeError;
	}
}

/* Raises the exception of a library error with the calling thread's detail message (read it
 * on the thread that made the failing call, before any other library call). Returns NULL. */
static PyObject *raise_pc(int rc)
{
	const char *detail = pcpy_error_detail();
	PyObject *type = exc_type(rc);
	PyObject *msg = PyUnicode_FromString(detail && *detail ? detail : pcpy_strerror(rc));
	if (!msg)
		return NULL;
	PyObject *exc = PyObject_CallOneArg(type, msg);
	Py_DECREF(msg);
	if (!exc)
		return NULL;
	PyObject *name = PyUnicode_FromString(pcpy_errname(rc));
	if (name) {
		PyObject_SetAttrString(exc, "errname", name);
		Py_DECREF(name);
	}
	PyErr_Clear();
	PyErr_SetObject(type, exc);
	Py_DECREF(exc);
	return NULL;
}

/* PyErr_Format with C printf semantics (PyErr_Format knows no %g). Returns NULL. */
static PyObject *err_printf(PyObject *type, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static PyObject *err_printf(PyObject *type, const char *fmt, ...)
{
	char buf[1024];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(buf, sizeof buf, fmt, ap);
	va_end(ap);
	PyErr_SetString(type, buf);
	return NULL;
}

/* ------------------------------------------------------------------------------------------
 * arrays
 */

static const char *dtype_name(PyArrayObject *a)
{
	static char buf[64];
	PyObject *s = PyObject_Str((PyObject *)PyArray_DESCR(a));
	const char *u = s ? PyUnicode_AsUTF8(s) : NULL;
	snprintf(buf, sizeof buf, "%s", u ? u : "?");
	Py_XDECREF(s);
	PyErr_Clear();
	return buf;
}

/* A new C-contiguous array whose data starts on a 64-byte boundary (a cache line; numpy's own
 * allocations are only 16-byte aligned): a view into a numpy uint8 buffer 63 bytes longer
 * than the data, which the view keeps alive as its base. The library writes large aligned
 * planar outputs with non-temporal stores (pc_stokes_streams) and its vector stores never
 * straddle two cache lines; values are the same either way. */
#define OUT_ALIGN 64
static PyObject *new_array(int nd, const npy_intp *dims, int type)
{
	PyArray_Descr *descr = PyArray_DescrFromType(type);
	if (!descr)
		return NULL;
	npy_intp n = (npy_intp)descr->elsize;
	for (int i = 0; i < nd; i++) {
		if (dims[i] < 0 || (dims[i] && n > (NPY_MAX_INTP - OUT_ALIGN) / dims[i])) {
			Py_DECREF(descr);
			return PyErr_NoMemory();
		}
		n *= dims[i];
	}
	npy_intp bytes = n + OUT_ALIGN - 1;
	PyObject *buf = PyArray_SimpleNew(1, &bytes, NPY_UINT8);
	if (!buf) {
		Py_DECREF(descr);
		return NULL;
	}
	char *p = PyArray_DATA((PyArrayObject *)buf);
	p += (OUT_ALIGN - (uintptr_t)p % OUT_ALIGN) % OUT_ALIGN;
	/* steals descr */
	PyObject *a = PyArray_NewFromDescr(&PyArray_Type, descr, nd, (npy_intp *)dims, NULL, p,
	                                   NPY_ARRAY_CARRAY, NULL);
	if (!a || PyArray_SetBaseObject((PyArrayObject *)a, buf) < 0) { /* steals buf */
		if (!a)
			Py_DECREF(buf);
		Py_XDECREF(a);
		return NULL;
	}
	return a;
}

static PyArrayObject *as_ndarray(PyObject *o, const char *name, const char *expect)
{
	if (!PyArray_Check(o)) {
		PyErr_Format(PyExc_TypeError, "%s: expected a numpy.ndarray %s, got %s", name,
		             expect, Py_TYPE(o)->tp_name);
		return NULL;
	}
	return (PyArrayObject *)o;
}

/* Row stride, pixel stride (in elements) of a 2-D (or the first two axes of a 3-D) array, for
 * the library's views; 0 and a ValueError when the library cannot address it in place. */
static int axis_strides(PyArrayObject *a, const char *name, int need_adjacent, size_t *row,
                        size_t *pix)
{
	npy_intp isz = PyArray_ITEMSIZE(a);
	npy_intp rs = PyArray_STRIDE(a, 0), ps = PyArray_STRIDE(a, 1);
	npy_intp h = PyArray_DIM(a, 0), w = PyArray_DIM(a, 1);
	int ok = PyArray_ISALIGNED(a) && PyArray_ISNOTSWAPPED(a) && rs > 0 && ps > 0 &&
	         rs % isz == 0 && ps % isz == 0 && (!need_adjacent || ps == isz) &&
	         (h <= 1 || rs >= ps * w);
	if (!ok) {
		PyErr_Format(
		    PyExc_ValueError,
		    "%s: strides (%zd, %zd) bytes cannot be used in place (pixels of a row "
		    "must be %s, rows ascending, aligned, native byte order): pass "
		    "numpy.ascontiguousarray(%s) (a copy)",
		    name, (Py_ssize_t)rs, (Py_ssize_t)ps,
		    need_adjacent ? "adjacent" : "at positive element strides", name);
		return -1;
	}
	*row = (size_t)(rs / isz);
	*pix = (size_t)(ps / isz);
	return 0;
}

static int dims_ok(PyArrayObject *a, const char *name)
{
	for (int i = 0; i < PyArray_NDIM(a); i++)
		if (PyArray_DIM(a, i) > (npy_intp)UINT32_MAX / 2) {
			PyErr_Format(PyExc_ValueError, "%s: axis %d of size %zd is too large", name,
			             i, (Py_ssize_t)PyArray_DIM(a, i));
			return -1;
		}
	return 0;
}

/* A raw mosaic (H, W) uint8/uint16/float32 as a library view over the array's memory. */
static int raw_view(PyArrayObject *a, const char *name, unsigned bits, pc_view *v)
{
	if (PyArray_NDIM(a) != 2) {
		PyErr_Format(PyExc_ValueError, "%s: expected a 2-D (H, W) raw mosaic, got %d-D",
		             name, PyArray_NDIM(a));
		return -1;
	}
	pcpy_dtype dt;
	switch (PyArray_TYPE(a)) {
	case NPY_UINT8:
		dt = PCPY_U8;
		break;
	case NPY_UINT16:
		dt = PCPY_U16;
		break;
	case NPY_FLOAT32:
		dt = PCPY_F32;
		break;
	default:
		PyErr_Format(PyExc_TypeError,
		             "%s: dtype %s is not supported: pass uint8, uint16 or float32 (for "
		             "example %s.astype(numpy.uint16), an explicit copy)",
		             name, dtype_name(a), name);
		return -1;
	}
	size_t row, pix;
	if (dims_ok(a, name) || axis_strides(a, name, 1, &row, &pix))
		return -1;
	int rc =
	    pcpy_view(PyArray_DATA(a), (uint32_t)PyArray_DIM(a, 1), (uint32_t)PyArray_DIM(a, 0),
	              row * (size_t)PyArray_ITEMSIZE(a), dt, bits, v);
	if (rc) {
		raise_pc(rc);
		return -1;
	}
	return 0;
}

/* A float32 (H, W) plane of the library (strides in floats). */
static int fplane_of(PyArrayObject *a, const char *name, uint32_t w, uint32_t h, int writable,
                     pc_fplane *p)
{
	if (PyArray_TYPE(a) != NPY_FLOAT32) {
		PyErr_Format(PyExc_TypeError, "%s: expected float32, got %s", name, dtype_name(a));
		return -1;
	}
	if (PyArray_NDIM(a) != 2 || PyArray_DIM(a, 0) != (npy_intp)h ||
	    PyArray_DIM(a, 1) != (npy_intp)w) {
		PyErr_Format(PyExc_ValueError, "%s: expected shape (%u, %u)", name, h, w);
		return -1;
	}
	if (writable && !PyArray_ISWRITEABLE(a)) {
		PyErr_Format(PyExc_ValueError, "%s: the array is read-only", name);
		return -1;
	}
	size_t row, pix;
	if (axis_strides(a, name, 0, &row, &pix))
		return -1;
	*p = (pc_fplane){(float *)PyArray_DATA(a), row, pix};
	return 0;
}

/* A float32 image of any shape, for a 2-D plane of h rows and w columns. */
static int fplane_any(PyObject *o, const char *name, pc_fplane *p, uint32_t *w, uint32_t *h)
{
	PyArrayObject *a = as_ndarray(o, name, "(H, W) of float32");
	if (!a)
		return -1;
	if (PyArray_NDIM(a) != 2) {
		PyErr_Format(PyExc_ValueError, "%s: expected a 2-D (H, W) image, got %d-D", name,
		             PyArray_NDIM(a));
		return -1;
	}
	if (dims_ok(a, name))
		return -1;
	*w = (uint32_t)PyArray_DIM(a, 1);
	*h = (uint32_t)PyArray_DIM(a, 0);
	return fplane_of(a, name, *w, *h, 0, p);
}

static int get_bits(PyObject *o, unsigned *bits)
{
	*bits = 0;
	if (o == Py_None)
		return 0;
	long b = PyLong_AsLong(o);
	if (b == -1 && PyErr_Occurred())
		return -1;
	if (b < 1 || b > 32) {
		PyErr_Format(PyExc_ValueError, "bits=%ld: expected 1..16 (or None)", b);
		return -1;
	}
	*bits = (unsigned)b;
	return 0;
}

/* The value check a declared bit depth below the container's needs (a 12-bit frame holding
 * 4096 is corrupt data, not something to clamp). */
static unsigned bits_to_check(const pc_view *v, unsigned bits)
{
	unsigned container = pcpy_view_bits(v);
	if (container == 32)
		return 0; /* floats: the library checks finiteness */
	return bits && bits < (container <= 8 ? 8u : 16u) ? bits : 0;
}

/* ------------------------------------------------------------------------------------------
 * result types
 */

static PyStructSequence_Field stokes_fields[] = {
    {"s0", "float32 (H, W): S0 = (I0 + I45 + I90 + I135) / 2, in the raw's units"},
    {"s1", "float32 (H, W): S1 = I0 - I90"},
    {"s2", "float32 (H, W): S2 = I45 - I135"},
    {"dolp", "float32 (H, W): sqrt(S1^2 + S2^2) / S0 clipped to [0, 1] (0 where S0 <= 0)"},
    {"aolp", "float32 (H, W): 0.5 atan2(S2, S1) in radians in [0, pi), from the image x "
             "axis, counter-clockwise as seen by the viewer"},
    {"valid", "uint8 (H, W) or None: 1 where the output pixel depends only on trusted samples "
              "(below saturation_level, above dead_level, trusted in the calibration); None "
              "when nothing was checked"},
    {"n_invalid", "int: the number of 0s in valid (0 when nothing was checked)"},
    {NULL, NULL}};
static PyStructSequence_Desc stokes_desc = {
    "polarcam.Stokes",
    "Stokes(s0, s1, s2, dolp, aolp): the linear Stokes images of a frame, as polarcam process "
    "writes them.\nA Stokes (or any 5-sequence of float32 (H, W) arrays or None) can be "
    "passed as out= to stokes() to reuse its arrays; None entries are not computed. valid "
    "and n_invalid are attributes, not items: a Stokes unpacks to its 5 images.",
    stokes_fields, 5};
static PyTypeObject StokesType;

static PyStructSequence_Field minmax_fields[] = {
    {"imin", "float32 (H, W): Imin = (S0 - sqrt(S1^2 + S2^2)) / 2, the least light an ideal "
             "linear analyser passes (polanalyser's cvtStokesToImin)"},
    {"imax", "float32 (H, W): Imax = (S0 + sqrt(S1^2 + S2^2)) / 2 (cvtStokesToImax)"},
    {"diffuse", "float32 (H, W): 2 Imin, the unpolarized part"},
    {"specular", "float32 (H, W): Imax - Imin = sqrt(S1^2 + S2^2), the polarized part"},
    {NULL, NULL}};
static PyStructSequence_Desc minmax_desc = {
    "polarcam.MinMax",
    "MinMax(imin, imax, diffuse, specular): what polarcam process --minmax --split writes "
    "(imin.npy, imax.npy, diffuse.npy, specular.npy), in the units of S0; not clipped "
    "(noise makes Imin negative in dark pixels).",
    minmax_fields, 4};
static PyTypeObject MinMaxType;

static PyStructSequence_Field dec_fields[] = {
    {"D", "float64 (...): diattenuation |D|"},
    {"R", "float64 (...): retardance in radians, [0, pi] (NaN where undefined)"},
    {"Delta", "float64 (...): depolarization 1 - |tr m_Delta| / 3 (NaN where undefined)"},
    {"physical", "bool (...): the input passed the coherency-matrix realisability check"},
    {"diattenuation", "float64 (..., 3): the diattenuation vector (first row of M / M00)"},
    {"retardance_axis", "float64 (..., 3): unit retardance axis (a1, a2 linear, a3 circular)"},
    {"flags", "uint32 (...): LC_* flags (D_SINGULAR, R_NONUNIQUE, NONPHYSICAL, FILTERED, "
              "CLAMPED, ZERO_M00)"},
    {"filtered", "bool (...): Cloude filtering changed the input"},
    {"m00", "float64 (...): M00 of the input (the factors are of M / M00)"},
    {"R_linear", "float64 (...): linear retardance (radians)"},
    {"R_circular", "float64 (...): optical rotation (radians)"},
    {"depol_index", "float64 (...): Gil-Bernabeu depolarization index"},
    {"M_D", "float64 (..., 4, 4): the diattenuator"},
    {"M_R", "float64 (..., 4, 4): the retarder"},
    {"M_Delta", "float64 (..., 4, 4): the depolarizer"},
    {NULL, NULL}};
static PyStructSequence_Desc dec_desc = {
    "polarcam.Decomposition",
    "The Lu-Chipman decomposition M = M_Delta M_R M_D of Mueller matrices, as polarcam "
    "decompose prints it (docs/physics.md section 3).",
    dec_fields, 15};
static PyTypeObject DecType;

static PyStructSequence_Field frame_fields[] = {
    {"raw", "uint16 (H, W): the raw mosaic, values LSB-aligned (0 .. 2^bits - 1)"},
    {"sequence", "int: frame number from the source, strictly increasing"},
    {"timestamp_ns", "int: capture time on the source's clock, non-decreasing"},
    {"exposure_us", "float: exposure time"},
    {"gain_db", "float: gain"},
    {"status", "int: 0, or FRAME_INCOMPLETE | FRAME_CORRUPT | FRAME_SIMULATED flags"},
    {"offset_x", "int: ROI origin on the sensor (x)"},
    {"offset_y", "int: ROI origin on the sensor (y)"},
    {"layout", "str: the polarizer mosaic at pixel (0, 0) of the frame (for stokes(layout=))"},
    {"bits", "int: bit depth of the source's pixel format (for stokes(bits=))"},
    {NULL, NULL}};
static PyStructSequence_Desc frame_desc = {
    "polarcam.Frame", "One raw frame of a frame source, with its metadata.", frame_fields, 10};
static PyTypeObject FrameType;

/* ------------------------------------------------------------------------------------------
 * version, methods, backends
 */

static PyObject *py_methods(PyObject *self, PyObject *noargs)
{
	(void)self;
	(void)noargs;
	PyObject *l = PyList_New(0);
	for (unsigned i = 0; l; i++) {
		const pc_demosaic_method_info *mi = pcpy_method_info(i);
		if (!mi)
			break;
		PyObject *d = Py_BuildValue(
		    "{s:s,s:s,s:s,s:s,s:O,s:O,s:O,s:O}", "name", mi->name, "accuracy", mi->accuracy,
		    "cost", mi->cost, "source", mi->source, "monochrome",
		    (mi->flags & PC_DMF_MONO) ? Py_True : Py_False, "colour",
		    (mi->flags & PC_DMF_COLOR) ? Py_True : Py_False, "half_resolution",
		    (mi->flags & PC_DMF_HALF_RES) ? Py_True : Py_False, "noise_gain",
		    (mi->flags & PC_DMF_NOISE_GAIN) ? Py_True : Py_False);
		if (!d || PyList_Append(l, d)) {
			Py_XDECREF(d);
			Py_DECREF(l);
			return NULL;
		}
		Py_DECREF(d);
	}
	return l;
}

static PyObject *py_backends(PyObject *self, PyObject *noargs)
{
	(void)self;
	(void)noargs;
	PyObject *l = PyList_New(0);
	for (unsigned i = 0; l; i++) {
		bool built;
		const char *summary;
		const char *scheme = pcpy_backend(i, &built, &summary);
		if (!scheme)
			break;
		PyObject *d =
		    Py_BuildValue("{s:s,s:O,s:s}", "scheme", scheme, "built",
		                  built ? Py_True : Py_False, "summary", summary ? summary : "");
		if (!d || PyList_Append(l, d)) {
			Py_XDECREF(d);
			Py_DECREF(l);
			return NULL;
		}
		Py_DECREF(d);
	}
	return l;
}

/* ------------------------------------------------------------------------------------------
 * demosaic
 */

/* noise_gain=: None estimated (the library's 0); a number is given, and the library checks it
 * (negative, NaN, infinite: its ValueError naming noise_gain); 0 is refused here as ambiguous */
static int get_noise_gain(PyObject *o, double *v)
{
	*v = 0;
	if (o == Py_None)
		return 0;
	*v = PyFloat_AsDouble(o);
	if (*v == -1 && PyErr_Occurred()) {
		PyErr_SetString(PyExc_TypeError, "noise_gain: expected a number or None");
		return -1;
	}
	if (*v == 0) {
		PyErr_SetString(PyExc_ValueError,
		                "noise_gain 0: expected a gain > 0 (raw units per "
		                "unit signal), or None to estimate it from the "
		                "frame");
		return -1;
	}
	return 0;
}

static PyObject *py_demosaic(PyObject *self, PyObject *args, PyObject *kw)
{
	(void)self;
	static char *kwl[] = {"raw",     "method", "layout",     "bits",
	                      "threads", "out",    "noise_gain", NULL};
	PyObject *raw_o, *bits_o = Py_None, *out_o = Py_None, *ng_o = Py_None;
	const char *method = NULL, *layout = "90,45,135,0";
	int threads = 0;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "O|zsOiOO:demosaic", kwl, &raw_o, &method,
	                                 &layout, &bits_o, &threads, &out_o, &ng_o))
		return NULL;
	double noise_gain;
	if (get_noise_gain(ng_o, &noise_gain))
		return NULL;
	unsigned bits;
	pc_mosaic m;
	int dm, rc;
	pc_view v;
	PyArrayObject *raw = as_ndarray(raw_o, "raw", "(H, W) of uint8, uint16 or float32");
	if (!raw || get_bits(bits_o, &bits) || raw_view(raw, "raw", bits, &v))
		return NULL;
	if ((rc = pcpy_layout_parse(layout, &m)) || (rc = pcpy_method(method, &m, &dm)))
		return raise_pc(rc);
	unsigned nch = pcpy_channels(&m);
	uint32_t ow, oh;
	pcpy_out_size(dm, v.width, v.height, &ow, &oh);
	PyArrayObject *out;
	if (out_o == Py_None) {
		npy_intp dims[3] = {oh, ow, nch};
		out = (PyArrayObject *)new_array(3, dims, NPY_FLOAT32);
		if (!out)
			return NULL;
	} else {
		out = as_ndarray(out_o, "out", "(H, W, C) of float32");
		if (!out)
			return NULL;
		if (PyArray_TYPE(out) != NPY_FLOAT32 || PyArray_NDIM(out) != 3 ||
		    PyArray_DIM(out, 0) != oh || PyArray_DIM(out, 1) != ow ||
		    PyArray_DIM(out, 2) != nch) {
			PyErr_Format(PyExc_ValueError,
			             "out: expected float32 of shape (%u, %u, %u)", oh, ow, nch);
			return NULL;
		}
		if (!PyArray_ISWRITEABLE(out)) {
			PyErr_SetString(PyExc_ValueError, "out: the array is read-only");
			return NULL;
		}
		Py_INCREF(out);
	}
	size_t row, pix;
	if (axis_strides(out, "out", 0, &row, &pix)) {
		Py_DECREF(out);
		return NULL;
	}
	npy_intp cs = PyArray_STRIDE(out, 2);
	if (cs <= 0 || cs % 4) {
		Py_DECREF(out);
		PyErr_SetString(PyExc_ValueError, "out: the channel stride must be positive");
		return NULL;
	}
	pc_fplane planes[PC_DEMOSAIC_MAX_CHANNELS];
	for (unsigned c = 0; c < nch; c++)
		planes[c] =
		    (pc_fplane){(float *)PyArray_DATA(out) + (size_t)(cs / 4) * c, row, pix};
	unsigned check = bits_to_check(&v, bits);
	Py_BEGIN_ALLOW_THREADS;
	rc = check ? pcpy_check_bits(&v, check) : 0;
	if (!rc)
		rc = pcpy_demosaic(&v, &m, dm, threads, pcpy_full_scale(&v, bits), noise_gain,
		                   planes);
	Py_END_ALLOW_THREADS;
	if (rc) {
		Py_DECREF(out);
		return raise_pc(rc);
	}
	return (PyObject *)out;
}

/* ------------------------------------------------------------------------------------------
 * stokes
 */

static PyTypeObject CalibrationType;
typedef struct CalibrationObject {
	PyObject_HEAD pcpy_calib *cal;
	PyObject *path;
} CalibrationObject;

/* calibration=: None; a float32 (3, 4) or (3, 4, GH, GW) array of analyser pseudo-inverses
 * (C-contiguous; the layout of pc_analyser_pinv); a Calibration; or the path of a calibration
 * file (read now, for this call). One of *pinv (array) or *cal (new reference) is set. */
static int get_calibration(PyObject *o, pc_analyser_pinv *p, int *have_pinv,
                           CalibrationObject **cal)
{
	*have_pinv = 0;
	*cal = NULL;
	if (o == Py_None)
		return 0;
	if (PyObject_TypeCheck(o, &CalibrationType)) {
		Py_INCREF(o);
		*cal = (CalibrationObject *)o;
		return 0;
	}
	if (PyUnicode_Check(o) || PyBytes_Check(o) || PyObject_HasAttrString(o, "__fspath__")) {
		*cal = (CalibrationObject *)PyObject_CallOneArg((PyObject *)&CalibrationType, o);
		return *cal ? 0 : -1;
	}
	if (!PyArray_Check(o)) {
		PyErr_Format(
		    PyExc_TypeError,
		    "calibration: expected None, a Calibration, the path of a calibration "
		    "file, or a float32 (3, 4, GH, GW) array of analyser pseudo-inverses; got "
		    "%s",
		    Py_TYPE(o)->tp_name);
		return -1;
	}
	PyArrayObject *a = (PyArrayObject *)o;
	int nd = PyArray_NDIM(a);
	if (PyArray_TYPE(a) != NPY_FLOAT32 || !PyArray_IS_C_CONTIGUOUS(a) ||
	    !PyArray_ISALIGNED(a) || (nd != 2 && nd != 4) || PyArray_DIM(a, 0) != 3 ||
	    PyArray_DIM(a, 1) != 4) {
		PyErr_SetString(
		    PyExc_ValueError,
		    "calibration: expected a C-contiguous float32 array of shape (3, 4) "
		    "or (3, 4, GH, GW) (numpy.ascontiguousarray(x, numpy.float32))");
		return -1;
	}
	if (dims_ok(a, "calibration"))
		return -1;
	p->m = (const float *)PyArray_DATA(a);
	p->grid_h = nd == 4 ? (uint32_t)PyArray_DIM(a, 2) : 1;
	p->grid_w = nd == 4 ? (uint32_t)PyArray_DIM(a, 3) : 1;
	if (!p->grid_w || !p->grid_h) {
		PyErr_SetString(PyExc_ValueError, "calibration: empty grid");
		return -1;
	}
	*have_pinv = 1;
	return 0;
}

/* A level argument: None -> 0 (not used), else a number. */
static int get_level(PyObject *o, const char *name, double *v)
{
	*v = 0;
	if (o == Py_None)
		return 0;
	*v = PyFloat_AsDouble(o);
	if (*v == -1 && PyErr_Occurred()) {
		PyErr_Format(PyExc_TypeError, "%s: expected a number or None", name);
		return -1;
	}
	return 0;
}

/* Sets the Stokes' valid and n_invalid (valid: a new reference or NULL for None). */
static void stokes_set_valid(PyObject *res, PyObject *valid, uint64_t n_invalid)
{
	if (!valid) {
		Py_INCREF(Py_None);
		valid = Py_None;
	}
	PyStructSequence_SET_ITEM(res, 5, valid);
	PyStructSequence_SET_ITEM(res, 6, PyLong_FromUnsignedLongLong(n_invalid));
}

/* Output planes: new arrays, or the caller's (a Stokes or a 5-sequence; None: not wanted). */
static PyObject *stokes_outputs(PyObject *out_o, uint32_t w, uint32_t h, pc_stokes_out *so)
{
	pc_fplane *pl[5] = {&so->s0, &so->s1, &so->s2, &so->dolp, &so->aolp};
	memset(so, 0, sizeof *so);
	PyObject *res = PyStructSequence_New(&StokesType);
	if (!res)
		return NULL;
	PyObject *seq = NULL;
	if (out_o != Py_None) {
		seq = PySequence_Fast(out_o, "out: expected a Stokes or a sequence of 5 arrays");
		if (!seq) {
			Py_DECREF(res);
			return NULL;
		}
		if (PySequence_Fast_GET_SIZE(seq) != 5) {
			PyErr_SetString(PyExc_ValueError,
			                "out: expected 5 entries (s0, s1, s2, dolp, aolp)");
			goto fail;
		}
	}
	for (int i = 0; i < 5; i++) {
		PyObject *a;
		if (!seq) {
			npy_intp dims[2] = {h, w};
			a = new_array(2, dims, NPY_FLOAT32);
			if (!a)
				goto fail;
		} else {
			a = PySequence_Fast_GET_ITEM(seq, i);
			Py_INCREF(a);
		}
		PyStructSequence_SET_ITEM(res, i, a);
		if (a == Py_None)
			continue;
		char name[16];
		snprintf(name, sizeof name, "out.%s", stokes_fields[i].name);
		PyArrayObject *arr = as_ndarray(a, name, "(H, W) of float32");
		if (!arr || fplane_of(arr, name, w, h, 1, pl[i]))
			goto fail;
	}
	Py_XDECREF(seq);
	return res;
fail:
	Py_XDECREF(seq);
	Py_DECREF(res);
	return NULL;
}

static PyObject *py_stokes(PyObject *self, PyObject *args, PyObject *kw)
{
	(void)self;
	static char *kwl[] = {
	    "raw",     "method", "layout",           "bits",       "black_level", "calibration",
	    "threads", "out",    "saturation_level", "dead_level", "noise_gain",  "gain_db",
	    NULL};
	PyObject *raw_o, *bits_o = Py_None, *black_o = Py_None, *cal_o = Py_None, *out_o = Py_None;
	PyObject *sat_o = Py_None, *dead_o = Py_None, *ng_o = Py_None, *gdb_o = Py_None;
	const char *method = NULL, *layout = NULL;
	int threads = 0, rc;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "O|zzOOOiOOOOO:stokes", kwl, &raw_o, &method,
	                                 &layout, &bits_o, &black_o, &cal_o, &threads, &out_o,
	                                 &sat_o, &dead_o, &ng_o, &gdb_o))
		return NULL;
	/* gain_db=: the frame's analog gain (frame.gain_db), which a calibration's system gain
	 * follows; None (or NaN, a frame that did not say): unknown */
	double gain_db = NAN;
	if (gdb_o != Py_None) {
		if (!PyNumber_Check(gdb_o) || PyBool_Check(gdb_o)) {
			PyErr_SetString(PyExc_TypeError, "gain_db: expected a number (dB) or None");
			return NULL;
		}
		gain_db = PyFloat_AsDouble(gdb_o);
		if (gain_db == -1 && PyErr_Occurred())
			return NULL;
		if (isinf(gain_db)) {
			PyErr_Format(PyExc_ValueError, "gain_db %g: expected a finite gain in dB",
			             gain_db);
			return NULL;
		}
		if (cal_o == Py_None || PyArray_Check(cal_o)) {
			PyErr_SetString(PyExc_ValueError,
			                "gain_db: applies with a calibration file (its system gain "
			                "and dark map follow the frame's analog gain)");
			return NULL;
		}
	}
	PyArrayObject *raw =
	    as_ndarray(raw_o, "raw", "(H, W) raw mosaic, or (H, W, 4) float32 analyser images");
	if (!raw)
		return NULL;
	unsigned bits;
	if (get_bits(bits_o, &bits))
		return NULL;
	pcpy_stokes_opts o = {0, threads, 0, 0, 0, 0, NULL, 0};
	if (get_noise_gain(ng_o, &o.noise_gain) ||
	    get_level(black_o, "black_level", &o.black_level) ||
	    get_level(sat_o, "saturation_level", &o.saturation_level) ||
	    get_level(dead_o, "dead_level", &o.dead_level))
		return NULL;
	int checked = sat_o != Py_None || dead_o != Py_None;
	pc_analyser_pinv pinv;
	int have_pinv;
	CalibrationObject *cal;
	if (get_calibration(cal_o, &pinv, &have_pinv, &cal))
		return NULL;
	if (have_pinv)
		o.pinv = &pinv;
	PyObject *res = NULL, *valid = NULL;
	uint64_t n_invalid = 0;
	pc_stokes_out so;
	if (PyArray_NDIM(raw) == 3) {
		/* already demosaicked: (H, W, 4) I0, I45, I90, I135 */
		if (PyArray_TYPE(raw) != NPY_FLOAT32 || PyArray_DIM(raw, 2) != 4) {
			PyErr_Format(
			    PyExc_ValueError,
			    "raw: a 3-D input must be float32 (H, W, 4) analyser images I0, "
			    "I45, I90, I135 (got %s with %zd channels; colour (H, W, 12): "
			    "average the colours of each analyser first)",
			    dtype_name(raw), (Py_ssize_t)PyArray_DIM(raw, 2));
			goto out;
		}
		if (black_o != Py_None || bits || checked || cal || ng_o != Py_None) {
			PyErr_SetString(
			    PyExc_ValueError,
			    "raw: black_level, bits, saturation_level, dead_level, "
			    "noise_gain and calibration files apply to raw mosaics, not to "
			    "(H, W, 4) analyser images (an array of pseudo-inverses does)");
			goto out;
		}
		size_t row, pix;
		if (dims_ok(raw, "raw") || axis_strides(raw, "raw", 0, &row, &pix))
			goto out;
		npy_intp cs = PyArray_STRIDE(raw, 2);
		if (cs <= 0 || cs % 4) {
			PyErr_SetString(PyExc_ValueError,
			                "raw: the channel stride must be positive");
			goto out;
		}
		uint32_t w = (uint32_t)PyArray_DIM(raw, 1), h = (uint32_t)PyArray_DIM(raw, 0);
		pc_fplane in[4];
		for (int c = 0; c < 4; c++)
			in[c] = (pc_fplane){(float *)PyArray_DATA(raw) + (size_t)(cs / 4) * c, row,
			                    pix};
		if (!(res = stokes_outputs(out_o, w, h, &so)))
			goto out;
		Py_BEGIN_ALLOW_THREADS;
		rc = pcpy_stokes_channels(in, w, h, o.pinv, &so);
		Py_END_ALLOW_THREADS;
	} else {
		pc_view v;
		pc_mosaic m;
		if (raw_view(raw, "raw", bits, &v))
			goto out;
		o.full_scale = pcpy_full_scale(&v, bits);
		if (cal && (black_o != Py_None || checked)) {
			PyErr_SetString(
			    PyExc_ValueError,
			    "calibration: a calibration file brings its own dark offsets (or "
			    "black level), saturation level and trusted pixels; black_level, "
			    "saturation_level and dead_level cannot be given with it");
			goto out;
		}
		if (layout) {
			rc = pcpy_layout_parse(layout, &m);
		} else if (cal) {
			m = pcpy_calib_get(cal->cal)->geo.mosaic;
			rc = 0;
		} else {
			rc = pcpy_layout_parse("90,45,135,0", &m);
		}
		if (rc || (rc = pcpy_method(method, &m, &o.method))) {
			raise_pc(rc);
			goto out;
		}
		uint32_t ow, oh;
		pcpy_out_size(o.method, v.width, v.height, &ow, &oh);
		if (!(res = stokes_outputs(out_o, ow, oh, &so)))
			goto out;
		pc_validity vd = {NULL, ow, 0};
		if (checked || cal) {
			npy_intp dims[2] = {oh, ow};
			if (!(valid = PyArray_ZEROS(2, dims, NPY_UINT8, 0))) {
				Py_CLEAR(res);
				goto out;
			}
			vd.mask = PyArray_DATA((PyArrayObject *)valid);
		}
		unsigned check = bits_to_check(&v, bits);
		Py_BEGIN_ALLOW_THREADS;
		rc = check ? pcpy_check_bits(&v, check) : 0;
		if (!rc && cal)
			rc = pcpy_calib_stokes(cal->cal, &v, layout ? &m : NULL, bits, o.method,
			                       threads, o.noise_gain, gain_db, &so, vd.mask,
			                       &vd.n_invalid);
		else if (!rc)
			rc = pcpy_stokes(&v, &m, &o, &so, checked ? &vd : NULL);
		Py_END_ALLOW_THREADS;
		n_invalid = vd.n_invalid;
	}
	if (rc) {
		Py_CLEAR(res);
		raise_pc(rc);
	} else {
		stokes_set_valid(res, valid, n_invalid);
		valid = NULL;
	}
out:
	Py_XDECREF(valid);
	Py_XDECREF(cal);
	return res;
}

static PyObject *py_analyser_pinv(PyObject *self, PyObject *arg)
{
	(void)self;
	PyArrayObject *a = as_ndarray(arg, "W", "(..., 4, 3) of float32");
	if (!a)
		return NULL;
	int nd = PyArray_NDIM(a);
	if (PyArray_TYPE(a) != NPY_FLOAT32 || !PyArray_IS_C_CONTIGUOUS(a) || nd < 2 ||
	    PyArray_DIM(a, nd - 2) != 4 || PyArray_DIM(a, nd - 1) != 3) {
		PyErr_SetString(PyExc_ValueError,
		                "W: expected a C-contiguous float32 array of shape "
		                "(..., 4, 3) (analyser rows of I0, I45, I90, I135)");
		return NULL;
	}
	npy_intp dims[NPY_MAXDIMS];
	dims[0] = 3;
	dims[1] = 4;
	for (int i = 0; i < nd - 2; i++)
		dims[2 + i] = PyArray_DIM(a, i);
	PyArrayObject *out = (PyArrayObject *)new_array(nd, dims, NPY_FLOAT32);
	if (!out)
		return NULL;
	size_t n = (size_t)(PyArray_SIZE(a) / 12);
	int rc;
	Py_BEGIN_ALLOW_THREADS;
	rc = pcpy_pinv(PyArray_DATA(a), n, PyArray_DATA(out));
	Py_END_ALLOW_THREADS;
	if (rc) {
		Py_DECREF(out);
		return raise_pc(rc);
	}
	return (PyObject *)out;
}

/* ------------------------------------------------------------------------------------------
 * Imin, Imax, diffuse, specular
 */

/* The MinMax of S0, S1, S2 arrays (pc_stokes_minmax, without the GIL). */
static PyObject *minmax_of(PyObject *s0, PyObject *s1, PyObject *s2)
{
	pc_fplane p[3];
	uint32_t w, h, w2, h2;
	static const char *names[3] = {"s0", "s1", "s2"};
	PyObject *in[3] = {s0, s1, s2};
	for (int i = 0; i < 3; i++) {
		if (!in[i] || in[i] == Py_None) {
			PyErr_Format(PyExc_ValueError,
			             "%s: needed (a Stokes with s0, s1, s2, or "
			             "s0 with s1= and s2=)",
			             names[i]);
			return NULL;
		}
		if (fplane_any(in[i], names[i], &p[i], i ? &w2 : &w, i ? &h2 : &h))
			return NULL;
		if (i && (w2 != w || h2 != h)) {
			PyErr_Format(PyExc_ValueError, "%s: shape differs from s0", names[i]);
			return NULL;
		}
	}
	PyObject *res = PyStructSequence_New(&MinMaxType);
	if (!res)
		return NULL;
	pc_fplane o[4];
	for (int i = 0; i < 4; i++) {
		npy_intp dims[2] = {h, w};
		PyObject *a = new_array(2, dims, NPY_FLOAT32);
		if (!a) {
			Py_DECREF(res);
			return NULL;
		}
		PyStructSequence_SET_ITEM(res, i, a);
		o[i] = (pc_fplane){PyArray_DATA((PyArrayObject *)a), w, 1};
	}
	pc_minmax_out mo = {o[0], o[1], o[2], o[3]};
	int rc;
	Py_BEGIN_ALLOW_THREADS;
	rc = pc_stokes_minmax(&p[0], &p[1], &p[2], w, h, &mo);
	Py_END_ALLOW_THREADS;
	if (rc) {
		Py_DECREF(res);
		return raise_pc(rc);
	}
	return res;
}

static PyObject *py_minmax(PyObject *self, PyObject *args, PyObject *kw)
{
	(void)self;
	static char *kwl[] = {"image", "s1", "s2", NULL};
	PyObject *img, *s1 = Py_None, *s2 = Py_None;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "O|OO:minmax", kwl, &img, &s1, &s2))
		return NULL;
	if (PyArray_Check(img))
		return minmax_of(img, s1, s2);
	/* a Stokes (or anything with s0, s1, s2 attributes) */
	PyObject *a[3] = {PyObject_GetAttrString(img, "s0"), PyObject_GetAttrString(img, "s1"),
	                  PyObject_GetAttrString(img, "s2")};
	PyObject *r = NULL;
	if (a[0] && a[1] && a[2])
		r = minmax_of(a[0], a[1], a[2]);
	else
		PyErr_Format(PyExc_TypeError,
		             "image: expected a Stokes or an S0 array (with s1=, s2=), got %s",
		             Py_TYPE(img)->tp_name);
	for (int i = 0; i < 3; i++)
		Py_XDECREF(a[i]);
	return r;
}

/* ------------------------------------------------------------------------------------------
 * picture
 */

static bool is_minmax_kind(const char *kind)
{
	return !strcmp(kind, "imin") || !strcmp(kind, "imax") || !strcmp(kind, "diffuse") ||
	       !strcmp(kind, "specular");
}

/* The picture of img (with dolp, s0 where the kind uses them; any may be NULL). */
static PyObject *picture_of(PyObject *img, PyObject *dolp, PyObject *s0, const char *kind, float lo,
                            float hi, double mask)
{
	pcpy_picture_kind k;
	if (!strcmp(kind, "s0") || !strcmp(kind, "grey"))
		k = PCPY_PIC_GREY;
	else if (!strcmp(kind, "s1") || !strcmp(kind, "s2"))
		k = PCPY_PIC_SIGNED;
	else if (!strcmp(kind, "dolp"))
		k = PCPY_PIC_DOLP;
	else if (!strcmp(kind, "aolp"))
		k = PCPY_PIC_AOLP;
	else if (!strcmp(kind, "aolp_sat"))
		k = PCPY_PIC_AOLP_SAT;
	else if (!strcmp(kind, "aolp_hue"))
		k = PCPY_PIC_AOLP_HUE;
	else if (is_minmax_kind(kind))
		k = PCPY_PIC_ON_S0;
	else {
		PyErr_Format(
		    PyExc_ValueError,
		    "kind='%s': expected s0, s1, s2, dolp, aolp, aolp_sat, aolp_hue, imin, "
		    "imax, diffuse, specular or grey",
		    kind);
		return NULL;
	}
	pc_fplane pi, pd, ps;
	uint32_t w, h, w2, h2;
	if (fplane_any(img, "image", &pi, &w, &h))
		return NULL;
	if ((k == PCPY_PIC_AOLP || k == PCPY_PIC_AOLP_SAT) && !dolp) {
		PyErr_Format(PyExc_ValueError,
		             "kind='%s' shows DoLP as %s: pass dolp= (or a Stokes), "
		             "or use kind='aolp_hue'",
		             kind, k == PCPY_PIC_AOLP ? "value" : "saturation");
		return NULL;
	}
	int use_dolp = dolp && (k == PCPY_PIC_AOLP || k == PCPY_PIC_AOLP_SAT);
	int use_s0 = s0 && (k == PCPY_PIC_DOLP || k == PCPY_PIC_AOLP || k == PCPY_PIC_AOLP_SAT ||
	                    k == PCPY_PIC_ON_S0);
	if (use_dolp &&
	    (fplane_any(dolp, "dolp", &pd, &w2, &h2) ||
	     ((w2 != w || h2 != h) &&
	      (PyErr_SetString(PyExc_ValueError, "dolp: shape differs from image"), 1))))
		return NULL;
	if (use_s0 && (fplane_any(s0, "s0", &ps, &w2, &h2) ||
	               ((w2 != w || h2 != h) &&
	                (PyErr_SetString(PyExc_ValueError, "s0: shape differs from image"), 1))))
		return NULL;
	npy_intp dims[3] = {h, w, 3};
	PyArrayObject *out = (PyArrayObject *)new_array(3, dims, NPY_UINT8);
	if (!out)
		return NULL;
	int rc = 0;
	Py_BEGIN_ALLOW_THREADS;
	rc = pcpy_picture(k, &pi, use_dolp ? &pd : NULL, use_s0 ? &ps : NULL, w, h, lo, hi, mask,
	                  PyArray_DATA(out), (size_t)w * 3);
	Py_END_ALLOW_THREADS;
	if (rc) {
		Py_DECREF(out);
		return raise_pc(rc);
	}
	return (PyObject *)out;
}

static PyObject *py_picture(PyObject *self, PyObject *args, PyObject *kw)
{
	(void)self;
	static char *kwl[] = {"image", "kind", "lo", "hi", "mask_s0", "dolp", "s0", NULL};
	PyObject *img_o, *lo_o = Py_None, *hi_o = Py_None, *mask_o = Py_None, *dolp_o = Py_None,
	                 *s0_o = Py_None;
	const char *kind = NULL;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "O|zOOOOO:picture", kwl, &img_o, &kind, &lo_o,
	                                 &hi_o, &mask_o, &dolp_o, &s0_o))
		return NULL;
	float lo = NAN, hi = NAN;
	double mask = 0;
	if (lo_o != Py_None && ((lo = (float)PyFloat_AsDouble(lo_o)) == -1.0f && PyErr_Occurred()))
		return NULL;
	if (hi_o != Py_None && ((hi = (float)PyFloat_AsDouble(hi_o)) == -1.0f && PyErr_Occurred()))
		return NULL;
	if (mask_o != Py_None) {
		double t = PyFloat_AsDouble(mask_o);
		if (t == -1 && PyErr_Occurred())
			return NULL;
		if (!(t >= 0)) {
			err_printf(PyExc_ValueError,
			           "mask_s0=%g: expected a threshold >= 0 (0: no "
			           "mask, None: 1 %% of the S0 99.9th percentile)",
			           t);
			return NULL;
		}
		mask = t > 0 ? t : -1; /* the adapter: 0 default, < 0 none */
	}
	PyObject *img = NULL, *dolp = NULL, *s0 = NULL; /* borrowed (from a[] or the arguments) */
	PyObject *a[5] = {0}; /* a Stokes' arrays, held until the picture is drawn */
	int is_stokes = !PyArray_Check(img_o);
	if (is_stokes) {
		/* a Stokes (or anything with s0, dolp, aolp attributes) */
		static const char *names[5] = {"s0", "s1", "s2", "dolp", "aolp"};
		for (int i = 0; i < 5; i++) {
			a[i] = PyObject_GetAttrString(img_o, names[i]);
			if (!a[i])
				PyErr_Clear();
		}
		if (!kind)
			kind = "aolp";
		if (is_minmax_kind(kind)) {
			/* Imin, Imax, diffuse, specular of the Stokes, on its S0's scale */
			PyObject *mm = minmax_of(a[0], a[1], a[2]);
			PyObject *r = NULL;
			if (mm) {
				int i = !strcmp(kind, "imin")      ? 0
				        : !strcmp(kind, "imax")    ? 1
				        : !strcmp(kind, "diffuse") ? 2
				                                   : 3;
				r = picture_of(PyStructSequence_GET_ITEM(mm, i), NULL, a[0], kind,
				               lo, hi, mask);
				Py_DECREF(mm);
			}
			for (int i = 0; i < 5; i++)
				Py_XDECREF(a[i]);
			return r;
		}
		const char *want = !strcmp(kind, "s0")     ? "s0"
		                   : !strcmp(kind, "s1")   ? "s1"
		                   : !strcmp(kind, "s2")   ? "s2"
		                   : !strcmp(kind, "dolp") ? "dolp"
		                                           : "aolp";
		for (int i = 0; i < 5; i++)
			if (!strcmp(names[i], want))
				img = a[i];
		dolp = a[3];
		s0 = a[0];
		if (!img || img == Py_None) {
			for (int i = 0; i < 5; i++)
				Py_XDECREF(a[i]);
			PyErr_Format(
			    PyExc_TypeError,
			    "image: expected a numpy array or a Stokes with a '%s' array, got %s",
			    want, Py_TYPE(img_o)->tp_name);
			return NULL;
		}
		if (dolp == Py_None)
			dolp = NULL;
		if (s0 == Py_None)
			s0 = NULL;
	} else {
		img = img_o;
		if (!kind) {
			PyErr_SetString(PyExc_TypeError,
			                "picture(array): say what the array is with "
			                "kind= ('s0', 'dolp', 'aolp', ...)");
			return NULL;
		}
		dolp = dolp_o != Py_None ? dolp_o : NULL;
		s0 = s0_o != Py_None ? s0_o : NULL;
	}
	PyObject *r = picture_of(img, dolp, s0, kind, lo, hi, mask);
	for (int i = 0; i < 5; i++)
		Py_XDECREF(a[i]);
	return r;
}

/* ------------------------------------------------------------------------------------------
 * pbrdf
 */

static PyObject *py_pbrdf(PyObject *self, PyObject *args, PyObject *kw)
{
	(void)self;
	static char *kwl[] = {"n",   "k",       "sigma",     "theta_i", "theta_r",
	                      "phi", "diffuse", "shadowing", "rho",     NULL};
	PyObject *in_o[6] = {0};
	const char *diffuse = "fresnel", *shadowing = "ts", *rho = "table";
	if (!PyArg_ParseTupleAndKeywords(args, kw, "OOOOO|Osss:pbrdf", kwl, &in_o[0], &in_o[1],
	                                 &in_o[2], &in_o[3], &in_o[4], &in_o[5], &diffuse,
	                                 &shadowing, &rho))
		return NULL;
	int dif, sh, rmode, rorder, rc;
	if ((rc = pcpy_pbrdf_diffuse(diffuse, &dif)) ||
	    (rc = pcpy_pbrdf_shadowing(shadowing, &sh)) ||
	    (rc = pcpy_pbrdf_rho(rho, &rmode, &rorder)))
		return raise_pc(rc);
	static const char *names[6] = {"n", "k", "sigma", "theta_i", "theta_r", "phi"};
	PyArrayObject *a[6] = {0};
	PyObject *multi = NULL, *out = NULL;
	pcpy_pbrdf_cache *cache = NULL;
	for (int i = 0; i < 6; i++) {
		PyObject *o = in_o[i];
		if (!o) {
			o = PyFloat_FromDouble(180);
			if (!o)
				goto done;
		} else {
			Py_INCREF(o);
		}
		/* parameters: converted to float64 (small arrays: a copy is cheap) */
		a[i] = (PyArrayObject *)PyArray_FROM_OTF(o, NPY_DOUBLE, NPY_ARRAY_IN_ARRAY);
		Py_DECREF(o);
		if (!a[i]) {
			PyErr_Clear();
			PyErr_Format(PyExc_TypeError,
			             "%s: expected a number or an array of numbers", names[i]);
			goto done;
		}
	}
	multi = PyArray_MultiIterNew(6, a[0], a[1], a[2], a[3], a[4], a[5]);
	if (!multi)
		goto done;
	PyArrayMultiIterObject *mi = (PyArrayMultiIterObject *)multi;
	npy_intp dims[NPY_MAXDIMS];
	int nd = mi->nd;
	if (nd + 2 > NPY_MAXDIMS) {
		PyErr_SetString(PyExc_ValueError, "too many dimensions");
		goto done;
	}
	for (int i = 0; i < nd; i++)
		dims[i] = mi->dimensions[i];
	dims[nd] = dims[nd + 1] = 4;
	out = new_array(nd + 2, dims, NPY_DOUBLE);
	if (!out || (rc = pcpy_pbrdf_cache_new(dif, sh, rmode, rorder, &cache))) {
		if (!out)
			goto done;
		raise_pc(rc);
		Py_CLEAR(out);
		goto done;
	}
	double *f = PyArray_DATA((PyArrayObject *)out), bad[6] = {0};
	npy_intp idx = 0;
	Py_BEGIN_ALLOW_THREADS;
	rc = 0;
	while (PyArray_MultiIter_NOTDONE(mi)) {
		double v[6];
		for (int j = 0; j < 6; j++)
			v[j] = *(double *)PyArray_MultiIter_DATA(mi, j);
		rc = pcpy_pbrdf_eval(cache, v[0], v[1], v[2], v[3], v[4], v[5],
		                     (double(*)[4])(f + 16 * idx));
		if (rc) {
			memcpy(bad, v, sizeof bad);
			break;
		}
		PyArray_MultiIter_NEXT(mi);
		idx++;
	}
	Py_END_ALLOW_THREADS;
	if (rc) {
		PyObject *exc = exc_type(rc);
		err_printf(exc,
		           "element %zd (n=%g, k=%g, sigma=%g, theta_i=%g, theta_r=%g, phi=%g): "
		           "%s",
		           (Py_ssize_t)idx, bad[0], bad[1], bad[2], bad[3], bad[4], bad[5],
		           pcpy_error_detail());
		Py_CLEAR(out);
	}
done:
	pcpy_pbrdf_cache_free(cache);
	Py_XDECREF(multi);
	for (int i = 0; i < 6; i++)
		Py_XDECREF(a[i]);
	return out;
}

/* ------------------------------------------------------------------------------------------
 * decompose
 */

static void index_str(npy_intp flat, int nd, const npy_intp *dims, char *buf, size_t size)
{
	npy_intp ix[NPY_MAXDIMS];
	for (int i = nd - 1; i >= 0; i--) {
		ix[i] = dims[i] ? flat % dims[i] : 0;
		flat = dims[i] ? flat / dims[i] : 0;
	}
	size_t n = (size_t)snprintf(buf, size, "M[");
	for (int i = 0; i < nd && n < size; i++)
		n += (size_t)snprintf(buf + n, size - n, "%s%zd", i ? ", " : "", (Py_ssize_t)ix[i]);
	if (n < size)
		snprintf(buf + n, size - n, "]");
}

static PyObject *py_decompose(PyObject *self, PyObject *args, PyObject *kw)
{
	(void)self;
	static char *kwl[] = {"M", "filter", NULL};
	PyObject *m_o;
	int filter = 1;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "O|p:decompose", kwl, &m_o, &filter))
		return NULL;
	/* float64 C order is used in place; anything else is converted (a copy) */
	PyArrayObject *M = (PyArrayObject *)PyArray_FROM_OTF(m_o, NPY_DOUBLE, NPY_ARRAY_IN_ARRAY);
	if (!M)
		return NULL;
	int nd = PyArray_NDIM(M);
	if (nd < 2 || PyArray_DIM(M, nd - 1) != 4 || PyArray_DIM(M, nd - 2) != 4) {
		PyErr_SetString(PyExc_ValueError,
		                "M: expected Mueller matrices of shape (..., 4, 4)");
		Py_DECREF(M);
		return NULL;
	}
	int bn = nd - 2;
	npy_intp d[NPY_MAXDIMS];
	for (int i = 0; i < bn; i++)
		d[i] = PyArray_DIM(M, i);
	PyObject *res = PyStructSequence_New(&DecType);
	if (!res) {
		Py_DECREF(M);
		return NULL;
	}
	/* field order of dec_fields: extra trailing dims and types */
	static const struct {
		int extra;
		int type;
	} spec[15] = {{0, NPY_DOUBLE},  {0, NPY_DOUBLE},  {0, NPY_DOUBLE}, {0, NPY_BOOL},
	              {3, NPY_DOUBLE},  {3, NPY_DOUBLE},  {0, NPY_UINT32}, {0, NPY_BOOL},
	              {0, NPY_DOUBLE},  {0, NPY_DOUBLE},  {0, NPY_DOUBLE}, {0, NPY_DOUBLE},
	              {16, NPY_DOUBLE}, {16, NPY_DOUBLE}, {16, NPY_DOUBLE}};
	void *p[15];
	for (int f = 0; f < 15; f++) {
		int k = bn;
		if (spec[f].extra == 3)
			d[k++] = 3;
		else if (spec[f].extra == 16)
			d[k++] = 4, d[k++] = 4;
		PyObject *a = new_array(k, d, spec[f].type);
		if (!a) {
			Py_DECREF(res);
			Py_DECREF(M);
			return NULL;
		}
		PyStructSequence_SET_ITEM(res, f, a);
		p[f] = PyArray_DATA((PyArrayObject *)a);
	}
	npy_intp n = PyArray_SIZE(M) / 16, i;
	const double *m = PyArray_DATA(M);
	int rc = 0;
	Py_BEGIN_ALLOW_THREADS;
	for (i = 0; i < n; i++) {
		pc_lu_chipman lc;
		if ((rc = pcpy_decompose((const double(*)[4])(m + 16 * i), filter, &lc)))
			break;
		((double *)p[0])[i] = lc.D;
		((double *)p[1])[i] = lc.R;
		((double *)p[2])[i] = lc.Delta;
		((npy_bool *)p[3])[i] = lc.physical;
		memcpy((double *)p[4] + 3 * i, lc.D_vec, 3 * sizeof(double));
		memcpy((double *)p[5] + 3 * i, lc.R_axis, 3 * sizeof(double));
		((uint32_t *)p[6])[i] = lc.flags;
		((npy_bool *)p[7])[i] = lc.filtered;
		((double *)p[8])[i] = lc.m00;
		((double *)p[9])[i] = lc.R_linear;
		((double *)p[10])[i] = lc.R_circular;
		((double *)p[11])[i] = lc.depol_index;
		memcpy((double *)p[12] + 16 * i, lc.M_D, 16 * sizeof(double));
		memcpy((double *)p[13] + 16 * i, lc.M_R, 16 * sizeof(double));
		memcpy((double *)p[14] + 16 * i, lc.M_Delta, 16 * sizeof(double));
	}
	Py_END_ALLOW_THREADS;
	if (rc) {
		char where[256];
		for (int k = 0; k < bn; k++)
			d[k] = PyArray_DIM(M, k);
		index_str(i, bn, d, where, sizeof where);
		PyErr_Format(exc_type(rc), "%s: %s", where, pcpy_error_detail());
		Py_CLEAR(res);
	}
	Py_DECREF(M);
	return res;
}

/* ------------------------------------------------------------------------------------------
 * render
 */

static PyObject *json_call(const char *fn, PyObject *arg)
{
	PyObject *json = PyImport_ImportModule("json");
	if (!json)
		return NULL;
	PyObject *r = PyObject_CallMethod(json, fn, "O", arg);
	Py_DECREF(json);
	return r;
}

static int dict_set(PyObject *d, const char *k, PyObject *v)
{
	if (!v)
		return -1;
	int rc = PyDict_SetItemString(d, k, v);
	Py_DECREF(v);
	return rc;
}

static int get_roi(PyObject *o, uint32_t roi[4])
{
	PyObject *seq = PySequence_Fast(o, "roi: expected (x, y, width, height)");
	if (!seq)
		return -1;
	int rc = 0;
	if (PySequence_Fast_GET_SIZE(seq) != 4) {
		PyErr_SetString(PyExc_ValueError, "roi: expected (x, y, width, height)");
		rc = -1;
	}
	for (int i = 0; !rc && i < 4; i++) {
		long v = PyLong_AsLong(PySequence_Fast_GET_ITEM(seq, i));
		if (v == -1 && PyErr_Occurred()) {
			rc = -1;
		} else if (v < 0 || v > (1 << 20) || (i >= 2 && v == 0)) {
			PyErr_Format(PyExc_ValueError,
			             "roi: %s = %ld: expected 0 .. 2^20 (width, height >= 1)",
			             (const char *[]){"x", "y", "width", "height"}[i], v);
			rc = -1;
		} else {
			roi[i] = (uint32_t)v;
		}
	}
	Py_DECREF(seq);
	return rc;
}

static PyObject *py_render(PyObject *self, PyObject *args, PyObject *kw)
{
	(void)self;
	static char *kwl[] = {"scene", "seed", "frame", "roi", "threads", NULL};
	PyObject *scene_o = Py_None, *seed_o = NULL, *frame_o = NULL, *roi_o = Py_None;
	int threads = 0;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "|OOOOi:render", kwl, &scene_o, &seed_o,
	                                 &frame_o, &roi_o, &threads))
		return NULL;
	unsigned long long seed = 0;
	if (seed_o && ((seed = PyLong_AsUnsignedLongLong(seed_o)) == (unsigned long long)-1 &&
	               PyErr_Occurred()))
		return NULL;
	/* frames: one number, or a sequence of them */
	uint64_t one = 0, *frames = &one;
	Py_ssize_t nf = 1;
	int multi = 0;
	PyObject *fseq = NULL, *keep_text = NULL, *keep_path = NULL, *res = NULL;
	PyObject *raw = NULL, *truth = NULL, *mueller = NULL, *meta = NULL;
	pcpy_render *r = NULL;
	if (frame_o && PyLong_Check(frame_o)) {
		if ((one = PyLong_AsUnsignedLongLong(frame_o)) == (unsigned long long)-1 &&
		    PyErr_Occurred())
			return NULL;
	} else if (frame_o) {
		fseq = PySequence_Fast(frame_o, "frame: expected an int or a sequence of ints");
		if (!fseq)
			return NULL;
		nf = PySequence_Fast_GET_SIZE(fseq);
		if (nf < 1) {
			PyErr_SetString(PyExc_ValueError, "frame: empty sequence");
			goto done;
		}
		frames = PyMem_Malloc((size_t)nf * sizeof *frames);
		if (!frames) {
			PyErr_NoMemory();
			goto done;
		}
		multi = 1;
		for (Py_ssize_t i = 0; i < nf; i++) {
			frames[i] = PyLong_AsUnsignedLongLong(PySequence_Fast_GET_ITEM(fseq, i));
			if (frames[i] == (unsigned long long)-1 && PyErr_Occurred())
				goto done;
		}
	}
	uint32_t roi[4];
	if (roi_o != Py_None && get_roi(roi_o, roi))
		goto done;
	const char *path = NULL, *text = NULL;
	if (PyDict_Check(scene_o)) {
		if (!(keep_text = json_call("dumps", scene_o)))
			goto done;
		text = PyUnicode_AsUTF8(keep_text);
	} else if (scene_o != Py_None) {
		if (!PyUnicode_FSConverter(scene_o, &keep_path))
			goto done;
		path = PyBytes_AS_STRING(keep_path);
		if (!strcmp(path, "default"))
			path = NULL;
	}
	if (!text && PyErr_Occurred())
		goto done;
	pcpy_render_info in;
	int rc;
	Py_BEGIN_ALLOW_THREADS;
	rc = pcpy_render_new(path, text, seed, roi_o != Py_None ? roi : NULL, threads, &r, &in);
	Py_END_ALLOW_THREADS;
	if (rc) {
		raise_pc(rc);
		goto done;
	}
	npy_intp rd[3] = {nf, in.height, in.width};
	raw = multi ? new_array(3, rd, NPY_UINT16) : new_array(2, rd + 1, NPY_UINT16);
	npy_intp td[5] = {in.height, in.width, in.colour_channels, 4, 4};
	if (in.colour_channels == 1) {
		td[2] = 4;
		td[3] = 4;
		truth = new_array(3, td, NPY_FLOAT32);
		if (in.mueller)
			mueller = new_array(4, td, NPY_FLOAT32);
	} else {
		truth = new_array(4, td, NPY_FLOAT32);
		if (in.mueller)
			mueller = new_array(5, td, NPY_FLOAT32);
	}
	meta = PyDict_New();
	if (!raw || !truth || (in.mueller && !mueller) || !meta)
		goto done;
	size_t plane = (size_t)in.width * in.height;
	PyObject *seqs = PyList_New(nf), *stamps = PyList_New(nf), *states = PyList_New(nf);
	if (!seqs || !stamps || !states) {
		Py_XDECREF(seqs);
		Py_XDECREF(stamps);
		Py_XDECREF(states);
		goto done;
	}
	pc_frame_meta fm = {0};
	Py_ssize_t i;
	uint16_t *rawp = PyArray_DATA((PyArrayObject *)raw);
	for (i = 0; i < nf; i++) {
		Py_BEGIN_ALLOW_THREADS;
		rc = pcpy_render_frame(
		    r, frames[i], rawp + plane * (size_t)i,
		    i ? NULL : PyArray_DATA((PyArrayObject *)truth),
		    i || !mueller ? NULL : PyArray_DATA((PyArrayObject *)mueller), &fm);
		Py_END_ALLOW_THREADS;
		if (rc)
			break;
		PyList_SET_ITEM(seqs, i, PyLong_FromUnsignedLongLong(fm.sequence));
		PyList_SET_ITEM(stamps, i, PyLong_FromUnsignedLongLong(fm.timestamp_ns));
		PyList_SET_ITEM(states, i,
		                PyLong_FromUnsignedLong(pcpy_render_state(r, frames[i])));
	}
	if (rc) {
		Py_DECREF(seqs);
		Py_DECREF(stamps);
		Py_DECREF(states);
		raise_pc(rc);
		goto done;
	}
	PyObject *effects = PyList_New(0);
	for (unsigned k = 0; effects; k++) {
		const char *e = pcpy_effect_name(in.effects, k);
		if (!e)
			break;
		PyObject *s = PyUnicode_FromString(e);
		if (!s || PyList_Append(effects, s)) {
			Py_XDECREF(s);
			Py_CLEAR(effects);
		}
		Py_XDECREF(s);
	}
	char *sj = pcpy_render_scene_json(r);
	PyObject *sjs = sj ? PyUnicode_FromString(sj) : NULL;
	free(sj);
	PyObject *scene_doc = sjs ? json_call("loads", sjs) : NULL;
	Py_XDECREF(sjs);
	PyObject *dpr = in.colour_channels == 1
	                    ? PyFloat_FromDouble(in.dn_per_radiance[0])
	                    : Py_BuildValue("[ddd]", in.dn_per_radiance[0], in.dn_per_radiance[1],
	                                    in.dn_per_radiance[2]);
	int bad =
	    dict_set(meta, "scene_name", PyUnicode_FromString(in.scene_name)) ||
	    dict_set(meta, "scene", scene_doc ? scene_doc : (Py_INCREF(Py_None), Py_None)) ||
	    dict_set(meta, "seed", PyLong_FromUnsignedLongLong(seed)) ||
	    dict_set(meta, "frame",
	             multi ? PySequence_List(fseq) : PyLong_FromUnsignedLongLong(one)) ||
	    dict_set(meta, "sequence",
	             multi ? (Py_INCREF(seqs), seqs) : PyLong_FromUnsignedLongLong(fm.sequence)) ||
	    dict_set(meta, "timestamp_ns",
	             multi ? (Py_INCREF(stamps), stamps)
	                   : PyLong_FromUnsignedLongLong(fm.timestamp_ns)) ||
	    dict_set(meta, "state",
	             multi ? (Py_INCREF(states), states)
	                   : (Py_INCREF(PyList_GET_ITEM(states, 0)), PyList_GET_ITEM(states, 0))) ||
	    dict_set(meta, "truth_state",
	             (Py_INCREF(PyList_GET_ITEM(states, 0)), PyList_GET_ITEM(states, 0))) ||
	    dict_set(meta, "exposure_us", PyFloat_FromDouble(fm.exposure_us)) ||
	    dict_set(meta, "gain_db", PyFloat_FromDouble(fm.gain_db)) ||
	    dict_set(meta, "status", PyLong_FromUnsignedLong(fm.status)) ||
	    dict_set(meta, "width", PyLong_FromUnsignedLong(in.width)) ||
	    dict_set(meta, "height", PyLong_FromUnsignedLong(in.height)) ||
	    dict_set(meta, "offset_x", PyLong_FromUnsignedLong(in.offset_x)) ||
	    dict_set(meta, "offset_y", PyLong_FromUnsignedLong(in.offset_y)) ||
	    dict_set(meta, "sensor_width", PyLong_FromUnsignedLong(in.sensor_width)) ||
	    dict_set(meta, "sensor_height", PyLong_FromUnsignedLong(in.sensor_height)) ||
	    dict_set(meta, "format", PyUnicode_FromString(in.format)) ||
	    dict_set(meta, "bits", PyLong_FromUnsignedLong(in.bits)) ||
	    dict_set(meta, "layout", PyUnicode_FromString(in.layout)) ||
	    dict_set(meta, "colour_channels", PyLong_FromUnsignedLong(in.colour_channels)) ||
	    dict_set(meta, "effects", effects) ||
	    dict_set(meta, "n_states", PyLong_FromUnsignedLong(in.n_states)) ||
	    dict_set(meta, "frame_rate_hz", PyFloat_FromDouble(in.frame_rate_hz)) ||
	    dict_set(meta, "black_level_dn", PyFloat_FromDouble(in.black_level_dn)) ||
	    dict_set(meta, "dn_per_radiance", dpr) ||
	    (mueller && PyDict_SetItemString(meta, "truth_mueller", mueller));
	Py_DECREF(seqs);
	Py_DECREF(stamps);
	Py_DECREF(states);
	if (!bad)
		res = PyTuple_Pack(3, raw, truth, meta);
done:
	pcpy_render_free(r);
	if (frames != &one)
		PyMem_Free(frames);
	Py_XDECREF(fseq);
	Py_XDECREF(keep_text);
	Py_XDECREF(keep_path);
	Py_XDECREF(raw);
	Py_XDECREF(truth);
	Py_XDECREF(mueller);
	Py_XDECREF(meta);
	return res;
}

/* ------------------------------------------------------------------------------------------
 * frame sources
 */

typedef struct {
	PyObject_HEAD pc_source *s;
	int busy;       /* a call runs without the GIL: other calls on this source must wait */
	int timeout_ms; /* default dequeue timeout */
	PyObject *uri;
} SourceObject;

static PyTypeObject SourceType;

static int src_ready(SourceObject *so)
{
	if (!so->s) {
		PyErr_SetString(PyExc_ValueError, "the source is closed");
		return -1;
	}
	if (so->busy) {
		PyErr_SetString(PyExc_RuntimeError,
		                "the source is in use by another thread (a source is used from one "
		                "thread at a time)");
		return -1;
	}
	return 0;
}

static int parse_controls(PyObject *kw, pcpy_stream_args *a, int *timeout_ms,
                          PyObject **keep_format)
{
	memset(a, 0, sizeof *a);
	a->exposure_us = a->gain_db = a->frame_rate_hz = -1;
	a->buffers = 8;
	*timeout_ms = 5000;
	*keep_format = NULL;
	if (!kw)
		return 0;
	PyObject *key, *val;
	Py_ssize_t pos = 0;
	while (PyDict_Next(kw, &pos, &key, &val)) {
		const char *k = PyUnicode_AsUTF8(key);
		if (!k)
			return -1;
		double *dst = !strcmp(k, "exposure_us")     ? &a->exposure_us
		              : !strcmp(k, "gain_db")       ? &a->gain_db
		              : !strcmp(k, "frame_rate_hz") ? &a->frame_rate_hz
		                                            : NULL;
		if (dst) {
			if (val == Py_None)
				continue;
			double v = PyFloat_AsDouble(val);
			if (v == -1 && PyErr_Occurred())
				return -1;
			if (!(v >= 0) || (dst == &a->exposure_us && v == 0)) {
				err_printf(PyExc_ValueError, "%s=%g: expected %s", k, v,
				           dst == &a->exposure_us ? "> 0" : ">= 0");
				return -1;
			}
			*dst = v;
		} else if (!strcmp(k, "roi")) {
			if (val == Py_None)
				continue;
			if (get_roi(val, a->roi))
				return -1;
			a->roi_set = true;
		} else if (!strcmp(k, "format")) {
			if (val == Py_None)
				continue;
			if (!PyUnicode_Check(val)) {
				PyErr_SetString(
				    PyExc_TypeError,
				    "format: expected a pixel format name such as 'Mono12'");
				return -1;
			}
			Py_INCREF(val);
			*keep_format = val;
			a->format = PyUnicode_AsUTF8(val);
			if (!a->format)
				return -1;
		} else if (!strcmp(k, "buffers") || !strcmp(k, "timeout_ms")) {
			long v = PyLong_AsLong(val);
			if (v == -1 && PyErr_Occurred())
				return -1;
			int buffers = k[0] == 'b';
			if (buffers ? (v < 1 || v > 64) : (v < -1 || v > 3600000)) {
				PyErr_Format(PyExc_ValueError, "%s=%ld: expected %s", k, v,
				             buffers ? "1 .. 64" : "-1 (forever) .. 3600000");
				return -1;
			}
			if (buffers)
				a->buffers = (unsigned)v;
			else
				*timeout_ms = (int)v;
		} else {
			PyErr_Format(PyExc_TypeError,
			             "open(): unknown control '%s' (known: exposure_us, gain_db, "
			             "frame_rate_hz, roi, format, buffers, timeout_ms)",
			             k);
			return -1;
		}
	}
	return 0;
}

static PyObject *py_open(PyObject *self, PyObject *args, PyObject *kw)
{
	(void)self;
	PyObject *uri_o;
	if (!PyArg_ParseTuple(args, "U:open", &uri_o))
		return NULL;
	const char *uri = PyUnicode_AsUTF8(uri_o);
	if (!uri)
		return NULL;
	pcpy_stream_args a;
	int timeout_ms;
	PyObject *keep_format;
	if (parse_controls(kw, &a, &timeout_ms, &keep_format)) {
		Py_XDECREF(keep_format);
		return NULL;
	}
	pc_source *s = NULL;
	int rc;
	Py_BEGIN_ALLOW_THREADS;
	rc = pcpy_source_open(uri, &a, &s);
	Py_END_ALLOW_THREADS;
	Py_XDECREF(keep_format);
	if (rc)
		return raise_pc(rc);
	SourceObject *so = PyObject_New(SourceObject, &SourceType);
	if (!so) {
		pcpy_source_close(s);
		return NULL;
	}
	so->s = s;
	so->busy = 0;
	so->timeout_ms = timeout_ms;
	Py_INCREF(uri_o);
	so->uri = uri_o;
	return (PyObject *)so;
}

static void src_close_now(SourceObject *so)
{
	pc_source *s = so->s;
	so->s = NULL;
	if (s) {
		Py_BEGIN_ALLOW_THREADS;
		pcpy_source_close(s);
		Py_END_ALLOW_THREADS;
	}
}

static void src_dealloc(SourceObject *so)
{
	src_close_now(so);
	Py_XDECREF(so->uri);
	PyObject_Free(so);
}

static PyObject *src_close(SourceObject *so, PyObject *noargs)
{
	(void)noargs;
	if (so->busy)
		return src_ready(so) ? NULL : NULL;
	src_close_now(so);
	Py_RETURN_NONE;
}

static PyObject *src_start(SourceObject *so, PyObject *noargs)
{
	(void)noargs;
	if (src_ready(so))
		return NULL;
	int rc;
	so->busy = 1;
	Py_BEGIN_ALLOW_THREADS;
	rc = pcpy_source_start(so->s);
	Py_END_ALLOW_THREADS;
	so->busy = 0;
	return rc ? raise_pc(rc) : (Py_INCREF(Py_None), Py_None);
}

static PyObject *src_stop(SourceObject *so, PyObject *noargs)
{
	(void)noargs;
	if (src_ready(so))
		return NULL;
	int rc;
	so->busy = 1;
	Py_BEGIN_ALLOW_THREADS;
	rc = pcpy_source_stop(so->s);
	Py_END_ALLOW_THREADS;
	so->busy = 0;
	return rc ? raise_pc(rc) : (Py_INCREF(Py_None), Py_None);
}

/* The next frame; NULL with no exception set at the end of a finite source when at_end_stop. */
static PyObject *src_read_frame(SourceObject *so, int timeout_ms, int at_end_stop)
{
	if (src_ready(so))
		return NULL;
	int rc = 0;
	pc_source_format f;
	if (!pcpy_source_streaming(so->s)) {
		so->busy = 1;
		Py_BEGIN_ALLOW_THREADS;
		rc = pcpy_source_start(so->s);
		Py_END_ALLOW_THREADS;
		so->busy = 0;
		if (rc)
			return raise_pc(rc);
	}
	if ((rc = pcpy_source_format(so->s, &f)))
		return raise_pc(rc);
	npy_intp dims[2] = {f.height, f.width};
	PyObject *arr = new_array(2, dims, NPY_UINT16);
	if (!arr)
		return NULL;
	pc_frame_meta m;
	pc_mosaic mos;
	unsigned bits = 0;
	so->busy = 1;
	Py_BEGIN_ALLOW_THREADS;
	rc = pcpy_source_read(so->s, timeout_ms, PyArray_DATA((PyArrayObject *)arr),
	                      (size_t)f.width * 2, &m, &mos, &bits);
	Py_END_ALLOW_THREADS;
	so->busy = 0;
	if (rc) {
		Py_DECREF(arr);
		if (rc == PC_EEND && at_end_stop)
			return NULL;
		return raise_pc(rc);
	}
	char layout[64] = "";
	if (f.polarized)
		pcpy_layout_format(&mos, layout, sizeof layout);
	PyObject *fr = PyStructSequence_New(&FrameType);
	if (!fr) {
		Py_DECREF(arr);
		return NULL;
	}
	PyStructSequence_SET_ITEM(fr, 0, arr);
	PyStructSequence_SET_ITEM(fr, 1, PyLong_FromUnsignedLongLong(m.sequence));
	PyStructSequence_SET_ITEM(fr, 2, PyLong_FromUnsignedLongLong(m.timestamp_ns));
	PyStructSequence_SET_ITEM(fr, 3, PyFloat_FromDouble(m.exposure_us));
	PyStructSequence_SET_ITEM(fr, 4, PyFloat_FromDouble(m.gain_db));
	PyStructSequence_SET_ITEM(fr, 5, PyLong_FromUnsignedLong(m.status));
	PyStructSequence_SET_ITEM(fr, 6, PyLong_FromUnsignedLong(m.offset_x));
	PyStructSequence_SET_ITEM(fr, 7, PyLong_FromUnsignedLong(m.offset_y));
	PyStructSequence_SET_ITEM(
	    fr, 8, f.polarized ? PyUnicode_FromString(layout) : (Py_INCREF(Py_None), Py_None));
	PyStructSequence_SET_ITEM(fr, 9, PyLong_FromUnsignedLong(bits));
	for (int i = 1; i < 10; i++)
		if (!PyStructSequence_GET_ITEM(fr, i)) {
			Py_DECREF(fr);
			return NULL;
		}
	return fr;
}

static PyObject *src_read(SourceObject *so, PyObject *args, PyObject *kw)
{
	static char *kwl[] = {"timeout_ms", NULL};
	PyObject *t_o = Py_None;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "|O:read", kwl, &t_o))
		return NULL;
	int t = so->timeout_ms;
	if (t_o != Py_None) {
		long v = PyLong_AsLong(t_o);
		if (v == -1 && PyErr_Occurred())
			return NULL;
		if (v < -1 || v > 3600000) {
			PyErr_Format(PyExc_ValueError,
			             "timeout_ms=%ld: expected -1 (forever) .. 3600000", v);
			return NULL;
		}
		t = (int)v;
	}
	PyObject *fr = src_read_frame(so, t, 1);
	if (!fr && !PyErr_Occurred())
		Py_RETURN_NONE; /* end of a recording */
	return fr;
}

static PyObject *src_iternext(SourceObject *so)
{
	return src_read_frame(so, so->timeout_ms, 1);
}

static PyObject *src_enter(SourceObject *so, PyObject *noargs)
{
	(void)noargs;
	if (!so->s) {
		PyErr_SetString(PyExc_ValueError, "the source is closed");
		return NULL;
	}
	Py_INCREF(so);
	return (PyObject *)so;
}

static PyObject *src_exit(SourceObject *so, PyObject *args)
{
	(void)args;
	if (!so->busy)
		src_close_now(so);
	Py_RETURN_FALSE;
}

static int control_arg(PyObject *name, int *id)
{
	const char *n = PyUnicode_Check(name) ? PyUnicode_AsUTF8(name) : NULL;
	if (!n) {
		PyErr_Clear();
		PyErr_SetString(PyExc_TypeError,
		                "control: expected a name ('exposure_us', 'gain_db', "
		                "'frame_rate_hz')");
		return -1;
	}
	if ((*id = pcpy_control_id(n)) < 0) {
		PyErr_Format(PyExc_ValueError,
		             "control '%s': unknown (exposure_us, gain_db, frame_rate_hz)", n);
		return -1;
	}
	return 0;
}

static PyObject *src_get(SourceObject *so, PyObject *name)
{
	int id, rc;
	double v;
	if (src_ready(so) || control_arg(name, &id))
		return NULL;
	if ((rc = pcpy_control_get(so->s, id, &v)))
		return raise_pc(rc);
	return PyFloat_FromDouble(v);
}

static PyObject *src_set(SourceObject *so, PyObject *args)
{
	PyObject *name;
	double v, applied = 0;
	int id, rc;
	if (!PyArg_ParseTuple(args, "Od:set", &name, &v))
		return NULL;
	if (src_ready(so) || control_arg(name, &id))
		return NULL;
	if ((rc = pcpy_control_set(so->s, id, v, &applied)))
		return raise_pc(rc);
	return PyFloat_FromDouble(applied);
}

static PyObject *src_controls(SourceObject *so, PyObject *noargs)
{
	(void)noargs;
	if (src_ready(so))
		return NULL;
	PyObject *d = PyDict_New();
	for (int id = 0; d && id < pcpy_control_count(); id++) {
		pc_control_info ci;
		double v;
		if (pcpy_control_query(so->s, id, &ci) || pcpy_control_get(so->s, id, &v))
			continue; /* not supported by this source */
		PyObject *e = Py_BuildValue("{s:d,s:d,s:d,s:d,s:O,s:d}", "min", ci.min, "max",
		                            ci.max, "step", ci.step, "default", ci.def, "live",
		                            ci.live ? Py_True : Py_False, "value", v);
		if (dict_set(d, pcpy_control_name(id), e))
			Py_CLEAR(d);
	}
	return d;
}

static PyObject *src_stats(SourceObject *so, PyObject *noargs)
{
	(void)noargs;
	if (src_ready(so))
		return NULL;
	pc_source_stats st;
	int rc = pcpy_source_stats(so->s, &st);
	if (rc)
		return raise_pc(rc);
	PyObject *d = Py_BuildValue(
	    "{s:K,s:K,s:K,s:K,s:K,s:K,s:K}", "completed", (unsigned long long)st.completed,
	    "failed", (unsigned long long)st.failed, "dropped", (unsigned long long)st.dropped,
	    "timeouts", (unsigned long long)st.timeouts, "underruns",
	    (unsigned long long)st.underruns, "transport_failures",
	    (unsigned long long)st.transport_failures, "bytes", (unsigned long long)st.bytes);
	if (d && st.has_packets) {
		if (dict_set(d, "missing_packets",
		             PyLong_FromUnsignedLongLong(st.missing_packets)) ||
		    dict_set(d, "resent_packets", PyLong_FromUnsignedLongLong(st.resent_packets)))
			Py_CLEAR(d);
	} else if (d) {
		if (PyDict_SetItemString(d, "missing_packets", Py_None) ||
		    PyDict_SetItemString(d, "resent_packets", Py_None))
			Py_CLEAR(d);
	}
	return d;
}

static PyObject *src_get_format(SourceObject *so, void *closure)
{
	(void)closure;
	if (src_ready(so))
		return NULL;
	pc_source_format f;
	int rc = pcpy_source_format(so->s, &f);
	if (rc)
		return raise_pc(rc);
	char layout[64] = "";
	if (f.polarized)
		pcpy_layout_format(&f.mosaic, layout, sizeof layout);
	return Py_BuildValue("{s:s,s:I,s:I,s:I,s:I,s:n,s:I,s:I,s:O,s:s}", "format", f.format_name,
	                     "width", f.width, "height", f.height, "offset_x", f.offset_x,
	                     "offset_y", f.offset_y, "stride", (Py_ssize_t)f.stride, "sensor_width",
	                     f.sensor_width, "sensor_height", f.sensor_height, "polarized",
	                     f.polarized ? Py_True : Py_False, "layout", layout);
}

static PyObject *src_get_info(SourceObject *so, void *closure)
{
	(void)closure;
	if (src_ready(so))
		return NULL;
	pc_source_info i;
	int rc = pcpy_source_info(so->s, &i);
	if (rc)
		return raise_pc(rc);
	char layout[64] = "";
	if (i.polarized)
		pcpy_layout_format(&i.mosaic, layout, sizeof layout);
	return Py_BuildValue("{s:s,s:s,s:s,s:s,s:s,s:s,s:I,s:I,s:O,s:s}", "scheme", i.scheme, "id",
	                     i.id, "vendor", i.vendor, "model", i.model, "serial", i.serial,
	                     "driver", i.driver, "sensor_width", i.sensor_width, "sensor_height",
	                     i.sensor_height, "polarized", i.polarized ? Py_True : Py_False,
	                     "layout", layout);
}

static PyObject *src_get_state(SourceObject *so, void *closure)
{
	(void)closure;
	char buf[32];
	snprintf(buf, sizeof buf, "%s", so->s ? pcpy_source_state(so->s) : "closed");
	for (char *c = buf; *c; c++)
		*c = (char)(*c >= 'A' && *c <= 'Z' ? *c - 'A' + 'a' : *c);
	return PyUnicode_FromString(buf);
}

static PyObject *src_repr(SourceObject *so)
{
	PyObject *st = src_get_state(so, NULL);
	if (!st)
		return NULL;
	PyObject *r = PyUnicode_FromFormat("<polarcam.Source %R (%U)>", so->uri, st);
	Py_DECREF(st);
	return r;
}

static PyMethodDef src_methods[] = {
    {"read", (PyCFunction)(void (*)(void))src_read, METH_VARARGS | METH_KEYWORDS,
     "read(timeout_ms=None)\n--\n\nThe next Frame (starting the stream if needed), or None "
     "after the last frame of a recording. TimeoutError when nothing came within timeout_ms "
     "(default: open()'s timeout_ms, 5000; -1 waits forever), ConnectionError when the device "
     "is gone."},
    {"start", (PyCFunction)src_start, METH_NOARGS,
     "start()\n--\n\nStarts streaming (iteration and read() start it when needed)."},
    {"stop", (PyCFunction)src_stop, METH_NOARGS,
     "stop()\n--\n\nStops streaming; frames not yet read are dropped; start() again resumes."},
    {"close", (PyCFunction)src_close, METH_NOARGS,
     "close()\n--\n\nStops and closes the source (also on leaving a with block)."},
    {"get", (PyCFunction)src_get, METH_O,
     "get(name)\n--\n\nThe value of a control: 'exposure_us', 'gain_db' or 'frame_rate_hz'."},
    {"set", (PyCFunction)src_set, METH_VARARGS,
     "set(name, value)\n--\n\nSets a control and returns the value applied (after rounding "
     "to the device's step). Outside its range: ValueError (never clamped); while streaming "
     "only live controls may change (RuntimeError otherwise)."},
    {"controls", (PyCFunction)src_controls, METH_NOARGS,
     "controls()\n--\n\nThe controls this source supports: {name: {min, max, step, default, "
     "live, value}}."},
    {"stats", (PyCFunction)src_stats, METH_NOARGS,
     "stats()\n--\n\nStatistics: completed, failed, dropped, timeouts, underruns, "
     "transport_failures, missing_packets, resent_packets (None unless GigE Vision), bytes."},
    {"__enter__", (PyCFunction)src_enter, METH_NOARGS, NULL},
    {"__exit__", (PyCFunction)src_exit, METH_VARARGS, NULL},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef src_getset[] = {
    {"format", (getter)src_get_format, NULL,
     "The negotiated format: {format, width, height, offset_x, offset_y, stride, "
     "sensor_width, sensor_height, polarized, layout}.",
     NULL},
    {"info", (getter)src_get_info, NULL,
     "What the source is: {scheme, id, vendor, model, serial, driver, sensor_width, "
     "sensor_height, polarized, layout}.",
     NULL},
    {"state", (getter)src_get_state, NULL, "'open', 'ready', 'streaming', 'failed' or 'closed'.",
     NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyObject *src_self_iter(PyObject *o)
{
	Py_INCREF(o);
	return o;
}

static PyTypeObject SourceType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "polarcam.Source",
    .tp_basicsize = sizeof(SourceObject),
    .tp_dealloc = (destructor)src_dealloc,
    .tp_repr = (reprfunc)src_repr,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A frame source opened by polarcam.open(): a context manager and an iterator "
              "of Frame objects.",
    .tp_iter = src_self_iter,
    .tp_iternext = (iternextfunc)src_iternext,
    .tp_methods = src_methods,
    .tp_getset = src_getset,
};

/* ------------------------------------------------------------------------------------------
 * Calibration: a calibration file of polarcam calibrate, read once (calib/, docs/calibration.md)
 */

static PyObject *cal_new(PyTypeObject *type, PyObject *args, PyObject *kw)
{
	static char *kwl[] = {"path", NULL};
	PyObject *path = NULL;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "O&:Calibration", kwl, PyUnicode_FSConverter,
	                                 &path))
		return NULL;
	const char *p = PyBytes_AS_STRING(path);
	pcpy_calib *c = NULL;
	int rc;
	Py_BEGIN_ALLOW_THREADS;
	rc = pcpy_calib_read(p, &c);
	Py_END_ALLOW_THREADS;
	if (rc) {
		Py_DECREF(path);
		return raise_pc(rc);
	}
	CalibrationObject *self = (CalibrationObject *)type->tp_alloc(type, 0);
	if (!self) {
		pcpy_calib_free(c);
		Py_DECREF(path);
		return NULL;
	}
	self->cal = c;
	self->path = PyUnicode_DecodeFSDefault(p);
	Py_DECREF(path);
	if (!self->path) {
		Py_DECREF(self);
		return NULL;
	}
	return (PyObject *)self;
}

static void cal_dealloc(CalibrationObject *self)
{
	pcpy_calib_free(self->cal);
	Py_XDECREF(self->path);
	Py_TYPE(self)->tp_free((PyObject *)self);
}

static const pc_calib *cal_of(CalibrationObject *self)
{
	return pcpy_calib_get(self->cal);
}

static PyObject *cal_repr(CalibrationObject *self)
{
	const pc_calib *c = cal_of(self);
	char lay[64];
	pcpy_layout_format(&c->geo.mosaic, lay, sizeof lay);
	return PyUnicode_FromFormat(
	    "<polarcam.Calibration %R: %ux%u at (%u, %u), %u bits, layout "
	    "%s, parts%s%s%s%s>",
	    self->path, c->geo.width, c->geo.height, c->geo.offset_x, c->geo.offset_y, c->geo.bits,
	    lay, (c->parts & PC_CAL_DARK) ? " dark" : "", (c->parts & PC_CAL_FLAT) ? " flat" : "",
	    (c->parts & PC_CAL_ANALYSER) ? " analyser" : "", (c->parts & PC_CAL_ECM) ? " ecm" : "");
}

/* A read-only view of memory owned by the calibration (kept alive by the array). */
static PyObject *cal_view(CalibrationObject *self, const void *data, int nd, npy_intp *dims,
                          int type, npy_intp *strides)
{
	if (!data)
		Py_RETURN_NONE;
	PyObject *a = PyArray_New(&PyArray_Type, nd, dims, type, strides, (void *)data, 0,
	                          NPY_ARRAY_ALIGNED, NULL);
	if (!a)
		return NULL;
	Py_INCREF(self);
	if (PyArray_SetBaseObject((PyArrayObject *)a, (PyObject *)self)) {
		Py_DECREF(a);
		return NULL;
	}
	return a;
}

enum {
	CAL_DARK,
	CAL_DARK_NOISE,
	CAL_GAIN,
	CAL_ANALYSIS,
	CAL_RESIDUAL,
	CAL_VALID,
	CAL_PINV_SP,
	CAL_ECM_W,
	CAL_ECM_A
};

static PyObject *cal_map(CalibrationObject *self, void *which)
{
	const pc_calib *c = cal_of(self);
	npy_intp H = c->geo.height, W = c->geo.width;
	npy_intp d2[2] = {H, W}, d3[3] = {H, W, 3}, d4[4] = {3, 4, H / 2, W / 2};
	switch ((int)(intptr_t)which) {
	case CAL_DARK:
		return cal_view(self, c->dark, 2, d2, NPY_FLOAT32, NULL);
	case CAL_DARK_NOISE:
		return cal_view(self, c->dark_noise, 2, d2, NPY_FLOAT32, NULL);
	case CAL_GAIN:
		return cal_view(self, c->gain, 2, d2, NPY_FLOAT32, NULL);
	case CAL_ANALYSIS:
		return cal_view(self, c->analysis, 3, d3, NPY_FLOAT32, NULL);
	case CAL_RESIDUAL:
		return cal_view(self, c->residual, 2, d2, NPY_FLOAT32, NULL);
	case CAL_VALID:
		return cal_view(self, c->valid, 2, d2, NPY_UINT8, NULL);
	case CAL_PINV_SP:
		return cal_view(self, c->pinv_sp, 4, d4, NPY_FLOAT32, NULL);
	case CAL_ECM_W: {
		if (!(c->parts & PC_CAL_ECM))
			Py_RETURN_NONE;
		npy_intp d[2] = {4, c->n_psg}, st[2] = {sizeof c->ecm_W[0], sizeof(double)};
		return cal_view(self, c->ecm_W, 2, d, NPY_FLOAT64, st);
	}
	case CAL_ECM_A: {
		if (!(c->parts & PC_CAL_ECM))
			Py_RETURN_NONE;
		npy_intp d[2] = {4 * (npy_intp)c->n_psa, 4},
		         st[2] = {sizeof c->ecm_A[0], sizeof(double)};
		return cal_view(self, c->ecm_A, 2, d, NPY_FLOAT64, st);
	}
	}
	Py_RETURN_NONE;
}

enum { CAL_WIDTH, CAL_HEIGHT, CAL_OFFSET_X, CAL_OFFSET_Y, CAL_SENSOR_W, CAL_SENSOR_H, CAL_BITS };

static PyObject *cal_int(CalibrationObject *self, void *which)
{
	const pc_calib_geometry *g = &cal_of(self)->geo;
	const unsigned v[] = {g->width,        g->height,        g->offset_x, g->offset_y,
	                      g->sensor_width, g->sensor_height, g->bits};
	return PyLong_FromUnsignedLong(v[(int)(intptr_t)which]);
}

static PyObject *cal_path(CalibrationObject *self, void *closure)
{
	(void)closure;
	Py_INCREF(self->path);
	return self->path;
}

static PyObject *cal_camera(CalibrationObject *self, void *closure)
{
	(void)closure;
	return PyUnicode_DecodeUTF8(cal_of(self)->camera, (Py_ssize_t)strlen(cal_of(self)->camera),
	                            "replace");
}

static PyObject *cal_layout(CalibrationObject *self, void *closure)
{
	(void)closure;
	char lay[64];
	pcpy_layout_format(&cal_of(self)->geo.mosaic, lay, sizeof lay);
	return PyUnicode_FromString(lay);
}

static PyObject *cal_black(CalibrationObject *self, void *closure)
{
	(void)closure;
	return PyFloat_FromDouble(cal_of(self)->black_level);
}

static PyObject *cal_saturation(CalibrationObject *self, void *closure)
{
	(void)closure;
	return PyFloat_FromDouble(cal_of(self)->saturation);
}

static PyObject *cal_system_gain(CalibrationObject *self, void *closure)
{
	(void)closure;
	const double k = cal_of(self)->system_gain;
	if (k > 0)
		return PyFloat_FromDouble(k);
	Py_RETURN_NONE;
}

static PyObject *cal_system_gain_db(CalibrationObject *self, void *closure)
{
	(void)closure;
	const pc_calib *c = cal_of(self);
	if (c->system_gain > 0 && isfinite(c->system_gain_db))
		return PyFloat_FromDouble(c->system_gain_db);
	Py_RETURN_NONE;
}

static PyObject *cal_dark_gain_db(CalibrationObject *self, void *closure)
{
	(void)closure;
	const pc_calib *c = cal_of(self);
	if (c->dark && isfinite(c->dark_gain_db))
		return PyFloat_FromDouble(c->dark_gain_db);
	Py_RETURN_NONE;
}

static PyObject *cal_parts(CalibrationObject *self, void *closure)
{
	(void)closure;
	unsigned p = cal_of(self)->parts;
	static const struct {
		unsigned bit;
		const char *name;
	} names[] = {{PC_CAL_DARK, "dark"},
	             {PC_CAL_FLAT, "flat"},
	             {PC_CAL_ANALYSER, "analyser"},
	             {PC_CAL_ECM, "ecm"}};
	PyObject *t = PyTuple_New(0);
	for (size_t i = 0; t && i < sizeof names / sizeof names[0]; i++) {
		if (!(p & names[i].bit))
			continue;
		PyObject *n = PyUnicode_FromString(names[i].name);
		if (!n || _PyTuple_Resize(&t, PyTuple_GET_SIZE(t) + 1)) {
			Py_XDECREF(n);
			Py_XDECREF(t);
			return NULL;
		}
		PyTuple_SET_ITEM(t, PyTuple_GET_SIZE(t) - 1, n);
	}
	return t;
}

static PyObject *cal_provenance(CalibrationObject *self, void *closure)
{
	(void)closure;
	const char *p = cal_of(self)->provenance;
	if (!p || !*p)
		Py_RETURN_NONE;
	PyObject *text = PyUnicode_FromString(p);
	if (!text)
		return NULL;
	PyObject *r = json_call("loads", text);
	Py_DECREF(text);
	return r;
}

static PyObject *cal_pinv(CalibrationObject *self, PyObject *args, PyObject *kw)
{
	static char *kwl[] = {"method", "threads", NULL};
	const char *method = NULL;
	int threads = 0, dm, rc;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "|zi:pinv", kwl, &method, &threads))
		return NULL;
	const pc_calib *c = cal_of(self);
	uint32_t gw, gh;
	if ((rc = pcpy_method(method, &c->geo.mosaic, &dm)) ||
	    (rc = pcpy_calib_pinv_grid(self->cal, dm, &gw, &gh)))
		return raise_pc(rc);
	npy_intp dims[4] = {3, 4, gh, gw};
	PyArrayObject *out = (PyArrayObject *)new_array(4, dims, NPY_FLOAT32);
	if (!out)
		return NULL;
	Py_BEGIN_ALLOW_THREADS;
	rc = pcpy_calib_pinv_copy(self->cal, dm, threads, PyArray_DATA(out));
	Py_END_ALLOW_THREADS;
	if (rc) {
		Py_DECREF(out);
		return raise_pc(rc);
	}
	return (PyObject *)out;
}

static PyMethodDef cal_methods[] = {
    {"pinv", KW(cal_pinv), METH_VARARGS | METH_KEYWORDS,
     "pinv(method=None, threads=0)\n--\n\n"
     "The per-output-pixel analyser pseudo-inverses W+ that stokes(raw, calibration=self, "
     "method=method) applies: float32 (3, 4, GH, GW), element (i, c) of output pixel (x, y) "
     "at [i, c, y, x] (W x H for the full-resolution methods, the analysis maps demosaicked "
     "with the method; W/2 x H/2 per 2x2 block for superpixel methods: pinv_superpixel). A "
     "copy. ValueError without an analyser part."},
    {NULL, NULL, 0, NULL}};

#define CAL_GET(name, fn, which, doc)                                                              \
	{                                                                                          \
		name, (getter)fn, NULL, doc, (void *)(intptr_t)(which)                             \
	}
static PyGetSetDef cal_getset[] = {
    {"path", (getter)cal_path, NULL, "str: the file read", NULL},
    {"camera", (getter)cal_camera, NULL, "str: the camera (source) it was measured on", NULL},
    CAL_GET("width", cal_int, CAL_WIDTH, "int: frame width the calibration applies to"),
    CAL_GET("height", cal_int, CAL_HEIGHT, "int: frame height"),
    CAL_GET("offset_x", cal_int, CAL_OFFSET_X, "int: ROI origin on the sensor (x)"),
    CAL_GET("offset_y", cal_int, CAL_OFFSET_Y, "int: ROI origin on the sensor (y)"),
    CAL_GET("sensor_width", cal_int, CAL_SENSOR_W, "int: sensor width (0: unknown)"),
    CAL_GET("sensor_height", cal_int, CAL_SENSOR_H, "int: sensor height (0: unknown)"),
    CAL_GET("bits", cal_int, CAL_BITS, "int: ADC bit depth"),
    {"layout", (getter)cal_layout, NULL, "str: the mosaic at pixel (0, 0) of the frames", NULL},
    {"black_level", (getter)cal_black, NULL, "float: mean dark offset (DN)", NULL},
    {"saturation", (getter)cal_saturation, NULL,
     "float: samples at or above it are not trusted (DN)", NULL},
    {"system_gain", (getter)cal_system_gain, NULL,
     "float or None: the system gain K (DN per electron) the flats measured (EMVA 1288 photon "
     "transfer), the noise gain of the noise-aware methods at the flats' settings",
     NULL},
    {"system_gain_db", (getter)cal_system_gain_db, NULL,
     "float or None: the flats' analog gain (dB) at which system_gain holds; at a gain g the "
     "system gain is system_gain * 10**((g - system_gain_db) / 20) (None: not recorded)",
     NULL},
    {"dark_gain_db", (getter)cal_dark_gain_db, NULL,
     "float or None: the dark frames' analog gain (dB); at a gain g the dark map's part above "
     "black_level is scaled by 10**((g - dark_gain_db) / 20) (None: not recorded, no dark map)",
     NULL},
    {"parts", (getter)cal_parts, NULL,
     "tuple of str: what the file holds ('dark', 'flat', 'analyser', 'ecm')", NULL},
    {"provenance", (getter)cal_provenance, NULL,
     "dict or None: inputs and options of every calibration step", NULL},
    CAL_GET("dark", cal_map, CAL_DARK, "float32 (H, W) or None: per-pixel offset, DN"),
    CAL_GET("dark_noise", cal_map, CAL_DARK_NOISE,
            "float32 (H, W) or None: temporal sigma of one frame, DN"),
    CAL_GET("gain", cal_map, CAL_GAIN, "float32 (H, W) or None: relative gain, mean 1"),
    CAL_GET("analysis", cal_map, CAL_ANALYSIS,
            "float32 (H, W, 3) or None: analysis vectors (a0, a1, a2) after dark and gain"),
    CAL_GET("residual", cal_map, CAL_RESIDUAL,
            "float32 (H, W) or None: RMS residual of the analyser fit, DN"),
    CAL_GET("valid", cal_map, CAL_VALID, "uint8 (H, W) or None: 1 = trusted pixel"),
    CAL_GET("pinv_superpixel", cal_map, CAL_PINV_SP,
            "float32 (3, 4, H/2, W/2) or None: W+ per 2x2 block"),
    CAL_GET("ecm_generator", cal_map, CAL_ECM_W,
            "float64 (4, n_psg) or None: ECM generator W (mean W[0] = 1)"),
    CAL_GET("ecm_analyser", cal_map, CAL_ECM_A,
            "float64 (4 n_psa, 4) or None: ECM analyser A (row 4a + c)"),
    {NULL, NULL, NULL, NULL, NULL}};

static PyTypeObject CalibrationType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "polarcam.Calibration",
    .tp_basicsize = sizeof(CalibrationObject),
    .tp_dealloc = (destructor)cal_dealloc,
    .tp_repr = (reprfunc)cal_repr,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Calibration(path)\n--\n\n"
              "A calibration file written by polarcam calibrate (docs/calibration.md), read "
              "and validated once: pass it as stokes(raw, calibration=cal) for any number of "
              "frames (from any number of threads). Its maps are read-only numpy views; "
              "geometry, layout, bit depth and levels are attributes. Errors name the file and "
              "the member (FileNotFoundError, ValueError for a malformed or newer file).",
    .tp_methods = cal_methods,
    .tp_getset = cal_getset,
    .tp_new = cal_new,
};

/* ------------------------------------------------------------------------------------------
 * the benchmark's baseline: the C pipeline timed in C
 */

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* _c_pipeline_seconds(raw, out, method, layout, threads, repeats): the seconds of each of
 * `repeats` calls of the library's raw -> Stokes front door on the same buffers, timed in C
 * without the interpreter (python/bench_polarcam.py compares polarcam.stokes with it). */
static PyObject *py_c_pipeline_seconds(PyObject *self, PyObject *args, PyObject *kw)
{
	(void)self;
	static char *kwl[] = {"raw", "out", "method", "layout", "threads", "repeats", NULL};
	PyObject *raw_o, *out_o;
	const char *method = NULL, *layout = "90,45,135,0";
	int threads = 0, repeats = 1, rc;
	if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|zsii:_c_pipeline_seconds", kwl, &raw_o,
	                                 &out_o, &method, &layout, &threads, &repeats))
		return NULL;
	pc_view v;
	pc_mosaic m;
	pcpy_stokes_opts o = {0, threads, 0, 0, 0, 0, NULL, 0};
	PyArrayObject *raw = as_ndarray(raw_o, "raw", "(H, W)");
	if (!raw || raw_view(raw, "raw", 0, &v))
		return NULL;
	if ((rc = pcpy_layout_parse(layout, &m)) || (rc = pcpy_method(method, &m, &o.method)))
		return raise_pc(rc);
	uint32_t ow, oh;
	pcpy_out_size(o.method, v.width, v.height, &ow, &oh);
	pc_stokes_out so;
	PyObject *res = stokes_outputs(out_o, ow, oh, &so);
	if (!res)
		return NULL;
	Py_DECREF(res); /* the caller's arrays stay alive through out_o */
	if (repeats < 1)
		repeats = 1;
	double *t = PyMem_Malloc(sizeof(double) * (size_t)repeats);
	if (!t)
		return PyErr_NoMemory();
	rc = 0;
	Py_BEGIN_ALLOW_THREADS;
	for (int i = 0; i < repeats && !rc; i++) {
		double t0 = now_s();
		rc = pcpy_stokes(&v, &m, &o, &so, NULL);
		t[i] = now_s() - t0;
	}
	Py_END_ALLOW_THREADS;
	PyObject *l = rc ? raise_pc(rc) : PyList_New(repeats);
	for (int i = 0; l && i < repeats; i++)
		PyList_SET_ITEM(l, i, PyFloat_FromDouble(t[i]));
	PyMem_Free(t);
	return l;
}

/* _stokes_streams(out): whether polarcam.stokes writes these five (H, W) planes (a Stokes or a
 * 5-sequence, s0 given) with non-temporal stores on this machine (pc_stokes_streams: the
 * library's rule, POLARCAM_NT_MIN_BYTES included), for python/bench_polarcam.py and tests. */
static PyObject *py_stokes_streams(PyObject *self, PyObject *out_o)
{
	(void)self;
	PyObject *s0 = PySequence_Check(out_o) ? PySequence_GetItem(out_o, 0) : NULL;
	if (!s0 || !PyArray_Check(s0) || PyArray_NDIM((PyArrayObject *)s0) != 2) {
		Py_XDECREF(s0);
		PyErr_SetString(PyExc_ValueError, "out: expected a Stokes or 5 arrays, s0 (H, W)");
		return NULL;
	}
	uint32_t h = (uint32_t)PyArray_DIM((PyArrayObject *)s0, 0);
	uint32_t w = (uint32_t)PyArray_DIM((PyArrayObject *)s0, 1);
	Py_DECREF(s0);
	pc_stokes_out so;
	PyObject *res = stokes_outputs(out_o, w, h, &so);
	if (!res)
		return NULL;
	/* the planes belong to arrays res holds */
	PyObject *r = PyBool_FromLong(pcpy_stokes_streams(&so, w, h));
	Py_DECREF(res);
	return r;
}

/* ------------------------------------------------------------------------------------------
 * the module
 */

PyDoc_STRVAR(
    doc_demosaic,
    "demosaic(raw, method=None, layout='90,45,135,0', bits=None, threads=0, out=None, "
    "noise_gain=None)\n--\n\n"
    "Demosaics a raw polarizer mosaic into full-resolution analyser images, as polarcam "
    "demosaic.\n\n"
    "raw: (H, W) uint8, uint16 or float32 numpy array, used in place (any row stride; pixels "
    "of a row adjacent). method: a name of methods() (None: bilinear, or bayer-first for "
    "colour layouts). layout: [BAYER:]A,B,C,D[@DX,DY], the analyser angles of the 2x2 block "
    "row by row (IMX250MZR: 90,45,135,0). bits: the sensor's bit depth (None: the dtype's; "
    "pass 12 for 12-bit frames: values above 2^bits - 1 are a ValueError, and edge-aware "
    "methods use it as full scale; float32 data in raw units of such a sensor, e.g. averaged "
    "frames: its full scale 2^bits - 1, not checked). threads: 0 all cores, 1 the calling "
    "thread only. noise_gain: the sensor's variance per unit signal in raw units (the system "
    "gain K in DN/e-, EMVA 1288) for the noise-aware methods (noise_gain True in methods(); the "
    "others ignore it); "
    "None: estimated from the frame. Negative, NaN or infinite: ValueError.\n"
    "Returns float32 (H, W, 4) I0, I45, I90, I135 in the raw's units ((H, W, 12) R, G, B x "
    "4 analysers for colour layouts; (H/2, W/2, C) for superpixel-half), or writes into out.");

PyDoc_STRVAR(
    doc_stokes,
    "stokes(raw, method=None, layout=None, bits=None, black_level=None, calibration=None, "
    "threads=0, out=None, saturation_level=None, dead_level=None, noise_gain=None, "
    "gain_db=None)\n--\n\n"
    "The pipeline of polarcam process: demosaic -> S0, S1, S2, DoLP, AoLP (float32 (H, W) "
    "each, the same values), through the library's front door.\n\n"
    "raw: (H, W) raw mosaic as for demosaic(), or float32 (H, W, 4) analyser images I0, I45, "
    "I90, I135. layout: as demosaic() (None: the calibration file's layout, else "
    "'90,45,135,0'). black_level: raw units subtracted before demosaicking (None: 0; values "
    "below it stay negative). saturation_level, dead_level: raw units; an output pixel that "
    "depends on a sample >= saturation_level or <= dead_level is 0 in the result's valid "
    "mask (its value is computed as any other). noise_gain: as demosaic()'s (the "
    "methods marked noise_gain in methods(); raw mosaics only); with a calibration file "
    "and no noise_gain, its system_gain, scaled to gain_db (the frame's analog gain in dB, "
    "frame.gain_db) when both it and the file's system_gain_db are known; gain_db also "
    "scales the file's dark map above its black_level from dark_gain_db to the frame's "
    "gain.\n"
    "calibration: a Calibration, the path of a calibration file of polarcam calibrate (read "
    "for this call; load a Calibration once for many frames), or float32 (3, 4) / (3, 4, "
    "GH, GW) analyser pseudo-inverses (analyser_pinv); None: ideal analysers. A calibration "
    "file corrects dark and gain per pixel and applies per-pixel pseudo-inverses; the frame "
    "must have its size, layout and (when bits is given) bit depth (ValueError naming the "
    "difference); its valid mask marks outputs depending on untrusted or saturated "
    "samples.\n"
    "out: a Stokes or 5 float32 (H, W) arrays (None entries are not computed).\n"
    "Returns a Stokes (s0, s1, s2, dolp, aolp) with attributes valid (uint8 (H, W), or None "
    "when no level and no calibration file was given) and n_invalid. AoLP is in radians in "
    "[0, pi), from the image x axis, counter-clockwise as the image is viewed.");

PyDoc_STRVAR(doc_pbrdf,
             "pbrdf(n, k, sigma, theta_i, theta_r, phi=180, diffuse='fresnel', shadowing='ts', "
             "rho='table')\n--\n\n"
             "The corrected microfacet polarized BRDF Mueller matrix in 1/sr (docs/physics.md "
             "section 2), as polarcam pbrdf. Arguments broadcast like numpy arrays; angles in "
             "degrees (theta in [0, 90], phi = 180 is the forward plane). diffuse: fresnel, "
             "geometric or none; shadowing: ts or none; rho: table, quad or quad:N.\n"
             "Returns float64 (..., 4, 4). Bad parameters: ValueError naming the element.");

PyDoc_STRVAR(doc_decompose,
             "decompose(M, filter=True)\n--\n\n"
             "Lu-Chipman decomposition of Mueller matrices M (..., 4, 4), as polarcam "
             "decompose (filter=False: --no-filter). M is used in place when float64 "
             "C-contiguous, else converted (a copy). Returns a Decomposition of arrays "
             "(D, R, Delta, physical, diattenuation, retardance_axis, flags, ...). A matrix "
             "with NaN or infinity: ValueError naming its index.");

PyDoc_STRVAR(
    doc_render,
    "render(scene=None, seed=0, frame=0, roi=None, threads=0)\n--\n\n"
    "Renders a scene through the sensor model, as polarcam render: returns (raw, truth, "
    "meta).\n\n"
    "scene: None or 'default' (the built-in default scene), a path to a scene file "
    "(docs/scene-format.md), or a dict in the scene format. frame: a frame number, or a "
    "sequence of them (raw is then (N, H, W)); frame N is reproducible from (scene, seed, N) "
    "alone. roi: (x, y, width, height) on the sensor (bit-identical to a crop).\n"
    "raw: uint16 (H, W) LSB-aligned at the sensor's bit depth; truth: float32 (H, W, 4) "
    "S0..S3 radiance in W/(m^2 sr) in the image-plane frame ((H, W, 3, 4) for colour "
    "sensors; S3 NaN unless the scene declares 'circular'), of the first frame's "
    "polarization state; meta: dict (layout, bits, black_level_dn, dn_per_radiance, "
    "sequence, timestamp_ns, effects, scene, ...; truth_mueller when the scene declares "
    "'mueller').");

PyDoc_STRVAR(
    doc_open,
    "open(uri, **controls)\n--\n\n"
    "Opens a frame source by URI, as polarcam capture: 'sim:SCENE[?seed=S&fps=F...]', "
    "'file:DIR' (a recording), 'aravis:ID', 'v4l2:/dev/videoN', 'libcamera:ID'.\n\n"
    "controls: exposure_us, gain_db, frame_rate_hz, roi=(x, y, width, height), format (pixel "
    "format name, e.g. 'Mono12'), buffers (1..64, default 8), timeout_ms (default 5000). A "
    "request the source would adjust is a ValueError naming what it proposes.\n"
    "Returns a Source: use it in a with block and iterate over its Frames (raw uint16 with "
    "sequence, timestamp_ns, layout, bits, ...).");

PyDoc_STRVAR(
    doc_picture,
    "picture(image, kind=None, lo=None, hi=None, mask_s0=None, dolp=None, s0=None)\n--\n\n"
    "False-colour picture as uint8 RGB (H, W, 3), the colours of polarcam process's "
    "pictures.\n\n"
    "image: a Stokes (kind default 'aolp'), or a float32 (H, W) array with kind= saying what "
    "it is. kind: 's0' (grey, 0 to the 99.9th percentile), 's1', 's2' (grey, symmetric), "
    "'dolp' (grey 0..1), 'aolp' (hue = AoLP, value = DoLP), 'aolp_sat' (saturation = DoLP), "
    "'aolp_hue' (hue only), 'imin', 'imax', 'diffuse', 'specular' (of a Stokes, by minmax(); "
    "grey from 0 to the S0 picture's top, S0's 99.9th percentile, as process --minmax --split "
    "draws them; an array with s0= for the scale), 'grey' (lo..hi). mask_s0: the low-signal "
    "hatch where S0 < mask_s0 on dolp/aolp pictures (None: 1 % of the S0 99.9th percentile, "
    "as the CLI; 0: none); needs S0 (a Stokes, or s0=).");

PyDoc_STRVAR(doc_minmax,
             "minmax(image, s1=None, s2=None)\n--\n\n"
             "Imin, Imax and the diffuse/specular split of a Stokes (or of float32 (H, W) "
             "S0, S1, S2 arrays) as a MinMax (imin, imax, diffuse, specular), the values of "
             "polarcam process --minmax --split: Imin/Imax = (S0 -/+ sqrt(S1^2 + S2^2)) / 2, "
             "diffuse = 2 Imin, specular = Imax - Imin (docs/physics-notes.md).");

PyDoc_STRVAR(doc_pinv,
             "analyser_pinv(W)\n--\n\n"
             "Pseudo-inverses (W^T W)^-1 W^T of float32 analyser matrices W (..., 4, 3) (rows: "
             "the responses of I0, I45, I90, I135 to S0, S1, S2), for stokes(calibration=): "
             "float32 (3, 4, ...) (element (i, c) of matrix k at [i, c, k...]: the layout of "
             "the library's pc_analyser_pinv and of a calibration file's pinv_superpixel; "
             "(3, 4) for one matrix, as numpy.linalg.pinv). ValueError naming the first "
             "singular matrix.");

static PyMethodDef module_methods[] = {
    {"demosaic", KW(py_demosaic), METH_VARARGS | METH_KEYWORDS, doc_demosaic},
    {"stokes", KW(py_stokes), METH_VARARGS | METH_KEYWORDS, doc_stokes},
    {"pbrdf", KW(py_pbrdf), METH_VARARGS | METH_KEYWORDS, doc_pbrdf},
    {"decompose", KW(py_decompose), METH_VARARGS | METH_KEYWORDS, doc_decompose},
    {"render", KW(py_render), METH_VARARGS | METH_KEYWORDS, doc_render},
    {"open", KW(py_open), METH_VARARGS | METH_KEYWORDS, doc_open},
    {"picture", KW(py_picture), METH_VARARGS | METH_KEYWORDS, doc_picture},
    {"minmax", KW(py_minmax), METH_VARARGS | METH_KEYWORDS, doc_minmax},
    {"analyser_pinv", py_analyser_pinv, METH_O, doc_pinv},
    {"methods", py_methods, METH_NOARGS,
     "methods()\n--\n\nThe demosaicking methods: [{name, accuracy, cost, source, monochrome, "
     "colour, half_resolution, noise_gain}] (noise_gain: demosaic's noise_gain applies)."},
    {"_c_pipeline_seconds", KW(py_c_pipeline_seconds), METH_VARARGS | METH_KEYWORDS,
     "_c_pipeline_seconds(raw, out, method=None, layout='90,45,135,0', threads=0, "
     "repeats=1)\n--\n\nFor python/bench_polarcam.py: seconds of each of `repeats` calls of "
     "the C pipeline (raw -> Stokes) on the same buffers, timed in C."},
    {"_stokes_streams", py_stokes_streams, METH_O,
     "_stokes_streams(out)\n--\n\nFor python/bench_polarcam.py: whether stokes(raw, out=out) "
     "writes these planes with non-temporal stores on this machine."},
    {"backends", py_backends, METH_NOARGS,
     "backends()\n--\n\nThe frame-source URI schemes: [{scheme, built, summary}]."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT,
    "polarcam._polarcam",
    "The polarcam C library in memory: see the polarcam package.",
    -1,
    module_methods,
    NULL,
    NULL,
    NULL,
    NULL};

PyMODINIT_FUNC PyInit__polarcam(void)
{
	import_array();
	PyObject *m = PyModule_Create(&module_def);
	if (!m)
		return NULL;
	if ((!StokesType.tp_name && PyStructSequence_InitType2(&StokesType, &stokes_desc)) ||
	    (!MinMaxType.tp_name && PyStructSequence_InitType2(&MinMaxType, &minmax_desc)) ||
	    (!DecType.tp_name && PyStructSequence_InitType2(&DecType, &dec_desc)) ||
	    (!FrameType.tp_name && PyStructSequence_InitType2(&FrameType, &frame_desc)) ||
	    PyType_Ready(&SourceType) || PyType_Ready(&CalibrationType))
		goto fail;
	Py_INCREF(&StokesType);
	Py_INCREF(&MinMaxType);
	Py_INCREF(&DecType);
	Py_INCREF(&FrameType);
	Py_INCREF(&SourceType);
	Py_INCREF(&CalibrationType);
	if (PyModule_AddObject(m, "Stokes", (PyObject *)&StokesType) ||
	    PyModule_AddObject(m, "MinMax", (PyObject *)&MinMaxType) ||
	    PyModule_AddObject(m, "Decomposition", (PyObject *)&DecType) ||
	    PyModule_AddObject(m, "Frame", (PyObject *)&FrameType) ||
	    PyModule_AddObject(m, "Source", (PyObject *)&SourceType) ||
	    PyModule_AddObject(m, "Calibration", (PyObject *)&CalibrationType) ||
	    PyModule_AddStringConstant(m, "__version__", pcpy_version()) ||
	    PyModule_AddIntConstant(m, "LC_D_SINGULAR", PC_LC_D_SINGULAR) ||
	    PyModule_AddIntConstant(m, "LC_R_NONUNIQUE", PC_LC_R_NONUNIQUE) ||
	    PyModule_AddIntConstant(m, "LC_NONPHYSICAL", PC_LC_NONPHYSICAL) ||
	    PyModule_AddIntConstant(m, "LC_FILTERED", PC_LC_FILTERED) ||
	    PyModule_AddIntConstant(m, "LC_CLAMPED", PC_LC_CLAMPED) ||
	    PyModule_AddIntConstant(m, "LC_ZERO_M00", PC_LC_ZERO_M00) ||
	    PyModule_AddIntConstant(m, "FRAME_INCOMPLETE", PC_FRAME_INCOMPLETE) ||
	    PyModule_AddIntConstant(m, "FRAME_CORRUPT", PC_FRAME_CORRUPT) ||
	    PyModule_AddIntConstant(m, "FRAME_SIMULATED", PC_FRAME_SIMULATED))
		goto fail;
	return m;
fail:
	Py_DECREF(m);
	return NULL;
}
