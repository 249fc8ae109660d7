/* Unit tests for control/ctrl: open-loop voltage at the advanced angle,
 * torque deadbeat against a plant written here (continuous model, RK4,
 * stator-frame voltage held over the period, one-period delay), speed-loop
 * limit and anti-windup, bumpless mode change, non-finite handling. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "ctrl.h"

#define PI_D 3.14159265358979323846
#define TS   1e-4
#define RS   3.0
#define LS   0.011
#define PSIF 0.24
#define PP   3
#define LINES 4096u
#define CPR  (4u * LINES)

static ctrl_cfg_t make_cfg(void)
{
    ctrl_cfg_t cfg = {
        .Ts_s = (float)TS, .R_Ohm = (float)RS, .L_H = (float)LS, .psi_f_Wb = (float)PSIF,
        .pole_pairs = PP, .enc_lines = LINES, .enc_offset_el_rad = 0.0f,
        .enc_pll_bw_rad_s = 500.0f, .speed_kp_Nms_rad = 0.5f, .speed_ki_Nm_rad = 20.0f,
        .te_max_Nm = 12.0f, .i_max_A = 60.0f, .u_max_V = 5000.0f,
        .omega_max_el_rad_s = 3000.0f, .psi_max_Wb = 1.0f,
    };
    return cfg;
}

/* ---- the test-side plant: SPMSM at a held speed, eq. (1)-(3) ---------- */
typedef struct {
    double id, iq;      /* rotor-frame currents */
    double th_el;       /* electrical angle */
    double w_el;        /* held electrical speed */
    double ua, ub;      /* stator-frame voltage being applied this period */
} tplant_t;

static void tp_deriv(const tplant_t *p, double id, double iq, double th, double *did, double *diq)
{
    const double ud = p->ua * cos(th) + p->ub * sin(th);
    const double uq = -p->ua * sin(th) + p->ub * cos(th);
    *did = (ud - RS * id + p->w_el * LS * iq) / LS;
    *diq = (uq - RS * iq - p->w_el * (LS * id + PSIF)) / LS;
}

static void tp_period(tplant_t *p)
{
    const int n = 50;
    const double h = TS / n;
    for (int k = 0; k < n; k++) {
        const double th = p->th_el;
        double d1, q1, d2, q2, d3, q3, d4, q4;
        tp_deriv(p, p->id, p->iq, th, &d1, &q1);
        tp_deriv(p, p->id + 0.5 * h * d1, p->iq + 0.5 * h * q1, th + 0.5 * h * p->w_el, &d2, &q2);
        tp_deriv(p, p->id + 0.5 * h * d2, p->iq + 0.5 * h * q2, th + 0.5 * h * p->w_el, &d3, &q3);
        tp_deriv(p, p->id + h * d3, p->iq + h * q3, th + h * p->w_el, &d4, &q4);
        p->id += h / 6.0 * (d1 + 2.0 * d2 + 2.0 * d3 + d4);
        p->iq += h / 6.0 * (q1 + 2.0 * q2 + 2.0 * q3 + q4);
        p->th_el += h * p->w_el;
    }
}

/* Duties to the stator-frame voltage they average to (amplitude-invariant). */
static void duties_to_ab(const float duty[3], double vdc, double *ua, double *ub)
{
    const double va = duty[0] * vdc, vb = duty[1] * vdc, vc = duty[2] * vdc;
    *ua = (2.0 * va - vb - vc) / 3.0;
    *ub = (vb - vc) / sqrt(3.0);
}

static ctrl_in_t tp_sample(const tplant_t *p, double vdc)
{
    ctrl_in_t in;
    const double th = p->th_el;
    const double ia = p->id * cos(th) - p->iq * sin(th);
    const double ib_beta = p->id * sin(th) + p->iq * cos(th);
    const double ib = -0.5 * ia + 0.5 * sqrt(3.0) * ib_beta;
    double th_m = fmod(th / PP, 2.0 * PI_D);
    if (th_m < 0.0) {
        th_m += 2.0 * PI_D;
    }
    in.ia_A = (float)ia;
    in.ib_A = (float)ib;
    in.vdc_V = (float)vdc;
    in.enc_count = (uint32_t)floor(th_m / (2.0 * PI_D) * CPR) % CPR;
    return in;
}

/* One closed-loop period: sample, step, then the plant runs the previous
 * period's duties; this period's duties take effect at the next one. */
static void cl_period(ctrl_t *c, tplant_t *p, double vdc, ctrl_out_t *out)
{
    ctrl_in_t in = tp_sample(p, vdc);
    ctrl_step(c, &in, out);
    tp_period(p);                                 /* previous duties */
    duties_to_ab(out->duty, vdc, &p->ua, &p->ub); /* from the next period on */
}

static double tp_te(const tplant_t *p) { return 1.5 * PP * PSIF * p->iq; }

/* Open loop: the duties reproduce (ud, uq) at theta + 1.5*omega*Ts. */
static void open_loop_voltage_at_advanced_angle(void **state)
{
    (void)state;
    ctrl_cfg_t cfg = make_cfg();
    ctrl_t c;
    ctrl_init(&c, &cfg);
    ctrl_set_mode(&c, CTRL_MODE_OPEN_LOOP);
    ctrl_ref_t ref = { 0.0f, 0.0f, 20.0f, 50.0f };
    ctrl_set_ref(&c, &ref);
    tplant_t p = { 0.0, 0.0, 0.3, 2.0 * PI_D * 500.0 / 60.0 * PP, 0.0, 0.0 };
    const double vdc = 300.0;
    ctrl_out_t out;
    for (int k = 0; k < 400; k++) { /* PLL settles */
        ctrl_in_t in = tp_sample(&p, vdc);
        ctrl_step(&c, &in, &out);
        p.th_el += p.w_el * TS;
        if (k < 399) {
            continue;
        }
        assert_int_equal(out.flags, 0u);
        assert_float_equal(c.mon.omega_el_rad_s, p.w_el, 0.01 * p.w_el);
        double ua, ub;
        duties_to_ab(out.duty, vdc, &ua, &ub);
        const double tha = c.mon.theta_el_rad + 1.5 * c.mon.omega_el_rad_s * TS;
        assert_float_equal(ua * cos(tha) + ub * sin(tha), 20.0, 1e-3);
        assert_float_equal(-ua * sin(tha) + ub * cos(tha), 50.0, 1e-3);
        /* the angle is the encoder's: within one count of the plant's (before this period's advance) */
        const double th_meas = p.th_el - p.w_el * TS;
        double err = fmod(c.mon.theta_el_rad - th_meas, 2.0 * PI_D);
        err = (err > PI_D) ? err - 2.0 * PI_D : ((err < -PI_D) ? err + 2.0 * PI_D : err);
        assert_true(fabs(err) <= 2.0 * PI_D * PP / CPR);
        assert_float_equal(c.mon.ud_V, 20.0, 1e-3);
        assert_float_equal(c.mon.uq_V, 50.0, 1e-3);
    }
}

/* Torque mode, exact parameters, 500 r/min held: a 2 -> 4 N m step is on
 * target (95 %) two periods after the command and stays within 1 %. */
static void torque_step_in_two_periods(void **state)
{
    (void)state;
    ctrl_cfg_t cfg = make_cfg();
    ctrl_t c;
    ctrl_init(&c, &cfg);
    ctrl_set_mode(&c, CTRL_MODE_TORQUE);
    ctrl_ref_t ref = { 0.0f, 2.0f, 0.0f, 0.0f };
    ctrl_set_ref(&c, &ref);
    tplant_t p = { 0.0, 0.0, 1.0, 2.0 * PI_D * 500.0 / 60.0 * PP, 0.0, 0.0 };
    const double vdc = 540.0;
    ctrl_out_t out;
    for (int k = 0; k < 500; k++) {
        cl_period(&c, &p, vdc, &out);
    }
    assert_float_equal(tp_te(&p), 2.0, 0.02);
    ref.te_ref_Nm = 4.0f;
    ctrl_set_ref(&c, &ref);
    cl_period(&c, &p, vdc, &out); /* command taken at sample k0 */
    assert_int_equal(out.flags, 0u);
    cl_period(&c, &p, vdc, &out); /* at k0+1: still the old voltage */
    assert_true(tp_te(&p) > 3.8); /* sample k0+2 */
    for (int k = 0; k < 50; k++) {
        cl_period(&c, &p, vdc, &out);
        assert_float_equal(tp_te(&p), 4.0, 0.04);
        assert_float_equal(p.id, 0.0, 0.05);
    }
    /* the flux follows the MTPA reference */
    const double psi = hypot(LS * p.id + PSIF, LS * p.iq);
    assert_float_equal(psi, c.mon.psi_ref_Wb, 0.005 * psi);
}

/* Speed mode: a large error asks for the torque limit; with a bus too low
 * for it the integrator does not wind up beyond the achieved torque. */
static void speed_mode_limit_and_anti_windup(void **state)
{
    (void)state;
    ctrl_cfg_t cfg = make_cfg();
    ctrl_t c;
    ctrl_init(&c, &cfg);
    ctrl_set_mode(&c, CTRL_MODE_SPEED);
    ctrl_ref_t ref = { 200.0f, 0.0f, 0.0f, 0.0f };
    ctrl_set_ref(&c, &ref);
    tplant_t p = { 0.0, 0.0, 0.0, 2.0 * PI_D * 300.0 / 60.0 * PP, 0.0, 0.0 };
    ctrl_out_t out;
    const double vdc = 60.0; /* back-EMF at 300 r/min: 22.6 V; 12 N m needs more than this bus */
    uint16_t seen = 0u;
    for (int k = 0; k < 2000; k++) {
        cl_period(&c, &p, vdc, &out);
        seen |= out.flags;
        assert_true(c.mon.te_ref_Nm <= 12.0f);
    }
    assert_true((seen & CTRL_FLAG_VOLTAGE_LIMIT) != 0u);
    assert_true(c.mon.te_ref_Nm >= 11.99f); /* the demand stays at the limit */
    /* the integral part is held near what the bus can make, not at the limit */
    assert_true(c.speed_pi.xi < 12.0f);
    /* speed error reverses: the demand falls below zero within 20 periods */
    ref.speed_ref_rad_s = (float)(p.w_el / PP) - 50.0f;
    ctrl_set_ref(&c, &ref);
    int k = 0;
    while (c.mon.te_ref_Nm > 0.0f && k < 1000) {
        cl_period(&c, &p, vdc, &out);
        k++;
    }
    assert_true(k < 20);
}

/* Torque -> speed mode: the first speed-mode demand is the torque there is. */
static void mode_change_is_bumpless(void **state)
{
    (void)state;
    ctrl_cfg_t cfg = make_cfg();
    ctrl_t c;
    ctrl_init(&c, &cfg);
    ctrl_ref_t ref = { 0.0f, 3.0f, 0.0f, 0.0f };
    ctrl_set_ref(&c, &ref);
    tplant_t p = { 0.0, 0.0, 0.0, 100.0, 0.0, 0.0 };
    ctrl_out_t out;
    for (int k = 0; k < 300; k++) {
        cl_period(&c, &p, 540.0, &out);
    }
    ref.speed_ref_rad_s = c.mon.speed_mech_rad_s; /* zero error */
    ctrl_set_ref(&c, &ref);
    ctrl_set_mode(&c, CTRL_MODE_SPEED);
    cl_period(&c, &p, 540.0, &out);
    assert_float_equal(c.mon.te_ref_Nm, 3.0, 0.05);
}

/* Any non-finite input: 50 % duties and the flag; finite again: normal. */
static void non_finite_gives_half_duty(void **state)
{
    (void)state;
    ctrl_cfg_t cfg = make_cfg();
    ctrl_t c;
    ctrl_init(&c, &cfg);
    ctrl_ref_t ref = { 0.0f, 3.0f, 0.0f, 0.0f };
    ctrl_set_ref(&c, &ref);
    ctrl_out_t out;
    const float bad[] = { NAN, INFINITY, -INFINITY };
    for (int b = 0; b < 3; b++) {
        for (int field = 0; field < 4; field++) {
            ctrl_in_t in = { 1.0f, -0.5f, 300.0f, 123u };
            ctrl_ref_t r = ref;
            if (field == 0) {
                in.ia_A = bad[b];
            } else if (field == 1) {
                in.ib_A = bad[b];
            } else if (field == 2) {
                in.vdc_V = bad[b];
            } else {
                r.te_ref_Nm = bad[b];
            }
            ctrl_set_ref(&c, &r);
            ctrl_step(&c, &in, &out);
            assert_true((out.flags & CTRL_FLAG_NONFINITE) != 0u);
            for (int j = 0; j < 3; j++) {
                assert_float_equal(out.duty[j], 0.5, 0.0);
            }
            assert_float_equal(c.u_applied_V.d, 0.0, 0.0);
        }
    }
    ctrl_set_ref(&c, &ref);
    ctrl_in_t in = { 1.0f, -0.5f, 300.0f, 123u };
    ctrl_step(&c, &in, &out);
    assert_true((out.flags & CTRL_FLAG_NONFINITE) == 0u);
    assert_true(isfinite(c.mon.psi_est_Wb) && isfinite(c.mon.te_est_Nm));
}

/* The monitor reports the parameters in use and the estimates at k+1. */
static void monitor_filled(void **state)
{
    (void)state;
    ctrl_cfg_t cfg = make_cfg();
    cfg.L_H = (float)(1.5 * LS);
    ctrl_t c;
    ctrl_init(&c, &cfg);
    ctrl_ref_t ref = { 0.0f, 2.0f, 0.0f, 0.0f };
    ctrl_set_ref(&c, &ref);
    ctrl_in_t in = { 0.0f, 0.0f, 300.0f, 0u };
    ctrl_out_t out;
    ctrl_step(&c, &in, &out);
    assert_float_equal(est_output(ctrl_est(&c))->L_H, 1.5 * LS, 1e-9);
    assert_float_equal(est_output(ctrl_est(&c))->R_Ohm, RS, 1e-6);
    assert_float_equal(est_output(ctrl_est(&c))->psi_f_Wb, PSIF, 1e-7);
    assert_float_equal(c.mon.te_ref_Nm, 2.0, 1e-6);
    /* MTPA with the controller's L: sqrt(psi_f^2 + (L Te/(1.5 p psi_f))^2) */
    const double psq = 1.5 * LS * 2.0 / (1.5 * PP * PSIF);
    assert_float_equal(c.mon.psi_ref_Wb, sqrt(PSIF * PSIF + psq * psq), 1e-6);
    /* the current aimed at: MTPA's, id* = 0, iq* = Te / (1.5 p psi_f), on the q axis at theta + 90 deg */
    const double iq_aim = 2.0 / (1.5 * PP * PSIF);
    assert_float_equal(c.mon.i_aim_alpha_A, -iq_aim * sin(c.mon.theta_el_rad), 1e-3);
    assert_float_equal(c.mon.i_aim_beta_A, iq_aim * cos(c.mon.theta_el_rad), 1e-3);
    /* from rest with zero voltage applied: nothing moves, psi = psi_f */
    assert_float_equal(c.mon.te_est_Nm, 0.0, 1e-6);
    assert_float_equal(c.mon.psi_est_Wb, PSIF, 1e-6);
    assert_float_equal(est_f_V(ctrl_est(&c)).d, 0.0, 0.0);
}

/* ctrl_init reports every block's refusal as its own bit; a valid
 * configuration with the proposed method's defaults has none. */
static void init_reports_each_refusal(void **state)
{
    (void)state;
    static const struct { const char *what; ctrl_status_t bit; } cases[] = {
        { "PLL bandwidth x Ts 0.6 > 0.5", CTRL_CFG_ENCODER },
        { "no encoder lines", CTRL_CFG_ENCODER },
        { "speed PI Kp 0", CTRL_CFG_SPEED_PI },
        { "speed PI Ts Ki > Kp", CTRL_CFG_SPEED_PI },
        { "L 0", CTRL_CFG_DBDTC },
        { "dead time 0.2 Ts", CTRL_CFG_DEADTIME },
        { "dead time NaN", CTRL_CFG_DEADTIME },
        { "dead time < 0", CTRL_CFG_DEADTIME },
        { "device drop < 0", CTRL_CFG_DEADTIME },
        { "device drop NaN", CTRL_CFG_DEADTIME },
        { "device drop above 0.1 u_max", CTRL_CFG_DEADTIME },
    };
    ctrl_t c;
    ctrl_cfg_t cfg = make_cfg();
    ctrl_cfg_proposed_defaults(&cfg, 0.2f * (float)RS, 2.0f * (float)RS);
    assert_int_equal(ctrl_init(&c, &cfg), CTRL_CFG_OK);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        ctrl_cfg_t bad = cfg;
        switch (k) {
        case 0: bad.enc_pll_bw_rad_s = 6000.0f; break;
        case 1: bad.enc_lines = 0u; break;
        case 2: bad.speed_kp_Nms_rad = 0.0f; break;
        case 3: bad.speed_ki_Nm_rad = 1.0e5f; break;
        case 4: bad.L_H = 0.0f; break;
        case 5: bad.deadtime_s = 2.0e-5f; break;
        case 6: bad.deadtime_s = NAN; break;
        case 7: bad.deadtime_s = -1.0e-6f; break;
        case 8: bad.device_drop_V = -0.1f; break;
        case 9: bad.device_drop_V = NAN; break;
        default: bad.device_drop_V = 0.11f * bad.u_max_V; break;
        }
        const ctrl_status_t st = ctrl_init(&c, &bad);
        if ((st & cases[k].bit) == 0u) {
            fail_msg("%s: status 0x%x lacks 0x%x", cases[k].what, (unsigned)st, (unsigned)cases[k].bit);
        }
        assert_int_equal(c.status, st);
    }
    /* the proposed method's refusal alone leaves the conventional blocks accepted */
    ctrl_cfg_t obs = cfg;
    ctrl_cfg_proposed_defaults(&obs, 0.2f * (float)RS, 1000.0f);
    const ctrl_status_t st = ctrl_init(&c, &obs);
    assert_int_not_equal(st & CTRL_CFG_NEEDED_PROPOSED, 0);
    assert_int_equal(st & CTRL_CFG_NEEDED_ALWAYS, 0);
    assert_false(ctrl_set_method(&c, CTRL_METHOD_PROPOSED));
}

/* The default R^ band holds the motor's R with margin for a controller R
 * from 0.25x to 5x it, and the observer built on it is valid:
 * by hand, [0.1, 6] x Rs with the top at 0.9 (Ks - ef_max) / phi =
 * 0.9 x (100 - 50) / 2.5 = 18 Ohm. */
static void default_band_holds_the_motor_r(void **state)
{
    static const double factors[] = { 0.25, 0.5, 1.0, 2.0, 4.3, 5.0 };
    (void)state;
    for (size_t i = 0; i < sizeof factors / sizeof factors[0]; i++) {
        ctrl_cfg_t cfg = make_cfg();
        ctrl_t c;
        float R_min;
        float R_max;
        cfg.R_Ohm = (float)(factors[i] * RS);
        ctrl_rsid_band_default(&cfg, &R_min, &R_max);
        print_message("controller R %.2f x: band [%.3f, %.3f] Ohm\n", factors[i], R_min, R_max);
        assert_float_equal(R_min, 0.1 * factors[i] * RS, 1e-5);
        assert_float_equal(R_max, fmin(6.0 * factors[i] * RS, 18.0), 1e-4);
        assert_true(R_min <= 0.5 * RS);   /* the motor's R at least 2x inside */
        assert_true(R_max >= 1.5 * RS);   /*   and 1.5x inside at the top */
        ctrl_cfg_proposed_defaults(&cfg, R_min, R_max);
        assert_int_equal(ctrl_init(&c, &cfg), CTRL_CFG_OK);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(open_loop_voltage_at_advanced_angle),
        cmocka_unit_test(torque_step_in_two_periods),
        cmocka_unit_test(speed_mode_limit_and_anti_windup),
        cmocka_unit_test(mode_change_is_bumpless),
        cmocka_unit_test(non_finite_gives_half_duty),
        cmocka_unit_test(monitor_filled),
        cmocka_unit_test(init_reports_each_refusal),
        cmocka_unit_test(default_band_holds_the_motor_r),
    };
    return cmocka_run_group_tests_name("ctrl", tests, NULL, NULL);
}
