#include "ss_port_posix.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

static uint64_t posix_time_ns(void *ctx)
{
    (void)ctx;
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

static int32_t write_all(int fd, const uint8_t *buf, size_t n, int is_socket)
{
    size_t done = 0;
    while (done < n) {
        const ssize_t w =
            is_socket ? send(fd, buf + done, n - done, MSG_NOSIGNAL) : write(fd, buf + done, n - done);
        if (w < 0) {
            if (errno == EINTR) {
                continue;
            }
            if (errno == EAGAIN) {
                struct pollfd p = {fd, POLLOUT, 0};
                (void)poll(&p, 1, 100);
                continue;
            }
            return -1;
        }
        done += (size_t)w;
    }
    return (int32_t)n;
}

/* ---------------------------------------------------------------- pty */

static int32_t pty_read(void *ctx, uint8_t *buf, size_t max)
{
    ss_posix_link_t *l = ctx;
    const ssize_t r = read(l->master_fd, buf, max);
    if (r < 0) {
        return (errno == EAGAIN || errno == EINTR || errno == EIO) ? 0 : -1;
    }
    return (int32_t)r;
}

static int32_t pty_write(void *ctx, const uint8_t *buf, size_t n)
{
    ss_posix_link_t *l = ctx;
    return write_all(l->master_fd, buf, n, 0);
}

int ss_posix_pty_open(ss_posix_link_t *l, char *path, size_t cap)
{
    memset(l, 0, sizeof *l);
    l->listen_fd = l->client_fd = -1;
    l->master_fd = posix_openpt(O_RDWR | O_NOCTTY);
    if (l->master_fd < 0 || grantpt(l->master_fd) != 0 || unlockpt(l->master_fd) != 0) {
        return -1;
    }
    const char *name = ptsname(l->master_fd);
    if (name == NULL || strlen(name) + 1u > cap) {
        return -1;
    }
    memcpy(path, name, strlen(name) + 1u); /* length checked above */
    l->slave_fd = open(name, O_RDWR | O_NOCTTY);
    if (l->slave_fd < 0) {
        return -1;
    }
    struct termios t;
    if (tcgetattr(l->slave_fd, &t) == 0) {
        cfmakeraw(&t); /* bytes as they are: no echo, no CR/LF translation */
        (void)tcsetattr(l->slave_fd, TCSANOW, &t);
    }
    (void)fcntl(l->master_fd, F_SETFL, fcntl(l->master_fd, F_GETFL) | O_NONBLOCK);
    l->kind = 0;
    l->link.ctx = l;
    l->link.read = pty_read;
    l->link.write = pty_write;
    l->link.time_ns = posix_time_ns;
    return 0;
}

/* ---------------------------------------------------------------- tcp */

/* The application's words to a client that comes while another is connected (this port knows no
 * frame layout), then the door. */
static void refuse_second_client(const ss_posix_link_t *l, int fd)
{
    if (l->refusal_len > 0u) {
        (void)write_all(fd, l->refusal, l->refusal_len, 1);
    }
    close(fd);
}

/* Is the current client's connection closed (it may have gone without our noticing yet)? */
static int client_closed(const ss_posix_link_t *l)
{
    uint8_t b;
    const ssize_t r = recv(l->client_fd, &b, 1, MSG_PEEK | MSG_DONTWAIT);
    return r == 0 || (r < 0 && errno != EAGAIN && errno != EINTR);
}

static void accept_pending(ss_posix_link_t *l)
{
    for (;;) {
        const int fd = accept(l->listen_fd, NULL, NULL);
        if (fd < 0) {
            return;
        }
        if (l->client_fd >= 0 && client_closed(l)) {
            close(l->client_fd); /* the old session is over: tell the node on this read */
            l->client_fd = -1;
            l->session_over = 1;
        }
        if (l->client_fd >= 0) {
            refuse_second_client(l, fd);
            continue;
        }
        const int one = 1;
        (void)setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one); /* no Nagle delay on replies */
        (void)fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
        l->client_fd = fd;
    }
}

static int32_t tcp_read(void *ctx, uint8_t *buf, size_t max)
{
    ss_posix_link_t *l = ctx;
    accept_pending(l);
    if (l->session_over) {
        l->session_over = 0;
        return -1;
    }
    if (l->client_fd < 0) {
        return 0;
    }
    const ssize_t r = recv(l->client_fd, buf, max, 0);
    if (r > 0) {
        return (int32_t)r;
    }
    if (r < 0 && (errno == EAGAIN || errno == EINTR)) {
        return 0;
    }
    close(l->client_fd); /* orderly close or error: the session is over */
    l->client_fd = -1;
    return -1;
}

static int32_t tcp_write(void *ctx, const uint8_t *buf, size_t n)
{
    ss_posix_link_t *l = ctx;
    if (l->client_fd < 0) {
        return -1;
    }
    return write_all(l->client_fd, buf, n, 1);
}

int ss_posix_tcp_listen(ss_posix_link_t *l, uint16_t port, const uint8_t *refusal, size_t refusal_len)
{
    memset(l, 0, sizeof *l);
    l->master_fd = l->slave_fd = l->client_fd = -1;
    l->refusal = refusal;
    l->refusal_len = refusal != 0 ? refusal_len : 0u;
    l->listen_fd = socket(AF_INET, SOCK_STREAM, 0);
    if (l->listen_fd < 0) {
        return -1;
    }
    const int one = 1;
    (void)setsockopt(l->listen_fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK); /* loopback only */
    socklen_t alen = sizeof a;
    if (bind(l->listen_fd, (struct sockaddr *)&a, sizeof a) != 0 || listen(l->listen_fd, 4) != 0 ||
        getsockname(l->listen_fd, (struct sockaddr *)&a, &alen) != 0) {
        return -1;
    }
    (void)fcntl(l->listen_fd, F_SETFL, fcntl(l->listen_fd, F_GETFL) | O_NONBLOCK);
    l->port = ntohs(a.sin_port);
    l->kind = 1;
    l->link.ctx = l;
    l->link.read = tcp_read;
    l->link.write = tcp_write;
    l->link.time_ns = posix_time_ns;
    return 0;
}

void ss_posix_wait(ss_posix_link_t *l, int timeout_ms)
{
    struct pollfd p[2];
    nfds_t n = 0;
    if (l->kind == 0) {
        p[n++] = (struct pollfd){l->master_fd, POLLIN, 0};
    } else {
        p[n++] = (struct pollfd){l->listen_fd, POLLIN, 0};
        if (l->client_fd >= 0) {
            p[n++] = (struct pollfd){l->client_fd, POLLIN, 0};
        }
    }
    (void)poll(p, n, timeout_ms);
}

void ss_posix_close(ss_posix_link_t *l)
{
    const int fds[4] = {l->master_fd, l->slave_fd, l->listen_fd, l->client_fd};
    for (int i = 0; i < 4; ++i) {
        if (fds[i] >= 0) {
            close(fds[i]);
        }
    }
}
