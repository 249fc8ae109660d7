/* Unit tests for control/ident (the commissioning's motor math): the
 * least-squares solves on exact lines; the DC regulator as the plain
 * integrator with a virtual resistance, its gain raised without a bump;
 * the rotating-frame PI a first-order loop of its bandwidth on an RL
 * winding; R from two DC points; the inverter's per-leg error, its
 * polarities' mean and spread from four points built by hand, and its
 * split into the told dead time and a drop; L from steps on an exact
 * discrete RL winding; the encoder offset from an ideal sweep; psi_f, J and
 * B from sweeps carrying an inverter error odd in the current, part of it
 * even in the speed. Expectations derived in each test's comment. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "ident.h"
#include "spmsm.h"

#define TS 1e-4f
#define PI_D 3.141592653589793

/* y = 2.5 x1 - 0.75 x2 + 4 on a grid: both solves exact (to float). */
static void least_squares_solve_exact_lines(void **state)
{
    ident_ls_t a;
    ident_ls_t b;
    (void)state;
    ident_ls_reset(&a);
    ident_ls_reset(&b);
    for (int k = 0; k < 50; k++) {
        const float x1 = 0.1f * (float)k;
        const float x2 = (float)((k * 7) % 5) - 2.0f;
        ident_ls_add(&a, x1, 0.0f, 2.5f * x1 + 4.0f);
        ident_ls_add(&b, x1, x2, 2.5f * x1 - 0.75f * x2 + 4.0f);
    }
    assert_float_equal(ident_ls_slope(&a), 2.5f, 1e-4f);
    assert_float_equal(ident_ls_coef1(&b), 2.5f, 1e-4f);
}

/* Fewer samples than IDENT_LS_N_MIN, or a constant regressor: 0 (no sign). */
static void least_squares_refuse_too_little_data(void **state)
{
    ident_ls_t s;
    (void)state;
    ident_ls_reset(&s);
    for (int k = 0; k < (int)IDENT_LS_N_MIN - 1; k++) {
        ident_ls_add(&s, (float)k, 0.0f, (float)k);
    }
    assert_float_equal(ident_ls_slope(&s), 0.0f, 0.0f);
    ident_ls_reset(&s);
    for (int k = 0; k < 40; k++) {
        ident_ls_add(&s, 1.0f, (float)k, (float)k);
    }
    assert_float_equal(ident_ls_slope(&s), 0.0f, 0.0f);
    assert_float_equal(ident_ls_coef1(&s), 0.0f, 0.0f);
}

/* u = Kp e + xi, xi += Ts Ki e: a constant error e over n periods gives
 * Kp e + (n - 1) Ts Ki e in the n-th. Raising Ki keeps xi: the next output
 * with e = 0 is the integral reached. Ts Ki > Kp is refused. */
static void dc_regulator_integrates_and_raises_its_gain_bumplessly(void **state)
{
    const ident_dc_cfg_t cfg = { TS, 2.0f, 500.0f, 100.0f };
    const ab_t ref = { 1.0f, 0.0f };
    const ab_t i = { 0.5f, 0.0f };
    ab_t u = { 0.0f, 0.0f };
    ident_dc_t r;
    (void)state;
    assert_true(ident_dc_init(&r, &cfg));
    for (int k = 0; k < 10; k++) {
        u = ident_dc_step(&r, ref, i);
    }
    assert_float_equal(u.a, 2.0f * 0.5f + 9.0f * TS * 500.0f * 0.5f, 1e-5f);
    assert_float_equal(u.b, 0.0f, 0.0f);
    const float xi = 10.0f * TS * 500.0f * 0.5f;
    assert_true(ident_dc_set_ki_a(&r, 5000.0f));
    u = ident_dc_step(&r, i, i);
    assert_float_equal(u.a, xi, 1e-5f);
    assert_false(ident_dc_set_ki_a(&r, 2.0f / TS * 1.5f));
}

/* Kp = w L, Ki = w R on L di/dt = u - R i puts the PI's zero on the
 * winding's pole: i = i* (1 - exp(-w t)), 63 % at t = 1/w (the period's
 * delay of the discrete loop, a few per cent at w Ts = 0.1). */
static void current_pi_is_a_first_order_loop_of_its_bandwidth(void **state)
{
    const float R = 2.0f;
    const float L = 0.01f;
    const float w = 1000.0f;
    const dq_t u0 = { 0.0f, 0.0f };
    const dq_t ref = { 0.0f, 3.0f };
    ident_cur_t c;
    dq_t i = { 0.0f, 0.0f };
    (void)state;
    assert_true(ident_cur_init(&c, TS, w, R, L, 400.0f, u0));
    const int n = (int)(1.0f / (w * TS) + 0.5f);
    for (int k = 0; k < n; k++) {
        const dq_t u = ident_cur_step(&c, ref, i);
        const float a = expf(-R / L * TS);
        i.q = a * i.q + (1.0f - a) * u.q / R;
    }
    assert_float_equal(i.q / 3.0f, 1.0f - expf(-1.0f), 0.05f);
    assert_false(ident_cur_init(&c, TS, w, 10.0f * R, 0.5f * R * TS, 400.0f, u0)); /* L/R below a period */
}

/* U = R I + E at two currents: R exactly, E gone; equal currents: 0. */
static void resistance_from_two_points_cancels_a_constant_error(void **state)
{
    const ident_point_t p1 = { 0.7f * 1.0f + 0.44f, 1.0f };
    const ident_point_t p2 = { 0.7f * 2.5f + 0.44f, 2.5f };
    (void)state;
    assert_float_equal(ident_r_of_points(p1, p2), 0.7f, 1e-5f);
    assert_float_equal(ident_r_of_points(p1, p1), 0.0f, 0.0f);
}

/* The commanded voltage U = R I + (4/3) dv sign(I) + asym at +-I1, +-I2:
 * dv and asym back exactly, spread 0. One point off by d: asym moves by
 * d/4, dv by (3/4) d/4 = 3d/16; that point's per-leg value lies
 * (3/4)(3d/4) = 9d/16 above dv, so 6d/16 = 3d/8 from the new dv. */
static void inverter_error_from_both_polarities(void **state)
{
    const float R = 0.61f;
    const float dv = 7.5f;
    const float asym = 0.02f;
    const float I[2] = { 1.2f, 2.4f };
    ident_point_t pos[2];
    ident_point_t neg[2];
    ident_inv_t out;
    (void)state;
    for (int k = 0; k < 2; k++) {
        pos[k].I_A = I[k];
        pos[k].U_V = R * I[k] + (4.0f / 3.0f) * dv + asym;
        neg[k].I_A = -I[k];
        neg[k].U_V = -R * I[k] - (4.0f / 3.0f) * dv + asym;
    }
    ident_inv_solve(R, pos, neg, &out);
    assert_float_equal(out.dv_V, dv, 1e-4f);
    assert_float_equal(out.asym_V, asym, 1e-5f);
    assert_float_equal(out.spread_V, 0.0f, 1e-4f);
    pos[0].U_V += 0.16f;
    ident_inv_solve(R, pos, neg, &out);
    assert_float_equal(out.dv_V, dv + 3.0f * 0.16f / 16.0f, 1e-4f);
    assert_float_equal(out.spread_V, 3.0f * 0.16f / 8.0f, 1e-4f);
}

/* 24 V, 100 us, told 0.9 us: 0.216 V of dead time. dv = 0.333 V: the told
 * dead time and 0.117 V of drop; dv = 0.1 V below it: all dead time,
 * 0.1 V x 100 us / 24 V = 0.4167 us, no drop. */
static void inverter_split_keeps_the_told_dead_time(void **state)
{
    float td;
    float drop;
    (void)state;
    ident_inv_split(0.333f, 24.0f, TS, 0.9e-6f, &td, &drop);
    assert_float_equal(td, 0.9e-6f, 1e-12f);
    assert_float_equal(drop, 0.333f - 0.216f, 1e-5f);
    ident_inv_split(0.1f, 24.0f, TS, 0.9e-6f, &td, &drop);
    assert_float_equal(td, 0.1f * TS / 24.0f, 1e-11f);
    assert_float_equal(drop, 0.0f, 0.0f);
}

/* An exact discrete RL winding (tau 10 periods) under voltage steps of
 * -R dI around (U0, I0), the voltage computed at a call acting over the
 * next period (seen two calls later, spmsm.h), an inverter error of 0.3 V
 * in U0: L within the trapezoid rule's (Ts/tau)^2 / 12 = 0.08 %. */
static void inductance_from_steps_on_an_rl_winding(void **state)
{
    const float R = 1.0f;
    const float L = 10.0f * TS * R;
    const float I0 = 2.0f;
    const ident_point_t op = { R * I0 + 0.3f, I0 };
    const float a = expf(-R / L * TS);
    float u1 = op.U_V;            /* computed one call ago: acts over the coming period */
    float u2 = op.U_V;            /* two calls ago: acted over the period just ended */
    float i = I0;
    ident_l_t l;
    (void)state;
    ident_l_start(&l, TS, op);
    for (int k = 0; k < 800; k++) {
        ident_l_step(&l, i, u2, R);
        const float u = (((k / 100) % 2) == 0) ? op.U_V - R * 1.0f : op.U_V;
        i = a * i + (1.0f - a) * (u1 - 0.3f) / R;
        u2 = u1;
        u1 = u;
    }
    assert_float_equal(ident_l_solve(&l) / L, 1.0f, 0.005f);
}

/* A rotor exactly on the vector: the count N = floor((theta - off) cpr /
 * (2 pi p)) (unwrapped), whose centre encoder.h reads as off + p 2 pi
 * (N + 1/2) / cpr. One electrical turn from count0 = N(0) mod cpr: the
 * offset within a count's angle, the slope cpr / (2 pi p) per rad el. */
static void encoder_offset_from_an_ideal_sweep(void **state)
{
    const uint32_t cpr = 10000u;
    const uint16_t p = 3u;
    const double off = 2.5;
    const double per_rad = (double)cpr / (2.0 * PI_D * (double)p);
    const double N0 = floor((0.0 - off) * per_rad);
    const uint32_t count0 = (uint32_t)(N0 + (double)cpr);
    ident_ls_t ls;
    float s;
    (void)state;
    ident_ls_reset(&ls);
    for (int k = 0; k < 2000; k++) {
        const double th = 2.0 * PI_D * (double)k / 2000.0;
        ident_ls_add(&ls, (float)(th - PI_D), 0.0f, (float)(floor((th - off) * per_rad) - N0));
    }
    const float est = ident_enc_offset(&ls, count0, p, cpr, &s);
    const double d = fmod((double)est - off + 3.0 * PI_D, 2.0 * PI_D) - PI_D;
    assert_float_equal(s, (float)per_rad, 0.5f);
    assert_true(fabs(d) < 2.0 * PI_D * (double)p / (double)cpr);
}

/* The spin's sweeps on a motor: up at +I (0 -> top), down at -I (top ->
 * -top), up at +I (-top -> 0), each sweep's first `skip` periods left out
 * as the commissioning's (the speed estimate settling);
 * u_q = R i_q + w_el psi + sign(i) (E0 + k w_el^2), an inverter error
 * odd in the current, its part k even in the speed; J dw/dt = 1.5 p psi i - B w. */
#define SPIN_P 4u
#define SPIN_PSI 0.1f
#define SPIN_J 2e-4f
#define SPIN_B 1e-4f
static bool spin_run(float E0_V, float k_V_s2, int skip, ident_spin_out_t *o)
{
    const float R = 0.5f;
    const float I = 2.0f;
    const float top = 200.0f;
    const float T = spmsm_kt_Nm_A(SPIN_P, SPIN_PSI) * I;
    ident_spin_t s;
    float w = 0.0f;
    ident_spin_reset(&s);
    for (int phase = 0; phase < 3; phase++) {
        const float sgn = (phase == 1) ? -1.0f : 1.0f;
        float t = 0.0f;
        for (int k = 0; (phase == 0 && w < top) || (phase == 1 && w > -top) || (phase == 2 && w < 0.0f); k++) {
            const float we = (float)SPIN_P * w;
            const dq_t i_dq = { 0.0f, sgn * I };
            const float uq = R * sgn * I + we * SPIN_PSI + sgn * (E0_V + k_V_s2 * we * we);
            if (k >= skip) {
                ident_spin_add_flux(&s, w, SPIN_P, i_dq, uq, R, phase == 1);
            }
            if ((k >= skip) && (phase < 2) && (w > 0.2f * top)) {
                ident_spin_add_motion(&s, t, w, sgn * I, phase == 1);
            }
            w += TS * (sgn * T - SPIN_B * w) / SPIN_J;
            t += TS;
        }
    }
    return ident_spin_solve(&s, SPIN_P, o);
}

/* A constant error odd in the current (10 V, the 600 V board's) lands in
 * the sign's coefficient, not in the slope, though the fitted speeds of
 * the two currents differ (100 periods of each sweep skipped: a third of
 * the first). J a = T - B w
 * on each motion fit with T = 1.5 p psi i: J and B exactly. */
static void spin_fit_takes_an_odd_error_into_the_sign(void **state)
{
    ident_spin_out_t o;
    (void)state;
    assert_true(spin_run(10.0f, 0.0f, 100, &o));
    assert_float_equal(o.psi_f_Wb / SPIN_PSI, 1.0f, 1e-3f);
    assert_float_equal(o.J_kgm2 / SPIN_J, 1.0f, 0.01f);
    assert_float_equal(o.B_Nms / SPIN_B, 1.0f, 0.1f);
}

/* An error that grows with |w| (k w_el^2: 12.8 V at the top) has no slope
 * over speeds swept both ways at each current: psi_f exactly, where a fit
 * over the first sweep alone would carry its mean slope k w_top = 16 % of
 * psi_f. */
static void spin_sweeps_both_ways_leave_an_even_error_out(void **state)
{
    ident_spin_out_t o;
    (void)state;
    assert_true(spin_run(0.0f, 2e-5f, 0, &o));
    assert_float_equal(o.psi_f_Wb / SPIN_PSI, 1.0f, 2e-3f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(least_squares_solve_exact_lines),
        cmocka_unit_test(least_squares_refuse_too_little_data),
        cmocka_unit_test(dc_regulator_integrates_and_raises_its_gain_bumplessly),
        cmocka_unit_test(current_pi_is_a_first_order_loop_of_its_bandwidth),
        cmocka_unit_test(resistance_from_two_points_cancels_a_constant_error),
        cmocka_unit_test(inverter_error_from_both_polarities),
        cmocka_unit_test(inverter_split_keeps_the_told_dead_time),
        cmocka_unit_test(inductance_from_steps_on_an_rl_winding),
        cmocka_unit_test(encoder_offset_from_an_ideal_sweep),
        cmocka_unit_test(spin_fit_takes_an_odd_error_into_the_sign),
        cmocka_unit_test(spin_sweeps_both_ways_leave_an_even_error_out),
    };
    return cmocka_run_group_tests_name("ident", tests, NULL, NULL);
}
