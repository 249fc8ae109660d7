/* link_sil.c - the link's byte pipe in the SIL (TCP or pty), paced at the baud rate; see link_sil.h. */
#define _DEFAULT_SOURCE   /* cfmakeraw */
#define _XOPEN_SOURCE 600 /* posix_openpt, grantpt, ptsname */
#include "link_sil.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "hal.h"
#include "hal_sim.h"
#include "link.h"
#include "link_nv.h"
#include "mathx.h"

#define IN_MAX 4096                 /* bytes from the host waiting for the line */
#define BITS_PER_BYTE_8N1 10.0
#define BAUD_MIN 300L
#define BAUD_MAX 12000000L
#define REALTIME_CHECK_PERIODS 16u  /* wall clock read every this many periods */
#define NS_PER_S 1e9
#define FIRMWARE_ID "drive_sil"
#define CLOSE_WAIT_MS 2000           /* pty: at most this long for the host to read the last reply */
#define CLOSE_POLL_NS 1000000L      /* 1 ms */
#define CLOSE_SETTLE_POLLS 20
#define LISTEN_BACKLOG 8            /* connections waiting for accept: a second client is told at once */
#define CLOSING_MAX 4               /* clients being closed at once (refused, dropped); more: closed at once */
#define CLOSING_LINGER_S 2.0        /* a closing client's bytes read and dropped this long at most (wall) */
#define HALF_CLOSE_DRAIN_S 2.0      /* a half-closed client gets the drive's bytes this long at most (wall) */
#define NOTICE_HELD_TEXT "the link is held by another client"
#define NOTICE_IDLE_TEXT "the link dropped this client: silent for [link] idle_timeout_s"

/* A client the link is closing: its notice sent and its sending side shut, what it still sends
 * is read and dropped until it closes or CLOSING_LINGER_S passed (no reset that could eat the notice). */
typedef struct {
    int fd;                         /* -1: free */
    double since_s;                 /* wall time it began closing */
} closing_t;

typedef struct {
    link_sil_opts_t o;
    const scenario_t *sc;           /* its [link] keys, and the app's configuration for new parameters */
    drive_params_t params;          /* the drive's parameter set: the link's parameters (link_params.h) */
    link_nv_t store;                /* the parameter store (--nv: link_nv.h), on the simulated board's sector */
    int listen_fd;
    int fd;                         /* the client or the pty master; -1: none */
    int slave_fd;                   /* pty: kept open so the master never reads EOF */
    double last_rx_s;               /* wall time of the client's last byte (or its connection) */
    bool rx_eof;                    /* the client shut its sending side: its replies go out, then it is closed */
    double eof_s;                   /* wall time of that */
    closing_t closing[CLOSING_MAX];
    link_t link;
    cmd_t cmd;
    cmd_limits_t lim;
    app_t *app;
    unsigned char in[IN_MAX];
    size_t in_n, in_off;
    double bytes_per_period, rx_credit, tx_credit;
    double Ts_s;
    struct timespec t0;
    uint32_t k;
} link_sil_t;

static link_sil_t g;

/* Wall-clock seconds (monotonic). */
static double wall_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec / NS_PER_S;
}

int link_sil_arg(link_sil_opts_t *o, int argc, char **argv, int *i)
{
    const char *s = argv[*i];
    if (strcmp(s, "--link") != 0 && strcmp(s, "--baud") != 0 && strcmp(s, "--realtime") != 0) {
        return 0;
    }
    if (*i + 1 >= argc) {
        fprintf(stderr, "drive_sil: %s needs a value\n", s);
        return -1;
    }
    const char *v = argv[++*i];
    char *end = NULL;
    if (strcmp(s, "--link") == 0) {
        o->on = 1;
        if (strcmp(v, "pty") == 0) {
            o->pty = 1;
            return 1;
        }
        if (strncmp(v, "tcp:", 4) == 0) {
            long port = strtol(v + 4, &end, 10);
            if (end != v + 4 && *end == '\0' && port >= 0 && port <= 65535) {
                o->port = (int)port;
                return 1;
            }
        }
        fprintf(stderr, "drive_sil: --link %s: expected tcp:PORT (0..65535) or pty\n", v);
        return -1;
    }
    if (strcmp(s, "--baud") == 0) {
        long b = strtol(v, &end, 10);
        if (end != v && *end == '\0' && b >= BAUD_MIN && b <= BAUD_MAX) {
            o->baud = b;
            return 1;
        }
        fprintf(stderr, "drive_sil: --baud %s: expected a whole number in %ld..%ld\n", v, BAUD_MIN, BAUD_MAX);
        return -1;
    }
    double f = strtod(v, &end);
    if (end != v && *end == '\0' && isfinite(f) && f >= 0.0) {
        o->realtime = f;
        return 1;
    }
    fprintf(stderr, "drive_sil: --realtime %s: expected a factor >= 0 (1 real time, 0 unpaced)\n", v);
    return -1;
}

static int set_nonblock(int fd)
{
    int fl = fcntl(fd, F_GETFL, 0);
    return (fl < 0 || fcntl(fd, F_SETFL, fl | O_NONBLOCK) != 0) ? -1 : 0;
}

static int open_tcp(int port)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0) {
        perror("drive_sil: --link: socket");
        return -1;
    }
    int one = 1;
    (void)setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in a;
    memset(&a, 0, sizeof a);
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons((uint16_t)port);
    socklen_t len = sizeof a;
    if (bind(fd, (struct sockaddr *)&a, sizeof a) != 0 || listen(fd, LISTEN_BACKLOG) != 0 || set_nonblock(fd) != 0 ||
        getsockname(fd, (struct sockaddr *)&a, &len) != 0) {
        fprintf(stderr, "drive_sil: --link tcp:%d: cannot listen on 127.0.0.1:%d: %s\n", port, port, strerror(errno));
        close(fd);
        return -1;
    }
    g.listen_fd = fd;
    fprintf(stderr, "listening on 127.0.0.1:%d\n", (int)ntohs(a.sin_port));
    return 0;
}

static int open_pty(void)
{
    int m = posix_openpt(O_RDWR | O_NOCTTY);
    if (m < 0 || grantpt(m) != 0 || unlockpt(m) != 0 || set_nonblock(m) != 0) {
        perror("drive_sil: --link pty");
        if (m >= 0) {
            close(m);
        }
        return -1;
    }
    const char *path = ptsname(m);
    int s = (path != NULL) ? open(path, O_RDWR | O_NOCTTY) : -1;
    struct termios t;
    if (s < 0 || tcgetattr(s, &t) != 0) {
        perror("drive_sil: --link pty");
        close(m);
        return -1;
    }
    cfmakeraw(&t);
    (void)tcsetattr(s, TCSANOW, &t);
    g.fd = m;
    g.slave_fd = s;
    fprintf(stderr, "link on %s\n", path);
    return 0;
}

/* Bytes to the port, never a signal (MSG_NOSIGNAL: a closed peer is EPIPE, not SIGPIPE); a pty
 * takes write(). As send(2): the count, or -1 with errno. */
static ssize_t port_send(int fd, const void *b, size_t n)
{
    return g.o.pty ? write(fd, b, n) : send(fd, b, n, MSG_NOSIGNAL);
}

/* The client went away: what was on the wire is lost. */
static void disconnect(void)
{
    close(g.fd);
    g.fd = -1;
    g.in_n = 0;
    g.in_off = 0;
    g.rx_eof = false;
    link_drop(&g.link);
}

/* A LINK_NOTICE frame (link.h) to fd: the code, then the text. One try: the socket is fresh or
 * idle, the frame fits its buffer; a failure changes nothing (the client is closed either way). */
static void notice(int fd, uint16_t code, const char *text)
{
    link_frame_t f;
    uint16_t w[LINK_ENCODED_MAX];
    unsigned char b[LINK_ENCODED_MAX];
    f.type = LINK_NOTICE;
    f.seq = 0u;
    f.payload[0] = code;
    f.len = 1u;
    for (size_t k = 0; text[k] != '\0' && f.len < LINK_PAYLOAD_MAX; k++) {
        f.payload[f.len++] = (uint16_t)(unsigned char)text[k];
    }
    const uint16_t n = link_frame_encode(&f, w);
    for (uint16_t k = 0u; k < n; k++) {
        b[k] = (unsigned char)w[k];
    }
    (void)port_send(fd, b, n);
}

/* Close fd gently: the notice, its sending side shut, then into the closing list (the oldest
 * closed at once when the list is full). */
static void close_gently(int fd, uint16_t code, const char *text)
{
    notice(fd, code, text);
    (void)shutdown(fd, SHUT_WR);
    int slot = 0;
    for (int k = 0; k < CLOSING_MAX; k++) {
        if (g.closing[k].fd < 0) {
            slot = k;
            break;
        }
        if (g.closing[k].since_s < g.closing[slot].since_s) {
            slot = k;
        }
    }
    if (g.closing[slot].fd >= 0) {
        close(g.closing[slot].fd);
    }
    g.closing[slot].fd = fd;
    g.closing[slot].since_s = wall_s();
}

/* The closing clients: what they send read and dropped; closed at their end of file, an error,
 * or after CLOSING_LINGER_S. */
static void poll_closing(void)
{
    unsigned char scratch[IN_MAX];
    const double now = wall_s();
    for (int k = 0; k < CLOSING_MAX; k++) {
        closing_t *c = &g.closing[k];
        if (c->fd < 0) {
            continue;
        }
        ssize_t r;
        do {
            r = recv(c->fd, scratch, sizeof scratch, 0);
        } while (r > 0);
        const bool gone = (r == 0) || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR);
        if (gone || now - c->since_s > CLOSING_LINGER_S) {
            close(c->fd);
            c->fd = -1;
        }
    }
}

/* The command's limits from the app's configuration. */
static void limits_from(const app_cfg_t *c)
{
    g.lim.speed_max_rpm = c->prot.speed_max_rad_s / MATHX_RAD_S_PER_RPM_F;
    g.lim.te_max_Nm = c->ctrl.te_max_Nm;
    g.lim.u_max_V = c->ctrl.u_max_V;
}

/* Parameter k was written (the drive stopped): the app's configuration from the changed set, as
 * sil_run builds it, and the ISR's re-initialisation asked for. */
static void on_params(void *user, uint16_t k)
{
    (void)user;
    sil_app_cfg(g.sc, &g.params, &g.app->cfg);   /* between periods: the ISR is not running */
    limits_from(&g.app->cfg);
    app_request_reconfigure(g.app, (k == (uint16_t)LINK_PARAM_ENC_OFFSET) ? APP_RECONF_ENC_OFFSET : 0u);
}

static void on_start(void *user, app_t *app)
{
    (void)user;
    const app_cfg_t *c = &app->cfg;
    link_cfg_t lc;
    g.app = app;
    g.Ts_s = (double)c->ctrl.Ts_s;
    g.bytes_per_period = (double)g.o.baud / BITS_PER_BYTE_8N1 * g.Ts_s;
    limits_from(c);
    sil_drive_params(g.sc, &g.params);
    (void)drive_params_derive(&g.params); /* as the target: the link shows the values in use */
    cmd_init(&g.cmd);
    g.cmd.run = 1u;        /* sil_run starts the drive itself */
    g.cmd.run_taken = 1u;
    link_cfg_default(&lc);
    scenario_map(g.sc, SC_TO_LINK, &lc, g.Ts_s);   /* [link] host_timeout_s */
    lc.Ts_s = c->ctrl.Ts_s;
    lc.baud = (uint32_t)g.o.baud;
    lc.firmware_id = FIRMWARE_ID;
    lc.params.set = &g.params;
    lc.params.apply = on_params;
    if (g.o.nv) {
        const nv_dev_t dev = { HAL_SIM_NV_WORDS, hal_nv_read, hal_nv_write };
        link_nv_init(&g.store, &dev);
        g.store.status = link_nv_status_of((nv_status_t)g.o.nv_loaded);
        lc.params.store = &g.store;
    }
    link_init(&g.link, &lc, app, &g.cmd, &g.lim);
    clock_gettime(CLOCK_MONOTONIC, &g.t0);
    g.k = 0u;
}

static void on_isr_end(void *user)
{
    (void)user;
    link_isr(&g.link);
}

/* Fields the host wrote keep the host's value over the scenario's profile. */
static void on_refs(void *user, app_op_t *op)
{
    (void)user;
    const uint32_t w = g.link.written;
    const volatile app_op_t *cur = &g.app->op_req;
    if (w & (1ul << LV_SPEED_REF_RPM)) {
        op->ref.speed_ref_rad_s = cur->ref.speed_ref_rad_s;
    }
    if (w & (1ul << LV_TE_CMD_NM)) {
        op->ref.te_ref_Nm = cur->ref.te_ref_Nm;
    }
    if (w & (1ul << LV_UD_REF_V)) {
        op->ref.ud_ref_V = cur->ref.ud_ref_V;
    }
    if (w & (1ul << LV_UQ_REF_V)) {
        op->ref.uq_ref_V = cur->ref.uq_ref_V;
    }
    if (w & (1ul << LV_MODE)) {
        op->mode = cur->mode;
    }
    if (w & (1ul << LV_METHOD)) {
        op->method = cur->method;
    }
}

/* Every connection waiting: the first while none is served becomes the client, any other is
 * told the link is held and closed. */
static void accept_clients(void)
{
    if (g.listen_fd < 0) {
        return;
    }
    for (;;) {
        int c = accept(g.listen_fd, NULL, NULL);
        if (c < 0) {
            return;
        }
        int one = 1;
        (void)setsockopt(c, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        if (set_nonblock(c) != 0) {
            close(c);
            continue;
        }
        if (g.fd >= 0) {
            close_gently(c, LINK_NOTICE_HELD, NOTICE_HELD_TEXT);
            continue;
        }
        g.fd = c;
        g.rx_eof = false;
        g.last_rx_s = wall_s();
        link_drop(&g.link);    /* a new cable: nothing of the last client's */
    }
}

/* The client's end: silent longer than [link] idle_timeout_s (told, then closed); half-closed
 * and its replies sent, or HALF_CLOSE_DRAIN_S after (closed). */
static void client_timeouts(void)
{
    if (g.fd < 0 || g.o.pty) {
        return;
    }
    const double now = wall_s();
    if (g.rx_eof) {
        if ((link_tx_pending(&g.link) == 0u && g.in_off == g.in_n) || now - g.eof_s > HALF_CLOSE_DRAIN_S) {
            disconnect();
        }
        return;
    }
    if (g.sc->link.idle_timeout_s > 0.0 && now - g.last_rx_s > g.sc->link.idle_timeout_s) {
        fprintf(stderr, "drive_sil: link: the client was silent for %g s ([link] idle_timeout_s): dropped\n",
                g.sc->link.idle_timeout_s);
        close_gently(g.fd, LINK_NOTICE_IDLE, NOTICE_IDLE_TEXT);
        g.fd = -1;
        g.in_n = 0;
        g.in_off = 0;
        link_drop(&g.link);
    }
}

/* Host -> drive: read what the host sent, deliver it at the line's rate. A closed or reset
 * connection drops the client; a half-closed one (end of file) still gets its replies. */
static void receive(void)
{
    if (g.fd >= 0 && !g.rx_eof && g.in_off == g.in_n) {
        g.in_off = 0;
        g.in_n = 0;
        ssize_t r = read(g.fd, g.in, sizeof g.in);
        if (r > 0) {
            g.in_n = (size_t)r;
            g.last_rx_s = wall_s();
        } else if (!g.o.pty && r == 0) {
            g.rx_eof = true;
            g.eof_s = wall_s();
        } else if (!g.o.pty && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
            disconnect();
            return;
        }
    }
    g.rx_credit += g.bytes_per_period;
    while (g.rx_credit >= 1.0 && g.in_off < g.in_n) {
        (void)link_rx_put(&g.link, g.in[g.in_off++]);   /* a full queue counts an overrun, as the SCI */
        g.rx_credit -= 1.0;
    }
    if (g.in_off == g.in_n && g.rx_credit > 1.0) {
        g.rx_credit = 1.0;   /* an idle line banks no bytes */
    }
}

/* Drive -> host: at the line's rate; with no client the bytes are lost. */
static void transmit(void)
{
    unsigned char out[IN_MAX];
    size_t n = 0;
    uint16_t b;
    g.tx_credit += g.bytes_per_period;
    while (g.tx_credit >= 1.0 && n < sizeof out && link_tx_get(&g.link, &b)) {
        out[n++] = (unsigned char)b;
        g.tx_credit -= 1.0;
    }
    if (link_tx_pending(&g.link) == 0u && g.tx_credit > 1.0) {
        g.tx_credit = 1.0;
    }
    size_t off = 0;
    while (g.fd >= 0 && off < n) {
        ssize_t w = port_send(g.fd, out + off, n - off);
        if (w > 0) {
            off += (size_t)w;
        } else if (w < 0 && errno == EINTR) {
            continue;
        } else if (w < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            break;           /* a host that does not read loses the bytes, as a UART's would */
        } else {
            if (!g.o.pty) {
                disconnect();    /* EPIPE, ECONNRESET: the client went away */
            }
            break;
        }
    }
}

static void pace(void)
{
    g.k++;
    if (g.o.realtime <= 0.0 || (g.k % REALTIME_CHECK_PERIODS) != 0u) {
        return;
    }
    const double due_s = (double)g.k * g.Ts_s / g.o.realtime;
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    const double el_s = (double)(now.tv_sec - g.t0.tv_sec) + (double)(now.tv_nsec - g.t0.tv_nsec) / NS_PER_S;
    if (due_s > el_s) {
        const double d = due_s - el_s;
        struct timespec ts = { (time_t)d, (long)((d - floor(d)) * NS_PER_S) };
        nanosleep(&ts, NULL);
    }
}

/* The save the link asked for, between periods (the ISR not running, as the board holds it off):
 * the link's parameters as the sector's newest block, which nv_file.h writes to FILE. */
static void save_asked(void)
{
    if (!link_nv_due(&g.store)) {
        return;
    }
    const nv_status_t st = link_nv_save(&g.store, &g.params, app_stopped(g.app));
    if (st == NV_OK) {
        fprintf(stderr, "drive_sil: link: save: the link's %u parameters saved (--nv FILE)\n",
                (unsigned)LINK_NV_PARAMS.count);
    } else {
        fprintf(stderr, "drive_sil: link: save: nothing saved: %s\n",
                app_stopped(g.app) ? "the sector refused the block" : "the drive was started first");
    }
}

static int on_period_end(void *user)
{
    (void)user;
    accept_clients();
    receive();
    link_poll(&g.link);
    save_asked();
    transmit();
    client_timeouts();
    poll_closing();
    pace();
    return (g.link.quit && link_tx_pending(&g.link) == 0u) ? 1 : 0;
}

int link_sil_open(const link_sil_opts_t *o, const scenario_t *sc, sil_hooks_t *hooks)
{
    memset(&g, 0, sizeof g);
    g.o = *o;
    g.sc = sc;
    if (g.o.baud == 0) {
        g.o.baud = LINK_SIL_BAUD_DEFAULT;
    }
    g.listen_fd = -1;
    g.fd = -1;
    g.slave_fd = -1;
    for (int k = 0; k < CLOSING_MAX; k++) {
        g.closing[k].fd = -1;
    }
    /* a peer that closes while bytes are on their way must never end the run: every send is
     * MSG_NOSIGNAL and its error handled, and SIGPIPE is ignored besides (a pty, a library) */
    (void)signal(SIGPIPE, SIG_IGN);
    if ((o->pty ? open_pty() : open_tcp(o->port)) != 0) {
        return -1;
    }
    hooks->start = on_start;
    hooks->isr_end = on_isr_end;
    hooks->refs = on_refs;
    hooks->period_end = on_period_end;
    hooks->user = NULL;
    return 0;
}

void link_sil_close(void)
{
    /* pty: closing the master drops what the host has not read yet; wait until it has read
     * quit's reply (the tty layer moves written bytes to the reader's side a little later:
     * a few polls first) */
    int pending = 0;
    for (int k = 0; g.o.pty && g.slave_fd >= 0 && k < CLOSE_WAIT_MS; k++) {
        if (ioctl(g.slave_fd, FIONREAD, &pending) != 0 || (pending == 0 && k >= CLOSE_SETTLE_POLLS)) {
            break;
        }
        const struct timespec ts = { 0, CLOSE_POLL_NS };
        nanosleep(&ts, NULL);
    }
    if (g.fd >= 0) {
        /* the last reply (quit's) is on its way: let the peer read it before the close */
        shutdown(g.fd, SHUT_WR);
        close(g.fd);
    }
    if (g.slave_fd >= 0) {
        close(g.slave_fd);
    }
    if (g.listen_fd >= 0) {
        close(g.listen_fd);
    }
    for (int k = 0; k < CLOSING_MAX; k++) {
        if (g.closing[k].fd >= 0) {
            close(g.closing[k].fd);
            g.closing[k].fd = -1;
        }
    }
    g.fd = g.slave_fd = g.listen_fd = -1;
}
