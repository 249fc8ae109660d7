/* Unit tests for firmware/commission: the step machine alone on a small
 * test-side motor (stationary-frame RL with back-EMF, a rotor with inertia
 * and viscous friction, an incremental encoder; the voltage of a call
 * applied over the next period, as the PWM shadow registers do): a healthy
 * motor is measured within the commissioning's tolerances; a reversed
 * encoder, legs b and c swapped, told pole pairs one off either way
 * (enc_check.h's faults), an open circuit and a stage
 * timeout each end in their fault, stage, value and limit. The three
 * motors on the simulated board: tests/cli/test_commission.py. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>

#include "app.h"
#include "commission.h"

#define TS 1e-4
#define SUBSTEPS 20
#define PI_D 3.141592653589793
/* Table I's motor, a little friction */
#define R_T 3.0
#define L_T 0.011
#define PSI_T 0.24
#define P_T 3
#define J_T 0.00129
#define B_T 1e-4
#define OFF_T 2.5                  /* d axis at count 0 [rad el] */
#define CPR 10000u
#define VDC 311.0
#define PERIODS_MAX 100000u        /* 10 s */

typedef struct {
    double ia, ib;                 /* alpha-beta current [A] */
    double th, w;                  /* rotor angle, speed, mechanical */
    double ua, ub;                 /* voltage applied this period */
    int dir;                       /* encoder direction: +1, -1 reversed */
    int open;                      /* 1: the winding is open (no current) */
    int acb;                       /* 1: legs b and c swapped before the motor (beta voltage reversed) */
    double pll_pos, pll_vel;       /* a speed estimate as the controller's PLL (bw 500 rad/s) */
} motor_t;

static uint32_t count_of(const motor_t *m)
{
    double c = floor((double)m->dir * m->th / (2.0 * PI_D) * CPR);
    c = fmod(c, (double)CPR);
    return (uint32_t)(c < 0.0 ? c + CPR : c);
}

static void motor_period(motor_t *m)
{
    const double dt = TS / SUBSTEPS;
    for (int k = 0; k < SUBSTEPS; k++) {
        const double te = P_T * m->th + OFF_T;
        const double we = P_T * m->w;
        if (m->open) {
            m->ia = 0.0;
            m->ib = 0.0;
        } else {
            m->ia += dt / L_T * (m->ua - R_T * m->ia + we * PSI_T * sin(te));
            m->ib += dt / L_T * (m->ub - R_T * m->ib - we * PSI_T * cos(te));
        }
        const double T = 1.5 * P_T * PSI_T * (m->ib * cos(te) - m->ia * sin(te));
        m->w += dt / J_T * (T - B_T * m->w);
        m->th += dt * m->w;
    }
    /* PLL on the encoder's angle (ctrl's encoder: kp 2 bw, ki bw^2) */
    const double bw = 500.0;
    const double meas = (double)m->dir * floor((double)m->dir * m->th / (2.0 * PI_D) * CPR) * 2.0 * PI_D / CPR;
    const double e = meas - m->pll_pos;
    m->pll_vel += TS * bw * bw * e;
    m->pll_pos += TS * (m->pll_vel + 2.0 * bw * e);
}

static comm_cfg_t cfg_default(void)
{
    app_cfg_t ac;
    app_cfg_default(&ac);
    ac.comm.i_max_A = 5.56f;
    ac.comm.speed_max_rad_s = 209.4f;   /* 2000 r/min */
    return ac.comm;
}

/* Runs the sequence to its end; the outcome, the periods in *n. */
static app_step_t run_p(comm_t *c, const comm_cfg_t *cfg, motor_t *m, uint32_t *n, uint16_t p_told)
{
    static const double S3_2 = 0.8660254037844386;
    app_step_t r = app_step_running();
    comm_init(c, cfg, (float)TS, CPR, p_told);
    comm_start(c);
    for (*n = 0u; *n < PERIODS_MAX && r.status == APP_STEP_RUNNING; (*n)++) {
        ctrl_in_t in;
        ab_t u;
        in.ia_A = (float)m->ia;
        in.ib_A = (float)(-0.5 * m->ia + S3_2 * m->ib);
        in.vdc_V = (float)VDC;
        in.enc_count = count_of(m);
        r = comm_step(c, &in, (float)(m->dir * m->pll_vel), &u);
        motor_period(m);            /* the last call's voltage over this period */
        m->ua = (double)u.a;
        m->ub = m->acb ? -(double)u.b : (double)u.b;
    }
    return r;
}

/* The same, the controller told the motor's pole pairs. */
static app_step_t run(comm_t *c, const comm_cfg_t *cfg, motor_t *m, uint32_t *n)
{
    return run_p(c, cfg, m, n, P_T);
}

static double wrapped(double a)
{
    double d = fmod(a + PI_D, 2.0 * PI_D);
    return (d < 0.0 ? d + 2.0 * PI_D : d) - PI_D;
}

static void healthy_motor_is_measured(void **state)
{
    static comm_t c;
    motor_t m = { 0 };
    uint32_t n;
    const comm_cfg_t cfg = cfg_default();
    (void)state;
    m.dir = 1;
    const app_step_t r = run(&c, &cfg, &m, &n);
    printf("  %u periods: R %.4f L %.6f psi %.4f J %.6f B %.2e p %u offset %.4f\n", n, (double)c.res.R_Ohm,
           (double)c.res.L_H, (double)c.res.psi_f_Wb, (double)c.res.J_kgm2, (double)c.res.B_Nms, c.res.pole_pairs,
           (double)c.res.enc_offset_el_rad);
    assert_int_equal(r.status, APP_STEP_DONE);
    assert_int_equal(c.stage, COMM_STAGE_DONE);
    assert_true(fabs((double)c.res.R_Ohm / R_T - 1.0) < 0.03);
    assert_true(fabs((double)c.res.L_H / L_T - 1.0) < 0.03);
    assert_true(fabs((double)c.res.psi_f_Wb / PSI_T - 1.0) < 0.03);
    assert_true(fabs((double)c.res.J_kgm2 / J_T - 1.0) < 0.10);
    assert_int_equal(c.res.pole_pairs, P_T);
    assert_true(fabs(wrapped((double)c.res.enc_offset_el_rad - OFF_T)) < 2.0 * PI_D / 180.0);
    /* the speed PI from J^ by the default's rule: kp / J and ki / J as the default motor's */
    assert_float_equal(c.res.speed_kp_Nms_rad, cfg.speed_kp_per_J_1_s * c.res.J_kgm2, 1e-6);
    assert_float_equal(c.res.speed_ki_Nm_rad, cfg.speed_ki_per_J_1_s2 * c.res.J_kgm2, 1e-4);
}

/* enc_check.h's faults: the phase order in WIRING (a 200 Hz vector), the
 * direction and pole pairs in ENCODER's sweep of one mechanical turn (3
 * electrical turns): about CPR counts. */
static void reversed_encoder_is_named(void **state)
{
    static comm_t c;
    motor_t m = { 0 };
    uint32_t n;
    const comm_cfg_t cfg = cfg_default();
    (void)state;
    m.dir = -1;
    const app_step_t r = run(&c, &cfg, &m, &n);
    assert_int_equal(r.fault, APP_FAULT_ENCODER_DIRECTION);
    assert_int_equal(c.stage, COMM_STAGE_ENCODER);
    assert_float_equal(r.value, -(float)CPR, 0.01f * CPR);
    assert_float_equal(r.limit, 0.0f, 0.0f);
}

static void swapped_phase_pair_is_named(void **state)
{
    static comm_t c;
    motor_t m = { 0 };
    uint32_t n;
    const comm_cfg_t cfg = cfg_default();
    (void)state;
    m.dir = 1;
    m.acb = 1;
    const app_step_t r = run(&c, &cfg, &m, &n);
    assert_int_equal(r.fault, APP_FAULT_PHASE_ORDER);
    assert_int_equal(c.stage, COMM_STAGE_WIRING);
    assert_true(r.value > r.limit);   /* negative sequence above positive */
}

static void wrong_told_pole_pairs_are_named(void **state)
{
    static comm_t c;
    motor_t m = { 0 };
    uint32_t n;
    const comm_cfg_t cfg = cfg_default();
    (void)state;
    for (uint16_t p = P_T - 1; p <= P_T + 1; p += 2) {
        m = (motor_t){ 0 };
        m.dir = 1;
        const app_step_t r = run_p(&c, &cfg, &m, &n, p);
        assert_int_equal(r.fault, APP_FAULT_POLE_PAIRS);
        assert_int_equal(c.stage, COMM_STAGE_ENCODER);
        assert_float_equal(r.value, (float)P_T, 0.05f);   /* p^ from the counts */
        assert_float_equal(r.limit, (float)p, 0.0f);
    }
}

static void open_circuit_needs_too_much_voltage(void **state)
{
    static comm_t c;
    motor_t m = { 0 };
    uint32_t n;
    const comm_cfg_t cfg = cfg_default();
    (void)state;
    m.dir = 1;
    m.open = 1;
    const app_step_t r = run(&c, &cfg, &m, &n);
    assert_int_equal(r.fault, APP_FAULT_COMM_IMPLAUSIBLE);
    assert_int_equal(c.stage, COMM_STAGE_R);   /* WIRING sees no current of either sequence */
    assert_float_equal(r.limit, cfg.u_frac * VDC / sqrt(3.0), 1e-3);
    assert_true(r.value > r.limit);
}

static void a_stage_outlasting_its_timeout(void **state)
{
    static comm_t c;
    motor_t m = { 0 };
    uint32_t n;
    comm_cfg_t cfg = cfg_default();
    (void)state;
    m.dir = 1;
    cfg.r_max_s = 0.05f;              /* shorter than the first current's ramp */
    const app_step_t r = run(&c, &cfg, &m, &n);
    assert_int_equal(r.fault, APP_FAULT_COMM_TIMEOUT);
    assert_int_equal(c.stage, COMM_STAGE_R);
    assert_float_equal(r.limit, 0.05f, 0.0f);
    assert_true(r.value > r.limit);
    /* WIRING first: 0.3 s ramp, 0.1 s hold, 0.1 s of 200 Hz turns, each
     * phase ending in the call its time is complete in (3001 + 1001 + 1001
     * calls), then 0.05 s / Ts of R: the call after its 501st period */
    assert_int_equal(n, 5003u + 502u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(healthy_motor_is_measured),
        cmocka_unit_test(reversed_encoder_is_named),
        cmocka_unit_test(swapped_phase_pair_is_named),
        cmocka_unit_test(wrong_told_pole_pairs_are_named),
        cmocka_unit_test(open_circuit_needs_too_much_voltage),
        cmocka_unit_test(a_stage_outlasting_its_timeout),
    };
    return cmocka_run_group_tests_name("commission", tests, NULL, NULL);
}
