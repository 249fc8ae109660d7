/* Unit tests for control/est: the estimation's one output. While step 2
 * does not run it is the told model on the conventional path with
 * est_hold NO_STEP2; step 2 with a trusted R gives the observer's model
 * above the speed floor and the told one (the conventional path, no
 * inverter compensation) below it; a refused start or a finish without a
 * step 1 changes nothing. Expected values from the told configuration
 * and est.h's rules. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "ctrl.h"
#include "est_defaults.h"
#include "est.h"

#define TS   1e-4f
#define RS   3.0f
#define LS   0.011f
#define PSIF 0.24f

static est_t e;

static void init(void)
{
    ctrl_cfg_t c = { .Ts_s = TS, .R_Ohm = RS, .L_H = LS, .psi_f_Wb = PSIF, .pole_pairs = 3u,
                     .i_max_A = 60.0f, .u_max_V = 500.0f, .omega_max_el_rad_s = 3000.0f, .psi_max_Wb = 1.0f };
    float R_min;
    float R_max;
    test_est_band_default(&c, &R_min, &R_max);
    test_est_defaults(&c, R_min, R_max);
    est_told_t told;
    ctrl_cfg_told(&c, &told);
    told.deadtime_s = 0.0f;
    assert_int_equal(est_init(&e, &c.est_cfg, &told), EST_CFG_OK);
}

/* n periods at a held operating point: i = (0, iq), w, the voltage of
 * the told model's steady state u = (-w L iq, R iq + w psi_f). */
static void run(int n, float iq, float w)
{
    zoh_turn_t turn;
    zoh_turn(w * TS, w, &turn);
    est_in_t in = { .i_dq_A = { 0.0f, iq }, .omega_el_rad_s = w, .turn = &turn, .sin_el = 0.0f, .cos_el = 1.0f,
                    .u_V = { -w * LS * iq, RS * iq + w * PSIF }, .vdc_V = 311.0f, .te_ref_Nm = 2.0f,
                    .voltage_limited = false };
    for (int k = 0; k < n; k++) {
        est_step(&e, &in);
    }
}

static void off_is_the_told_model(void **state)
{
    (void)state;
    init();
    run(10, 2.0f, 157.0f);
    const est_out_t *o = est_output(&e);
    assert_int_equal(o->phase, EST_OFF);
    assert_int_equal(o->src, EST_SRC_TOLD);
    assert_int_equal(o->hold, EST_HOLD_NO_STEP2);
    assert_float_equal(o->R_Ohm, RS, 0.0);
    assert_float_equal(o->L_H, LS, 0.0);
    assert_float_equal(o->psi_f_Wb, PSIF, 0.0);
    assert_float_equal(o->inv_dv_V, 0.0, 0.0);
    assert_float_equal(est_f_V(&e).q, 0.0, 0.0);
    /* no step 1 under way: a finish refuses and stays off */
    assert_int_equal(est_rsid_finish(&e), RS_IDENT_TOO_FEW);
    assert_int_equal(est_output(&e)->phase, EST_OFF);
    /* an R outside the band is refused */
    assert_false(est_start_trusted(&e, 100.0f * RS));
    assert_int_equal(est_output(&e)->phase, EST_OFF);
}

static void trusted_start_above_and_below_the_floor(void **state)
{
    (void)state;
    init();
    assert_true(est_start_trusted(&e, 1.1f * RS));
    /* 500 r/min (157 rad/s el), the told model exact: above the floor the
     * observer's model, R the trusted one */
    run(200, 2.0f, 157.0f);
    const est_out_t *o = est_output(&e);
    assert_int_equal(o->phase, EST_STEP2);
    assert_int_equal(o->hold & EST_HOLD_SPEED_FLOOR, 0u);
    assert_true(o->src != EST_SRC_TOLD);
    assert_float_equal(o->R_Ohm, 1.1 * RS, 1e-6);
    /* at standstill (|w| <= w_min): the floor at once; the model taken
     * above it is kept (trusted), eq. (10) */
    run(1, 2.0f, 0.0f);
    o = est_output(&e);
    assert_int_equal(o->hold & EST_HOLD_SPEED_FLOOR, EST_HOLD_SPEED_FLOOR);
    assert_int_equal(o->src, EST_SRC_HELD);
    assert_float_equal(o->R_Ohm, 1.1 * RS, 1e-6);
    assert_int_equal(o->moved, 0u);
}

static void floor_before_any_trusted_model_is_the_told_one(void **state)
{
    (void)state;
    init();
    assert_true(est_start_trusted(&e, 1.1f * RS));
    /* step 2 starts at standstill: nothing taken above the floor yet */
    run(5, 2.0f, 0.0f);
    const est_out_t *o = est_output(&e);
    assert_int_equal(o->hold & EST_HOLD_SPEED_FLOOR, EST_HOLD_SPEED_FLOOR);
    assert_int_equal(o->src, EST_SRC_TOLD);
    assert_float_equal(o->R_Ohm, RS, 0.0);
    assert_float_equal(o->inv_dv_V, 0.0, 0.0);
    /* reset: off, told */
    est_reset(&e);
    assert_int_equal(est_output(&e)->phase, EST_OFF);
    assert_int_equal(est_output(&e)->hold, EST_HOLD_NO_STEP2);
}

/* The oscillation watch's cut L^ (est_hold_oscillation) above the speed
 * floor: L^ at L_scale of its value, taken at once, held, and said in
 * est_hold (EST_HOLD_OSCILLATION: the app's warning reads it) while the
 * model is the observer's. */
static void oscillation_cut_is_said_above_the_floor(void **state)
{
    (void)state;
    init();
    assert_true(est_start_trusted(&e, RS));
    run(200, 2.0f, 157.0f);
    assert_int_equal(est_output(&e)->hold & EST_HOLD_SPEED_FLOOR, 0u);
    est_hold_oscillation(&e, 0.5f, 157.0f, 2.0f);
    run(1, 2.0f, 157.0f);
    const est_out_t *o = est_output(&e);
    assert_int_equal(o->hold & EST_HOLD_OSCILLATION, EST_HOLD_OSCILLATION);
    assert_true(o->src != EST_SRC_TOLD);
    assert_float_equal(o->L_H, 0.5 * LS, 0.05 * LS);
    run(200, 2.0f, 157.0f);
    assert_int_equal(est_output(&e)->hold & EST_HOLD_OSCILLATION, EST_HOLD_OSCILLATION);
}

/* Every est_hold bit has a name, and the reason of a set of bits is its
 * most telling one: a refused step 1 over step 2 not running, an
 * unmeasured inverter over the speed floor, any told-model reason over
 * the step-2 gate's transients; a bit nobody named has none. */
static void every_hold_bit_is_named(void **state)
{
    (void)state;
    static const struct {
        uint16_t bit;
        const char *name;
    } names[] = {
        { EST_HOLD_ACCEL, "ACCEL" }, { EST_HOLD_CURRENT, "CURRENT" }, { EST_HOLD_TORQUE, "TORQUE" },
        { EST_HOLD_VOLTAGE, "VOLTAGE" }, { EST_HOLD_SETTLE, "SETTLE" }, { EST_HOLD_SPEED_FLOOR, "SPEED_FLOOR" },
        { EST_HOLD_NO_STEP2, "NO_STEP2" }, { EST_HOLD_ANGLE, "ANGLE" },
        { EST_HOLD_STEP1_REFUSED, "STEP1_REFUSED" }, { EST_HOLD_INVERTER_UNKNOWN, "INVERTER_UNKNOWN" },
        { EST_HOLD_OSCILLATION, "OSCILLATION" },
    };
    assert_int_equal(sizeof names / sizeof names[0], EST_HOLD_NAMES_N);
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
        assert_string_equal(est_hold_name(names[k].bit), names[k].name);
        assert_string_equal(est_hold_reason(names[k].bit), names[k].name);
    }
    assert_string_equal(est_hold_name(0x8000u), "");
    assert_string_equal(est_hold_reason(0u), "");
    assert_string_equal(est_hold_reason(EST_HOLD_NO_STEP2 | EST_HOLD_STEP1_REFUSED), "STEP1_REFUSED");
    assert_string_equal(est_hold_reason(EST_HOLD_OSCILLATION | EST_HOLD_SPEED_FLOOR), "OSCILLATION");
    assert_string_equal(est_hold_reason(EST_HOLD_SPEED_FLOOR | EST_HOLD_INVERTER_UNKNOWN), "INVERTER_UNKNOWN");
    assert_string_equal(est_hold_reason(EST_HOLD_SPEED_FLOOR | EST_HOLD_CURRENT | EST_HOLD_SETTLE), "SPEED_FLOOR");
    assert_int_equal(est_hold_reason_bit(EST_HOLD_TORQUE | EST_HOLD_ACCEL), EST_HOLD_TORQUE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_hold_bit_is_named),
        cmocka_unit_test(off_is_the_told_model),
        cmocka_unit_test(trusted_start_above_and_below_the_floor),
        cmocka_unit_test(floor_before_any_trusted_model_is_the_told_one),
        cmocka_unit_test(oscillation_cut_is_said_above_the_floor),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
