/* Unit tests for control/zoh: the exact discrete model of the SPMSM over a
 * period against a fine-step Runge-Kutta integration of the continuous
 * model (tests/rk4_motor.h, double), its decay and turn against libm in
 * double, and the paper's Euler forms (4), (10) as its limit Ts -> 0. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "rk4_motor.h"
#include "zoh.h"

#define TS 1e-4

/* Motors of the campaigns (R [ohm], L [H], psi_f [Wb]): Table I; the
 * D5065 (L/R 4 periods); the maxon EC 45 flat; a 600 V servo; one at the
 * L/R floor of 2 periods. */
static const double MOTORS[][3] = {
    { 3.0, 0.011, 0.24 },
    { 0.039, 15.7e-6, 0.0029 },
    { 0.2865, 150.5e-6, 0.0029 },
    { 0.61, 0.0042, 0.148 },
    { 0.5, 2.0 * TS * 0.5, 0.01 },
};

/* The decay (1 - e^-x)/x and e^-x against libm over the whole range
 * (L/R from Ts/20 to 10^4 Ts): at float's rounding of 1 (the squarings of
 * the range reduction multiply a small rho's relative error). */
static void decay_matches_exp(void **state)
{
    (void)state;
    for (double x = 1e-4; x <= 20.0; x *= 1.37) {
        zoh_model_t m;
        const double R = 1.0;
        const double L = TS * R / x;
        assert_true(zoh_model((float)R, (float)L, (float)TS, &m));
        const double xf = (double)(float)TS * (double)(float)R / (double)(float)L; /* as the floats give it */
        const double rho = exp(-xf);
        assert_float_equal(m.rho, rho, 4e-7 * rho + 1e-7);
        assert_float_equal(m.one_m_rho, 1.0 - rho, 4e-7 * (1.0 - rho));
        assert_float_equal(m.gamma_A_V, (1.0 - rho) / R, 5e-7 * (1.0 - rho) / R);
        assert_float_equal(m.kappa_1_s, R / (L * (1.0 - rho)), 8e-7 * R / (L * (1.0 - rho)));
    }
    zoh_model_t m;
    assert_false(zoh_model(0.0f, 1e-3f, 1e-4f, &m));
    assert_false(zoh_model(1.0f, -1e-3f, 1e-4f, &m));
    assert_false(zoh_model(NAN, 1e-3f, 1e-4f, &m));
}

/* The turn's half-angle series against libm up to the bound, clamped beyond. */
static void turn_matches_sincos(void **state)
{
    (void)state;
    for (double th = -1.0; th <= 1.0; th += 0.01) {
        zoh_turn_t t;
        zoh_turn((float)th, 1.0f, &t);
        assert_float_equal(t.c1, cos(th), 5e-7);
        assert_float_equal(t.s1, sin(th), 5e-7);
        assert_float_equal(t.ch, cos(0.5 * th), 5e-7);
        assert_float_equal(t.sh, sin(0.5 * th), 5e-7);
    }
    zoh_turn_t t;
    zoh_turn(3.0f, 1.0f, &t);
    assert_float_equal(t.s1, sin(1.0), 1e-6); /* held at 1 rad */
}

/* i(k+1) = Phi i + g_u u_m + g_c (-j w psi_f - v) against RK4 of the
 * continuous model, five motors, speeds up to 0.5 rad a period both ways,
 * the inverter's and a rotor-frame voltage: within 2e-6 of the current
 * step (float's rounding of the coefficients). */
static void step_matches_rk4(void **state)
{
    (void)state;
    const double thetas[] = { 0.0, 0.05, -0.12, 0.36, -0.5 };
    for (size_t k = 0; k < sizeof MOTORS / sizeof MOTORS[0]; k++) {
        for (size_t j = 0; j < sizeof thetas / sizeof thetas[0]; j++) {
            const double R = MOTORS[k][0];
            const double L = MOTORS[k][1];
            const double w = thetas[j] / TS;
            rk4_motor_t m = { R, L, MOTORS[k][2], w, TS, 0.0, 0.0, 0.0, 0.0 };
            /* voltages of the motor's scale: the back-EMF at 0.5 rad a period and R x 10 A */
            const double vs = 0.5 / TS * MOTORS[k][2] + 10.0 * R;
            m.um_d = -0.7 * vs;
            m.um_q = 1.1 * vs;
            m.v_d = 0.05 * vs;
            m.v_q = -0.08 * vs;
            double id = 3.0;
            double iq = -7.0;
            const double id0 = id;
            const double iq0 = iq;
            rk4_motor_period(&m, &id, &iq);

            zoh_model_t zm;
            zoh_turn_t t;
            zoh_step_t s;
            assert_true(zoh_model((float)R, (float)L, (float)TS, &zm));
            zoh_turn((float)thetas[j], (float)w, &t);
            zoh_step(&zm, &t, &s);
            const double vd = -m.v_d;
            const double vq = -w * MOTORS[k][2] - m.v_q;
            const double pd = s.Phi.d * id0 - s.Phi.q * iq0 + s.g_u.d * m.um_d - s.g_u.q * m.um_q + s.g_c.d * vd - s.g_c.q * vq;
            const double pq = s.Phi.d * iq0 + s.Phi.q * id0 + s.g_u.d * m.um_q + s.g_u.q * m.um_d + s.g_c.d * vq + s.g_c.q * vd;
            const double scale = fabs(id - id0) + fabs(iq - iq0) + 1.0;
            if (fabs(pd - id) > 2e-6 * scale || fabs(pq - iq) > 2e-6 * scale) {
                fail_msg("motor %zu, theta %.2f: zoh (%.9f, %.9f), rk4 (%.9f, %.9f)", k, thetas[j], pd, pq, id, iq);
            }
        }
    }
}

/* The paper's Euler forms are the limit Ts -> 0: eq. (10)'s one-period
 * error against the exact step falls as Ts^2 (Table I motor at 500 r/min,
 * the period halved five times: each halving quarters it, within 10 %). */
static void euler_is_the_limit(void **state)
{
    (void)state;
    const double R = 3.0, L = 0.011, psi = 0.24, w = 157.0;
    const double id = 1.0, iq = 4.0, ud = -20.0, uq = 60.0;
    double err_prev = 0.0;
    for (int n = 0; n < 5; n++) {
        const double Ts = TS / (double)(1 << n);
        rk4_motor_t m = { R, L, psi, w, Ts, ud, uq, 0.0, 0.0 };
        double xd = id;
        double xq = iq;
        rk4_motor_period(&m, &xd, &xq);
        /* eq. (10) */
        const double ed = id + Ts / L * (ud - R * id + w * L * iq);
        const double eq = iq + Ts / L * (uq - R * iq - w * L * id - w * psi);
        const double err = hypot(ed - xd, eq - xq);
        if (n > 0) {
            assert_float_equal(err_prev / err, 4.0, 0.4);
        }
        err_prev = err;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(decay_matches_exp),
        cmocka_unit_test(turn_matches_sincos),
        cmocka_unit_test(step_matches_rk4),
        cmocka_unit_test(euler_is_the_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
