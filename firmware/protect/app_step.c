/* app_step.c - helpers shared by the start-up steps; see app_step.h. */
#include "app_step.h"

/* Longest time converted to periods: keeps the float-to-integer cast defined. */
#define PERIODS_MAX 1.0e9f

FLASHFUNC uint32_t app_periods_of(float t_s, float Ts_s)
{
    float n = t_s / Ts_s;
    if (!(n > 0.0f)) {
        return 0u;
    }
    if (!(n < PERIODS_MAX)) {
        n = PERIODS_MAX;
    }
    return (uint32_t)(n + 0.5f);
}
