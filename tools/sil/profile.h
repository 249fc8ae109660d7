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

#endif /* PROFILE_H */
