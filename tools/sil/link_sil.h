/*
 * link_sil.h - drive_sil's side of the link (firmware/link/link_protocol.md):
 *   --link tcp:PORT   listen on 127.0.0.1:PORT (0: any free port) before the
 *                     first period; prints "listening on 127.0.0.1:PORT" on
 *                     stderr. One client at a time; when it disconnects the
 *                     bytes not yet delivered are dropped (a pulled cable)
 *                     and the next connection is accepted. Another client
 *                     meanwhile gets a LINK_NOTICE "held" frame at once and
 *                     is closed; a client silent for [link] idle_timeout_s
 *                     (wall time) gets an "idle" notice and is closed; one
 *                     that shuts its sending side gets its replies, then is
 *                     closed. No client can end the run: SIGPIPE is ignored
 *                     and every send's error handled.
 *   --link pty        a pseudo-terminal; prints "link on /dev/pts/N" on stderr
 *   --baud B          the line's rate in simulated time (default 115200, 8N1:
 *                     B/10 bytes per second each way), so overruns behave
 *                     as on the board
 *   --realtime F      pace the simulation to wall time (1 real time, 2 twice
 *                     as fast; 0, the default, unpaced)
 * The firmware's link (firmware/link/link.h) runs as on the board: link_isr()
 * after every ISR call, link_poll() in the background after each period.
 * A value written over the link overrides the scenario's profile for that
 * variable from then on. ACTION quit stops the drive and ends the run once
 * its reply is sent (the CSV is kept, complete). With drive_sil --nv FILE
 * the drive has its parameter store (firmware/link/link_nv.h): ACTION save
 * (drivetool save, the drive stopped) writes the link's parameters as the
 * sector's newest block at the end of that period (nv_file.h then writes
 * FILE), said on stderr; without --nv there is no store (nv_status NONE,
 * save an unknown action).
 */
#ifndef LINK_SIL_H
#define LINK_SIL_H

#include "sil.h"

#define LINK_SIL_BAUD_DEFAULT 115200L

typedef struct {
    int on;                 /* --link given */
    int pty;                /* 1: --link pty, 0: tcp */
    int port;
    long baud;
    double realtime;
    int nv;                 /* --nv FILE given: the drive has its parameter store */
    int nv_loaded;          /* ... and its start-up load's nv_status_t (nv_file_apply's, drive_sil) */
} link_sil_opts_t;

/* Parse argv[*i] if it is one of the options above (advancing *i past its value): 1 taken,
 * 0 not a link option, -1 bad (message printed). */
int link_sil_arg(link_sil_opts_t *o, int argc, char **argv, int *i);

/* Open the port (listening socket or pty) and announce it on stderr; fills *hooks for
 * sil_ctl_t.hooks. The scenario's [link] keys configure it and the firmware's link (kept: *sc
 * must outlive the run). 0, or -1 with a message. */
int link_sil_open(const link_sil_opts_t *o, const scenario_t *sc, sil_hooks_t *hooks);

/* Close the port. */
void link_sil_close(void);

#endif /* LINK_SIL_H */
