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
        s = skip_ws(s);
        if (parse_num(&s, &pt.t_s) != 0) {
            snprintf(err, errlen, "expected a time in seconds at \"%s\"", s);
            return -1;
        }
        s = skip_ws(s);
        if (*s != TIME_SEP) {
            snprintf(err, errlen, "expected '%c' after the time at \"%s\"", TIME_SEP, s);
            return -1;
        }
        s = skip_ws(s + 1);
        if (parse_num(&s, &pt.value) != 0) {
            snprintf(err, errlen, "expected a value at \"%s\"", s);
            return -1;
        }
        s = skip_ws(s);
        if (*s == RAMP_MARK) {
            pt.ramp = true;
            s = skip_ws(s + 1);
        }
        if (pt.t_s < 0.0) {
            snprintf(err, errlen, "negative time %g", pt.t_s);
            return -1;
        }
        if (q.n > 0u && !(pt.t_s > q.pt[q.n - 1u].t_s)) {
            snprintf(err, errlen, "times must increase (%g after %g)", pt.t_s, q.pt[q.n - 1u].t_s);
            return -1;
        }
        if (q.n >= PROFILE_MAX_POINTS) {
            snprintf(err, errlen, "more than %d points", PROFILE_MAX_POINTS);
            return -1;
        }
        q.pt[q.n++] = pt;
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

double profile_eval(const profile_t *p, double t_s)
{
    double t_prev = 0.0;
    double v_prev = 0.0;
    for (uint32_t k = 0; k < p->n; k++) {
        const profile_point_t *pt = &p->pt[k];
        if (t_s < pt->t_s) {
            if (pt->ramp) {
                return v_prev + (pt->value - v_prev) * (t_s - t_prev) / (pt->t_s - t_prev);
            }
            return v_prev;
        }
        t_prev = pt->t_s;
        v_prev = pt->value;
    }
    return v_prev;
}

void profile_const(profile_t *p, double v)
{
    p->n = 1u;
    p->pt[0].t_s = 0.0;
    p->pt[0].value = v;
    p->pt[0].ramp = false;
}
