/*
 * profile.h - time profiles of references and load for SIL scenarios.
 *
 * Text form: comma-separated points "t:value", t in seconds, strictly
 * increasing, t >= 0. A point is a step: the value holds from t until the
 * next point. A value ending in '~' is reached by a linear ramp from the
 * previous point instead ("0:0, 0.1:0, 0.3:500~" holds 0 until 0.1 s,
 * then ramps to 500 at 0.3 s). Before the first point the profile is 0
 * (a ramp on the first point starts from 0 at t = 0). A bare number is a
 * constant from t = 0. An empty text is the constant 0.
 */
#ifndef PROFILE_H
#define PROFILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define PROFILE_MAX_POINTS 32

typedef struct {
    double t_s;
    double value;
    bool ramp;          /* reached linearly from the previous point */
} profile_point_t;

typedef struct {
    uint32_t n;
    profile_point_t pt[PROFILE_MAX_POINTS];
} profile_t;

/* Append the points of text to *p (so continuation lines extend a profile).
 * Returns 0, or -1 with a message in err[errlen] (then *p is unchanged). */
int profile_parse_append(profile_t *p, const char *text, char *err, size_t errlen);

/* Value of *p at time t_s. */
double profile_eval(const profile_t *p, double t_s);

/* The constant profile v from t = 0. */
void profile_const(profile_t *p, double v);

/* A reader of one profile for times that mostly grow (a run's periods):
 * it keeps the segment of the last time asked and, on a step's segment,
 * the value held there, so a period costs two compares. */
typedef struct {
    const profile_t *p;
    uint32_t k;             /* segment: the first point after the last time asked (n: past the last) */
    double hold_from_s;     /* the value hold_value holds on [hold_from_s, hold_until_s) (empty on a ramp) */
    double hold_until_s;
    double hold_value;
} profile_cursor_t;

/* A cursor on *p (kept, not copied: *p must outlive it), at no segment yet. */
void profile_cursor_init(profile_cursor_t *c, const profile_t *p);

/* profile_eval(c->p, t_s), found from the cursor's segment (any t_s; slower backwards). */
double profile_cursor_seek(profile_cursor_t *c, double t_s);

/* The value of the last eval holds up to this time (exclusive) for later
 * times; -inf after one on a ramp. */
static inline double profile_cursor_until_s(const profile_cursor_t *c)
{
    return c->hold_until_s;
}

/* profile_eval(c->p, t_s), bit for bit. */
static inline double profile_cursor_eval(profile_cursor_t *c, double t_s)
{
    if ((t_s >= c->hold_from_s) && (t_s < c->hold_until_s)) {
        return c->hold_value;
    }
    return profile_cursor_seek(c, t_s);
}

#endif /* PROFILE_H */
