/* The node application over an in-memory link and a fake clock: every request, every rejection,
 * and that nothing rejected changes the model. */
#include "ss_test.h"

#include <math.h>
#include <string.h>

#include "ss_fake_link.h"
#include "ss_node_can.h"
#include "ss_node_serial.h"

static fake_t fk;
static ss_port_link_t link_ = {&fk, fake_read, fake_write, fake_time};
static ss_node_serial_t node;
static uint8_t host_seq;

static int setup(void **unused)
{
    (void)unused;
    memset(&fk, 0, sizeof fk);
    host_seq = 0;
    memset(&node, 0, sizeof node);
    ss_node_serial_init(&node, &link_);
    return 0;
}

static void push_bytes(const uint8_t *b, size_t n)
{
    memcpy(fk.in + fk.in_n, b, n);
    fk.in_n += n;
}

static void send_req(uint8_t type, uint8_t seq, const uint8_t *p, size_t n)
{
    uint8_t w[SS_PROTO_MAX_WIRE];
    const size_t m = ss_proto_build(type, seq, p, n, w, sizeof w);
    assert_true(m > 0u);
    push_bytes(w, m);
}

/* The next frame the node wrote, decoding from out[*at] on (NULL: no more); every frame good. */
static ss_proto_packet_t reply;
static const ss_proto_packet_t *next_frame(ss_proto_rx_t *rx, size_t *at)
{
    while (*at < fk.out_n) {
        int c = 0;
        assert_int_equal(ss_proto_rx_push(rx, fk.out[(*at)++], &reply, &c), SS_PERR_NONE);
        if (c) {
            return &reply;
        }
    }
    return NULL;
}

/* Send a request with the next seq, poll, and return the node's last frame (NULL if none: a
 * RUN answers when it ends). */
static const ss_proto_packet_t *request(uint8_t type, const uint8_t *p, size_t n)
{
    fk.out_n = 0;
    send_req(type, host_seq++, p, n);
    ss_node_serial_poll(&node);
    ss_proto_rx_t rx;
    ss_proto_rx_init(&rx);
    size_t at = 0;
    const ss_proto_packet_t *last = NULL;
    for (const ss_proto_packet_t *f; (f = next_frame(&rx, &at)) != NULL;) {
        last = f;
    }
    return last;
}

static void expect_error(const ss_proto_packet_t *r, ss_proto_error_t code, const char *in_reason)
{
    assert_non_null(r);
    assert_int_equal(r->type, SS_MSG_ERROR);
    assert_int_equal(r->payload[1], code);
    char reason[128] = {0};
    memcpy(reason, &r->payload[3], r->len - 3u < sizeof reason - 1u ? r->len - 3u : sizeof reason - 1u);
    if (strstr(reason, in_reason) == NULL) {
        fail_msg("reason '%s' lacks '%s'", reason, in_reason);
    }
}

static void test_hello(void **unused)
{
    (void)unused;
    const ss_proto_packet_t *r = request(SS_MSG_HELLO, NULL, 0);
    assert_int_equal(r->type, SS_MSG_HELLO | SS_MSG_REPLY);
    assert_int_equal(r->payload[0], 0); /* ref_seq */
    assert_int_equal(r->payload[1], SS_PROTO_VERSION);
    assert_int_equal(r->payload[4], SS_NODE_N_PARAMS);
    assert_true(ss_get_f32(&r->payload[5]) == 1e-6f);
}

static void test_params(void **unused)
{
    (void)unused;
    uint8_t p[32] = {5};
    const ss_proto_packet_t *r = request(SS_MSG_GET_PARAM, p, 1);
    assert_true(ss_get_f32(&r->payload[2]) == 0.36f);
    /* set by name, read back by id */
    p[0] = 0xFF;
    ss_put_f32(&p[1], 0.5f);
    memcpy(&p[5], "mu_s", 4);
    r = request(SS_MSG_SET_PARAM, p, 9);
    assert_int_equal(r->type, SS_MSG_SET_PARAM | SS_MSG_REPLY);
    p[0] = 5;
    r = request(SS_MSG_GET_PARAM, p, 1);
    assert_true(ss_get_f32(&r->payload[2]) == 0.5f);
    /* refusals name the parameter and change nothing */
    const ss_node_params_t before = node.core.params;
    p[0] = 6; /* mu_d above mu_s: Fc > Fs */
    ss_put_f32(&p[1], 0.7f);
    expect_error(request(SS_MSG_SET_PARAM, p, 5), SS_PERR_OUT_OF_RANGE, "mu_d");
    p[0] = 2;
    ss_put_f32(&p[1], NAN);
    expect_error(request(SS_MSG_SET_PARAM, p, 5), SS_PERR_NON_FINITE, "rod_mass_kg");
    ss_put_f32(&p[1], -1.0f);
    expect_error(request(SS_MSG_SET_PARAM, p, 5), SS_PERR_OUT_OF_RANGE, "rod_mass_kg");
    p[0] = 12;
    ss_put_f32(&p[1], 0.5f);
    expect_error(request(SS_MSG_SET_PARAM, p, 5), SS_PERR_OUT_OF_RANGE, "friction_model");
    p[0] = 40;
    expect_error(request(SS_MSG_SET_PARAM, p, 5), SS_PERR_UNKNOWN_PARAM, "id");
    p[0] = 0xFF;
    memcpy(&p[5], "mass", 4);
    expect_error(request(SS_MSG_SET_PARAM, p, 9), SS_PERR_UNKNOWN_PARAM, "name");
    expect_error(request(SS_MSG_SET_PARAM, p, 3), SS_PERR_BAD_PAYLOAD, "SET_PARAM");
    assert_memory_equal(&node.core.params, &before, sizeof before);
    /* PARAM_INFO */
    p[0] = 9;
    r = request(SS_MSG_PARAM_INFO, p, 1);
    assert_memory_equal(&r->payload[14], "sigma0_n_per_m", 14);
}

/* SET_MODEL: every pair at once, the library judges the set; one bad field and nothing changes. */
static void test_set_model_is_all_or_nothing(void **unused)
{
    (void)unused;
    uint8_t p[64];
    const struct {
        uint8_t id;
        float v;
    } good[] = {
        {SS_NODE_P_HALPHA, 0.1f}, {SS_NODE_P_HWIDTH, 2e-7f}, {SS_NODE_P_LOAD, 0.05f}, {SS_NODE_P_N, 12.0f}};
    for (size_t i = 0; i < 4; ++i) {
        p[5 * i] = good[i].id;
        ss_put_f32(&p[5 * i + 1], good[i].v);
    }
    const ss_proto_packet_t *r = request(SS_MSG_SET_MODEL, p, 20);
    assert_int_equal(r->type, SS_MSG_SET_MODEL | SS_MSG_REPLY);
    assert_int_equal(r->payload[1], 4);
    assert_true(node.core.cfg.effects.hysteresis_alpha == 0.1f && node.core.cfg.effects.load_n == 0.05f);
    assert_true(node.core.cfg.friction.fs_n == 0.36f * 12.0f);
    /* a hysteresis without its width alone is a rule between fields: the library's field named */
    const ss_node_params_t before = node.core.params;
    p[0] = SS_NODE_P_HWIDTH;
    ss_put_f32(&p[1], 0.0f);
    p[5] = SS_NODE_P_LOAD;
    ss_put_f32(&p[6], 0.2f);
    expect_error(request(SS_MSG_SET_MODEL, p, 10), SS_PERR_OUT_OF_RANGE, "model: effects.hysteresis_width_m");
    /* one field out of its table range: named, and the valid one before it not applied either */
    p[0] = SS_NODE_P_LOAD;
    ss_put_f32(&p[1], 0.3f);
    p[5] = SS_NODE_P_SLEW;
    ss_put_f32(&p[6], -1.0f);
    expect_error(request(SS_MSG_SET_MODEL, p, 10), SS_PERR_OUT_OF_RANGE, "slew_v_per_s: outside its range");
    p[5] = 99;
    expect_error(request(SS_MSG_SET_MODEL, p, 10), SS_PERR_UNKNOWN_PARAM, "id");
    expect_error(request(SS_MSG_SET_MODEL, p, 7), SS_PERR_BAD_PAYLOAD, "SET_MODEL takes 1 to 29");
    expect_error(request(SS_MSG_SET_MODEL, p, 0), SS_PERR_BAD_PAYLOAD, "SET_MODEL");
    assert_memory_equal(&node.core.params, &before, sizeof before);
}

/* DRIVE_BLOCK steps exactly like the library does, and a duplicate is not executed again. */
static void test_drive_block_lockstep_and_duplicate(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
    ss_actuator_state_f32_t ref;
    memset(&ref, 0, sizeof ref);
    ss_actuator_init_f32(&cfg, &ref, 0.0f);
    uint8_t p[2 + 4 * 40];
    ss_put_u16(p, 4);
    for (int i = 0; i < 40; ++i) {
        const float v = 2.5f * (float)(i + 1);
        ss_put_f32(&p[2 + 4 * i], v);
        ss_actuator_step_f32(&cfg, &ref, v);
    }
    const ss_proto_packet_t *r = request(SS_MSG_DRIVE_BLOCK, p, sizeof p);
    assert_int_equal(r->type, SS_MSG_DRIVE_BLOCK | SS_MSG_REPLY);
    assert_int_equal(ss_get_u32(&r->payload[1]), 4);  /* first row: after step 4 */
    assert_int_equal(ss_get_u16(&r->payload[5]), 10); /* 40 samples / 4 */
    const uint8_t *last = &r->payload[7 + 9 * SS_PROTO_ROW_BYTES];
    assert_int_equal(ss_get_u32(last), 40);
    assert_true(ss_get_f32(last + 8) == ref.x_rod_m);
    assert_true(ss_get_f32(last + 12) == ref.x_slider.hi_m);
    assert_true(ss_get_f32(last + 20) == ref.force_n);
    /* the same frame again (same seq): refused, the model does not move */
    const uint32_t steps = node.core.st.steps;
    fk.out_n = 0;
    send_req(SS_MSG_DRIVE_BLOCK, (uint8_t)(host_seq - 1u), p, sizeof p);
    ss_node_serial_poll(&node);
    assert_int_equal(node.core.st.steps, steps);
    assert_true(fk.out_n > 0);
    /* a NaN anywhere in a block: refused as a whole */
    const ss_actuator_state_f32_t before = node.core.st;
    ss_put_f32(&p[2 + 4 * 30], NAN);
    expect_error(request(SS_MSG_DRIVE_BLOCK, p, sizeof p), SS_PERR_NON_FINITE, "drive sample");
    /* beyond the documented drive limit: refused by name (1e38 V made the state NaN for good) */
    ss_put_f32(&p[2 + 4 * 30], 1e38f);
    expect_error(request(SS_MSG_DRIVE_BLOCK, p, sizeof p), SS_PERR_OUT_OF_RANGE,
                 "drive sample: outside " SS_NODE_MAX_DRIVE_V_TEXT);
    ss_put_f32(&p[2 + 4 * 30], -1.5e5f);
    expect_error(request(SS_MSG_DRIVE_BLOCK, p, sizeof p), SS_PERR_OUT_OF_RANGE, "drive sample");
    ss_put_u16(p, 3); /* 40 / 3 rows is fine, decimation 0 is not */
    ss_put_u16(p, 0);
    expect_error(request(SS_MSG_DRIVE_BLOCK, p, sizeof p), SS_PERR_OUT_OF_RANGE, "decimation");
    expect_error(request(SS_MSG_DRIVE_BLOCK, p, 5), SS_PERR_BAD_PAYLOAD, "DRIVE_BLOCK");
    assert_memory_equal(&node.core.st, &before, sizeof before);
}

/* Property: no drive the node accepts can bring the model to a non-finite state. Every law, 20 000
 * steps each of drives drawn over the whole accepted range (a fixed LCG, so the test is the same
 * on every machine), with jumps from one end to the other; both ends are in every draw's set. */
static void test_no_accepted_drive_makes_the_state_non_finite(void **unused)
{
    (void)unused;
    static const int32_t laws[] = {SS_FRICTION_LS, SS_FRICTION_LUGRE, SS_FRICTION_GMS};
    uint32_t lcg = 12345u;
    for (size_t k = 0; k < sizeof laws / sizeof laws[0]; ++k) {
        ss_node_core_t core;
        ss_node_core_init(&core);
        core.cfg.friction_model = laws[k];
        ss_node_model_init(&core.cfg, &core.st, ss_node_model_drive_from_v(0.0f));
        for (int i = 0; i < 20000; ++i) {
            lcg = lcg * 1664525u + 1013904223u;
            float v = ((float)(lcg >> 8) / 8388608.0f - 1.0f) * SS_NODE_MAX_DRIVE_V;
            if (i % 1000 < 4) {
                v = (i % 2 == 0) ? SS_NODE_MAX_DRIVE_V : -SS_NODE_MAX_DRIVE_V;
            }
            assert_int_equal(ss_node_core_drive(&core, v), SS_PERR_NONE);
            const ss_node_row_t r = ss_node_core_row(&core);
            assert_true(isfinite(r.x_rod_m) && isfinite(r.x_slider_hi_m) && isfinite(r.x_slider_lo_m));
            assert_true(isfinite(r.force_n)); /* the friction state feeds it */
        }
        assert_int_equal(ss_node_core_drive(&core, 1e38f), SS_PERR_OUT_OF_RANGE);
        assert_int_equal(ss_node_core_drive(&core, nextafterf(SS_NODE_MAX_DRIVE_V, INFINITY)),
                         SS_PERR_OUT_OF_RANGE);
    }
}

/* Every parameter at either end of its range, one at a time, then drives across the whole
 * range: the state stays finite. Found by bench/fuzz/fuzz_node_core.c: a 10 ug rod (in range)
 * made the over-damped rod flow inf x 0 = NaN on the first step. */
static void test_parameter_extremes_keep_the_state_finite(void **unused)
{
    (void)unused;
    static const float drives[] = {0.0f, SS_NODE_MAX_DRIVE_V, -SS_NODE_MAX_DRIVE_V, 1.0f};
    for (uint32_t id = 0; id < SS_NODE_N_PARAMS; ++id) {
        const ss_node_param_def_t *d = ss_node_core_param_def(id);
        for (int end = 0; end < 2; ++end) {
            ss_node_core_t core;
            ss_node_refusal_t why;
            ss_node_core_init(&core);
            if (ss_node_core_set_param(&core, id, end ? d->max : d->min, &why) != SS_PERR_NONE) {
                continue; /* refused as a combination (mu_s < mu_d): nothing changed */
            }
            for (int i = 0; i < 400; ++i) {
                assert_int_equal(ss_node_core_drive(&core, drives[(i / 50) % 4]), SS_PERR_NONE);
                const ss_node_row_t r = ss_node_core_row(&core);
                if (!(isfinite(r.x_rod_m) && isfinite(r.x_slider_hi_m) && isfinite(r.force_n))) {
                    fail_msg("%s = %g: state not finite at step %d", d->name, (double)(end ? d->max : d->min),
                             i);
                }
            }
        }
    }
}

/* A refused waveform names its field (it said "waveform: parameter out of range"). */
static void test_refused_waveform_names_its_field(void **unused)
{
    (void)unused;
    const ss_waveform_config_f32_t good = ss_waveform_sawtooth_f32(500.0f, 100.0f, 0.0f, 0.95f, 1, 20);
    static const char *const names[] = {"frequency_hz", "amplitude_v", "offset_v", "rise_fraction",
                                        "direction"};
    struct {
        int field;
        float value;
        ss_proto_error_t code;
    } cases[] = {
        {0, 2e6f, SS_PERR_OUT_OF_RANGE}, {0, 0.0f, SS_PERR_OUT_OF_RANGE},   {1, -2e5f, SS_PERR_OUT_OF_RANGE},
        {2, NAN, SS_PERR_NON_FINITE},    {3, 1.0f, SS_PERR_OUT_OF_RANGE},   {3, 0.0f, SS_PERR_OUT_OF_RANGE},
        {4, 0.0f, SS_PERR_OUT_OF_RANGE}, {1, INFINITY, SS_PERR_NON_FINITE},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        ss_waveform_config_f32_t w = good;
        float *f[4] = {&w.frequency_hz, &w.amplitude_v, &w.offset_v, &w.rise_fraction};
        if (cases[k].field == 4) {
            w.direction = (int32_t)cases[k].value;
        } else {
            *f[cases[k].field] = cases[k].value;
        }
        ss_node_core_t core;
        ss_node_refusal_t why = {"", ""};
        ss_node_core_init(&core);
        assert_int_equal(ss_node_core_load_waveform(&core, &w, &why), cases[k].code);
        assert_string_equal(why.what, names[cases[k].field]);
        assert_true(why.why[0] != '\0');
        assert_false(core.wave_loaded);
    }
}

static void test_free_run_paced_busy_stop(void **unused)
{
    (void)unused;
    uint8_t run[7];
    ss_put_u32(run, 1000);
    ss_put_u16(&run[4], 10);
    run[6] = 1; /* paced */
    expect_error(request(SS_MSG_RUN, run, 7), SS_PERR_NO_WAVEFORM, "LOAD_WAVEFORM");
    uint8_t w[21];
    ss_put_f32(w, 500.0f);
    ss_put_f32(&w[4], 100.0f);
    ss_put_f32(&w[8], 0.0f);
    ss_put_f32(&w[12], 1.5f); /* bad rise fraction */
    w[16] = 1;
    ss_put_u32(&w[17], 2);
    expect_error(request(SS_MSG_LOAD_WAVEFORM, w, 21), SS_PERR_OUT_OF_RANGE, "rise_fraction: outside (0, 1)");
    ss_put_f32(&w[12], 0.95f);
    assert_int_equal(request(SS_MSG_LOAD_WAVEFORM, w, 21)->type, SS_MSG_LOAD_WAVEFORM | SS_MSG_REPLY);
    request(SS_MSG_RUN, run, 7);
    assert_int_equal(node.core.running, 1);
    /* paced: nothing is due until the clock moves */
    ss_node_serial_poll(&node);
    assert_int_equal(node.core.run_done, 0);
    fk.now_ns += 250000u; /* 250 us: 250 steps due */
    ss_node_serial_poll(&node);
    assert_int_equal(node.core.run_done, 250);
    expect_error(request(SS_MSG_RESET, w, 4), SS_PERR_BUSY, "run");
    const ss_proto_packet_t *r = request(SS_MSG_STOP, NULL, 0);
    assert_int_equal(r->type, SS_MSG_STOP | SS_MSG_REPLY);
    assert_int_equal(ss_get_u32(&r->payload[1]), 250);
    assert_int_equal(node.core.running, 0);
    /* unpaced to the end: RUN reply with all steps done */
    run[6] = 0;
    ss_put_u32(run, 3000);
    request(SS_MSG_RUN, run, 7);
    for (int i = 0; i < 5 && node.core.running; ++i) {
        ss_node_serial_poll(&node);
    }
    assert_int_equal(node.core.running, 0);
    assert_int_equal(node.core.run_done, 3000);
}

static void load_paper_waveform(uint32_t cycles)
{
    uint8_t w[21] = {0};
    ss_put_f32(w, 500.0f);
    ss_put_f32(&w[4], 100.0f);
    ss_put_f32(&w[12], 0.95f);
    w[16] = 1;
    ss_put_u32(&w[17], cycles);
    assert_int_equal(request(SS_MSG_LOAD_WAVEFORM, w, 21)->type, SS_MSG_LOAD_WAVEFORM | SS_MSG_REPLY);
}

static void run_to_end(uint32_t steps, uint16_t decimation)
{
    uint8_t run[7];
    ss_put_u32(run, steps);
    ss_put_u16(&run[4], decimation);
    run[6] = 0;
    request(SS_MSG_RUN, run, 7);
    while (node.core.running) {
        ss_node_serial_poll(&node);
    }
}

/* SET_PARAM after a run that stopped mid-ramp: the model goes to rest where the next RUN starts
 * (the waveform at t = 0), so the next RUN's first step moves the drive by one step of the ramp,
 * not from the old run's last drive back to the start (52 V at once, before the fix). */
static void test_set_param_then_run_does_not_jump(void **unused)
{
    (void)unused;
    load_paper_waveform(2);
    run_to_end(1000, 1000); /* half way up the first ramp: about 52 V */
    assert_true(node.core.st.drive_v > 50.0f);
    uint8_t p[5] = {7}; /* normal_force_n, set to what it is */
    ss_put_f32(&p[1], 10.0f);
    assert_int_equal(request(SS_MSG_SET_PARAM, p, 5)->type, SS_MSG_SET_PARAM | SS_MSG_REPLY);
    const float rest_v = node.core.st.drive_v;
    run_to_end(1, 1);
    assert_true(fabsf(node.core.st.drive_v - rest_v) < 0.1f); /* 100 V / 1900 steps a step */
}

/* A paced run's deadline in integers: after 2^24 + 3 us exactly 2^24 + 3 steps of 1 us are due
 * (a float deadline rounds the time to 2^24 + 4 us). */
static void test_paced_deadline_after_16_s(void **unused)
{
    (void)unused;
    load_paper_waveform(20000);
    fk.now_ns = 1000000u;
    uint8_t run[7];
    ss_put_u32(run, 20000000u);
    ss_put_u16(&run[4], 60000);
    run[6] = 1;
    request(SS_MSG_RUN, run, 7);
    fk.now_ns += 16777219000u;
    uint32_t before;
    do {
        before = node.core.run_done;
        ss_node_serial_poll(&node);
    } while (node.core.run_done != before);
    assert_int_equal(node.core.run_done, 16777219u);
}

/* The last frame of type among what the node wrote since the last request (NULL: none). */
static ss_proto_packet_t found;
static const ss_proto_packet_t *last_of_type(uint8_t type)
{
    ss_proto_rx_t rx;
    ss_proto_rx_init(&rx);
    size_t at = 0;
    const ss_proto_packet_t *last = NULL;
    for (const ss_proto_packet_t *f; (f = next_frame(&rx, &at)) != NULL;) {
        if (f->type == type) {
            found = *f;
            last = &found;
        }
    }
    return last;
}

/* A paced run of steps steps at slot paced x dt, the test's clock moving 1 us between polls (and
 * tick_us at each reading of it): the RUN reply's steps done and deadline misses, and the last
 * telemetry frame's count so far. */
static void paced_run(uint32_t steps, uint8_t paced, uint64_t tick_us, uint32_t *misses, uint32_t *tel_misses)
{
    uint8_t run[7];
    ss_put_u32(run, steps);
    ss_put_u16(&run[4], 50);
    run[6] = paced;
    fk.tick_ns = 0;
    request(SS_MSG_RUN, run, 7); /* an unpaced run ends in this poll */
    fk.tick_ns = tick_us * 1000u;
    while (node.core.running) {
        fk.now_ns += 1000u;
        ss_node_serial_poll(&node);
    }
    fk.tick_ns = 0;
    const ss_proto_packet_t *r = last_of_type(SS_MSG_RUN | SS_MSG_REPLY);
    assert_non_null(r);
    assert_int_equal(r->len, 9); /* ref_seq, u32 steps done, u32 misses */
    assert_int_equal(ss_get_u32(&r->payload[1]), steps);
    *misses = ss_get_u32(&r->payload[5]);
    const ss_proto_packet_t *t = last_of_type(SS_MSG_TELEMETRY);
    assert_non_null(t);
    const uint16_t rows = ss_get_u16(&t->payload[5]);
    assert_int_equal(t->len, 7u + rows * SS_PROTO_ROW_BYTES + 4u); /* rows, then the misses so far */
    *tel_misses = ss_get_u32(&t->payload[7u + rows * SS_PROTO_ROW_BYTES]);
}

/* Deadline misses: a step that ends after the next step's due time. A node that keeps up misses
 * none; one that needs more than its slot misses nearly all; slowed down (a longer slot), the same
 * node keeps up again. Unpaced runs count none. */
static void test_paced_deadline_misses(void **unused)
{
    (void)unused;
    load_paper_waveform(2);
    fk.now_ns = 100000u;
    uint32_t misses = 0;
    uint32_t tel = 0;
    /* the clock stands still while the node works: every step ends within its slot */
    paced_run(200, 1, 0, &misses, &tel);
    assert_int_equal(misses, 0);
    assert_int_equal(tel, 0);
    /* each reading of the clock takes 1 us: a step costs about 2 us against a 1 us slot */
    paced_run(200, 1, 1, &misses, &tel);
    print_message("2 us a step in 1 us slots: %u of 200 missed\n", misses);
    assert_true(misses >= 190u && misses <= 200u);
    assert_true(tel <= misses && tel >= 150u);
    /* the same node slowed 3 times: 3 us slots */
    paced_run(200, 3, 1, &misses, &tel);
    assert_int_equal(misses, 0);
    /* unpaced: no deadlines */
    paced_run(200, 0, 1, &misses, &tel);
    assert_int_equal(misses, 0);
}

/* Every TELEMETRY row the node wrote since out_n was last cleared, in order, into rows (at most
 * cap bytes); returns the bytes. */
static size_t telemetry_rows(uint8_t *rows, size_t cap)
{
    ss_proto_rx_t rx;
    ss_proto_rx_init(&rx);
    size_t at = 0;
    size_t n = 0;
    for (const ss_proto_packet_t *f; (f = next_frame(&rx, &at)) != NULL;) {
        if (f->type == SS_MSG_TELEMETRY) {
            const size_t bytes = (size_t)ss_get_u16(&f->payload[5]) * SS_PROTO_ROW_BYTES;
            assert_true(n + bytes <= cap);
            memcpy(rows + n, &f->payload[7], bytes);
            n += bytes;
        }
    }
    return n;
}

/* A paced run's telemetry goes out a piece at a time between steps: a frame of 40 rows is on its
 * way across several slots, no step waits for it, and the rows are the unpaced run's. */
static void test_paced_telemetry_goes_out_between_steps(void **unused)
{
    (void)unused;
    static uint8_t want[100 * SS_PROTO_ROW_BYTES];
    static uint8_t got[100 * SS_PROTO_ROW_BYTES];
    load_paper_waveform(2);
    uint8_t zero[4] = {0};
    request(SS_MSG_RESET, zero, 4);
    fk.out_n = 0;
    uint8_t run[7];
    ss_put_u32(run, 400);
    ss_put_u16(&run[4], 5); /* 80 rows: two full frames */
    run[6] = 0;
    send_req(SS_MSG_RUN, host_seq++, run, 7);
    while (fk.in_at < fk.in_n || node.core.running) {
        ss_node_serial_poll(&node);
    }
    const size_t n_want = telemetry_rows(want, sizeof want);
    assert_int_equal(n_want, 80u * SS_PROTO_ROW_BYTES);
    request(SS_MSG_RESET, zero, 4);
    fk.out_n = 0;
    run[6] = 1; /* paced: 1 us slots; a reading of the clock takes 100 ns, and between polls the
                 * node's loop spins until the next step is due */
    send_req(SS_MSG_RUN, host_seq++, run, 7);
    fk.tick_ns = 100u;
    int polls_streaming = 0;
    while (fk.in_at < fk.in_n || node.core.running) {
        fk.now_ns += (ss_node_core_idle_fs(&node.core, fk.now_ns) + 999999u) / 1000000u;
        ss_node_serial_poll(&node);
        polls_streaming += node.tx_active;
    }
    fk.tick_ns = 0;
    assert_int_equal(telemetry_rows(got, sizeof got), n_want);
    assert_memory_equal(got, want, n_want);
    assert_true(polls_streaming > 5); /* a frame took several slots' idle time */
    const ss_proto_packet_t *r = last_of_type(SS_MSG_RUN | SS_MSG_REPLY);
    assert_non_null(r);
    assert_int_equal(ss_get_u32(&r->payload[5]), 0); /* no step missed its deadline */
}

/* The model's step is a parameter (step_s, id 27): HELLO reports it, the model steps by it, and a
 * paced run's slot follows it, so the node that missed 1 us slots keeps up with 4 us ones. */
static void test_step_is_a_parameter(void **unused)
{
    (void)unused;
    uint8_t p[5] = {27};
    ss_put_f32(&p[1], 4e-6f);
    const ss_proto_packet_t *r = request(SS_MSG_SET_PARAM, p, 5);
    assert_int_equal(r->type, SS_MSG_SET_PARAM | SS_MSG_REPLY);
    r = request(SS_MSG_HELLO, NULL, 0);
    assert_true(ss_get_f32(&r->payload[5]) == 4e-6f);
    assert_true(node.core.cfg.dt_s == 4e-6f);
    load_paper_waveform(2);
    fk.now_ns = 100000u;
    uint32_t misses = 0;
    uint32_t tel = 0;
    paced_run(200, 1, 1, &misses, &tel); /* about 2 us a step, as above, in 4 us slots */
    assert_int_equal(misses, 0);
    /* 200 steps of 4 us: 0.8 ms of the 2 ms period, as the library steps it */
    ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
    cfg.dt_s = 4e-6f;
    ss_actuator_state_f32_t st;
    ss_waveform_state_f32_t ws;
    assert_int_equal(ss_waveform_init_f32(&node.core.wave, cfg.dt_s, &ws), SS_OK);
    assert_int_equal(ss_actuator_init_f32(&cfg, &st, ss_waveform_value_f32(&node.core.wave, &ws)), SS_OK);
    for (int k = 0; k < 200; ++k) {
        assert_int_equal(ss_actuator_wave_step_f32(&cfg, &st, &node.core.wave, &ws), SS_OK);
    }
    assert_memory_equal(&node.core.st.x_slider, &st.x_slider, sizeof st.x_slider);
    /* out of the library's range, or not a number: refused by name, nothing changes */
    const ss_node_params_t before = node.core.params;
    const float bad[] = {0.0f, 2e-3f, NAN};
    for (int i = 0; i < 3; ++i) {
        ss_put_f32(&p[1], bad[i]);
        expect_error(request(SS_MSG_SET_PARAM, p, 5),
                     isnan(bad[i]) ? SS_PERR_NON_FINITE : SS_PERR_OUT_OF_RANGE, "step_s");
    }
    assert_memory_equal(&node.core.params, &before, sizeof before);
}

static void test_garbage_unknown_and_disconnect(void **unused)
{
    (void)unused;
    const ss_actuator_state_f32_t before = node.core.st;
    uint8_t junk[300];
    for (int i = 0; i < 300; ++i) {
        junk[i] = (uint8_t)(i * 37 + 11);
    }
    junk[100] = 0;
    junk[299] = 0;
    push_bytes(junk, sizeof junk);
    ss_node_serial_poll(&node);
    assert_memory_equal(&node.core.st, &before, sizeof before);
    expect_error(request(0x33, NULL, 0), SS_PERR_UNKNOWN_TYPE, "unknown");
    /* the peer goes away mid-run: the run stops, the node answers the next session */
    uint8_t w[21] = {0};
    ss_put_f32(w, 500.0f);
    ss_put_f32(&w[4], 100.0f);
    ss_put_f32(&w[12], 0.95f);
    w[16] = 1;
    ss_put_u32(&w[17], 2);
    request(SS_MSG_LOAD_WAVEFORM, w, 21);
    uint8_t run[7];
    ss_put_u32(run, 100000);
    ss_put_u16(&run[4], 1);
    run[6] = 1;
    request(SS_MSG_RUN, run, 7);
    fk.gone = 1;
    assert_int_equal(ss_node_serial_poll(&node), -1);
    assert_int_equal(node.core.running, 0);
    host_seq = 0;
    assert_int_equal(request(SS_MSG_HELLO, NULL, 0)->type, SS_MSG_HELLO | SS_MSG_REPLY);
}

/* ---------------------------------------------------------------- the CAN front end */

static ss_node_can_t can_node;
static ss_can_frame_t can_in[64], can_out[512];
static size_t can_in_n, can_in_at, can_out_n;
static int can_gone;

static int32_t can_read(void *ctx, ss_can_frame_t *f)
{
    (void)ctx;
    if (can_gone) {
        can_gone = 0;
        return -1;
    }
    if (can_in_at == can_in_n) {
        return 0;
    }
    *f = can_in[can_in_at++];
    return 1;
}

static int32_t can_write(void *ctx, const ss_can_frame_t *f)
{
    (void)ctx;
    if (can_out_n < sizeof can_out / sizeof can_out[0]) {
        can_out[can_out_n++] = *f;
    }
    return 1;
}

static ss_port_can_t can_port = {&fk, can_read, can_write, fake_time};

static int setup_can(void **unused)
{
    (void)unused;
    memset(&fk, 0, sizeof fk);
    can_in_n = can_in_at = can_out_n = 0;
    can_gone = 0;
    memset(&can_node, 0, sizeof can_node);
    ss_node_can_init(&can_node, &can_port);
    return 0;
}

static ss_can_reply_t can_cmd(uint8_t cmd, uint8_t seq, uint8_t index, uint8_t flags, float value)
{
    const ss_can_cmd_t c = {cmd, seq, index, flags, value};
    ss_can_pack_cmd(&c, &can_in[can_in_n++]);
    can_out_n = 0;
    ss_node_can_poll(&can_node);
    ss_can_reply_t r;
    memset(&r, 0, sizeof r);
    for (size_t i = 0; i < can_out_n; ++i) {
        (void)ss_can_unpack_reply(&can_out[i], &r);
    }
    return r;
}

static void test_can_commands(void **unused)
{
    (void)unused;
    ss_can_reply_t r = can_cmd(SS_CAN_CMD_HELLO, 0, 0, 0, 0.0f);
    assert_int_equal(r.cmd, SS_CAN_CMD_HELLO);
    assert_int_equal(r.index, 0); /* LS, float32 */
    assert_true(r.value == 1e-6f);
    r = can_cmd(SS_CAN_CMD_GET_PARAM, 1, 5, 0, 0.0f);
    assert_true(r.status == 0 && r.value == 0.36f);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 2, 2, 0, -1.0f).status, SS_PERR_OUT_OF_RANGE);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 3, 9, 0, NAN).status, SS_PERR_NON_FINITE);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 4, 77, 0, 1.0f).status, SS_PERR_UNKNOWN_PARAM);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 4, 7, 0, 12.0f).status,
                     SS_PERR_DUPLICATE); /* seq 4 again */
    r = can_cmd(SS_CAN_CMD_SET_PARAM, 5, 7, 0, 12.0f);
    assert_true(r.status == 0 && r.value == 12.0f);
    assert_int_equal(can_cmd(SS_CAN_CMD_RESET, 6, 0, 0, INFINITY).status, SS_PERR_NON_FINITE);
    assert_int_equal(can_cmd(SS_CAN_CMD_RESET, 7, 0, 0, 2e5f).status, SS_PERR_OUT_OF_RANGE);
    assert_int_equal(can_cmd(SS_CAN_CMD_RESET, 8, 0, 0, 1.0f).status, 0);
    assert_int_equal(can_cmd(SS_CAN_CMD_RUN, 9, 1, 0, 100.0f).status, SS_PERR_NO_WAVEFORM);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_WAVE, 10, 4, 0, 0.5f).status, SS_PERR_OUT_OF_RANGE);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_WAVE, 11, 5, 0, 2.5f).status, SS_PERR_OUT_OF_RANGE);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_WAVE, 12, 9, 0, 1.0f).status, SS_PERR_OUT_OF_RANGE);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_WAVE, 13, 0, 0, NAN).status, SS_PERR_NON_FINITE);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_WAVE, 14, 3, 0, 1.5f).status, 0); /* checked at LOAD */
    assert_int_equal(can_cmd(SS_CAN_CMD_LOAD_WAVE, 15, 0, 0, 0.0f).status, SS_PERR_OUT_OF_RANGE);
    const float fields[6] = {500.0f, 100.0f, 0.0f, 0.95f, -1.0f, 2.0f};
    for (uint8_t i = 0; i < 6; ++i) {
        assert_int_equal(can_cmd(SS_CAN_CMD_SET_WAVE, (uint8_t)(16 + i), i, 0, fields[i]).status, 0);
    }
    assert_int_equal(can_cmd(SS_CAN_CMD_LOAD_WAVE, 22, 0, 0, 0.0f).status, 0);
    assert_int_equal(can_cmd(SS_CAN_CMD_RUN, 23, 0, 0, 100.0f).status,
                     SS_PERR_OUT_OF_RANGE); /* decimation 0 */
    assert_int_equal(can_cmd(SS_CAN_CMD_RUN, 24, 1, 0, 10.5f).status, SS_PERR_OUT_OF_RANGE);
    assert_int_equal(can_cmd(0x55, 25, 0, 0, 0.0f).status, SS_PERR_UNKNOWN_TYPE);
    /* an unpaced run of 100 steps at decimation 10: 10 states of 3 frames, then the RUN reply */
    r = can_cmd(SS_CAN_CMD_RUN, 26, 10, 0, 100.0f);
    assert_int_equal(can_out_n, 31);
    assert_int_equal(can_out[0].id, SS_CAN_ID_STATE_A);
    assert_true(r.cmd == SS_CAN_CMD_RUN && r.value == 100.0f);
    assert_true(ss_get_u32(can_out[27].data) == 100u);
    /* STOP when idle, and a zero-step run answered at once */
    assert_int_equal(can_cmd(SS_CAN_CMD_STOP, 27, 0, 0, 0.0f).status, 0);
    r = can_cmd(SS_CAN_CMD_RUN, 28, 1, 0, 0.0f);
    assert_true(r.cmd == SS_CAN_CMD_RUN && r.value == 0.0f);
}

/* A refusal says why on CAN too: SS_REASON frames before the SS_REPLY, the serial ERROR's text. */
static void test_can_refusal_sends_its_reason(void **unused)
{
    (void)unused;
    const ss_can_reply_t r = can_cmd(SS_CAN_CMD_SET_PARAM, 1, 6, 0, 0.7f); /* mu_d above mu_s */
    assert_int_equal(r.status, SS_PERR_OUT_OF_RANGE);
    char text[64] = {0};
    size_t len = 0;
    for (size_t i = 0; i + 1u < can_out_n; ++i) {
        ss_can_reason_t m;
        assert_true(ss_can_unpack_reason(&can_out[i], &m));
        assert_true(m.cmd == SS_CAN_CMD_SET_PARAM && m.seq == 1);
        for (size_t k = 0; k < SS_CAN_REASON_CHARS && m.text[k] != '\0'; ++k) {
            text[len++] = m.text[k];
        }
    }
    assert_true(can_out_n >= 2u);
    assert_int_equal(can_out[can_out_n - 1u].id, SS_CAN_ID_REPLY);
    assert_string_equal(text, "mu_d: Fc = mu_d N: in [1e-6, 1e4] N, <= Fs");
    /* an accepted command sends no reason */
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 2, 6, 0, 0.3f).status, 0);
    assert_int_equal(can_out_n, 1);
}

/* SET_PARAM with flags 1 stages, APPLY_MODEL applies the set: all or none, staging cleared. */
static void test_can_model_staged_then_applied(void **unused)
{
    (void)unused;
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 1, SS_NODE_P_LOAD, 1, 0.3f).status, 0);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 2, SS_NODE_P_HALPHA, 1, 0.2f).status, 0);
    assert_true(can_node.core.cfg.effects.load_n == 0.0f); /* staged, not applied */
    ss_can_reply_t r = can_cmd(SS_CAN_CMD_APPLY_MODEL, 3, 0, 0, 0.0f);
    assert_int_equal(r.status, SS_PERR_OUT_OF_RANGE); /* a hysteresis without its width */
    assert_true(can_node.core.cfg.effects.load_n == 0.0f && can_node.n_staged == 0u);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 4, SS_NODE_P_LOAD, 1, 0.1f).status, 0);
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 5, SS_NODE_P_LOAD, 1, 0.05f).status, 0); /* replaces */
    assert_int_equal(can_cmd(SS_CAN_CMD_SET_PARAM, 6, 99, 1, 1.0f).status, SS_PERR_UNKNOWN_PARAM);
    r = can_cmd(SS_CAN_CMD_APPLY_MODEL, 7, 0, 0, 0.0f);
    assert_int_equal(r.status, 0);
    assert_true(r.value == 1.0f && can_node.core.cfg.effects.load_n == 0.05f);
    /* nothing staged: nothing to apply, said so */
    assert_int_equal(can_cmd(SS_CAN_CMD_APPLY_MODEL, 8, 0, 0, 0.0f).status, SS_PERR_BAD_PAYLOAD);
}

static void test_can_lockstep_busy_and_traffic(void **unused)
{
    (void)unused;
    ss_actuator_config_f32_t cfg = ss_actuator_config_table1_f32();
    ss_actuator_state_f32_t ref;
    memset(&ref, 0, sizeof ref);
    ss_actuator_init_f32(&cfg, &ref, 0.0f);
    for (uint8_t i = 1; i <= 20; ++i) {
        const ss_can_drive_t d = {2.0f * (float)i, i, (uint8_t)(i == 20)};
        ss_can_pack_drive(&d, &can_in[can_in_n++]);
        ss_actuator_step_f32(&cfg, &ref, d.drive_v);
    }
    const ss_can_frame_t other = {0x7FF, 2, 0, 0, {1, 2}}; /* someone else's frame on the bus */
    can_in[can_in_n++] = other;
    can_out_n = 0;
    ss_node_can_poll(&can_node);
    assert_int_equal(can_out_n, 3); /* one reported state */
    assert_int_equal(ss_get_u32(can_out[0].data), 20);
    assert_true(ss_get_f32(can_out[1].data) == ref.x_rod_m);
    assert_true(ss_get_f32(&can_out[2].data[0]) == ref.x_slider.hi_m);
    /* the last drive frame again: refused, not stepped */
    const ss_can_drive_t again = {40.0f, 20, 1};
    ss_can_pack_drive(&again, &can_in[can_in_n++]);
    const ss_can_drive_t bad = {NAN, 21, 1};
    ss_can_pack_drive(&bad, &can_in[can_in_n++]);
    const ss_can_drive_t huge = {1e38f, 22, 1};
    ss_can_pack_drive(&huge, &can_in[can_in_n++]);
    can_out_n = 0;
    ss_node_can_poll(&can_node);
    ss_can_reply_t r;
    assert_true(ss_can_unpack_reply(&can_out[0], &r) && r.status == SS_PERR_DUPLICATE);
    assert_true(ss_can_unpack_reply(&can_out[1], &r) && r.status == SS_PERR_NON_FINITE);
    /* the reason frames, then the reply */
    assert_true(ss_can_unpack_reply(&can_out[can_out_n - 1], &r) && r.status == SS_PERR_OUT_OF_RANGE);
    assert_int_equal(can_node.core.st.steps, 20);
    /* during a paced run: drive frames and commands are busy; HELLO stops the run */
    can_cmd(SS_CAN_CMD_SET_WAVE, 40, 0, 0, 500.0f);
    can_cmd(SS_CAN_CMD_LOAD_WAVE, 41, 0, 0, 0.0f);
    can_cmd(SS_CAN_CMD_RUN, 42, 1, 1, 1e6f);
    assert_int_equal(can_node.core.running, 1);
    const ss_can_drive_t during = {1.0f, 22, 0};
    ss_can_pack_drive(&during, &can_in[can_in_n++]);
    can_out_n = 0;
    ss_node_can_poll(&can_node);
    assert_true(ss_can_unpack_reply(&can_out[can_out_n - 1], &r) && r.status == SS_PERR_BUSY);
    assert_int_equal(can_cmd(SS_CAN_CMD_RESET, 43, 0, 0, 0.0f).status, SS_PERR_BUSY);
    fk.now_ns += 500000u;
    ss_node_can_poll(&can_node);
    assert_true(can_node.core.run_done > 0);
    r = can_cmd(SS_CAN_CMD_STOP, 44, 0, 0, 0.0f);
    assert_true(r.cmd == SS_CAN_CMD_STOP && r.value > 0.0f);
    /* the bus peer goes away: the session is forgotten, the node serves on */
    can_gone = 1;
    assert_int_equal(ss_node_can_poll(&can_node), -1);
    assert_int_equal(can_cmd(SS_CAN_CMD_HELLO, 0, 0, 0, 0.0f).cmd, SS_CAN_CMD_HELLO);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_hello, setup),
        cmocka_unit_test_setup(test_params, setup),
        cmocka_unit_test_setup(test_set_model_is_all_or_nothing, setup),
        cmocka_unit_test_setup(test_drive_block_lockstep_and_duplicate, setup),
        cmocka_unit_test(test_no_accepted_drive_makes_the_state_non_finite),
        cmocka_unit_test_setup(test_free_run_paced_busy_stop, setup),
        cmocka_unit_test_setup(test_paced_deadline_misses, setup),
        cmocka_unit_test_setup(test_step_is_a_parameter, setup),
        cmocka_unit_test_setup(test_paced_telemetry_goes_out_between_steps, setup),
        cmocka_unit_test_setup(test_garbage_unknown_and_disconnect, setup),
        cmocka_unit_test_setup(test_set_param_then_run_does_not_jump, setup),
        cmocka_unit_test_setup(test_paced_deadline_after_16_s, setup),
        cmocka_unit_test(test_parameter_extremes_keep_the_state_finite),
        cmocka_unit_test(test_refused_waveform_names_its_field),
        cmocka_unit_test_setup(test_can_commands, setup_can),
        cmocka_unit_test_setup(test_can_refusal_sends_its_reason, setup_can),
        cmocka_unit_test_setup(test_can_model_staged_then_applied, setup_can),
        cmocka_unit_test_setup(test_can_lockstep_busy_and_traffic, setup_can),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
