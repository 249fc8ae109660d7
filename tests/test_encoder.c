/* Unit tests for control/encoder.c: angle hand values, offset and alignment,
 * PLL speed convergence (hand-derived settling), wrap-around at both ends
 * in both directions, reset behaviour, invalid configuration. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <float.h>

#include "encoder.h"

#define PI_D 3.141592653589793
#define TOL 1e-5

/* 2500 lines -> 10000 counts, p = 3, 10 kHz, PLL 200 rad/s. */
#define CPR 10000u
#define TS 1.0e-4
#define BW 200.0
/* The angle is the centre of the count's interval: half a mechanical count,
 * p/2 = 1.5 electrical counts, after the interval's start [rad]. */
#define CENTRE_EL (1.5 * 2.0 * PI_D / CPR)

static encoder_cfg_t cfg_default(float offset_rad)
{
    encoder_cfg_t c = { CPR, 3u, offset_rad, (float)TS, (float)BW };
    return c;
}

/* Distance between two angles modulo 2*pi [rad]. */
static double angle_dist(double x, double y)
{
    return fabs(remainder(x - y, 2.0 * PI_D));
}

/*
 * theta_e = 2*pi * ((p*count mod cpr) + p/2) / cpr + offset, i.e. the hand
 * values below plus CENTRE_EL (3333 -> 9999 + 1.5 wraps to 0.5 counts):
 * count 2500 -> 7500/10000 of a turn = 3*pi/2; 5000 -> 15000 mod 10000 = 5000 -> pi;
 * 3333 -> 9999 -> 2*pi*0.9999 = 6.2825575; 3334 -> 10002 mod 10000 = 2 -> 0.0012566.
 */
static void angle_hand_values(void **state)
{
    (void)state;
    encoder_t enc;
    encoder_cfg_t c = cfg_default(0.0f);
    assert_true(encoder_init(&enc, &c));
    const uint32_t counts[] = { 0u, 2500u, 5000u, 3333u, 3334u, 9999u };
    const double expect[] = { CENTRE_EL, 3.0 * PI_D / 2.0 + CENTRE_EL, PI_D + CENTRE_EL,
                              6.282557 + CENTRE_EL - 2.0 * PI_D, 0.0012566371 + CENTRE_EL,
                              6.2813059 + CENTRE_EL };
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        encoder_step(&enc, counts[i]);
        assert_float_equal(enc.theta_e_rad, expect[i], TOL);
        assert_true(enc.theta_e_rad >= 0.0f && enc.theta_e_rad < 6.2831855f);
    }
    /* A count at or beyond cpr (HAL fault) is reduced modulo cpr: 12500 -> 2500. */
    encoder_step(&enc, 12500u);
    assert_float_equal(enc.theta_e_rad, 3.0 * PI_D / 2.0 + CENTRE_EL, TOL);
}

/*
 * Offset is the electrical angle at the start of count 0: +1 rad at count
 * 2500 gives 3*pi/2 + 1 = 5.712389; +2 rad wraps to 3*pi/2 + 2 - 2*pi =
 * 0.429204; a cfg offset of -1 rad reads 2*pi - 1 = 5.283185 at count 0;
 * each plus CENTRE_EL.
 */
static void offset_handling(void **state)
{
    (void)state;
    encoder_t enc;
    encoder_cfg_t c = cfg_default(1.0f);
    assert_true(encoder_init(&enc, &c));
    encoder_step(&enc, 2500u);
    assert_float_equal(enc.theta_e_rad, 5.712388980384690 + CENTRE_EL, TOL);
    encoder_set_offset(&enc, 2.0f);
    encoder_step(&enc, 2500u);
    assert_float_equal(enc.theta_e_rad, 0.429203673205103 + CENTRE_EL, TOL);
    encoder_set_offset(&enc, NAN);
    encoder_step(&enc, 2500u);
    assert_float_equal(enc.theta_e_rad, 0.429203673205103 + CENTRE_EL, TOL);

    c = cfg_default(-1.0f);
    assert_true(encoder_init(&enc, &c));
    encoder_step(&enc, 0u);
    assert_float_equal(enc.theta_e_rad, 5.283185307179586 + CENTRE_EL, TOL);
}

/* Alignment at count 1234 makes 1234 read 0; 2500 counts on (3/4 of an
 * electrical turn times 3 = 7500/10000 of 2*pi) reads 3*pi/2. */
static void align_sets_zero_at_count(void **state)
{
    (void)state;
    encoder_t enc;
    encoder_cfg_t c = cfg_default(0.7f);
    assert_true(encoder_init(&enc, &c));
    encoder_align(&enc, 1234u);
    encoder_step(&enc, 1234u);
    assert_float_equal(angle_dist(enc.theta_e_rad, 0.0), 0.0, TOL);
    encoder_step(&enc, 1234u + 2500u);
    assert_float_equal(enc.theta_e_rad, 3.0 * PI_D / 2.0, 1e-4);
    /* Backwards across count 0: 1234 - 2500 = -1266 -> 8734, -3*pi/2 = pi/2. */
    encoder_step(&enc, 8734u);
    assert_float_equal(enc.theta_e_rad, PI_D / 2.0, 1e-4);
}

/*
 * Drives the encoder with a rotor turning at rpm from position x0 [counts]
 * (count = floor(x) mod cpr) for n periods and returns, in err[k], the
 * relative speed error of period k. Also checks the electrical speed and
 * that each angle step matches the true one within one count.
 */
static void run_constant_speed(double rpm, double x0, int n, double *err)
{
    encoder_t enc;
    encoder_cfg_t c = cfg_default(0.0f);
    assert_true(encoder_init(&enc, &c));
    const double v_counts = rpm / 60.0 * CPR * TS; /* counts per period */
    const double w_true = rpm * 2.0 * PI_D / 60.0;
    double prev_theta = 0.0;
    for (int k = 0; k < n; k++) {
        double x = x0 + v_counts * k;
        double turns = floor(x / CPR);
        uint32_t cnt = (uint32_t)(floor(x) - turns * CPR);
        encoder_step(&enc, cnt);
        err[k] = (double)enc.omega_m_rad_s / w_true - 1.0;
        assert_float_equal(enc.omega_e_rad_s, 3.0 * (double)enc.omega_m_rad_s,
                           1e-6 * fabs(3.0 * w_true));
        if (k > 0) {
            double dth = remainder((double)enc.theta_e_rad - prev_theta, 2.0 * PI_D);
            double dth_true = 3.0 * v_counts * 2.0 * PI_D / CPR;
            assert_float_equal(dth, dth_true, 3.0 * 2.0 * PI_D / CPR + 1e-5);
        }
        prev_theta = enc.theta_e_rad;
    }
}

/*
 * Settling, hand-derived: seeded at rest on the right position, the PLL
 * (p' = v + 2bw*e, v' = bw^2*e, e = x - p) sees e(0) = 0, e'(0) = V, so
 * e(t) = V*t*exp(-bw*t) and the speed error is V*(1 + bw*t)*exp(-bw*t).
 * Below 0.5 % needs bw*t > 7.43, i.e. 37 ms = 372 periods at bw = 200 rad/s
 * (the discrete loop is a few periods slower): assert from N = 400 on.
 * At 300 periods (bw*t = 6) the error is still -7*exp(-6) = -1.74 %, which
 * checks that the bandwidth really is 200 rad/s.
 * 500 r/min = 8.33 counts per period; 50 r/min = 0.83 counts per period
 * (mostly 0, sometimes 1: the quantisation case).
 */
static void steady_speed_converges(void **state)
{
    (void)state;
    static double err[14000];
    const double rpms[] = { 500.0, -500.0, 50.0, -50.0 };
    for (size_t r = 0; r < 4; r++) {
        const int n = (fabs(rpms[r]) > 100.0) ? 4000 : 14000;
        run_constant_speed(rpms[r], 1234.4, n, err);
        assert_float_equal(err[300], -0.0174, 0.002);
        for (int k = 400; k < n; k++) {
            assert_float_equal(err[k], 0.0, 0.005);
        }
    }
}

/* Starting right at either end so the first wraps happen early; the speed
 * stays right across many wraps: 500 r/min crosses 9999 -> 0 (or 0 -> 9999
 * reversed) every 1200 periods. */
static void wrap_both_ends_both_directions(void **state)
{
    (void)state;
    static double err[6000];
    const double starts[] = { 9990.5, 5.5 };
    const double rpms[] = { 500.0, -500.0 };
    for (size_t s = 0; s < 2; s++) {
        for (size_t r = 0; r < 2; r++) {
            run_constant_speed(rpms[r], starts[s], 6000, err);
            for (int k = 400; k < 6000; k++) {
                assert_float_equal(err[k], 0.0, 0.005);
            }
            /* Seeded at rest, the speed estimate rises from 0 with the
             * sign of the motion even through the very first wrap. */
            for (int k = 1; k < 400; k++) {
                assert_true(err[k] > -1.0 && err[k] < 0.2);
            }
        }
    }
    /* One count per period straight across the boundary, both ways. */
    encoder_t enc;
    encoder_cfg_t c = cfg_default(0.0f);
    assert_true(encoder_init(&enc, &c));
    encoder_step(&enc, 9998u);
    encoder_step(&enc, 9999u);
    encoder_step(&enc, 0u);
    encoder_step(&enc, 1u);
    assert_true(enc.omega_m_rad_s > 0.0f);
    assert_true(enc.omega_m_rad_s < 2.0f * (float)(2.0 * PI_D / CPR / TS));
    assert_true(encoder_init(&enc, &c));
    encoder_step(&enc, 1u);
    encoder_step(&enc, 0u);
    encoder_step(&enc, 9999u);
    encoder_step(&enc, 9998u);
    assert_true(enc.omega_m_rad_s < 0.0f);
    assert_true(enc.omega_m_rad_s > -2.0f * (float)(2.0 * PI_D / CPR / TS));
}

/*
 * First sample after init or reset gives exactly 0 speed wherever the count
 * is; the next one moves the speed by only ki*Ts*e: one count ahead gives
 * bw^2*Ts*1 = 4 counts/s = 2.513e-3 rad/s.
 */
static void reset_gives_no_speed_spike(void **state)
{
    (void)state;
    encoder_t enc;
    encoder_cfg_t c = cfg_default(0.0f);
    assert_true(encoder_init(&enc, &c));
    assert_true(enc.omega_m_rad_s == 0.0f && enc.theta_e_rad == 0.0f);
    encoder_step(&enc, 5000u);
    assert_true(enc.omega_m_rad_s == 0.0f);
    for (uint32_t k = 1; k <= 50; k++) {
        encoder_step(&enc, 5000u + 8u * k);
    }
    assert_true(enc.omega_m_rad_s > 1.0f);
    encoder_reset(&enc);
    assert_true(enc.omega_m_rad_s == 0.0f && enc.omega_e_rad_s == 0.0f);
    /* The count jumped by half a turn while the drive was off. */
    encoder_step(&enc, 100u);
    assert_true(enc.omega_m_rad_s == 0.0f);
    assert_float_equal(enc.theta_e_rad, 2.0 * PI_D * 300.0 / CPR + CENTRE_EL, TOL);
    encoder_step(&enc, 101u);
    assert_float_equal(enc.omega_m_rad_s, BW * BW * TS * 2.0 * PI_D / CPR, 1e-6);
}

/* Invalid configurations are refused and read 0 angle, 0 speed. */
static void invalid_cfg_rejected(void **state)
{
    (void)state;
    encoder_t enc;
    encoder_cfg_t bad[7];
    for (int i = 0; i < 7; i++) {
        bad[i] = cfg_default(0.0f);
    }
    bad[0].counts_per_rev = 0u;
    bad[1].pole_pairs = 0u;
    bad[2].Ts_s = 0.0f;
    bad[3].pll_bw_rad_s = 6000.0f; /* bw*Ts = 0.6 > 0.5 */
    bad[4].offset_el_rad = NAN;
    bad[5].counts_per_rev = ENCODER_CPR_MAX + 1u;
    bad[6].counts_per_rev = ENCODER_CPR_MAX;
    bad[6].pole_pairs = 300u; /* 2^24 * 300 > 2^32 */
    for (int i = 0; i < 7; i++) {
        assert_false(encoder_init(&enc, &bad[i]));
        encoder_step(&enc, 2500u);
        encoder_step(&enc, 2600u);
        assert_true(enc.theta_e_rad == 0.0f && enc.omega_m_rad_s == 0.0f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(angle_hand_values),
        cmocka_unit_test(offset_handling),
        cmocka_unit_test(align_sets_zero_at_count),
        cmocka_unit_test(steady_speed_converges),
        cmocka_unit_test(wrap_both_ends_both_directions),
        cmocka_unit_test(reset_gives_no_speed_spike),
        cmocka_unit_test(invalid_cfg_rejected),
    };
    return cmocka_run_group_tests_name("encoder", tests, NULL, NULL);
}
