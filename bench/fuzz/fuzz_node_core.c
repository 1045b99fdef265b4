/* libFuzzer target: the node's requests with values across the whole float32 range.
 * The link fuzzer (fuzz_parsers.c) rarely gets a frame past the CRC; this one calls the core
 * directly with what a well-formed frame could carry: any 32-bit pattern as a drive, a RESET's
 * drive0, a parameter (any id) or a waveform field (NaN, inf, denormals, 1e38 included), and runs.
 * Whatever the core accepts, the model must stay finite (issue 15: the node never carries a NaN).
 * Built twice by bench/fuzz.sh: the float32 node, and with SS_NODE_MODEL_Q the fixed-point one. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "ss_node_core.h"

typedef struct {
    const uint8_t *data;
    size_t n, at;
} ops_t;

static uint8_t take_u8(ops_t *o)
{
    return o->at < o->n ? o->data[o->at++] : 0u;
}

/* Any bit pattern: the protocol carries raw float32. */
static float take_f32(ops_t *o)
{
    uint32_t u = 0;
    for (int i = 0; i < 4; ++i) {
        u |= (uint32_t)take_u8(o) << (8 * i);
    }
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

static void check_model(const ss_node_core_t *core)
{
    const ss_node_row_t r = ss_node_core_row(core);
    if (!isfinite(r.drive_v) || !isfinite(r.x_rod_m) || !isfinite(r.x_slider_hi_m) ||
        !isfinite(r.x_slider_lo_m) || !isfinite(r.force_n)) {
        abort();
    }
}

static void on_row(void *ctx, const ss_node_core_t *core)
{
    (void)ctx;
    check_model(core);
}

static void on_end(void *ctx, uint8_t req, uint8_t ref_seq, uint32_t steps_done, uint32_t misses)
{
    (void)ctx;
    (void)req;
    (void)ref_seq;
    (void)steps_done;
    (void)misses;
}

static uint64_t on_now(void *ctx)
{
    (void)ctx;
    return 0u; /* runs here are unpaced: no deadlines */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static ss_node_core_t core;
    ops_t o = {data, size, 0};
    ss_node_refusal_t why;
    const ss_node_run_sink_t sink = {NULL, on_row, on_end, on_now};
    uint8_t seq = 1;
    uint32_t steps_left = 20000u; /* per input: keeps an execution under a few ms */

    ss_node_core_init(&core);
    ss_node_core_hello(&core, 0);
    while (o.at < o.n && steps_left > 0u) {
        const uint8_t op = take_u8(&o);
        switch (op % 5u) {
        case 0: { /* SET_PARAM: any id (out-of-table ones included), any value */
            const uint32_t id = take_u8(&o) % (SS_NODE_N_PARAMS + 1u);
            (void)ss_node_core_set_param(&core, id, take_f32(&o), &why);
            break;
        }
        case 1: { /* RESET: drive, then where the slider starts */
            const float drive0 = take_f32(&o);
            (void)ss_node_core_reset(&core, drive0, take_f32(&o), &why);
            break;
        }
        case 2: { /* DRIVE_BLOCK: a few rows of one value */
            const float v = take_f32(&o);
            const uint32_t rows = 1u + take_u8(&o) % 40u;
            for (uint32_t i = 0; i < rows && steps_left > 0u; ++i, --steps_left) {
                (void)ss_node_core_drive(&core, v);
                check_model(&core);
            }
            break;
        }
        case 3: { /* LOAD_WAVEFORM: every field raw */
            ss_waveform_config_f32_t w;
            w.frequency_hz = take_f32(&o);
            w.amplitude_v = take_f32(&o);
            w.offset_v = take_f32(&o);
            w.rise_fraction = take_f32(&o);
            w = ss_waveform_sawtooth_f32(w.frequency_hz, w.amplitude_v, w.offset_v, w.rise_fraction,
                                         (int32_t)(int8_t)take_u8(&o), (uint32_t)take_u8(&o));
            (void)ss_node_core_load_waveform(&core, &w, &why);
            break;
        }
        default: { /* RUN, not paced, polled to its end within the step budget */
            const uint32_t steps = (uint32_t)take_u8(&o) * 64u;
            const uint32_t decimation = 1u + take_u8(&o) % 64u;
            if (ss_node_core_admit(&core, ++seq, 0, &why) == SS_PERR_NONE &&
                ss_node_core_run(&core, seq, steps, decimation, 0u, 0u, &sink, &why) == SS_PERR_NONE) {
                while (core.running && steps_left > SS_NODE_MAX_STEPS_PER_POLL) {
                    ss_node_core_run_poll(&core, 0u, &sink);
                    steps_left -= SS_NODE_MAX_STEPS_PER_POLL;
                }
                (void)ss_node_core_stop(&core, ++seq, &sink);
            }
            break;
        }
        }
        check_model(&core);
    }
    return 0;
}
