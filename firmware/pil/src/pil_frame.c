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

static void w_init(pil_writer_t *w, uint8_t *buf, uint32_t cap, uint32_t pos)
{
    w->buf = buf;
    w->cap = cap;
    w->pos = pos;
    w->overflow = 0;
}

static void r_init(pil_reader_t *r, const uint8_t *buf, uint32_t len)
{
    r->buf = buf;
    r->len = len;
    r->pos = 0U;
    r->underflow = 0;
}

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
            pil_writer_t w;                                                            \
            w_init(&w, out, cap, 0U);                                                  \
            put_##FN(&w, x);                                                           \
            err = w_result(&w, BYTES);                                                 \
        }                                                                              \
        return err;                                                                    \
    }                                                                                  \
    aocs_pil_err_t aocs_pil_##FN##_decode(const uint8_t *p, uint32_t len, TYPE *x)     \
    {                                                                                  \
        aocs_pil_err_t err = AOCS_PIL_ERR_NULL_ARG;                                    \
        if ((p != NULL) && (x != NULL)) {                                              \
            pil_reader_t r;                                                            \
            TYPE v;                                                                    \
            (void)memset(&v, 0, sizeof(v));                                            \
            r_init(&r, p, len);                                                        \
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
     * CRC-32/ISO-HDLC, reflected polynomial 0xEDB88320: byte-wise table
     * (crc_table[i] = the CRC register after shifting the byte i through the
     * polynomial 8 times; checked against zlib in tests/unit/test_pil_frame.c).
     */
    static const uint32_t crc_table[256] = {
        0x00000000U, 0x77073096U, 0xEE0E612CU, 0x990951BAU, 0x076DC419U, 0x706AF48FU,
        0xE963A535U, 0x9E6495A3U, 0x0EDB8832U, 0x79DCB8A4U, 0xE0D5E91EU, 0x97D2D988U,
        0x09B64C2BU, 0x7EB17CBDU, 0xE7B82D07U, 0x90BF1D91U, 0x1DB71064U, 0x6AB020F2U,
        0xF3B97148U, 0x84BE41DEU, 0x1ADAD47DU, 0x6DDDE4EBU, 0xF4D4B551U, 0x83D385C7U,
        0x136C9856U, 0x646BA8C0U, 0xFD62F97AU, 0x8A65C9ECU, 0x14015C4FU, 0x63066CD9U,
        0xFA0F3D63U, 0x8D080DF5U, 0x3B6E20C8U, 0x4C69105EU, 0xD56041E4U, 0xA2677172U,
        0x3C03E4D1U, 0x4B04D447U, 0xD20D85FDU, 0xA50AB56BU, 0x35B5A8FAU, 0x42B2986CU,
        0xDBBBC9D6U, 0xACBCF940U, 0x32D86CE3U, 0x45DF5C75U, 0xDCD60DCFU, 0xABD13D59U,
        0x26D930ACU, 0x51DE003AU, 0xC8D75180U, 0xBFD06116U, 0x21B4F4B5U, 0x56B3C423U,
        0xCFBA9599U, 0xB8BDA50FU, 0x2802B89EU, 0x5F058808U, 0xC60CD9B2U, 0xB10BE924U,
        0x2F6F7C87U, 0x58684C11U, 0xC1611DABU, 0xB6662D3DU, 0x76DC4190U, 0x01DB7106U,
        0x98D220BCU, 0xEFD5102AU, 0x71B18589U, 0x06B6B51FU, 0x9FBFE4A5U, 0xE8B8D433U,
        0x7807C9A2U, 0x0F00F934U, 0x9609A88EU, 0xE10E9818U, 0x7F6A0DBBU, 0x086D3D2DU,
        0x91646C97U, 0xE6635C01U, 0x6B6B51F4U, 0x1C6C6162U, 0x856530D8U, 0xF262004EU,
        0x6C0695EDU, 0x1B01A57BU, 0x8208F4C1U, 0xF50FC457U, 0x65B0D9C6U, 0x12B7E950U,
        0x8BBEB8EAU, 0xFCB9887CU, 0x62DD1DDFU, 0x15DA2D49U, 0x8CD37CF3U, 0xFBD44C65U,
        0x4DB26158U, 0x3AB551CEU, 0xA3BC0074U, 0xD4BB30E2U, 0x4ADFA541U, 0x3DD895D7U,
        0xA4D1C46DU, 0xD3D6F4FBU, 0x4369E96AU, 0x346ED9FCU, 0xAD678846U, 0xDA60B8D0U,
        0x44042D73U, 0x33031DE5U, 0xAA0A4C5FU, 0xDD0D7CC9U, 0x5005713CU, 0x270241AAU,
        0xBE0B1010U, 0xC90C2086U, 0x5768B525U, 0x206F85B3U, 0xB966D409U, 0xCE61E49FU,
        0x5EDEF90EU, 0x29D9C998U, 0xB0D09822U, 0xC7D7A8B4U, 0x59B33D17U, 0x2EB40D81U,
        0xB7BD5C3BU, 0xC0BA6CADU, 0xEDB88320U, 0x9ABFB3B6U, 0x03B6E20CU, 0x74B1D29AU,
        0xEAD54739U, 0x9DD277AFU, 0x04DB2615U, 0x73DC1683U, 0xE3630B12U, 0x94643B84U,
        0x0D6D6A3EU, 0x7A6A5AA8U, 0xE40ECF0BU, 0x9309FF9DU, 0x0A00AE27U, 0x7D079EB1U,
        0xF00F9344U, 0x8708A3D2U, 0x1E01F268U, 0x6906C2FEU, 0xF762575DU, 0x806567CBU,
        0x196C3671U, 0x6E6B06E7U, 0xFED41B76U, 0x89D32BE0U, 0x10DA7A5AU, 0x67DD4ACCU,
        0xF9B9DF6FU, 0x8EBEEFF9U, 0x17B7BE43U, 0x60B08ED5U, 0xD6D6A3E8U, 0xA1D1937EU,
        0x38D8C2C4U, 0x4FDFF252U, 0xD1BB67F1U, 0xA6BC5767U, 0x3FB506DDU, 0x48B2364BU,
        0xD80D2BDAU, 0xAF0A1B4CU, 0x36034AF6U, 0x41047A60U, 0xDF60EFC3U, 0xA867DF55U,
        0x316E8EEFU, 0x4669BE79U, 0xCB61B38CU, 0xBC66831AU, 0x256FD2A0U, 0x5268E236U,
        0xCC0C7795U, 0xBB0B4703U, 0x220216B9U, 0x5505262FU, 0xC5BA3BBEU, 0xB2BD0B28U,
        0x2BB45A92U, 0x5CB36A04U, 0xC2D7FFA7U, 0xB5D0CF31U, 0x2CD99E8BU, 0x5BDEAE1DU,
        0x9B64C2B0U, 0xEC63F226U, 0x756AA39CU, 0x026D930AU, 0x9C0906A9U, 0xEB0E363FU,
        0x72076785U, 0x05005713U, 0x95BF4A82U, 0xE2B87A14U, 0x7BB12BAEU, 0x0CB61B38U,
        0x92D28E9BU, 0xE5D5BE0DU, 0x7CDCEFB7U, 0x0BDBDF21U, 0x86D3D2D4U, 0xF1D4E242U,
        0x68DDB3F8U, 0x1FDA836EU, 0x81BE16CDU, 0xF6B9265BU, 0x6FB077E1U, 0x18B74777U,
        0x88085AE6U, 0xFF0F6A70U, 0x66063BCAU, 0x11010B5CU, 0x8F659EFFU, 0xF862AE69U,
        0x616BFFD3U, 0x166CCF45U, 0xA00AE278U, 0xD70DD2EEU, 0x4E048354U, 0x3903B3C2U,
        0xA7672661U, 0xD06016F7U, 0x4969474DU, 0x3E6E77DBU, 0xAED16A4AU, 0xD9D65ADCU,
        0x40DF0B66U, 0x37D83BF0U, 0xA9BCAE53U, 0xDEBB9EC5U, 0x47B2CF7FU, 0x30B5FFE9U,
        0xBDBDF21CU, 0xCABAC28AU, 0x53B39330U, 0x24B4A3A6U, 0xBAD03605U, 0xCDD70693U,
        0x54DE5729U, 0x23D967BFU, 0xB3667A2EU, 0xC4614AB8U, 0x5D681B02U, 0x2A6F2B94U,
        0xB40BBE37U, 0xC30C8EA1U, 0x5A05DF1BU, 0x2D02EF8DU,
    };
    uint32_t crc = 0xFFFFFFFFU;
    if (data != NULL) {
        uint32_t i;
        for (i = 0U; i < len; i++) {
            const uint32_t index = (crc ^ (uint32_t)data[i]) & 0xFFU;
            crc = (crc >> 8U) ^ crc_table[index];
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
        pil_writer_t w;
        uint32_t i;
        w_init(&w, out, cap, 0U);
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
        pil_reader_t r;
        uint32_t magic;
        aocs_pil_header_t h;
        r_init(&r, buf, AOCS_PIL_HEADER_BYTES);
        magic = (uint32_t)r_uint(&r, 4U);
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
            pil_reader_t r;
            r_init(&r, &buf[body], AOCS_PIL_CRC_BYTES);
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
/* the widest real field: the 3x9 gain of lqr_quat_i (laws.def GAIN) */
#define PIL_CFG_COUNT_MAX AOCS_CONFIG_VALUES_MAX

aocs_pil_err_t aocs_pil_config_put_reals(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field,
                                         const real_t *values, uint32_t count)
{
    aocs_pil_err_t err = AOCS_PIL_OK;
    if ((out == NULL) || (pos == NULL) || (values == NULL)) {
        err = AOCS_PIL_ERR_NULL_ARG;
    } else if ((count == 0U) || (count > PIL_CFG_COUNT_MAX)) {
        err = AOCS_PIL_ERR_FIELD;
    } else {
        pil_writer_t w;
        w_init(&w, out, cap, *pos);
        w_uint(&w, (uint64_t)(uint32_t)field, 1U);
        w_uint(&w, (uint64_t)count, 1U);
        put_reals(&w, values, count);
        if (w.overflow != 0) {
            err = AOCS_PIL_ERR_BUFFER;
        } else {
            *pos = w.pos;
        }
    }
    return err;
}

aocs_pil_err_t aocs_pil_config_put_u64(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field,
                                       uint64_t value)
{
    aocs_pil_err_t err = AOCS_PIL_OK;
    if ((out == NULL) || (pos == NULL)) {
        err = AOCS_PIL_ERR_NULL_ARG;
    } else {
        pil_writer_t w;
        w_init(&w, out, cap, *pos);
        w_uint(&w, (uint64_t)(uint32_t)field, 1U);
        w_uint(&w, 1U, 1U);
        w_uint(&w, value, 8U);
        if (w.overflow != 0) {
            err = AOCS_PIL_ERR_BUFFER;
        } else {
            *pos = w.pos;
        }
    }
    return err;
}

aocs_pil_err_t aocs_pil_config_put_name(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field,
                                        const char *name)
{
    aocs_pil_err_t err = AOCS_PIL_OK;
    if ((out == NULL) || (pos == NULL) || (name == NULL)) {
        err = AOCS_PIL_ERR_NULL_ARG;
    } else {
        uint32_t n = 0U;
        while ((n <= AOCS_PIL_TABLE_NAME_MAX) && (name[n] != '\0')) {
            n++;
        }
        if ((n == 0U) || (n > AOCS_PIL_TABLE_NAME_MAX)) {
            err = AOCS_PIL_ERR_FIELD;
        } else {
            pil_writer_t w;
            uint32_t i;
            w_init(&w, out, cap, *pos);
            w_uint(&w, (uint64_t)(uint32_t)field, 1U);
            w_uint(&w, (uint64_t)n, 1U);
            for (i = 0U; i < n; i++) {
                w_uint(&w, (uint64_t)(uint8_t)name[i], 1U);
            }
            if (w.overflow != 0) {
                err = AOCS_PIL_ERR_BUFFER;
            } else {
                *pos = w.pos;
            }
        }
    }
    return err;
}

/*
 * One CONFIG entry into *cfg through the configuration registry: its row
 * (aocs_config_find_pil) gives the value kind and count, its setter applies
 * the row's rule, so the image refuses what fsw_node refuses. Returns the
 * registry status (AOCS_ERR_CONFIG_FIELD for a shape the row does not take).
 */
static aocs_status_t cfg_apply_entry(pil_reader_t *r, aocs_exec_config_t *cfg, uint64_t *budget_instr,
                                     aocs_config_ref_t ref, uint32_t count)
{
    const aocs_config_field_t *f = ref.field;
    aocs_status_t st = AOCS_ERR_CONFIG_FIELD;
    if ((f->kind == AOCS_CONFIG_KIND_REALS) || (f->kind == AOCS_CONFIG_KIND_INERTIA)) {
        if ((count == f->count) && (count <= AOCS_CONFIG_VALUES_MAX)) {
            double vals[AOCS_CONFIG_VALUES_MAX];
            for (uint32_t i = 0U; i < count; i++) {
                vals[i] = f64_from_bits(r_uint(r, 8U));
            }
            st = aocs_config_set_reals(cfg, ref, vals, count);
        }
    } else if (f->kind == AOCS_CONFIG_KIND_TABLE) {
        if ((count > 0U) && (count <= AOCS_PIL_TABLE_NAME_MAX)) {
            char name[AOCS_PIL_TABLE_NAME_MAX + 1U];
            for (uint32_t i = 0U; i < count; i++) {
                name[i] = (char)(uint8_t)r_uint(r, 1U);
            }
            name[count] = '\0';
            st = aocs_config_set_table(cfg, ref, name);
        }
    } else if (count == 1U) {
        const uint64_t value = r_uint(r, 8U);
        if (f->kind == AOCS_CONFIG_KIND_BUDGET) {
            /* the image's budget is an instruction count (the table's when 0), not the node's ns */
            st = (value > (uint64_t)UINT32_MAX) ? AOCS_ERR_CONFIG_RULE : AOCS_OK;
            if (st == AOCS_OK) {
                *budget_instr = value;
            }
        } else {
            st = aocs_config_set_uint(cfg, ref, value);
        }
    } else {
        st = AOCS_ERR_CONFIG_FIELD;
    }
    return st;
}

/* 1 when an entry of `count` values has the shape of field f: its reals, a name of 1 .. 31 bytes, one integer. */
static int cfg_entry_shape_ok(const aocs_config_field_t *f, uint32_t count)
{
    uint32_t lo = 1U;
    uint32_t hi = 1U;
    int ok = 0;
    if ((f->kind == AOCS_CONFIG_KIND_REALS) || (f->kind == AOCS_CONFIG_KIND_INERTIA)) {
        lo = f->count;
        hi = f->count;
    } else if (f->kind == AOCS_CONFIG_KIND_TABLE) {
        hi = AOCS_PIL_TABLE_NAME_MAX;
    } else {
        /* one integer */
    }
    if ((count >= lo) && (count <= hi)) {
        ok = 1;
    }
    return ok;
}

/* Bytes an entry of `count` values of field f takes after its two-byte head. */
static uint32_t cfg_entry_bytes(const aocs_config_field_t *f, uint32_t count)
{
    return (f->kind == AOCS_CONFIG_KIND_TABLE) ? count : (count * 8U);
}

aocs_pil_err_t aocs_pil_config_decode(const uint8_t *p, uint32_t len, aocs_exec_config_t *cfg,
                                      uint64_t *budget_instr, uint32_t *field, aocs_status_t *status)
{
    aocs_pil_err_t err = AOCS_PIL_OK;
    if ((p == NULL) || (cfg == NULL) || (budget_instr == NULL) || (field == NULL) || (status == NULL)) {
        err = AOCS_PIL_ERR_NULL_ARG;
    } else {
        pil_reader_t r;
        *field = 0U;
        *status = AOCS_OK;
        r_init(&r, p, len);
        while ((err == AOCS_PIL_OK) && (r.pos < r.len)) {
            aocs_config_ref_t ref = {NULL, 0U};
            const uint32_t id = (uint32_t)r_uint(&r, 1U);
            const uint32_t count = (uint32_t)r_uint(&r, 1U);
            if (r.underflow != 0) {
                err = AOCS_PIL_ERR_PAYLOAD;
            } else if ((aocs_config_find_pil(id, &ref) == 0) || (cfg_entry_shape_ok(ref.field, count) == 0)) {
                err = AOCS_PIL_ERR_FIELD;
                *field = id;
            } else if (cfg_entry_bytes(ref.field, count) > (r.len - r.pos)) {
                err = AOCS_PIL_ERR_PAYLOAD;
                *field = id;
            } else {
                const aocs_status_t st = cfg_apply_entry(&r, cfg, budget_instr, ref, count);
                if (st != AOCS_OK) {
                    err = AOCS_PIL_ERR_FIELD;
                    *field = id;
                    /* a gain table's own status says which; a value or shape refused is the field's fault */
                    *status = ((st == AOCS_ERR_GAIN_TABLE_UNKNOWN) || (st == AOCS_ERR_GAIN_TABLE_WRONG_LAW)) ? st : AOCS_OK;
                }
            }
        }
        /* one inertia, as in fsw_node: the plant's (the inertia field) also sizes the slew guidance and gives
         * the wheel array's total momentum */
        cfg->guidance.slew.inertia_kgm2 = cfg->laws.smc.inertia;
        cfg->wheels.inertia_B_kgm2 = cfg->laws.smc.inertia;
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
