/* POSIX port: the node's byte link on a pseudo-terminal or on TCP (127.0.0.1), and the clock. */
#ifndef SS_PORT_POSIX_H
#define SS_PORT_POSIX_H

#include <stddef.h>
#include <stdint.h>

#include "ss_port.h"

typedef struct {
    int kind;               /* 0 pty, 1 tcp */
    int master_fd;          /* pty master */
    int slave_fd;           /* kept open so a client closing the pty does not end it */
    int listen_fd;          /* tcp */
    int client_fd;          /* tcp, -1 when no client */
    uint16_t port;          /* tcp, the bound port */
    uint8_t session_over;   /* tcp: the last client left; the next read reports it */
    const uint8_t *refusal; /* tcp: sent to a second client before it is closed (may be NULL) */
    size_t refusal_len;
    ss_port_link_t link;
} ss_posix_link_t;

/* Open a pseudo-terminal in raw mode; its client path goes to path. 0 on success, -1 (errno). */
int ss_posix_pty_open(ss_posix_link_t *l, char *path, size_t cap);

/* Listen on 127.0.0.1:port (0 picks a free port, see l->port). One client at a time: a second one
 * is sent the refusal_len bytes at refusal (the application's words, e.g. a protocol ERROR frame;
 * none if NULL) and closed; refusal must outlive the link. 0 on success, -1 (errno). */
int ss_posix_tcp_listen(ss_posix_link_t *l, uint16_t port, const uint8_t *refusal, size_t refusal_len);

/* Wait up to timeout_ms for input (or a connection). */
void ss_posix_wait(ss_posix_link_t *l, int timeout_ms);

void ss_posix_close(ss_posix_link_t *l);

#endif /* SS_PORT_POSIX_H */
