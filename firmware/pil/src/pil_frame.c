/*
 * PIL frame codec (aocs/pil_frame.h, docs/pil.md): byte-exact little-endian
 * encoding independent of the host's byte order, CRC-32, and the payloads
 * expanded from their rows. Every decoder checks the size before it reads;
 * nothing here trusts a length it has not checked.
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "aocs/pil_frame.h"

/* Sequential writer / reader over a byte buffer; an overflow sticks and is reported once. */
typedef struct {
    uint8_t *buf;
    uint32_t cap;
    uint32_t pos;
    int overflow;
} pil_writer_t;

typedef struct {
    const uint8_t *buf;
    uint32_t len;
    uint32_t pos;
    int underflow;
} pil_reader_t;

/* n little-endian bytes of value */
static void w_uint(pil_writer_t *w, uint64_t value, uint32_t n)
{
    if ((w->overflow != 0) || (n > (w->cap - w->pos)) || (w->pos > w->cap)) {
        w->overflow = 1;
    } else {
        uint32_t i;
        for (i = 0U; i < n; i++) {
            const uint32_t shift = 8U * i;
            const uint64_t byte = (value >> shift) & 0xFFULL;
            w->buf[w->pos + i] = (uint8_t)byte;
        }
        w->pos += n;
    }
}

static uint64_t r_uint(pil_reader_t *r, uint32_t n)
{
    uint64_t value = 0U;
    if ((r->underflow != 0) || (r->pos > r->len) || (n > (r->len - r->pos))) {
        r->underflow = 1;
    } else {
        uint32_t i;
        for (i = 0U; i < n; i++) {
            const uint32_t shift = 8U * i;
            value |= ((uint64_t)r->buf[r->pos + i]) << shift;
        }
        r->pos += n;
    }
    return value;
}

static void w_i32(pil_writer_t *w, int32_t value)
{
    w_uint(w, (uint64_t)(uint32_t)value, 4U);
}

static int32_t r_i32(pil_reader_t *r)
{
    const uint32_t u = (uint32_t)r_uint(r, 4U);
    int32_t value;
    /* two's complement back to signed without implementation-defined conversion */
    if (u > 0x7FFFFFFFU) {
        const uint32_t below = 0xFFFFFFFFU - u; /* -(value + 1), at most 0x7FFFFFFF */
        value = -(int32_t)below - 1;
    } else {
        value = (int32_t)u;
    }
    return value;
}

/*
 * binary64 <-> bits, computed arithmetically (frexp / ldexp are exact), so
 * the wire format does not depend on how the platform stores a double.
 * Every finite value, both zeros and both infinities are exact both ways;
 * a NaN travels as the quiet NaN 0x7FF8000000000000 (the executive rejects
 * any NaN, its payload carries nothing).
 */
#define PIL_F64_SIGN 0x8000000000000000ULL
#define PIL_F64_EXP_MASK 0x7FF0000000000000ULL
#define PIL_F64_QNAN 0x7FF8000000000000ULL
#define PIL_F64_FRAC_MASK 0x000FFFFFFFFFFFFFULL
#define PIL_F64_HIDDEN 0x0010000000000000ULL
#define PIL_TWO_POW_52 4503599627370496.0

static uint64_t f64_to_bits(double x)
{
    uint64_t bits;
    uint64_t sign = 0U;
    double mag = x;
    if (signbit(x) != 0) {
        sign = PIL_F64_SIGN;
        mag = -x;
    }
    if (isnan(x) != 0) {
        bits = PIL_F64_QNAN;
    } else if (isinf(x) != 0) {
        bits = sign | PIL_F64_EXP_MASK;
    } else if (!(mag > 0.0)) {
        bits = sign; /* +-0 */
    } else {
        int e = 0;
        const double m = frexp(mag, &e); /* mag = m 2^e, 0.5 <= m < 1 */
        const int biased = e + 1022;     /* mag = 1.f 2^(e - 1), bias 1023 */
        if (biased >= 1) {
            const double frac = ldexp(m, 53) - PIL_TWO_POW_52; /* (2 m - 1) 2^52: an integer below 2^52 */
            const uint64_t exponent = (uint64_t)biased;
            bits = sign | (exponent << 52U) | (uint64_t)frac;
        } else {
            const double frac = ldexp(mag, 1074); /* subnormal: mag / 2^-1074, an integer below 2^52 */
            bits = sign | (uint64_t)frac;
        }
    }
    return bits;
}

static double f64_from_bits(uint64_t bits)
{
    const uint64_t frac = bits & PIL_F64_FRAC_MASK;
    const uint64_t biased = (bits & PIL_F64_EXP_MASK) >> 52U;
    double mag;
    if (biased == 0x7FFU) {
        mag = (frac == 0U) ? (double)INFINITY : (double)NAN;
    } else if (biased == 0U) {
        mag = ldexp((double)frac, -1074);
    } else {
        const int exponent = (int)biased - 1075;
        const uint64_t mantissa = frac | PIL_F64_HIDDEN;
        mag = ldexp((double)mantissa, exponent);
    }
    return ((bits & PIL_F64_SIGN) != 0U) ? -mag : mag;
}

/* A real_t goes on the wire as binary64 (widening a float is exact) and comes back as (real_t) of the binary64,
 * as the SIL node converts the LCM doubles. */
static void put_reals(pil_writer_t *w, const real_t *x, uint32_t n)
{
    for (uint32_t i = 0U; i < n; i++) {
        w_uint(w, f64_to_bits((double)x[i]), 8U);
    }
}

static void get_reals(pil_reader_t *r, real_t *x, uint32_t n)
{
    for (uint32_t i = 0U; i < n; i++) {
        x[i] = (real_t)f64_from_bits(r_uint(r, 8U));
    }
}

/* ---- one writer and one reader per row kind (pil_frame.h, AOCS_PIL_WIRE_<KIND>) ---- */
static void put_u32(pil_writer_t *w, const uint32_t *x) { w_uint(w, (uint64_t)*x, 4U); }
static void get_u32(pil_reader_t *r, uint32_t *x) { *x = (uint32_t)r_uint(r, 4U); }
static void put_u64(pil_writer_t *w, const uint64_t *x) { w_uint(w, *x, 8U); }
static void get_u64(pil_reader_t *r, uint64_t *x) { *x = r_uint(r, 8U); }
static void put_status(pil_writer_t *w, const aocs_status_t *x) { w_i32(w, (int32_t)*x); }
static void get_status(pil_reader_t *r, aocs_status_t *x) { *x = (aocs_status_t)r_i32(r); }
static void put_law(pil_writer_t *w, const aocs_law_id_t *x) { w_i32(w, (int32_t)*x); }
static void get_law(pil_reader_t *r, aocs_law_id_t *x) { *x = (aocs_law_id_t)r_i32(r); }
static void put_mode(pil_writer_t *w, const aocs_exec_mode_t *x) { w_i32(w, (int32_t)*x); }
static void get_mode(pil_reader_t *r, aocs_exec_mode_t *x) { *x = (aocs_exec_mode_t)r_i32(r); }
static void put_pil_err(pil_writer_t *w, const aocs_pil_err_t *x) { w_i32(w, (int32_t)*x); }
static void get_pil_err(pil_reader_t *r, aocs_pil_err_t *x) { *x = (aocs_pil_err_t)r_i32(r); }
static void put_real(pil_writer_t *w, const real_t *x) { put_reals(w, x, 1U); }
static void get_real(pil_reader_t *r, real_t *x) { get_reals(r, x, 1U); }
static void put_vec3(pil_writer_t *w, const aocs_vec3_t *x) { put_reals(w, x->v, 3U); }
static void get_vec3(pil_reader_t *r, aocs_vec3_t *x) { get_reals(r, x->v, 3U); }
static void put_quat(pil_writer_t *w, const aocs_quat_t *x) { put_reals(w, x->q, 4U); }
static void get_quat(pil_reader_t *r, aocs_quat_t *x) { get_reals(r, x->q, 4U); }
static void put_wheels(pil_writer_t *w, const real_t (*x)[AOCS_WHEELS_MAX]) { put_reals(w, *x, AOCS_WHEELS_MAX); }
static void get_wheels(pil_reader_t *r, real_t (*x)[AOCS_WHEELS_MAX]) { get_reals(r, *x, AOCS_WHEELS_MAX); }
static void put_cov(pil_writer_t *w, const real_t (*x)[AOCS_EST_P_UPPER_COUNT]) { put_reals(w, *x, AOCS_EST_P_UPPER_COUNT); }
static void get_cov(pil_reader_t *r, real_t (*x)[AOCS_EST_P_UPPER_COUNT]) { get_reals(r, *x, AOCS_EST_P_UPPER_COUNT); }
static void put_thrusters(pil_writer_t *w, const real_t (*x)[AOCS_MOM_THRUSTERS_MAX]) { put_reals(w, *x, AOCS_MOM_THRUSTERS_MAX); }
static void get_thrusters(pil_reader_t *r, real_t (*x)[AOCS_MOM_THRUSTERS_MAX]) { get_reals(r, *x, AOCS_MOM_THRUSTERS_MAX); }

/* encode epilogue: exactly `size` bytes written */
static aocs_pil_err_t w_result(const pil_writer_t *w, uint32_t size)
{
    return ((w->overflow != 0) || (w->pos != size)) ? AOCS_PIL_ERR_BUFFER : AOCS_PIL_OK;
}

/* decode epilogue: exactly the whole payload consumed */
static aocs_pil_err_t r_result(const pil_reader_t *r)
{
    return ((r->underflow != 0) || (r->pos != r->len)) ? AOCS_PIL_ERR_PAYLOAD : AOCS_PIL_OK;
}

/* ---- the payloads: each one's writer and reader are its rows, one kind's writer / reader per row ---- */
#define PIL_PUT(NAME, KIND, MEMBER) put_##KIND(w, &x->MEMBER);
#define PIL_GET(NAME, KIND, MEMBER) get_##KIND(r, &x->MEMBER);
#define PIL_ROWS_CODEC(FN, TYPE, ROWS)                        \
    static void put_##FN(pil_writer_t *w, const TYPE *x)      \
    {                                                         \
        ROWS(PIL_PUT)                                         \
    }                                                         \
    static void get_##FN(pil_reader_t *r, TYPE *x)            \
    {                                                         \
        ROWS(PIL_GET)                                         \
    }

/* the public pair of a payload (pil_frame.h): encode writes exactly BYTES; decode takes exactly BYTES, the members
 * that are not on the wire read 0, and *x is written only on success */
#define PIL_PAYLOAD_CODEC(NAME, FN, TYPE, ROWS, BYTES)                                 \
    PIL_ROWS_CODEC(FN, TYPE, ROWS)                                                     \
    aocs_pil_err_t aocs_pil_##FN##_encode(const TYPE *x, uint8_t *out, uint32_t cap)   \
    {                                                                                  \
        aocs_pil_err_t err = AOCS_PIL_ERR_NULL_ARG;                                    \
        if ((x != NULL) && (out != NULL)) {                                            \
            pil_writer_t w = {out, cap, 0U, 0};                                        \
            put_##FN(&w, x);                                                           \
            err = w_result(&w, BYTES);                                                 \
        }                                                                              \
        return err;                                                                    \
    }                                                                                  \
    aocs_pil_err_t aocs_pil_##FN##_decode(const uint8_t *p, uint32_t len, TYPE *x)     \
    {                                                                                  \
        aocs_pil_err_t err = AOCS_PIL_ERR_NULL_ARG;                                    \
        if ((p != NULL) && (x != NULL)) {                                              \
            pil_reader_t r = {p, len, 0U, 0};                                          \
            TYPE v;                                                                    \
            (void)memset(&v, 0, sizeof(v));                                            \
            get_##FN(&r, &v);                                                          \
            err = r_result(&r);                                                        \
            if (err == AOCS_PIL_OK) {                                                  \
                *x = v;                                                                \
            }                                                                          \
        }                                                                              \
        return err;                                                                    \
    }

PIL_ROWS_CODEC(counters, aocs_exec_counters_t, AOCS_PIL_COUNTER_ROWS)
AOCS_PIL_PAYLOAD_ROWS(PIL_PAYLOAD_CODEC)

uint32_t aocs_pil_crc32(const uint8_t *data, uint32_t len)
{
    /*
     * CRC-32/ISO-HDLC, reflected polynomial 0xEDB88320, four bits at a time
     * (crc_nibble[i] = the CRC register after shifting the nibble i through
     * the polynomial 4 times; checked against a bitwise CRC and zlib in
     * tests/unit/test_pil_frame.c).
     */
    static const uint32_t crc_nibble[16] = {
        0x00000000U, 0x1DB71064U, 0x3B6E20C8U, 0x26D930ACU, 0x76DC4190U, 0x6B6B51F4U, 0x4DB26158U, 0x5005713CU,
        0xEDB88320U, 0xF00F9344U, 0xD6D6A3E8U, 0xCB61B38CU, 0x9B64C2B0U, 0x86D3D2D4U, 0xA00AE278U, 0xBDBDF21CU,
    };
    uint32_t crc = 0xFFFFFFFFU;
    if (data != NULL) {
        uint32_t i;
        for (i = 0U; i < len; i++) {
            const uint32_t byte = (uint32_t)data[i];
            crc = (crc >> 4U) ^ crc_nibble[(crc ^ byte) & 0x0FU];
            crc = (crc >> 4U) ^ crc_nibble[(crc ^ (byte >> 4U)) & 0x0FU];
        }
    }
    return crc ^ 0xFFFFFFFFU;
}

aocs_pil_err_t aocs_pil_frame_encode(aocs_pil_type_t type, uint32_t seq, const uint8_t *payload, uint32_t len,
                                     uint8_t *out, uint32_t cap, uint32_t *frame_len)
{
    aocs_pil_err_t err = AOCS_PIL_OK;
    if ((out == NULL) || (frame_len == NULL) || ((payload == NULL) && (len > 0U))) {
        err = AOCS_PIL_ERR_NULL_ARG;
    } else if (len > AOCS_PIL_PAYLOAD_MAX) {
        err = AOCS_PIL_ERR_LENGTH;
    } else if (cap < (AOCS_PIL_HEADER_BYTES + len + AOCS_PIL_CRC_BYTES)) {
        err = AOCS_PIL_ERR_BUFFER;
    } else {
        pil_writer_t w = {out, cap, 0U, 0};
        uint32_t i;
        w_uint(&w, (uint64_t)AOCS_PIL_MAGIC, 4U);
        w_uint(&w, (uint64_t)AOCS_PIL_VERSION, 1U);
        w_uint(&w, (uint64_t)(uint32_t)type, 1U);
        w_uint(&w, (uint64_t)len, 2U);
        w_uint(&w, (uint64_t)seq, 4U);
        for (i = 0U; i < len; i++) {
            out[AOCS_PIL_HEADER_BYTES + i] = payload[i];
        }
        w.pos = AOCS_PIL_HEADER_BYTES + len;
        w_uint(&w, (uint64_t)aocs_pil_crc32(out, AOCS_PIL_HEADER_BYTES + len), 4U);
        *frame_len = w.pos;
    }
    return err;
}

aocs_pil_err_t aocs_pil_header_decode(const uint8_t *buf, uint32_t len, aocs_pil_header_t *hdr)
{
    aocs_pil_err_t err = AOCS_PIL_OK;
    if ((buf == NULL) || (hdr == NULL)) {
        err = AOCS_PIL_ERR_NULL_ARG;
    } else if (len < AOCS_PIL_HEADER_BYTES) {
        err = AOCS_PIL_ERR_LENGTH;
    } else {
        pil_reader_t r = {buf, AOCS_PIL_HEADER_BYTES, 0U, 0};
        const uint32_t magic = (uint32_t)r_uint(&r, 4U);
        aocs_pil_header_t h;
        h.version = (uint8_t)r_uint(&r, 1U);
        h.type = (uint8_t)r_uint(&r, 1U);
        h.length = (uint16_t)r_uint(&r, 2U);
        h.seq = (uint32_t)r_uint(&r, 4U);
        if (magic != (uint32_t)AOCS_PIL_MAGIC) {
            err = AOCS_PIL_ERR_MAGIC;
        } else if ((uint32_t)h.version != AOCS_PIL_VERSION) {
            err = AOCS_PIL_ERR_VERSION;
        } else if ((uint32_t)h.length > AOCS_PIL_PAYLOAD_MAX) {
            err = AOCS_PIL_ERR_LENGTH;
        } else {
            *hdr = h;
        }
    }
    return err;
}

aocs_pil_err_t aocs_pil_frame_check(const uint8_t *buf, uint32_t len, aocs_pil_header_t *hdr)
{
    aocs_pil_header_t h;
    aocs_pil_err_t err = aocs_pil_header_decode(buf, len, &h);
    if ((err == AOCS_PIL_OK) && (hdr == NULL)) {
        err = AOCS_PIL_ERR_NULL_ARG;
    }
    if (err == AOCS_PIL_OK) {
        const uint32_t body = AOCS_PIL_HEADER_BYTES + (uint32_t)h.length;
        if (len != (body + AOCS_PIL_CRC_BYTES)) {
            err = AOCS_PIL_ERR_LENGTH;
        } else {
            pil_reader_t r = {&buf[body], AOCS_PIL_CRC_BYTES, 0U, 0};
            if ((uint32_t)r_uint(&r, 4U) != aocs_pil_crc32(buf, body)) {
                err = AOCS_PIL_ERR_CRC;
            } else {
                *hdr = h;
            }
        }
    }
    return err;
}

/* ---- CONFIG field list ---- */
/* One entry at *pos: field, count, then the count reals, the count bytes of name, or (neither given) the one
 * integer; *pos moves past it only when it fits. */
static aocs_pil_err_t cfg_put(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field, uint32_t count,
                              const real_t *values, const char *name, uint64_t value)
{
    aocs_pil_err_t err = AOCS_PIL_ERR_BUFFER;
    pil_writer_t w = {out, cap, *pos, 0};
    w_uint(&w, (uint64_t)(uint32_t)field, 1U);
    w_uint(&w, (uint64_t)count, 1U);
    if (values != NULL) {
        put_reals(&w, values, count);
    } else if (name != NULL) {
        for (uint32_t i = 0U; i < count; i++) {
            w_uint(&w, (uint64_t)(uint8_t)name[i], 1U);
        }
    } else {
        w_uint(&w, value, 8U);
    }
    if (w.overflow == 0) {
        err = AOCS_PIL_OK;
        *pos = w.pos;
    }
    return err;
}

aocs_pil_err_t aocs_pil_config_put_reals(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field,
                                         const real_t *values, uint32_t count)
{
    aocs_pil_err_t err = AOCS_PIL_OK;
    if ((out == NULL) || (pos == NULL) || (values == NULL)) {
        err = AOCS_PIL_ERR_NULL_ARG;
    } else if ((count == 0U) || (count > AOCS_CONFIG_VALUES_MAX)) {
        err = AOCS_PIL_ERR_FIELD;
    } else {
        err = cfg_put(out, cap, pos, field, count, values, NULL, 0U);
    }
    return err;
}

aocs_pil_err_t aocs_pil_config_put_u64(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field,
                                       uint64_t value)
{
    aocs_pil_err_t err = AOCS_PIL_ERR_NULL_ARG;
    if ((out != NULL) && (pos != NULL)) {
        err = cfg_put(out, cap, pos, field, 1U, NULL, NULL, value);
    }
    return err;
}

aocs_pil_err_t aocs_pil_config_put_name(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field,
                                        const char *name)
{
    aocs_pil_err_t err = AOCS_PIL_ERR_NULL_ARG;
    if ((out != NULL) && (pos != NULL) && (name != NULL)) {
        uint32_t n = 0U;
        while ((n <= AOCS_PIL_TABLE_NAME_MAX) && (name[n] != '\0')) {
            n++;
        }
        if ((n == 0U) || (n > AOCS_PIL_TABLE_NAME_MAX)) {
            err = AOCS_PIL_ERR_FIELD;
        } else {
            err = cfg_put(out, cap, pos, field, n, NULL, name, 0U);
        }
    }
    return err;
}

/* Bytes after the two-byte head of an entry of `count` values of field f: count binary64 reals (REALS, INERTIA),
 * a name of 1 .. AOCS_PIL_TABLE_NAME_MAX bytes (TABLE) or one uint64; 0 for a count the field does not take. */
static uint32_t cfg_entry_bytes(const aocs_config_field_t *f, uint32_t count)
{
    uint32_t bytes = 0U;
    if ((f->kind == AOCS_CONFIG_KIND_REALS) || (f->kind == AOCS_CONFIG_KIND_INERTIA)) {
        if ((count == f->count) && (count <= AOCS_CONFIG_VALUES_MAX)) {
            bytes = count * 8U;
        }
    } else if (f->kind == AOCS_CONFIG_KIND_TABLE) {
        if ((count > 0U) && (count <= AOCS_PIL_TABLE_NAME_MAX)) {
            bytes = count;
        }
    } else if (count == 1U) {
        bytes = 8U;
    } else {
        /* not one integer */
    }
    return bytes;
}

/*
 * One CONFIG entry, of a shape cfg_entry_bytes took, into *cfg through the configuration registry: the row's
 * setter applies its rule, so the image refuses what fsw_node refuses. Returns the registry status.
 */
static aocs_status_t cfg_apply_entry(pil_reader_t *r, aocs_exec_config_t *cfg, uint64_t *budget_instr,
                                     aocs_config_ref_t ref, uint32_t count)
{
    const aocs_config_kind_t kind = ref.field->kind;
    aocs_status_t st;
    if ((kind == AOCS_CONFIG_KIND_REALS) || (kind == AOCS_CONFIG_KIND_INERTIA)) {
        double vals[AOCS_CONFIG_VALUES_MAX];
        for (uint32_t i = 0U; i < count; i++) {
            vals[i] = f64_from_bits(r_uint(r, 8U));
        }
        st = aocs_config_set_reals(cfg, ref, vals, count);
    } else if (kind == AOCS_CONFIG_KIND_TABLE) {
        char name[AOCS_PIL_TABLE_NAME_MAX + 1U];
        for (uint32_t i = 0U; i < count; i++) {
            name[i] = (char)(uint8_t)r_uint(r, 1U);
        }
        name[count] = '\0';
        st = aocs_config_set_table(cfg, ref, name);
    } else if (kind == AOCS_CONFIG_KIND_BUDGET) {
        /* the image's budget is an instruction count (the table's when 0), not the node's ns */
        const uint64_t value = r_uint(r, 8U);
        st = (value > (uint64_t)UINT32_MAX) ? AOCS_ERR_CONFIG_RULE : AOCS_OK;
        if (st == AOCS_OK) {
            *budget_instr = value;
        }
    } else {
        st = aocs_config_set_uint(cfg, ref, r_uint(r, 8U));
    }
    return st;
}

aocs_pil_err_t aocs_pil_config_decode(const uint8_t *p, uint32_t len, aocs_exec_config_t *cfg,
                                      uint64_t *budget_instr, uint32_t *field, aocs_status_t *status)
{
    aocs_pil_err_t err = AOCS_PIL_OK;
    if ((p == NULL) || (cfg == NULL) || (budget_instr == NULL) || (field == NULL) || (status == NULL)) {
        err = AOCS_PIL_ERR_NULL_ARG;
    } else {
        pil_reader_t r = {p, len, 0U, 0};
        *field = 0U;
        *status = AOCS_OK;
        while ((err == AOCS_PIL_OK) && (r.pos < r.len)) {
            aocs_config_ref_t ref = {NULL, 0U};
            const uint32_t id = (uint32_t)r_uint(&r, 1U);
            const uint32_t count = (uint32_t)r_uint(&r, 1U);
            const uint32_t bytes = (aocs_config_find_pil(id, &ref) != 0) ? cfg_entry_bytes(ref.field, count) : 0U;
            if (r.underflow != 0) {
                err = AOCS_PIL_ERR_PAYLOAD;
            } else if (bytes == 0U) {
                err = AOCS_PIL_ERR_FIELD;
                *field = id;
            } else if (bytes > (r.len - r.pos)) {
                err = AOCS_PIL_ERR_PAYLOAD;
                *field = id;
            } else {
                const aocs_status_t st = cfg_apply_entry(&r, cfg, budget_instr, ref, count);
                if (st != AOCS_OK) {
                    err = AOCS_PIL_ERR_FIELD;
                    *field = id;
                    /* a gain table's own status says which; a value or shape refused is the field's fault */
                    *status =
                        ((st == AOCS_ERR_GAIN_TABLE_UNKNOWN) || (st == AOCS_ERR_GAIN_TABLE_WRONG_LAW)) ? st : AOCS_OK;
                }
            }
        }
        aocs_config_share_inertia(cfg); /* one inertia, as in fsw_node */
    }
    return err;
}

const char *aocs_pil_err_name(aocs_pil_err_t err)
{
    static const char *const names[AOCS_PIL_ERR_COUNT] = {
        "AOCS_PIL_OK",          "AOCS_PIL_ERR_NULL_ARG", "AOCS_PIL_ERR_MAGIC",   "AOCS_PIL_ERR_VERSION",
        "AOCS_PIL_ERR_LENGTH",  "AOCS_PIL_ERR_CRC",      "AOCS_PIL_ERR_TYPE",    "AOCS_PIL_ERR_PAYLOAD",
        "AOCS_PIL_ERR_BUFFER",  "AOCS_PIL_ERR_FIELD",    "AOCS_PIL_ERR_STATE",
    };
    const char *name = "AOCS_PIL_ERR_UNKNOWN";
    if (((int32_t)err >= 0) && (err < AOCS_PIL_ERR_COUNT)) {
        name = names[err];
    }
    return name;
}
