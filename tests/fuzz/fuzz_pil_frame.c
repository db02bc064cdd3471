/*
 * libFuzzer target: the PIL frame codec (aocs/pil_frame.h; at the time of
 * writing firmware/src/pil/pil_frame.c, being moved to firmware/pil/ on
 * another branch: the build takes whichever path exists). The bytes are one
 * received frame: header and CRC check, then the payload decoder of its
 * type; every payload decoder also gets the raw bytes (the fixed payloads
 * from their rows: one that decodes must be exactly its size and encode
 * again). A CONFIG payload that decodes is given to aocs_exec_init and, when
 * accepted, one step whose command must be within the limits
 * (fuzz_support.h).
 */
#include "fuzz_support.h"

#include "aocs/pil_frame.h"

/* Every fixed payload (the rows of pil_frame.h): a payload that decodes is exactly its size and encodes again. */
#define FUZZ_PAYLOAD(NAME, FN, TYPE, ROWS, BYTES)                                        \
    {                                                                                    \
        TYPE v;                                                                          \
        uint8_t back[BYTES];                                                             \
        if ((aocs_pil_##FN##_decode(p, len, &v) == AOCS_PIL_OK) &&                       \
            ((len != (BYTES)) || (aocs_pil_##FN##_encode(&v, back, sizeof(back)) != AOCS_PIL_OK))) {   \
            abort();                                                                     \
        }                                                                                \
    }

static void decode_payload(const uint8_t *p, uint32_t len)
{
    aocs_exec_config_t cfg;
    uint64_t budget = 0u;
    uint32_t field = 0u;
    aocs_status_t st = AOCS_OK;
    AOCS_PIL_PAYLOAD_ROWS(FUZZ_PAYLOAD)
    aocs_exec_config_default(&cfg);
    if (aocs_pil_config_decode(p, len, &cfg, &budget, &field, &st) == AOCS_PIL_OK) {
        aocs_exec_t exec;
        aocs_exec_output_t out;
        aocs_exec_input_t s;
        cfg.clock = AOCS_EXEC_CLOCK_LOCKSTEP;
        if (aocs_exec_init(&exec, &cfg) == AOCS_OK) {
            memset(&s, 0, sizeof(s));
            s.tick = 1u;
            s.t_sensor_ns = exec.period_ns;
            s.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ORBIT;
            s.q_BN = aocs_quat_make(AOCS_R(0.1), AOCS_R(-0.2), AOCS_R(0.3), AOCS_R(0.9273618495495703));
            s.w_BN_B = aocs_vec3_make(AOCS_R(0.5), AOCS_R(-0.2), AOCS_R(0.03));
            if (aocs_exec_step(&exec, &s, &out) != AOCS_OK) {
                abort();
            }
            fuzz_check_output(&cfg, &out);
        }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    aocs_pil_header_t hdr;
    uint32_t len = (size > 0xFFFFFFFFu) ? 0xFFFFFFFFu : (uint32_t)size;
    (void)aocs_pil_header_decode(data, len, &hdr);
    if (aocs_pil_frame_check(data, len, &hdr) == AOCS_PIL_OK) {
        if ((uint32_t)hdr.length + AOCS_PIL_HEADER_BYTES > len) {
            abort(); /* a checked frame's payload lies inside the buffer */
        }
        decode_payload(data + AOCS_PIL_HEADER_BYTES, hdr.length);
    }
    decode_payload(data, len);
    return 0;
}
