/* The node application built with SS_NODE_MODEL_Q (the fixed-point model) over an in-memory link:
 * lock-step and free run give exactly what the q model gives directly, through the conversion
 * rules of docs/protocol.md (float32 volts in, float32 SI telemetry out). */
#include "ss_test.h"

#include <string.h>

#include "ss_convert_q.h"
#include "ss_fake_link.h"
#include "ss_node_can.h"
#include "ss_node_serial.h"

#if SS_NODE_VARIANT != 1u
#error "test_node_q is built with SS_NODE_MODEL_Q"
#endif

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

/* Every frame the node sent since the last request, in order. */
static ss_proto_packet_t frames[64];
static int n_frames;

static const ss_proto_packet_t *request(uint8_t type, const uint8_t *p, size_t n)
{
    fk.out_n = 0;
    fk.in_n = fk.in_at = 0;
    const size_t m = ss_proto_build(type, host_seq++, p, n, fk.in, sizeof fk.in);
    assert_true(m > 0u);
    fk.in_n = m;
    while (fk.in_at < fk.in_n) {
        ss_node_serial_poll(&node); /* the node reads up to 256 bytes a poll */
    }
    for (int i = 0; i < 10 && node.core.running; ++i) {
        ss_node_serial_poll(&node); /* an unpaced run ends within a few polls */
    }
    ss_proto_rx_t rx;
    ss_proto_rx_init(&rx);
    n_frames = 0;
    for (size_t i = 0; i < fk.out_n; ++i) {
        int c = 0;
        assert_int_equal(ss_proto_rx_push(&rx, fk.out[i], &frames[n_frames], &c), SS_PERR_NONE);
        n_frames += c;
        assert_true(n_frames < 64);
    }
    return (n_frames > 0) ? &frames[n_frames - 1] : NULL;
}

/* The telemetry row the protocol promises for a q state (docs/protocol.md), built here from the
 * rule itself, not from the node's code. */
static void expect_row(const uint8_t *row, const ss_actuator_state_q_t *ref)
{
    assert_int_equal(ss_get_u32(row), ref->steps);
    assert_true(ss_get_f32(row + 4) == (float)ref->drive_q16 / 65536.0f);
    assert_true(ss_get_f32(row + 8) == (float)ref->x_rod_q40 / 1099511627776.0f);
    const float hi = (float)ref->x_slider_q40;
    assert_true(ss_get_f32(row + 12) == hi / 1099511627776.0f);
    assert_true(ss_get_f32(row + 16) == (float)(ref->x_slider_q40 - (int64_t)hi) / 1099511627776.0f);
    assert_true(ss_get_f32(row + 20) == (float)ref->force_q24 / 16777216.0f);
    /* hi + lo in double is the q position exactly */
    const double x = (double)ss_get_f32(row + 12) + (double)ss_get_f32(row + 16);
    assert_true(x * 1099511627776.0 == (double)ref->x_slider_q40);
}

static void test_hello_reports_fixed_point(void **unused)
{
    (void)unused;
    const ss_proto_packet_t *r = request(SS_MSG_HELLO, NULL, 0);
    assert_int_equal(r->type, SS_MSG_HELLO | SS_MSG_REPLY);
    assert_int_equal(r->payload[3], 1);                                       /* variant: fixed point */
    assert_true(ss_get_f32(&r->payload[5]) == 1099512.0f / 1099511627776.0f); /* dt_q40 of Table I */
    const ss_actuator_config_q_t t1 = ss_actuator_config_table1_q();
    assert_memory_equal(&node.core.cfg, &t1, sizeof t1);
}

/* Volts to Q16.16: floor(v 2^16 + 1/2), saturated, as ss_volts_to_q16. */
static void test_drive_conversion_rule(void **unused)
{
    (void)unused;
    const float v[] = {0.5f / 65536.0f,
                       -0.5f / 65536.0f,
                       1.5f / 65536.0f,
                       -1.5f / 65536.0f,
                       0.49999997f / 65536.0f,
                       99.99999f /* 100 - 2^-17: a half */,
                       -1e5f,
                       1e5f,
                       32767.99f};
    const int32_t q[] = {1, 0, 2, -1, 0, 6553600, INT32_MIN, INT32_MAX, 2147483008};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; ++i) {
        uint8_t p[4];
        ss_put_f32(p, v[i]);
        assert_int_equal(request(SS_MSG_RESET, p, 4)->type, SS_MSG_RESET | SS_MSG_REPLY);
        assert_int_equal(node.core.st.drive_q16, q[i]);
        assert_int_equal(q[i], ss_volts_to_q16((double)v[i]));
    }
}

/* DRIVE_BLOCK: one ss_actuator_step_q per sample, exactly. */
static void test_lockstep_is_the_q_model(void **unused)
{
    (void)unused;
    const ss_actuator_config_q_t cfg = ss_actuator_config_table1_q();
    ss_actuator_state_q_t ref;
    memset(&ref, 0, sizeof ref);
    assert_int_equal(ss_actuator_init_q(&cfg, &ref, 0), SS_OK);
    static ss_actuator_state_q_t want[40];
    uint8_t p[2 + 4 * 200];
    for (int block = 0; block < 10; ++block) {
        ss_put_u16(p, 5);
        int rows = 0;
        for (int i = 0; i < 200; ++i) {
            const int k = 200 * block + i;
            /* a fast sawtooth with samples off the Q16.16 grid */
            const float v = 100.0f * (float)(k % 400) / 399.7f - 3.3f;
            ss_put_f32(&p[2 + 4 * i], v);
            assert_int_equal(ss_actuator_step_q(&cfg, &ref, ss_volts_to_q16((double)v)), SS_OK);
            if ((i + 1) % 5 == 0) {
                want[rows++] = ref;
            }
        }
        const ss_proto_packet_t *r = request(SS_MSG_DRIVE_BLOCK, p, sizeof p);
        assert_int_equal(r->type, SS_MSG_DRIVE_BLOCK | SS_MSG_REPLY);
        assert_int_equal(ss_get_u16(&r->payload[5]), rows);
        for (int i = 0; i < rows; ++i) {
            expect_row(&r->payload[7 + (size_t)i * SS_PROTO_ROW_BYTES], &want[i]);
        }
    }
    assert_memory_equal(&node.core.st, &ref, sizeof ref);
}

/* RUN plays the sawtooth the converter makes of the float32 fields (rise 0.95f): the rows are
 * those of ss_actuator_run_q. */
static void test_free_run_is_the_q_model(void **unused)
{
    (void)unused;
    uint8_t w[21];
    ss_put_f32(w, 500.0f);
    ss_put_f32(&w[4], 100.0f);
    ss_put_f32(&w[8], 0.0f);
    ss_put_f32(&w[12], 0.95f);
    w[16] = 1;
    ss_put_u32(&w[17], 2);
    assert_int_equal(request(SS_MSG_LOAD_WAVEFORM, w, 21)->type, SS_MSG_LOAD_WAVEFORM | SS_MSG_REPLY);
    const ss_actuator_config_q_t cfg = ss_actuator_config_table1_q();
    const ss_waveform_config_f32_t wf = ss_waveform_sawtooth_f32(500.0f, 100.0f, 0.0f, 0.95f, 1, 2);
    ss_waveform_config_q_t wq;
    assert_int_equal(ss_waveform_config_to_q(&wf, &wq, NULL), SS_OK);
    assert_int_equal(wq.rise_q32, 4080218880u);
    ss_waveform_state_q_t ws;
    ss_actuator_state_q_t ref;
    memset(&ref, 0, sizeof ref);
    assert_int_equal(ss_waveform_init_q(&wq, cfg.dt_q40, &ws), SS_OK);
    assert_int_equal(ss_actuator_init_q(&cfg, &ref, ss_waveform_value_q(&wq, &ws)), SS_OK);
    uint8_t run[7];
    ss_put_u32(run, 4000);
    ss_put_u16(&run[4], 10);
    run[6] = 0;
    const ss_proto_packet_t *r = request(SS_MSG_RUN, run, 7);
    assert_int_equal(r->type, SS_MSG_RUN | SS_MSG_REPLY);
    assert_int_equal(ss_get_u32(&r->payload[1]), 4000);
    uint32_t seen = 0;
    for (int f = 0; f < n_frames; ++f) {
        if (frames[f].type != SS_MSG_TELEMETRY) {
            continue;
        }
        const uint32_t n = ss_get_u16(&frames[f].payload[5]);
        for (uint32_t i = 0; i < n; ++i) {
            for (int s = 0; s < 10; ++s) {
                (void)ss_actuator_wave_step_q(&cfg, &ref, &wq, &ws);
            }
            expect_row(&frames[f].payload[7 + (size_t)i * SS_PROTO_ROW_BYTES], &ref);
            seen++;
        }
    }
    assert_int_equal(seen, 400);
}

/* SET_PARAM goes through the converter; a value that passes the float check but does not fit a Q
 * format is refused with the parameter's name, and nothing changes. */
static void test_set_param_converts(void **unused)
{
    (void)unused;
    uint8_t p[5] = {7};
    ss_put_f32(&p[1], 12.5f);
    assert_int_equal(request(SS_MSG_SET_PARAM, p, 5)->type, SS_MSG_SET_PARAM | SS_MSG_REPLY);
    ss_actuator_config_f32_t f = ss_actuator_config_table1_f32();
    f.friction = ss_friction_config_from_mu_f32(0.36f, 0.30f, 12.5f, 4.0e-4f, 1.0e7f, 80.0f, 8.0f);
    ss_actuator_config_q_t want;
    assert_int_equal(ss_actuator_config_to_q(&f, &want, NULL), SS_OK);
    assert_memory_equal(&node.core.cfg, &want, sizeof want);
    const ss_actuator_config_q_t before = node.core.cfg;
    p[0] = 2; /* a rod of 1 ug: the kick dt/(2 M_R) does not fit its format */
    ss_put_f32(&p[1], 1e-9f);
    const ss_proto_packet_t *r = request(SS_MSG_SET_PARAM, p, 5);
    assert_int_equal(r->type, SS_MSG_ERROR);
    assert_int_equal(r->payload[1], SS_PERR_OUT_OF_RANGE);
    assert_memory_equal(&r->payload[3], "rod_mass_kg", 11);
    assert_memory_equal(&node.core.cfg, &before, sizeof before);
    /* LuGre through the converter as well */
    p[0] = 12;
    ss_put_f32(&p[1], 1.0f);
    assert_int_equal(request(SS_MSG_SET_PARAM, p, 5)->type, SS_MSG_SET_PARAM | SS_MSG_REPLY);
    assert_int_equal(node.core.cfg.friction_model, SS_FRICTION_Q_LUGRE);
    /* the step (step_s) too: 4 us as the converter gives it; 10 ns is below dt_q40's range */
    p[0] = 27;
    ss_put_f32(&p[1], 4e-6f);
    assert_int_equal(request(SS_MSG_SET_PARAM, p, 5)->type, SS_MSG_SET_PARAM | SS_MSG_REPLY);
    f.friction_model = SS_FRICTION_LUGRE;
    f.dt_s = 4e-6f;
    assert_int_equal(ss_actuator_config_to_q(&f, &want, NULL), SS_OK);
    assert_memory_equal(&node.core.cfg, &want, sizeof want);
    ss_put_f32(&p[1], 1e-8f);
    r = request(SS_MSG_SET_PARAM, p, 5);
    assert_int_equal(r->type, SS_MSG_ERROR);
    assert_int_equal(r->payload[1], SS_PERR_OUT_OF_RANGE);
    assert_memory_equal(&r->payload[3], "step_s", 6);
    assert_memory_equal(&node.core.cfg, &want, sizeof want);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_hello_reports_fixed_point, setup),
        cmocka_unit_test_setup(test_drive_conversion_rule, setup),
        cmocka_unit_test_setup(test_lockstep_is_the_q_model, setup),
        cmocka_unit_test_setup(test_free_run_is_the_q_model, setup),
        cmocka_unit_test_setup(test_set_param_converts, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
