/* The node application over an in-memory link and a fake clock: every request, every rejection,
 * and that nothing rejected changes the model. */
#include "ss_test.h"

#include <string.h>

#include "ss_node.h"

typedef struct {
    uint8_t in[8192];
    size_t in_n, in_at;
    uint8_t out[1 << 16];
    size_t out_n;
    uint64_t now_us;
    int gone; /* next read reports the peer gone */
} fake_t;

static int32_t fake_read(void *ctx, uint8_t *buf, size_t max)
{
    fake_t *f = ctx;
    if (f->gone) {
        f->gone = 0;
        return -1;
    }
    size_t n = f->in_n - f->in_at;
    n = n < max ? n : max;
    memcpy(buf, f->in + f->in_at, n);
    f->in_at += n;
    return (int32_t)n;
}

static int32_t fake_write(void *ctx, const uint8_t *buf, size_t n)
{
    fake_t *f = ctx;
    if (f->out_n + n > sizeof f->out) {
        return -1;
    }
    memcpy(f->out + f->out_n, buf, n);
    f->out_n += n;
    return (int32_t)n;
}

static uint64_t fake_time(void *ctx)
{
    return ((fake_t *)ctx)->now_us;
}

static fake_t fk;
static ss_port_link_t link_ = {&fk, fake_read, fake_write, fake_time};
static ss_node_t node;
static uint8_t host_seq;

static int setup(void **unused)
{
    (void)unused;
    memset(&fk, 0, sizeof fk);
    host_seq = 0;
    memset(&node, 0, sizeof node);
    ss_node_init(&node, &link_);
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

/* Send a request with the next seq, poll, and return the node's last frame (NULL if none: a
 * RUN answers when it ends). */
static ss_proto_packet_t reply;
static const ss_proto_packet_t *request(uint8_t type, const uint8_t *p, size_t n)
{
    fk.out_n = 0;
    send_req(type, host_seq++, p, n);
    ss_node_poll(&node);
    ss_proto_rx_t rx;
    ss_proto_rx_init(&rx);
    int frames = 0;
    for (size_t i = 0; i < fk.out_n; ++i) {
        int c = 0;
        assert_int_equal(ss_proto_rx_push(&rx, fk.out[i], &reply, &c), SS_PERR_NONE);
        frames += c;
    }
    return (frames > 0) ? &reply : NULL;
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
    const ss_node_params_t before = node.params;
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
    assert_memory_equal(&node.params, &before, sizeof before);
    /* PARAM_INFO */
    p[0] = 9;
    r = request(SS_MSG_PARAM_INFO, p, 1);
    assert_memory_equal(&r->payload[14], "sigma0_n_per_m", 14);
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
    const uint32_t steps = node.st.steps;
    fk.out_n = 0;
    send_req(SS_MSG_DRIVE_BLOCK, (uint8_t)(host_seq - 1u), p, sizeof p);
    ss_node_poll(&node);
    assert_int_equal(node.st.steps, steps);
    assert_true(fk.out_n > 0);
    /* a NaN anywhere in a block: refused as a whole */
    const ss_actuator_state_f32_t before = node.st;
    ss_put_f32(&p[2 + 4 * 30], NAN);
    expect_error(request(SS_MSG_DRIVE_BLOCK, p, sizeof p), SS_PERR_NON_FINITE, "drive sample");
    ss_put_u16(p, 3); /* 40 / 3 rows is fine, decimation 0 is not */
    ss_put_u16(p, 0);
    expect_error(request(SS_MSG_DRIVE_BLOCK, p, sizeof p), SS_PERR_OUT_OF_RANGE, "decimation");
    expect_error(request(SS_MSG_DRIVE_BLOCK, p, 5), SS_PERR_BAD_PAYLOAD, "DRIVE_BLOCK");
    assert_memory_equal(&node.st, &before, sizeof before);
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
    expect_error(request(SS_MSG_LOAD_WAVEFORM, w, 21), SS_PERR_OUT_OF_RANGE, "waveform");
    ss_put_f32(&w[12], 0.95f);
    assert_int_equal(request(SS_MSG_LOAD_WAVEFORM, w, 21)->type, SS_MSG_LOAD_WAVEFORM | SS_MSG_REPLY);
    request(SS_MSG_RUN, run, 7);
    assert_int_equal(node.running, 1);
    /* paced: nothing is due until the clock moves */
    ss_node_poll(&node);
    assert_int_equal(node.run_done, 0);
    fk.now_us += 250; /* 250 us: 250 steps due */
    ss_node_poll(&node);
    assert_int_equal(node.run_done, 250);
    expect_error(request(SS_MSG_RESET, w, 4), SS_PERR_BUSY, "run");
    const ss_proto_packet_t *r = request(SS_MSG_STOP, NULL, 0);
    assert_int_equal(r->type, SS_MSG_STOP | SS_MSG_REPLY);
    assert_int_equal(ss_get_u32(&r->payload[1]), 250);
    assert_int_equal(node.running, 0);
    /* unpaced to the end: RUN reply with all steps done */
    run[6] = 0;
    ss_put_u32(run, 3000);
    request(SS_MSG_RUN, run, 7);
    for (int i = 0; i < 5 && node.running; ++i) {
        ss_node_poll(&node);
    }
    assert_int_equal(node.running, 0);
    assert_int_equal(node.run_done, 3000);
}

static void test_garbage_unknown_and_disconnect(void **unused)
{
    (void)unused;
    const ss_actuator_state_f32_t before = node.st;
    uint8_t junk[300];
    for (int i = 0; i < 300; ++i) {
        junk[i] = (uint8_t)(i * 37 + 11);
    }
    junk[100] = 0;
    junk[299] = 0;
    push_bytes(junk, sizeof junk);
    ss_node_poll(&node);
    assert_memory_equal(&node.st, &before, sizeof before);
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
    assert_int_equal(ss_node_poll(&node), -1);
    assert_int_equal(node.running, 0);
    host_seq = 0;
    assert_int_equal(request(SS_MSG_HELLO, NULL, 0)->type, SS_MSG_HELLO | SS_MSG_REPLY);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(test_hello, setup),
        cmocka_unit_test_setup(test_params, setup),
        cmocka_unit_test_setup(test_drive_block_lockstep_and_duplicate, setup),
        cmocka_unit_test_setup(test_free_run_paced_busy_stop, setup),
        cmocka_unit_test_setup(test_garbage_unknown_and_disconnect, setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
