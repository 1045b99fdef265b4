/* stickslip_node (float32 model) and stickslip_node_q (fixed-point model, SS_NODE_MODEL_Q): the
 * stage model served over a serial link (docs/protocol.md).
 * The link is a pseudo-terminal (--pty, its path is printed) or TCP on 127.0.0.1 (--tcp PORT). */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ss_node_can.h"
#include "ss_node_serial.h"
#include "ss_port_posix.h"
#include "ss_proto.h"
#include "ss_slcan_port.h"
#include "ss_port_socketcan.h"

#ifndef SS_NODE_PROGRAM
#define SS_NODE_PROGRAM "stickslip_node"
#endif
#if SS_NODE_VARIANT == 1u
#define SS_NODE_MODEL_TEXT "fixed-point model"
#else
#define SS_NODE_MODEL_TEXT "float32 model"
#endif

static volatile sig_atomic_t stop_requested = 0;

static void on_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: " SS_NODE_PROGRAM
               " (--pty | --tcp PORT | --can-pty | --can-tcp PORT | --socketcan IFACE)\n"
               "Serve the stick-slip stage model (" SS_NODE_MODEL_TEXT ", Table I, LS friction, 1 us step)\n"
               "over a serial or CAN link.\n"
               "  --pty              serial protocol on a new pseudo-terminal (its path is printed)\n"
               "  --tcp PORT         serial protocol on 127.0.0.1:PORT (0: any free port, printed)\n"
               "  --can-pty          CAN frames over SLCAN on a new pseudo-terminal\n"
               "  --can-tcp PORT     CAN frames over SLCAN on 127.0.0.1:PORT (python-can slcan, socket://)\n"
               "  --socketcan IFACE  CAN frames on a SocketCAN interface (vcan0, can0)\n"
               "  --set NAME=VALUE   a parameter of the model served (repeatable; all applied at once)\n"
               "  --help             this text\n"
               "Protocol and CAN messages: docs/protocol.md, hil/stickslip/hil/stickslip.dbc.\n");
}

/* --set NAME=VALUE options, taken out of argv (the link options stay); 0 and a message when one
 * is malformed or names no parameter. */
static int take_sets(int *argc, char **argv, uint8_t *ids, float *values, uint32_t *n)
{
    int out = 1;
    *n = 0u;
    for (int i = 1; i < *argc; ++i) {
        if (strcmp(argv[i], "--set") != 0) {
            argv[out++] = argv[i];
            continue;
        }
        const char *arg = (i + 1 < *argc) ? argv[++i] : "";
        const char *eq = strchr(arg, '=');
        uint32_t id = 0;
        char *end = NULL;
        const double v = (eq != NULL) ? strtod(eq + 1, &end) : 0.0;
        if (eq == NULL || !ss_node_core_param_id((const uint8_t *)arg, (size_t)(eq - arg), &id)) {
            fprintf(stderr,
                    SS_NODE_PROGRAM ": --set: expected NAME=VALUE with a parameter name of "
                                    "docs/protocol.md, got '%s'\n",
                    arg);
            return 0;
        }
        if (end == eq + 1 || *end != '\0' || *n >= SS_NODE_N_PARAMS) {
            fprintf(stderr, SS_NODE_PROGRAM ": --set %.*s: expected a number, got '%s'\n", (int)(eq - arg),
                    arg, eq + 1);
            return 0;
        }
        ids[*n] = (uint8_t)id;
        values[(*n)++] = (float)v;
    }
    *argc = out;
    return 1;
}

int main(int argc, char **argv)
{
    /* the model to serve: Table I, changed by --set options, all at once (SET_MODEL's rules) */
    uint8_t set_ids[SS_NODE_N_PARAMS];
    float set_values[SS_NODE_N_PARAMS];
    uint32_t n_set = 0;
    if (!take_sets(&argc, argv, set_ids, set_values, &n_set)) {
        return 2;
    }
    static ss_node_core_t trial; /* judged before a link is opened: a refused model serves nothing */
    ss_node_refusal_t why;
    ss_node_core_init(&trial);
    if (n_set > 0u && ss_node_core_set_params(&trial, set_ids, set_values, n_set, &why) != SS_PERR_NONE) {
        fprintf(stderr, SS_NODE_PROGRAM ": --set refused: %s%s%s\n", why.what, why.why[0] ? ": " : "",
                why.why);
        return 2;
    }
    static ss_posix_link_t link; /* large buffers: not on the stack */
    static ss_slcan_port_t slcan;
    static ss_socketcan_t socketcan;
    static ss_node_serial_t node;  /* a serial node, or */
    static ss_node_can_t can_node; /* a CAN node, without the serial buffers */
    const ss_port_can_t *can = NULL;
    /* what a second TCP client hears before it is closed: ERROR busy (in the serial framing, on the
     * SLCAN link too, as before the port stopped building it) */
    static uint8_t refusal[SS_PROTO_MAX_WIRE];
    const size_t refusal_len =
        ss_proto_build_error(0, 0, SS_PERR_BUSY, 0, "another client is connected", refusal, sizeof refusal);
    int ok;
    if (argc == 2 && strcmp(argv[1], "--pty") == 0) {
        char path[256];
        ok = ss_posix_pty_open(&link, path, sizeof path) == 0;
        if (ok) {
            printf(SS_NODE_PROGRAM ": serial pty %s\n", path);
        }
    } else if (argc == 3 && strcmp(argv[1], "--tcp") == 0) {
        char *end = NULL;
        const long port = strtol(argv[2], &end, 10);
        if (end == argv[2] || *end != '\0' || port < 0 || port > 65535) {
            fprintf(stderr, SS_NODE_PROGRAM ": --tcp: expected a port number 0..65535, got '%s'\n", argv[2]);
            return 2;
        }
        ok = ss_posix_tcp_listen(&link, (uint16_t)port, refusal, refusal_len) == 0;
        if (ok) {
            printf(SS_NODE_PROGRAM ": serial tcp 127.0.0.1:%u\n", (unsigned)link.port);
        }
    } else if (argc == 2 && strcmp(argv[1], "--can-pty") == 0) {
        char path[256];
        ok = ss_posix_pty_open(&link, path, sizeof path) == 0;
        if (ok) {
            printf(SS_NODE_PROGRAM ": slcan pty %s\n", path);
        }
        can = &slcan.can;
    } else if (argc == 3 && strcmp(argv[1], "--can-tcp") == 0) {
        char *end = NULL;
        const long port = strtol(argv[2], &end, 10);
        if (end == argv[2] || *end != '\0' || port < 0 || port > 65535) {
            fprintf(stderr, SS_NODE_PROGRAM ": --can-tcp: expected a port number 0..65535, got '%s'\n",
                    argv[2]);
            return 2;
        }
        ok = ss_posix_tcp_listen(&link, (uint16_t)port, refusal, refusal_len) == 0;
        if (ok) {
            printf(SS_NODE_PROGRAM ": slcan tcp 127.0.0.1:%u\n", (unsigned)link.port);
        }
        can = &slcan.can;
    } else if (argc == 3 && strcmp(argv[1], "--socketcan") == 0) {
        ok = ss_socketcan_open(&socketcan, argv[2]) == 0;
        if (ok) {
            printf(SS_NODE_PROGRAM ": socketcan %s\n", argv[2]);
        }
        can = &socketcan.can;
    } else if (argc == 2 && strcmp(argv[1], "--help") == 0) {
        usage(stdout);
        return 0;
    } else {
        usage(stderr);
        return 2;
    }
    if (!ok) {
        perror(SS_NODE_PROGRAM ": cannot open the link");
        return 1;
    }
    fflush(stdout);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    if (can == &slcan.can) {
        ss_slcan_port_init(&slcan, &link.link);
    }
    ss_node_core_t *core = (can != NULL) ? &can_node.core : &node.core;
    if (can != NULL) {
        ss_node_can_init(&can_node, can);
    } else {
        ss_node_serial_init(&node, &link.link);
    }
    if (n_set > 0u) {
        (void)ss_node_core_set_params(core, set_ids, set_values, n_set, &why); /* accepted above */
    }
    while (!stop_requested) {
        if (can != NULL) {
            (void)ss_node_can_poll(&can_node);
        } else {
            (void)ss_node_serial_poll(&node);
        }
        if (can == &socketcan.can) {
            if (!core->running) {
                struct timespec ts = {0, 200000};
                nanosleep(&ts, NULL);
            }
        } else if (!core->running) {
            ss_posix_wait(&link, 20);
        } else if (core->paced) {
            ss_posix_wait(&link, 0);
        }
    }
    if (can != &socketcan.can) {
        ss_posix_close(&link);
    }
    return 0;
}
