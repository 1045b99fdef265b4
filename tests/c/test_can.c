/* CAN: the node's messages against cantools' encoding of the DBC (tests/vectors/can_frames.csv),
 * the SLCAN codec, and the SLCAN adapter's answers to python-can's commands. */
#include "ss_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ss_can_msg.h"
#include "ss_slcan_port.h"

static double field(const char *json, const char *key)
{
    char pat[48];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *p = strstr(json, pat);
    if (p == NULL) {
        fail_msg("no %s in %s", key, json);
    }
    return strtod(p + strlen(pat), NULL);
}

static void test_messages_match_cantools(void **unused)
{
    (void)unused;
    FILE *f = fopen(SS_VECTORS_DIR "/can_frames.csv", "r");
    assert_non_null(f);
    char line[512];
    int cases = 0;
    while (fgets(line, sizeof line, f) != NULL) {
        if (line[0] == '#') {
            continue;
        }
        char *name = strtok(line, ";");
        const unsigned id = (unsigned)atoi(strtok(NULL, ";"));
        const unsigned dlc = (unsigned)atoi(strtok(NULL, ";"));
        const char *json = strtok(NULL, ";");
        const char *hex = strtok(NULL, ";\n");
        uint8_t want[8] = {0};
        for (unsigned i = 0; i < dlc; ++i) {
            char b[3] = {hex[2 * i], hex[2 * i + 1], 0};
            want[i] = (uint8_t)strtoul(b, NULL, 16);
        }
        ss_can_frame_t fr[3];
        ss_can_frame_t *got = &fr[0];
        if (strcmp(name, "SS_CMD") == 0) {
            const ss_can_cmd_t m = {(uint8_t)field(json, "cmd"), (uint8_t)field(json, "seq"),
                                    (uint8_t)field(json, "index"), (uint8_t)field(json, "flags"),
                                    (float)field(json, "value")};
            ss_can_pack_cmd(&m, got);
            ss_can_cmd_t back;
            assert_true(ss_can_unpack_cmd(got, &back));
            assert_memory_equal(&back, &m, sizeof m);
        } else if (strcmp(name, "SS_REPLY") == 0) {
            const ss_can_reply_t m = {(uint8_t)field(json, "cmd"), (uint8_t)field(json, "seq"),
                                      (uint8_t)field(json, "status"), (uint8_t)field(json, "index"),
                                      (float)field(json, "value")};
            ss_can_pack_reply(&m, got);
            ss_can_reply_t back;
            assert_true(ss_can_unpack_reply(got, &back));
            assert_memory_equal(&back, &m, sizeof m);
        } else if (strcmp(name, "SS_REASON") == 0) {
            ss_can_reason_t m;
            memset(&m, 0, sizeof m);
            m.cmd = (uint8_t)field(json, "cmd");
            m.seq = (uint8_t)field(json, "seq");
            const double text = field(json, "text"); /* 48 bits, exact in double */
            for (unsigned i = 0; i < SS_CAN_REASON_CHARS; ++i) {
                m.text[i] = (char)((uint64_t)text >> (8u * i));
            }
            ss_can_pack_reason(&m, got);
            ss_can_reason_t back;
            assert_true(ss_can_unpack_reason(got, &back));
            assert_memory_equal(&back, &m, sizeof m);
        } else if (strcmp(name, "SS_DRIVE") == 0) {
            ss_can_drive_t m;
            memset(&m, 0, sizeof m);
            m.drive_v = (float)field(json, "drive_v");
            m.seq = (uint8_t)field(json, "seq");
            m.report = (uint8_t)field(json, "report");
            ss_can_pack_drive(&m, got);
            ss_can_drive_t back;
            memset(&back, 0, sizeof back);
            assert_true(ss_can_unpack_drive(got, &back));
            assert_memory_equal(&back, &m, sizeof m);
        } else {
            ss_can_state_t m;
            memset(&m, 0, sizeof m);
            const int which = name[9] - 'A';
            if (which == 0) {
                m.step = (uint32_t)field(json, "step");
                m.drive_v = (float)field(json, "drive_v");
            } else if (which == 1) {
                m.x_rod_m = (float)field(json, "x_rod_m");
                m.friction_n = (float)field(json, "friction_n");
            } else {
                m.x_slider_hi_m = (float)field(json, "x_slider_hi_m");
                m.x_slider_lo_m = (float)field(json, "x_slider_lo_m");
            }
            ss_can_pack_state(&m, fr);
            got = &fr[which];
        }
        assert_int_equal(got->id, id);
        assert_int_equal(got->dlc, dlc);
        assert_memory_equal(got->data, want, dlc);
        cases++;
    }
    fclose(f);
    assert_int_equal(cases, 10);
    ss_can_frame_t other = {0x300, 8, 0, 0, {0}};
    ss_can_cmd_t c;
    assert_false(ss_can_unpack_cmd(&other, &c)); /* other bus traffic is not a command */
}

static ss_slcan_event_t push_line(ss_slcan_rx_t *rx, const char *s, ss_can_frame_t *f, char *cmd)
{
    ss_slcan_event_t ev = SS_SLCAN_NONE;
    for (; *s != '\0'; ++s) {
        const ss_slcan_event_t e = ss_slcan_push(rx, (uint8_t)*s, f, cmd);
        if (e != SS_SLCAN_NONE) {
            ev = e;
        }
    }
    return ev;
}

static void test_slcan_codec(void **unused)
{
    (void)unused;
    ss_slcan_rx_t rx;
    ss_slcan_rx_init(&rx);
    ss_can_frame_t f;
    char cmd[SS_SLCAN_MAX_LINE + 1];
    assert_int_equal(push_line(&rx, "t1108000048410301aabb\r", &f, cmd), SS_SLCAN_FRAME);
    assert_int_equal(f.id, 0x110);
    assert_int_equal(f.dlc, 8);
    assert_int_equal(f.data[3], 0x41);
    char out[SS_SLCAN_MAX_LINE];
    const size_t n = ss_slcan_format(&f, out, sizeof out);
    assert_int_equal(n, 22);
    assert_memory_equal(out, "t1108000048410301AABB\r", n);
    assert_int_equal(push_line(&rx, "T01ABCDEF2beef\r", &f, cmd), SS_SLCAN_FRAME);
    assert_true(f.ext && f.id == 0x1ABCDEF && f.dlc == 2);
    assert_int_equal(push_line(&rx, "r1233\r", &f, cmd), SS_SLCAN_FRAME);
    assert_true(f.rtr && f.dlc == 3);
    assert_int_equal(push_line(&rx, "S8\r", &f, cmd), SS_SLCAN_COMMAND);
    assert_string_equal(cmd, "S8");
    const char *bad[] = {"t1109\r",         "t11G1aa\r", "t1102aabbcc\r", "t8001aa\r",
                         "T2000000001aa\r", "t12\r",     "t1102aZ\r"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        if (push_line(&rx, bad[i], &f, cmd) != SS_SLCAN_BAD) {
            fail_msg("accepted '%s'", bad[i]);
        }
    }
    char longline[80];
    memset(longline, 'x', sizeof longline);
    longline[78] = '\r';
    longline[79] = 0;
    assert_int_equal(push_line(&rx, longline, &f, cmd), SS_SLCAN_BAD);
    assert_int_equal(push_line(&rx, "\r\n", &f, cmd), SS_SLCAN_NONE);
    ss_can_frame_t wrong = {0x800, 1, 0, 0, {0}};
    assert_int_equal(ss_slcan_format(&wrong, out, sizeof out), 0);
}

/* ---- the adapter over a fake byte link */
static char link_in[256], link_out[256];
static size_t in_n, in_at, out_n;
static int32_t lread(void *c, uint8_t *b, size_t max)
{
    (void)c;
    size_t n = in_n - in_at < max ? in_n - in_at : max;
    memcpy(b, link_in + in_at, n);
    in_at += n;
    return (int32_t)n;
}
static int32_t lwrite(void *c, const uint8_t *b, size_t n)
{
    (void)c;
    memcpy(link_out + out_n, b, n);
    out_n += n;
    return (int32_t)n;
}
static uint64_t ltime(void *c)
{
    (void)c;
    return 0;
}

static void feed_adapter(ss_slcan_port_t *p, const char *s, int expect_frames)
{
    in_n = strlen(s);
    in_at = 0;
    memcpy(link_in, s, in_n);
    out_n = 0;
    memset(link_out, 0, sizeof link_out);
    ss_can_frame_t f;
    int frames = 0;
    while (p->can.read(p->can.ctx, &f) == 1) {
        frames++;
    }
    assert_int_equal(frames, expect_frames);
}

static void test_slcan_adapter(void **unused)
{
    (void)unused;
    const ss_port_link_t link = {NULL, lread, lwrite, ltime};
    ss_slcan_port_t p;
    ss_slcan_port_init(&p, &link);
    feed_adapter(&p, "t1101aa\r", 0); /* closed: refused */
    assert_string_equal(link_out, "\a");
    feed_adapter(&p, "C\rS8\rO\r", 0); /* what python-can sends on open */
    assert_string_equal(link_out, "\r\r\r");
    feed_adapter(&p, "t1101aa\rV\r", 1);
    assert_string_equal(link_out, "z\rV1013\r");
    feed_adapter(&p, "tZZZ\rS9\rX\r", 0);
    assert_string_equal(link_out, "\a\a\a");
    assert_int_equal(p.bad_lines, 2);
    ss_can_frame_t f = {0x101, 2, 0, 0, {1, 2}};
    out_n = 0;
    assert_int_equal(p.can.write(p.can.ctx, &f), 1);
    assert_memory_equal(link_out, "t10120102\r", 10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_messages_match_cantools),
        cmocka_unit_test(test_slcan_codec),
        cmocka_unit_test(test_slcan_adapter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
