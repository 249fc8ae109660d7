/* profile.c - step/ramp time profiles; see profile.h for the syntax. */
#include "profile.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define RAMP_MARK '~'
#define TIME_SEP ':'
#define POINT_SEP ','

static const char *skip_ws(const char *s)
{
    while (isspace((unsigned char)*s)) {
        s++;
    }
    return s;
}

/* A finite number at *s; advances *s past it. */
static int parse_num(const char **s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(*s, &end);
    if (end == *s || errno == ERANGE || !isfinite(v)) {
        return -1;
    }
    *out = v;
    *s = end;
    return 0;
}

/* One point "t:value" or "t:value~" at *s (blanks allowed around its
 * parts) into *pt, *s past it: 0, or -1 with the problem in err. */
static int parse_point(const char **s, profile_point_t *pt, char *err, size_t errlen)
{
    *s = skip_ws(*s);
    if (parse_num(s, &pt->t_s) != 0) {
        snprintf(err, errlen, "expected a time in seconds at \"%s\"", *s);
        return -1;
    }
    *s = skip_ws(*s);
    if (**s == '\0') {
        snprintf(err, errlen, "\"%g\" is a time without its value (a point is t%cvalue)", pt->t_s, TIME_SEP);
        return -1;
    }
    if (**s != TIME_SEP) {
        snprintf(err, errlen, "expected '%c' after the time at \"%s\"", TIME_SEP, *s);
        return -1;
    }
    *s = skip_ws(*s + 1);
    if (parse_num(s, &pt->value) != 0) {
        snprintf(err, errlen, "expected a value at \"%s\"", *s);
        return -1;
    }
    *s = skip_ws(*s);
    if (**s == RAMP_MARK) {
        pt->ramp = true;
        *s = skip_ws(*s + 1);
    }
    return 0;
}

/* pt appended to *q: its time not negative, after the last point's, and
 * room left. 0, or -1 with the problem in err. */
static int append_point(profile_t *q, profile_point_t pt, char *err, size_t errlen)
{
    if (pt.t_s < 0.0) {
        snprintf(err, errlen, "negative time %g", pt.t_s);
        return -1;
    }
    if (q->n > 0u && !(pt.t_s > q->pt[q->n - 1u].t_s)) {
        snprintf(err, errlen, "times must increase (%g after %g)", pt.t_s, q->pt[q->n - 1u].t_s);
        return -1;
    }
    if (q->n >= PROFILE_MAX_POINTS) {
        snprintf(err, errlen, "more than %d points", PROFILE_MAX_POINTS);
        return -1;
    }
    q->pt[q->n++] = pt;
    return 0;
}

int profile_parse_append(profile_t *p, const char *text, char *err, size_t errlen)
{
    profile_t q = *p;
    const char *s = skip_ws(text);
    if (*s == '\0') {
        return 0;
    }
    /* A bare number: constant from 0. */
    {
        const char *t = s;
        double v;
        if (q.n == 0u && parse_num(&t, &v) == 0 && *skip_ws(t) == '\0') {
            profile_const(p, v);
            return 0;
        }
    }
    for (;;) {
        profile_point_t pt = { 0.0, 0.0, false };
        if (parse_point(&s, &pt, err, errlen) != 0 || append_point(&q, pt, err, errlen) != 0) {
            return -1;
        }
        if (*s == '\0') {
            break;
        }
        if (*s != POINT_SEP) {
            snprintf(err, errlen, "expected '%c' or the end at \"%s\"", POINT_SEP, s);
            return -1;
        }
        s++;
    }
    *p = q;
    return 0;
}

/* The value at t_s on segment k of *p: before point k, or past the last for k = n. */
static double segment_value(const profile_t *p, uint32_t k, double t_s)
{
    const double t_prev = (k > 0u) ? p->pt[k - 1u].t_s : 0.0;
    const double v_prev = (k > 0u) ? p->pt[k - 1u].value : 0.0;
    if ((k < p->n) && p->pt[k].ramp) {
        return v_prev + (p->pt[k].value - v_prev) * (t_s - t_prev) / (p->pt[k].t_s - t_prev);
    }
    return v_prev;
}

/* The segment of t_s: the first point with t_s before it, searched from
 * point k on (the points before k are not after t_s); n if none. */
static uint32_t segment_from(const profile_t *p, uint32_t k, double t_s)
{
    while ((k < p->n) && !(t_s < p->pt[k].t_s)) {
        k++;
    }
    return k;
}

double profile_eval(const profile_t *p, double t_s)
{
    return segment_value(p, segment_from(p, 0u, t_s), t_s);
}

void profile_cursor_init(profile_cursor_t *c, const profile_t *p)
{
    c->p = p;
    c->k = 0u;
    c->hold_from_s = INFINITY;   /* empty: the first eval seeks */
    c->hold_until_s = -INFINITY;
    c->hold_value = 0.0;
}

double profile_cursor_seek(profile_cursor_t *c, double t_s)
{
    const profile_t *p = c->p;
    uint32_t k = c->k;

    if ((k > 0u) && !(t_s >= p->pt[k - 1u].t_s)) {
        k = 0u;   /* back before the segment (or NaN): from the start */
    }
    k = segment_from(p, k, t_s);
    c->k = k;
    const double v = segment_value(p, k, t_s);
    if ((k < p->n) && p->pt[k].ramp) {
        c->hold_from_s = INFINITY;
        c->hold_until_s = -INFINITY;
    } else {
        c->hold_from_s = (k > 0u) ? p->pt[k - 1u].t_s : -INFINITY;
        c->hold_until_s = (k < p->n) ? p->pt[k].t_s : INFINITY;
        c->hold_value = v;
    }
    return v;
}

void profile_const(profile_t *p, double v)
{
    p->n = 1u;
    p->pt[0].t_s = 0.0;
    p->pt[0].value = v;
    p->pt[0].ramp = false;
}
