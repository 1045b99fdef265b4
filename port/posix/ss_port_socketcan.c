#include "ss_port_socketcan.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/can.h>
#include <net/if.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

static int32_t sc_read(void *ctx, ss_can_frame_t *f)
{
    ss_socketcan_t *s = ctx;
    struct can_frame k;
    const ssize_t r = read(s->fd, &k, sizeof k);
    if (r < 0) {
        return (errno == EAGAIN || errno == EINTR) ? 0 : -1;
    }
    if (r != (ssize_t)sizeof k || k.can_dlc > 8u) {
        return 0;
    }
    f->ext = (k.can_id & CAN_EFF_FLAG) ? 1u : 0u;
    f->rtr = (k.can_id & CAN_RTR_FLAG) ? 1u : 0u;
    f->id = k.can_id & (f->ext ? CAN_EFF_MASK : CAN_SFF_MASK);
    f->dlc = k.can_dlc;
    memcpy(f->data, k.data, 8);
    return 1;
}

static int32_t sc_write(void *ctx, const ss_can_frame_t *f)
{
    ss_socketcan_t *s = ctx;
    struct can_frame k;
    memset(&k, 0, sizeof k);
    k.can_id = f->id | (f->ext ? CAN_EFF_FLAG : 0u) | (f->rtr ? CAN_RTR_FLAG : 0u);
    k.can_dlc = f->dlc;
    memcpy(k.data, f->data, 8);
    return (write(s->fd, &k, sizeof k) == (ssize_t)sizeof k) ? 1 : -1;
}

static uint64_t sc_time(void *ctx)
{
    (void)ctx;
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

int ss_socketcan_open(ss_socketcan_t *s, const char *ifname)
{
    s->fd = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (s->fd < 0) {
        return -1;
    }
    struct ifreq ifr;
    memset(&ifr, 0, sizeof ifr);
    if (strlen(ifname) >= sizeof ifr.ifr_name) {
        errno = ENAMETOOLONG;
        return -1;
    }
    memcpy(ifr.ifr_name, ifname, strlen(ifname) + 1u);
    if (ioctl(s->fd, SIOCGIFINDEX, &ifr) != 0) {
        close(s->fd);
        return -1;
    }
    struct sockaddr_can a;
    memset(&a, 0, sizeof a);
    a.can_family = AF_CAN;
    a.can_ifindex = ifr.ifr_ifindex;
    if (bind(s->fd, (struct sockaddr *)&a, sizeof a) != 0) {
        close(s->fd);
        return -1;
    }
    (void)fcntl(s->fd, F_SETFL, fcntl(s->fd, F_GETFL) | O_NONBLOCK);
    s->can.ctx = s;
    s->can.read = sc_read;
    s->can.write = sc_write;
    s->can.time_ns = sc_time;
    return 0;
}
