/*
 * encoder.h - incremental encoder: electrical angle and filtered speed.
 *
 * The HAL delivers the quadrature count in 0..cpr-1 (cpr = 4 * lines).
 * The angle comes straight from the count: the centre of the count's
 * interval, which is unbiased (the count is the floor of the position). The speed
 * from a position-tracking PLL on the count (ODrive style, kp = 2*bw,
 * ki = bw^2, critically damped), because at low speed the count moves by
 * less than one step per period and a plain difference is mostly
 * quantisation noise.
 */
#ifndef ENCODER_H
#define ENCODER_H

#include <stdbool.h>
#include <stdint.h>

/* PLL bandwidth times period above which init refuses the cfg: the discrete
 * loop is stable up to bw*Ts = 0.83 and well damped only well below it. */
#define ENCODER_PLL_BW_TS_MAX 0.5f
/* Quadrature counts per encoder line (both edges of both channels). */
#define ENCODER_COUNTS_PER_LINE 4u
/* Largest cpr whose counts are all exact in a float (2^24). */
#define ENCODER_CPR_MAX 16777216u
/* Proportional PLL gain per bandwidth: kp = 2*bw (critical damping). */
#define ENCODER_KP_PER_BW 2.0f

/* How long the speed estimate lags a constant acceleration [s] at the
 * PLL bandwidth bw_rad_s [rad/s]: the count's error settles at a/ki, the
 * integrator (the speed) trails the speed by kp a/ki: a lag kp/ki = 2/bw.
 * Any context. */
static inline float encoder_ramp_lag_s(float bw_rad_s)
{
    return ENCODER_KP_PER_BW / bw_rad_s;
}

typedef struct {
    uint32_t counts_per_rev; /* quadrature counts per mechanical turn (4 * lines) */
    uint16_t pole_pairs;
    float offset_el_rad;   /* electrical angle at count 0 [rad] */
    float Ts_s;              /* sampling period [s] */
    float pll_bw_rad_s;      /* speed PLL bandwidth [rad/s] */
} encoder_cfg_t;

typedef struct {
    encoder_cfg_t cfg;
    bool valid;
    bool seeded;          /* false until the first count after reset */
    float cpr;            /* counts_per_rev as float [counts] */
    float rad_per_count;  /* 2*pi / cpr [rad] */
    float kp_Ts;          /* 2*bw*Ts [1] */
    float ki_Ts;          /* bw^2*Ts [1/s] */
    float vel_max;        /* half a turn per period [counts/s]: beyond it counts alias */
    float offset_el_rad;  /* electrical offset in use, in [0, 2*pi) */
    float pole_pairs_f;   /* cfg.pole_pairs as float (exact): no conversion per step */
    float centre_el;      /* a count's centre in electrical counts, 0.5 pole_pairs (exact) */
    float pos;            /* PLL position [counts], in [0, cpr) */
    float vel;            /* PLL speed [counts/s] */
    float theta_e_rad;    /* output: electrical angle [rad], in [0, 2*pi) */
    float omega_m_rad_s;  /* output: mechanical speed [rad/s] */
    float omega_e_rad_s;  /* output: electrical speed [rad/s] */
} encoder_t;

/*
 * Copies cfg and resets. Needs 0 < counts_per_rev <= ENCODER_CPR_MAX,
 * counts_per_rev * pole_pairs < 2^32, pole_pairs >= 1, finite offset,
 * Ts_s > 0 and 0 < pll_bw_rad_s * Ts_s <= ENCODER_PLL_BW_TS_MAX. Returns
 * false otherwise; encoder_step() then outputs 0 angle and 0 speed.
 * Background.
 */
bool encoder_init(encoder_t *enc, const encoder_cfg_t *cfg);

/* Forgets the speed; the next count seeds the PLL, so no speed spike.
 * Outputs read 0 until then. Background or ISR context. */
void encoder_reset(encoder_t *enc);

/* One period with the count from the HAL (reduced modulo cpr); updates
 * theta_e_rad, omega_m_rad_s, omega_e_rad_s. ISR context. */
void encoder_step(encoder_t *enc, uint32_t count);

/* Sets the electrical angle at count 0 [rad] (non-finite is ignored). Background. */
void encoder_set_offset(encoder_t *enc, float offset_el_rad);

/* Rotor alignment: sets the offset so that count reads as electrical angle 0
 * (the d axis was locked on phase a). Background, or ISR in ALIGN (from
 * flash). */
void encoder_align(encoder_t *enc, uint32_t count);

#endif /* ENCODER_H */
