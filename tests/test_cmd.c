/* Unit tests for firmware/cmd: the operator's command block is checked
 * field by field, references reach the controller in SI units (through
 * the app's request, taken by the ISR at the start of its next period;
 * nothing before it), a refused
 * field keeps the previous command and is named, start/stop and fault
 * reset are sent once per change. Runs against the cmocka HAL mock. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "app.h"
#include "app_probe.h"
#include "cmd.h"
#include "mock_hal.h"

#define RPM_500_RAD_S 52.35987755982988  /* 500 * 2 pi / 60 */
#define TOL 1e-5

static const cmd_limits_t LIM = { 2000.0f, 12.0f, 300.0f };
static app_t app;          /* large: not on the stack */
static comm_t comm;        /* its commissioning state (app_attach_comm) */
static volatile cmd_t cmd;

static int setup(void **state)
{
    app_cfg_t cfg;
    (void)state;
    app_cfg_default(&cfg);
    expect_function_call(hal_pwm_disable);
    app_init(&app, &cfg);
    app_attach_comm(&app, &comm);
    cmd_init(&cmd);
    return 0;
}

static void run_change_sends_one_start_then_one_stop(void **state)
{
    (void)state;
    cmd.run = 1u;
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(app.req_start, 1u);
    app.req_start = 0u;
    cmd_apply(&cmd, &LIM, &app); /* unchanged: no second start */
    assert_int_equal(app.req_start, 0u);
    assert_int_equal(app.req_stop, 0u);
    cmd.run = 0u;
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(app.req_stop, 1u);
    assert_int_equal(cmd.error, CMD_OK);
}

/* cmd_apply in the background, then the ISR call that takes the request
 * at the start of its period (INIT: read, trip poll, ack). */
static void apply(void)
{
    static hal_sample_t s = { 0.0f, 0.0f, 311.0f, 0u };
    cmd_apply(&cmd, &LIM, &app);
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, &s);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
}

static void references_reach_the_controller_in_si_units(void **state)
{
    const ctrl_ref_t *ref = ctrl_ref(app_ctrl(&app));
    (void)state;
    cmd.speed_ref_rpm = 500.0f;
    cmd.te_ref_Nm = -4.0f;
    cmd.ud_ref_V = 12.5f;
    cmd.uq_ref_V = -60.0f;
    cmd.mode = (uint16_t)CTRL_MODE_TORQUE;
    cmd_apply(&cmd, &LIM, &app);
    assert_float_equal(ref->te_ref_Nm, 0.0, 0.0); /* nothing before the ISR */
    assert_int_equal(app.req_op, 1u);
    apply();
    assert_int_equal(app.req_op, 0u);
    assert_float_equal(ref->speed_ref_rad_s, RPM_500_RAD_S, TOL);
    assert_float_equal(ref->te_ref_Nm, -4.0, TOL);
    assert_float_equal(ref->ud_ref_V, 12.5, TOL);
    assert_float_equal(ref->uq_ref_V, -60.0, TOL);
    assert_int_equal(ctrl_mode(app_ctrl(&app)), CTRL_MODE_TORQUE);
    assert_int_equal(cmd.error, CMD_OK);
}

static void refused_reference_keeps_the_old_value_and_is_named(void **state)
{
    const ctrl_ref_t *ref = ctrl_ref(app_ctrl(&app));
    (void)state;
    cmd.speed_ref_rpm = 500.0f;
    cmd.te_ref_Nm = 4.0f;
    apply();

    cmd.speed_ref_rpm = NAN;
    apply();
    assert_int_equal(cmd.error, CMD_ERR_SPEED);
    assert_float_equal(ref->speed_ref_rad_s, RPM_500_RAD_S, TOL);

    cmd.speed_ref_rpm = 2000.5f; /* just beyond the limit */
    apply();
    assert_int_equal(cmd.error, CMD_ERR_SPEED);
    assert_float_equal(ref->speed_ref_rad_s, RPM_500_RAD_S, TOL);

    cmd.speed_ref_rpm = 500.0f;
    cmd.te_ref_Nm = 12.01f;
    apply();
    assert_int_equal(cmd.error, CMD_ERR_TORQUE);
    assert_float_equal(ref->te_ref_Nm, 4.0, TOL);

    cmd.te_ref_Nm = 4.0f;
    cmd.uq_ref_V = INFINITY;
    apply();
    assert_int_equal(cmd.error, CMD_ERR_VOLTAGE);
    assert_float_equal(ref->uq_ref_V, 0.0, TOL);

    cmd.uq_ref_V = 0.0f; /* all valid again: the error clears */
    apply();
    assert_int_equal(cmd.error, CMD_OK);
}

static void unknown_method_or_mode_is_refused(void **state)
{
    (void)state;
    cmd.method = 7u;
    apply();
    assert_int_equal(cmd.error, CMD_ERR_METHOD);
    assert_int_equal(ctrl_method(app_ctrl(&app)), CTRL_METHOD_CONVENTIONAL);

    cmd.method = (uint16_t)CTRL_METHOD_CONVENTIONAL;
    cmd.mode = 3u;
    apply();
    assert_int_equal(cmd.error, CMD_ERR_MODE);
    assert_int_equal(ctrl_mode(app_ctrl(&app)), CTRL_MODE_SPEED);
}

/* Step 1 off (the board's default BOARD_RSID_MODE 0): the proposed method
 * would control as the conventional one, so it is refused by name. */
static void proposed_method_without_step1_is_refused(void **state)
{
    (void)state;
    assert_int_equal(app.cfg.rsid.mode, APP_RSID_OFF);
    cmd.method = (uint16_t)CTRL_METHOD_PROPOSED;
    apply();
    assert_int_equal(cmd.error, CMD_ERR_METHOD_NO_STEP1);
    assert_int_equal(ctrl_method(app_ctrl(&app)), CTRL_METHOD_CONVENTIONAL);
    /* trusted R is an explicit choice: taken */
    app.cfg.rsid.mode = APP_RSID_TRUSTED;
    apply();
    assert_int_equal(cmd.error, CMD_OK);
    assert_int_equal(ctrl_method(app_ctrl(&app)), CTRL_METHOD_PROPOSED);
    /* and refused again once step 1 is off */
    cmd.method = (uint16_t)CTRL_METHOD_CONVENTIONAL;
    apply();
    app.cfg.rsid.mode = APP_RSID_OFF;
    cmd.method = (uint16_t)CTRL_METHOD_PROPOSED;
    apply();
    assert_int_equal(cmd.error, CMD_ERR_METHOD_NO_STEP1);
    assert_int_equal(ctrl_method(app_ctrl(&app)), CTRL_METHOD_CONVENTIONAL);
    /* step 1 configured but refused at this start (on_refusal = conventional): refused too */
    app.cfg.rsid.mode = APP_RSID_WINDOWS;
    app.cfg.rsid.on_refusal = APP_RSID_REFUSAL_CONVENTIONAL;
    app.warnings = APP_WARN_STEP1_REFUSED;
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(cmd.error, CMD_ERR_METHOD_NO_STEP1);
    assert_int_equal(ctrl_method(app_ctrl(&app)), CTRL_METHOD_CONVENTIONAL);
    /* ... with on_refusal = told step 2 runs from the told R: taken */
    app.cfg.rsid.on_refusal = APP_RSID_REFUSAL_TOLD;
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(cmd.error, CMD_OK);
}

static void proposed_method_is_taken_or_refused_by_its_configuration(void **state)
{
    (void)state;
    app.cfg.rsid.mode = APP_RSID_WINDOWS; /* step 1 configured */
    cmd.method = (uint16_t)CTRL_METHOD_PROPOSED;
    apply();
    assert_int_equal(ctrl_status(app_ctrl(&app)), CTRL_CFG_OK); /* board defaults pass (36) and the stability bound */
    assert_int_equal(cmd.error, CMD_OK);
    assert_int_equal(ctrl_method(app_ctrl(&app)), CTRL_METHOD_PROPOSED);

    cmd.method = (uint16_t)CTRL_METHOD_CONVENTIONAL;
    apply();
    probe_set_status(&app, EST_CFG_OBSERVER); /* as if smo_init had refused the gains */
    cmd.method = (uint16_t)CTRL_METHOD_PROPOSED;
    apply();
    assert_int_equal(cmd.error, CMD_ERR_METHOD_CFG);
    assert_int_equal(ctrl_method(app_ctrl(&app)), CTRL_METHOD_CONVENTIONAL);
}

static void fault_reset_is_passed_once_and_cleared(void **state)
{
    (void)state;
    app.state = APP_STATE_FAULT; /* as if a protection check had latched one */
    cmd.fault_reset = 1u;
    expect_function_call(hal_trip_clear);
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(app.req_fault_reset, 1u);
    assert_int_equal(cmd.fault_reset, 0u);
    app.req_fault_reset = 0u;
    cmd_apply(&cmd, &LIM, &app); /* no second reset: hal_trip_clear not expected */
    assert_int_equal(app.req_fault_reset, 0u);
}

/* D2: a reset written while nothing is latched is dropped: no
 * hal_trip_clear (it would force the outputs off under a running drive;
 * the mock fails on any unexpected call) and no request left for the ISR
 * to take when the next fault comes. */
static void fault_reset_outside_fault_is_dropped(void **state)
{
    (void)state;
    const app_state_t states[] = { APP_STATE_INIT, APP_STATE_IDLE, APP_STATE_CALIBRATE,
                                   APP_STATE_ALIGN, APP_STATE_IDENTIFY_R, APP_STATE_RUN };
    for (size_t k = 0; k < sizeof states / sizeof states[0]; k++) {
        app.state = states[k];
        cmd.fault_reset = 1u;
        cmd_apply(&cmd, &LIM, &app);
        assert_int_equal(app.req_fault_reset, 0u);
        assert_int_equal(cmd.fault_reset, 0u);
    }
}

/* start = 1 is a request while stopped, never while run = 1 (the drive
 * would be asked to start and commission at once); it is set back to 0
 * either way. */
static void commission_is_requested_only_while_stopped(void **state)
{
    static volatile cmd_comm_t cc;
    (void)state;
    cmd_comm_init(&cc);
    cc.start = 1u;
    cmd_comm_apply(&cc, &cmd, &app);
    assert_int_equal(app.req_commission, 1u);
    assert_int_equal(cc.start, 0u);
    app.req_commission = 0u;
    cmd.run = 1u;
    cmd_apply(&cmd, &LIM, &app);
    cc.start = 1u;
    cmd_comm_apply(&cc, &cmd, &app);
    assert_int_equal(app.req_commission, 0u);
    assert_int_equal(cc.start, 0u);
    assert_int_equal(app.req_start, 1u);
}

/* The report: nothing, running with its stage, the values once valid, a
 * refusal's fault with value and limit, which stays after a reset. */
static void commission_report_follows_the_app(void **state)
{
    static volatile cmd_comm_t rep;
    (void)state;
    cmd_comm_init(&rep);
    cmd_comm_apply(&rep, &cmd, &app);
    assert_int_equal(rep.state, 0u);
    app.state = APP_STATE_COMMISSION;
    app.comm->stage = COMM_STAGE_L;
    cmd_comm_apply(&rep, &cmd, &app);
    assert_int_equal(rep.state, 1u);
    assert_int_equal(rep.stage, (uint16_t)COMM_STAGE_L);
    app.state = APP_STATE_IDLE;
    app.comm_valid = true;
    app.comm->stage = COMM_STAGE_DONE;
    app.comm->res.R_Ohm = 2.5f;
    app.comm->res.pole_pairs = 4u;
    app.comm->res.J_kgm2 = 0.01f;
    cmd_comm_apply(&rep, &cmd, &app);
    assert_int_equal(rep.state, 2u);
    assert_float_equal(rep.R_Ohm, 2.5f, 0.0f);
    assert_int_equal(rep.pole_pairs, 4u);
    assert_float_equal(rep.J_kgm2, 0.01f, 0.0f);
    app.comm_valid = false;
    app.comm->stage = COMM_STAGE_ENCODER;
    app.state = APP_STATE_FAULT;
    app.fault = APP_FAULT_COMM_NO_ROTATION;
    app.snapshot.state = APP_STATE_COMMISSION;
    app.snapshot.value = 3.0f;
    app.snapshot.limit = 156.25f;
    cmd_comm_apply(&rep, &cmd, &app);
    assert_int_equal(rep.state, 3u);
    assert_int_equal(rep.fault, (uint16_t)APP_FAULT_COMM_NO_ROTATION);
    assert_int_equal(rep.stage, (uint16_t)COMM_STAGE_ENCODER);
    assert_float_equal(rep.fault_value, 3.0f, 0.0f);
    assert_float_equal(rep.fault_limit, 156.25f, 0.0f);
    app.state = APP_STATE_IDLE; /* reset: the refusal stays reported */
    cmd_comm_apply(&rep, &cmd, &app);
    assert_int_equal(rep.state, 3u);
}

/* The build level: 1..5 asked for the next start, 0 keeps the app's, 6
 * refused (CMD_ERR_LEVEL, the last request kept); the reports copied. */
static void level_requested_and_reported(void **state)
{
    (void)state;
    assert_int_equal(app.req_level, app.cfg.lvl.level); /* at power-on: the board's */
    cmd.level = 3u;
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(cmd.error, CMD_OK);
    assert_int_equal(app.req_level, 3u);
    cmd.level = 6u;
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(cmd.error, CMD_ERR_LEVEL);
    assert_int_equal(app.req_level, 3u);
    cmd.level = 0u;
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(cmd.error, CMD_OK);
    assert_int_equal(app.req_level, 3u);
    app.adc.ia_A = 0.125f;
    app.adc.ib_A = -0.25f;
    app.adc.vdc_V = 1.5f;
    app.offset_ia_A = 0.0625f;
    app.offset_ib_A = -0.03125f;
    app.rot.out.counts = -10000;
    app.rot.out.pole_pairs_est = 3.0f;
    cmd_apply(&cmd, &LIM, &app);
    assert_int_equal(cmd.level_now, app.cfg.lvl.level); /* no start yet */
    assert_float_equal(cmd.ia_adc_A, 0.125, 0.0);
    assert_float_equal(cmd.ib_adc_A, -0.25, 0.0);
    assert_float_equal(cmd.vdc_adc_V, 1.5, 0.0);
    assert_float_equal(cmd.ia_offset_A, 0.0625, 0.0);
    assert_float_equal(cmd.ib_offset_A, -0.03125, 0.0);
    assert_int_equal(cmd.enc_counts, -10000);
    assert_float_equal(cmd.pole_pairs_est, 3.0, 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup(level_requested_and_reported, setup),
        cmocka_unit_test_setup(run_change_sends_one_start_then_one_stop, setup),
        cmocka_unit_test_setup(references_reach_the_controller_in_si_units, setup),
        cmocka_unit_test_setup(refused_reference_keeps_the_old_value_and_is_named, setup),
        cmocka_unit_test_setup(unknown_method_or_mode_is_refused, setup),
        cmocka_unit_test_setup(proposed_method_without_step1_is_refused, setup),
        cmocka_unit_test_setup(proposed_method_is_taken_or_refused_by_its_configuration, setup),
        cmocka_unit_test_setup(fault_reset_is_passed_once_and_cleared, setup),
        cmocka_unit_test_setup(fault_reset_outside_fault_is_dropped, setup),
        cmocka_unit_test_setup(commission_is_requested_only_while_stopped, setup),
        cmocka_unit_test_setup(commission_report_follows_the_app, setup),
    };
    return cmocka_run_group_tests_name("cmd", tests, NULL, NULL);
}
