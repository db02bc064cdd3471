/* The bulk reader's walk of an lcm event log, compiled (aocs_wire.lcmlog; docs/spec.md 5.13.3).
 *
 * index(data) walks the events of a log file once, from byte 0: each event is the sync word 0xEDA1DA01, the event
 * number, the receive time (us), the channel length, the data length (big-endian, lcm/eventlog.c), the channel name
 * and the payload, and the next event starts where it ends. The file is clean when every event has the sync word,
 * a channel length in 1..63 and ends within the file, and the last one ends it: then index gives, per event, its
 * start, number, receive time, payload offset, data length and channel (an id into the names, in order of first
 * appearance), as
 * native int64 arrays in bytes objects; otherwise None (the caller reads the file with lcm.EventLog). The numpy
 * walk it replaces (lcmlog._event_starts, pointer doubling over the sync words) finds the same events; a channel
 * name that is not UTF-8 text is not clean either (lcm's reader cannot decode it).
 *
 * gather(data, offsets, width) copies the `width` bytes at each offset into one contiguous bytes object: the rows
 * of a channel's payloads that numpy then views as records.
 *
 * decode(data, offsets, fields) decodes the record at each offset into the channel's columns, the values and types
 * lcmlog._table_fast gives (lcmlog._convert): floats and doubles as float64, an int64 scalar as int64, any other
 * integer through float64 to int64.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdint.h>
#include <string.h>

#define SYNC_WORD 0xEDA1DA01u
#define HEADER_BYTES 28u
#define CHANNEL_MAX 63u /* lcm.h LCM_MAX_CHANNEL_NAME_LENGTH */

static inline uint32_t be32(const unsigned char *p)
{
    uint32_t v;
    memcpy(&v, p, sizeof(v));
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    v = __builtin_bswap32(v);
#endif
    return v;
}

static inline int64_t be64(const unsigned char *p)
{
    uint64_t v;
    int64_t out;
    memcpy(&v, p, sizeof(v));
#if __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    v = __builtin_bswap64(v);
#endif
    memcpy(&out, &v, sizeof(out));
    return out;
}

/* ---- channel names: an open-addressing hash of (offset, length) in the file, ids in order of first appearance */

typedef struct {
    Py_ssize_t off;   /* of the name in the file */
    uint32_t len;
    int64_t id;       /* -1: empty slot */
} name_slot;

typedef struct {
    name_slot *slots;
    size_t cap;       /* a power of two */
    int64_t count;
    Py_ssize_t *first_off;   /* by id: where the name is in the file */
    uint32_t *first_len;
} name_table;

static uint64_t fnv1a(const unsigned char *p, uint32_t n)
{
    uint64_t h = 1469598103934665603ull;
    for (uint32_t i = 0; i < n; ++i) {
        h = (h ^ p[i]) * 1099511628211ull;
    }
    return h;
}

static int table_init(name_table *t, size_t cap)
{
    t->cap = cap;
    t->count = 0;
    t->slots = PyMem_Malloc(cap * sizeof(name_slot));
    t->first_off = PyMem_Malloc(cap * sizeof(Py_ssize_t));
    t->first_len = PyMem_Malloc(cap * sizeof(uint32_t));
    if (t->slots == NULL || t->first_off == NULL || t->first_len == NULL) {
        return -1;
    }
    for (size_t i = 0; i < cap; ++i) {
        t->slots[i].id = -1;
    }
    return 0;
}

static void table_free(name_table *t)
{
    PyMem_Free(t->slots);
    PyMem_Free(t->first_off);
    PyMem_Free(t->first_len);
}

static int table_grow(name_table *t, const unsigned char *data)
{
    name_table bigger;
    if (table_init(&bigger, t->cap * 2u) < 0) {
        table_free(&bigger);
        return -1;
    }
    for (size_t i = 0; i < t->cap; ++i) {
        name_slot s = t->slots[i];
        if (s.id >= 0) {
            size_t j = (size_t)fnv1a(data + s.off, s.len) & (bigger.cap - 1u);
            while (bigger.slots[j].id >= 0) {
                j = (j + 1u) & (bigger.cap - 1u);
            }
            bigger.slots[j] = s;
        }
    }
    memcpy(bigger.first_off, t->first_off, (size_t)t->count * sizeof(Py_ssize_t));
    memcpy(bigger.first_len, t->first_len, (size_t)t->count * sizeof(uint32_t));
    bigger.count = t->count;
    table_free(t);
    *t = bigger;
    return 0;
}

/* the id of the name at data[off:off+len], added when new; -1 when out of memory */
static int64_t table_id(name_table *t, const unsigned char *data, Py_ssize_t off, uint32_t len)
{
    if ((size_t)(t->count + 1) * 2u > t->cap && table_grow(t, data) < 0) {
        return -1;
    }
    size_t j = (size_t)fnv1a(data + off, len) & (t->cap - 1u);
    while (t->slots[j].id >= 0) {
        name_slot s = t->slots[j];
        if (s.len == len && memcmp(data + s.off, data + off, len) == 0) {
            return s.id;
        }
        j = (j + 1u) & (t->cap - 1u);
    }
    t->slots[j].off = off;
    t->slots[j].len = len;
    t->slots[j].id = t->count;
    t->first_off[t->count] = off;
    t->first_len[t->count] = len;
    return t->count++;
}

/* ---- index ---------------------------------------------------------------------------------------------------- */

/* the number of events of a clean file, or -1 when it is not one */
static Py_ssize_t count_events(const unsigned char *data, Py_ssize_t size)
{
    Py_ssize_t off = 0;
    Py_ssize_t n = 0;
    while (off < size) {
        if (size - off < (Py_ssize_t)HEADER_BYTES || be32(data + off) != SYNC_WORD) {
            return -1;
        }
        uint32_t ch_len = be32(data + off + 20);
        uint32_t data_len = be32(data + off + 24);
        if (ch_len == 0u || ch_len > CHANNEL_MAX) {
            return -1;
        }
        /* the rest of the file is at most PY_SSIZE_T_MAX: compare without overflow */
        uint64_t need = (uint64_t)HEADER_BYTES + ch_len + data_len;
        if (need > (uint64_t)(size - off)) {
            return -1;
        }
        off += (Py_ssize_t)need;
        ++n;
    }
    return n;
}

static PyObject *new_int64s(Py_ssize_t n, int64_t **out)
{
    PyObject *b = PyBytes_FromStringAndSize(NULL, n * (Py_ssize_t)sizeof(int64_t));
    if (b != NULL) {
        *out = (int64_t *)(void *)PyBytes_AS_STRING(b);
    }
    return b;
}

static PyObject *names_list(const name_table *t, const unsigned char *data)
{
    PyObject *names = PyList_New((Py_ssize_t)t->count);
    if (names == NULL) {
        return NULL;
    }
    for (int64_t i = 0; i < t->count; ++i) {
        PyObject *s = PyUnicode_DecodeUTF8((const char *)data + t->first_off[i], (Py_ssize_t)t->first_len[i],
                                           "strict");
        if (s == NULL) {
            Py_DECREF(names);
            if (PyErr_ExceptionMatches(PyExc_UnicodeDecodeError)) {
                PyErr_Clear();
                Py_RETURN_NONE;   /* not text: the file is not one the bulk reader decodes */
            }
            return NULL;
        }
        PyList_SET_ITEM(names, (Py_ssize_t)i, s);
    }
    return names;
}

static PyObject *index_events(const unsigned char *data, Py_ssize_t size)
{
    Py_ssize_t n = count_events(data, size);
    if (n < 0) {
        Py_RETURN_NONE;
    }
    int64_t *starts, *num, *utime, *payload, *data_len, *chan;
    PyObject *arrays[6] = {new_int64s(n, &starts), new_int64s(n, &num), new_int64s(n, &utime),
                           new_int64s(n, &payload), new_int64s(n, &data_len), new_int64s(n, &chan)};
    PyObject *names = NULL;
    name_table table = {0};
    int ok = arrays[0] && arrays[1] && arrays[2] && arrays[3] && arrays[4] && arrays[5]
             && table_init(&table, 16u) == 0;
    Py_ssize_t off = 0;
    for (Py_ssize_t i = 0; ok && i < n; ++i) {
        uint32_t ch_len = be32(data + off + 20);
        uint32_t d_len = be32(data + off + 24);
        starts[i] = (int64_t)off;
        num[i] = be64(data + off + 4);
        utime[i] = be64(data + off + 12);
        payload[i] = (int64_t)off + (int64_t)HEADER_BYTES + (int64_t)ch_len;
        data_len[i] = (int64_t)d_len;
        chan[i] = table_id(&table, data, off + (Py_ssize_t)HEADER_BYTES, ch_len);
        ok = chan[i] >= 0;
        off += (Py_ssize_t)HEADER_BYTES + (Py_ssize_t)ch_len + (Py_ssize_t)d_len;
    }
    if (ok) {
        names = names_list(&table, data);
    } else if (!PyErr_Occurred()) {
        PyErr_NoMemory();
    }
    table_free(&table);
    if (names == NULL || names == Py_None) {
        for (int k = 0; k < 6; ++k) {
            Py_XDECREF(arrays[k]);
        }
        return names;   /* NULL: an error is set; None: not clean */
    }
    return Py_BuildValue("(NNNNNNN)", arrays[0], arrays[1], arrays[2], arrays[3], arrays[4], arrays[5], names);
}

static PyObject *kernel_index(PyObject *self, PyObject *arg)
{
    (void)self;
    Py_buffer buf;
    if (PyObject_GetBuffer(arg, &buf, PyBUF_SIMPLE) < 0) {
        return NULL;
    }
    PyObject *out = index_events((const unsigned char *)buf.buf, buf.len);
    PyBuffer_Release(&buf);
    return out;
}

/* ---- gather --------------------------------------------------------------------------------------------------- */

/* the file's bytes (args[0]) and the offsets (args[1], native int64, contiguous); -1 with an error set (nothing
 * held) when either is not one */
static int data_and_offsets(PyObject *const *args, const char *fn, Py_buffer *data, Py_buffer *at)
{
    if (PyObject_GetBuffer(args[0], data, PyBUF_SIMPLE) < 0) {
        return -1;
    }
    if (PyObject_GetBuffer(args[1], at, PyBUF_C_CONTIGUOUS | PyBUF_FORMAT) < 0) {
        PyBuffer_Release(data);
        return -1;
    }
    if (at->itemsize != (Py_ssize_t)sizeof(int64_t) || at->format == NULL
        || (strcmp(at->format, "q") != 0 && strcmp(at->format, "l") != 0)) {
        PyErr_Format(PyExc_TypeError, "%s: offsets must be native int64", fn);
        PyBuffer_Release(at);
        PyBuffer_Release(data);
        return -1;
    }
    return 0;
}

static PyObject *kernel_gather(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "gather(data, offsets, width): three arguments");
        return NULL;
    }
    Py_ssize_t width = PyLong_AsSsize_t(args[2]);
    if (width == -1 && PyErr_Occurred()) {
        return NULL;
    }
    if (width < 0) {
        PyErr_SetString(PyExc_ValueError, "gather: width must be >= 0");
        return NULL;
    }
    Py_buffer data, at;
    if (data_and_offsets(args, "gather", &data, &at) < 0) {
        return NULL;
    }
    PyObject *out = NULL;
    {
        Py_ssize_t n = at.len / (Py_ssize_t)sizeof(int64_t);
        const int64_t *off = (const int64_t *)at.buf;
        if (width > 0 && n > PY_SSIZE_T_MAX / width) {
            PyErr_NoMemory();
        } else {
            out = PyBytes_FromStringAndSize(NULL, n * width);
        }
        char *dst = out == NULL ? NULL : PyBytes_AS_STRING(out);
        for (Py_ssize_t i = 0; dst != NULL && i < n; ++i) {
            if (off[i] < 0 || off[i] > (int64_t)(data.len - width)) {
                PyErr_Format(PyExc_ValueError, "gather: offset %lld (row %zd) outside the %zd bytes",
                             (long long)off[i], i, data.len);
                Py_CLEAR(out);
                break;
            }
            memcpy(dst + i * width, (const char *)data.buf + off[i], (size_t)width);
        }
    }
    PyBuffer_Release(&at);
    PyBuffer_Release(&data);
    return out;
}

/* ---- decode -------------------------------------------------------------------------------------------------- */

/* how a field's values become its column (lcmlog._convert): a float or double as float64; an int64 scalar as
 * int64, exactly; any other integer (and int64 array elements) through float64 to int64 */
enum { AS_FLOAT64 = 0, AS_INT64 = 1, AS_INT64_VIA_FLOAT64 = 2 };

typedef struct {
    Py_ssize_t offset;   /* in the payload, bytes */
    char code;           /* struct code: b B h i q f d (big-endian) */
    Py_ssize_t count;    /* elements */
    int kind;
    Py_buffer out;       /* n * count values of 8 bytes */
} field_spec;

static Py_ssize_t code_size(char code)
{
    switch (code) {
    case 'b': case 'B': return 1;
    case 'h': return 2;
    case 'i': case 'f': return 4;
    case 'q': case 'd': return 8;
    default: return 0;
    }
}

/* an integer element into its column: as float64, as int64, or through float64 to int64 */
static inline void put_int(int64_t i, int kind, unsigned char *dst)
{
    if (kind == AS_FLOAT64) {
        double d = (double)i;
        memcpy(dst, &d, sizeof(d));
        return;
    }
    int64_t v = i;
    if (kind == AS_INT64_VIA_FLOAT64) {
        /* numpy's float64 -> int64 cast: 2^63 (INT64_MAX rounded) is out of range and becomes INT64_MIN */
        double via = (double)i;
        v = (via >= 9223372036854775808.0) ? INT64_MIN : (int64_t)via;
    }
    memcpy(dst, &v, sizeof(v));
}

/* the sp->count elements of a field at src into dst, 8 bytes each (the code's switch once per field) */
static void decode_field(const unsigned char *src, const field_spec *sp, unsigned char *dst)
{
    const Py_ssize_t n = sp->count;
    const int kind = sp->kind;
    switch (sp->code) {
    case 'd':   /* kind AS_FLOAT64 (read_specs): the double's bits */
        for (Py_ssize_t k = 0; k < n; ++k) {
            int64_t v = be64(src + 8 * k);
            memcpy(dst + 8 * k, &v, sizeof(v));
        }
        break;
    case 'f':
        for (Py_ssize_t k = 0; k < n; ++k) {
            uint32_t u = be32(src + 4 * k);
            float f;
            memcpy(&f, &u, sizeof(f));
            double d = (double)f;
            memcpy(dst + 8 * k, &d, sizeof(d));
        }
        break;
    case 'q':
        for (Py_ssize_t k = 0; k < n; ++k) {
            put_int(be64(src + 8 * k), kind, dst + 8 * k);
        }
        break;
    case 'i':
        for (Py_ssize_t k = 0; k < n; ++k) {
            put_int((int32_t)be32(src + 4 * k), kind, dst + 8 * k);
        }
        break;
    case 'h':
        for (Py_ssize_t k = 0; k < n; ++k) {
            put_int((int16_t)(uint16_t)(((uint16_t)src[2 * k] << 8) | src[2 * k + 1]), kind, dst + 8 * k);
        }
        break;
    case 'b':
        for (Py_ssize_t k = 0; k < n; ++k) {
            put_int((int8_t)src[k], kind, dst + 8 * k);
        }
        break;
    default:    /* 'B' (read_specs admits no other code) */
        for (Py_ssize_t k = 0; k < n; ++k) {
            put_int(src[k], kind, dst + 8 * k);
        }
        break;
    }
}

static void release_specs(field_spec *specs, Py_ssize_t n)
{
    for (Py_ssize_t f = 0; f < n; ++f) {
        PyBuffer_Release(&specs[f].out);
    }
    PyMem_Free(specs);
}

/* the fields argument: a sequence of (offset, code, count, kind, out); the record's width through *width */
static field_spec *read_specs(PyObject *fields, Py_ssize_t n_rows, Py_ssize_t *n_fields, Py_ssize_t *width)
{
    PyObject *seq = PySequence_Fast(fields, "decode: fields must be a sequence");
    if (seq == NULL) {
        return NULL;
    }
    Py_ssize_t nf = PySequence_Fast_GET_SIZE(seq);
    field_spec *specs = PyMem_Calloc((size_t)(nf > 0 ? nf : 1), sizeof(field_spec));
    Py_ssize_t got = 0;
    *width = 0;
    if (specs == NULL) {
        PyErr_NoMemory();
    }
    for (Py_ssize_t f = 0; specs != NULL && f < nf; ++f) {
        field_spec *sp = &specs[f];
        PyObject *out_obj;
        const char *code;
        if (!PyArg_ParseTuple(PySequence_Fast_GET_ITEM(seq, f), "nsniO;decode: a field is (offset, code, count, "
                              "kind, out)", &sp->offset, &code, &sp->count, &sp->kind, &out_obj)) {
            break;
        }
        sp->code = code[0];
        Py_ssize_t size = code_size(sp->code);
        if (size == 0 || code[1] != '\0' || sp->offset < 0 || sp->count < 1 || sp->kind < AS_FLOAT64
            || sp->kind > AS_INT64_VIA_FLOAT64 || (sp->kind != AS_FLOAT64 && (sp->code == 'f' || sp->code == 'd'))
            || sp->count > (PY_SSIZE_T_MAX - sp->offset) / 8) {
            PyErr_Format(PyExc_ValueError, "decode: field %zd: bad offset, code, count or kind", f);
            break;
        }
        if (PyObject_GetBuffer(out_obj, &sp->out, PyBUF_WRITABLE | PyBUF_C_CONTIGUOUS) < 0) {
            break;
        }
        ++got;
        if (sp->out.len != n_rows * sp->count * 8) {
            PyErr_Format(PyExc_ValueError, "decode: field %zd: output of %zd bytes for %zd rows", f, sp->out.len,
                         n_rows);
            break;
        }
        Py_ssize_t end = sp->offset + sp->count * size;
        *width = end > *width ? end : *width;
    }
    Py_DECREF(seq);
    if (PyErr_Occurred()) {
        if (specs != NULL) {
            release_specs(specs, got);
        }
        return NULL;
    }
    *n_fields = nf;
    return specs;
}

static PyObject *kernel_decode(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    (void)self;
    if (nargs != 3) {
        PyErr_SetString(PyExc_TypeError, "decode(data, offsets, fields): three arguments");
        return NULL;
    }
    Py_buffer data, at;
    if (data_and_offsets(args, "decode", &data, &at) < 0) {
        return NULL;
    }
    Py_ssize_t n_fields = 0, width = 0;
    Py_ssize_t n = at.len / (Py_ssize_t)sizeof(int64_t);
    const int64_t *off = (const int64_t *)at.buf;
    field_spec *specs = read_specs(args[2], n, &n_fields, &width);
    for (Py_ssize_t i = 0; specs != NULL && i < n; ++i) {
        if (off[i] < 0 || off[i] > (int64_t)(data.len - width)) {
            PyErr_Format(PyExc_ValueError, "decode: record %zd at byte %lld runs outside the %zd bytes", i,
                         (long long)off[i], data.len);
            break;
        }
    }
    if (specs != NULL && !PyErr_Occurred()) {
        /* record by record (each read once, from the cache), every field of it into its column */
        for (Py_ssize_t i = 0; i < n; ++i) {
            const unsigned char *rec = (const unsigned char *)data.buf + off[i];
            for (Py_ssize_t f = 0; f < n_fields; ++f) {
                const field_spec *sp = &specs[f];
                decode_field(rec + sp->offset, sp, (unsigned char *)sp->out.buf + i * sp->count * 8);
            }
        }
    }
    if (specs != NULL) {
        release_specs(specs, n_fields);
    }
    PyBuffer_Release(&at);
    PyBuffer_Release(&data);
    if (PyErr_Occurred()) {
        return NULL;
    }
    Py_RETURN_NONE;
}

static PyMethodDef kernel_methods[] = {
    {"index", kernel_index, METH_O,
     "index(data) -> (starts, num, utime, payload, data_len, channel, names) or None: the events of a clean lcm log, "
     "each array native int64 in bytes; channel indexes names (in order of first appearance)"},
    {"gather", (PyCFunction)(void (*)(void))kernel_gather, METH_FASTCALL,
     "gather(data, offsets, width) -> bytes: the width bytes at each offset (native int64), one after the other"},
    {"decode", (PyCFunction)(void (*)(void))kernel_decode, METH_FASTCALL,
     "decode(data, offsets, fields): the record at each offset decoded into columns; fields: (offset in the "
     "record, struct code, count, kind, out) each, kind 0 float64, 1 int64, 2 int64 through float64, out a writable "
     "buffer of rows * count values of 8 bytes"},
    {NULL, NULL, 0, NULL}
};

static struct PyModuleDef kernel_module = {
    PyModuleDef_HEAD_INIT, "aocs_lcmlog_kernel",
    "The bulk log reader's walk, compiled (sil/wire_kernels/lcmlog_kernel.c)", -1,
    kernel_methods, NULL, NULL, NULL, NULL
};

PyMODINIT_FUNC PyInit_aocs_lcmlog_kernel(void)
{
    return PyModule_Create(&kernel_module);
}
