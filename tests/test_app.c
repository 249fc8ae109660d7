/* Unit tests for firmware/app: the sequence that chains the start-up
 * steps (calibrate, align, run with hand values), the state transitions,
 * stops in each step, the ISR's HAL call order; against the cmocka mock
 * of the HAL (tests/mock_hal.c, tests/app_harness.h). Each step's own
 * tests: test_calib, test_align, test_rsid_seq, test_protect. */
#include "app_harness.h"
#include "drive_params.h"

/* ---- configuration ------------------------------------------------------ */

static void cfg_default_is_the_board(void **state)
{
    (void)state;
    app_cfg_t cfg;
    app_cfg_default(&cfg);
    assert_float_equal(cfg.ctrl.Ts_s, 1e-4, 1e-9);
    assert_float_equal(cfg.ctrl.R_Ohm, MOTOR_R_OHM, 0.0);
    assert_int_equal(cfg.ctrl.enc_lines, BOARD_ENC_LINES);
    assert_float_equal(cfg.prot.i_max_A, 14.0, 0.0); /* the reference design, to the bit */
    assert_float_equal(cfg.prot.vdc_max_V, BOARD_VDC_MAX_V, 0.0);
    assert_float_equal(cfg.prot.vdc_min_V, BOARD_VDC_MIN_V, 0.0);
    assert_float_equal(cfg.prot.speed_max_rad_s, SPEED_MAX, 1e-3);
    assert_int_equal(cfg.prot.isr_period_cycles, 15000u);
    assert_int_equal(cfg.prot.isr_budget_cycles, BOARD_ISR_BUDGET_CYCLES);
    assert_true(cfg.calibrate);
    assert_int_equal(cfg.cal.samples, BOARD_CAL_SAMPLES);
    assert_float_equal(cfg.cal.offset_max_A, BOARD_I_OFFSET_MAX_A, 0.0);
    assert_true(cfg.align == (BOARD_ENC_OFFSET_KNOWN == 0u));
    assert_float_equal(cfg.aln.u_V, 3.0 * MOTOR_R_OHM, 0.0); /* 3 A x 3 Ohm, to the bit */
    assert_float_equal(cfg.aln.prepos_el_rad, BOARD_ALIGN_PREPOS_EL_DEG * PI_F / 180.0f, 1e-6);
    assert_float_equal(cfg.aln.prepos_s, BOARD_ALIGN_PREPOS_S, 0.0);
    assert_float_equal(cfg.aln.settle_s, BOARD_ALIGN_SETTLE_S, 0.0);
}

/* ---- transitions ---------------------------------------------------------- */

static void init_is_init_with_pwm_off(void **state)
{
    (void)state;
    init_app();
    assert_int_equal(app.state, APP_STATE_INIT);
    assert_int_equal(app.fault, APP_FAULT_NONE);
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    isr_quiet(&s); /* INIT: no PWM call at all */
    assert_int_equal(app.state, APP_STATE_INIT);
    assert_int_equal(app.ticks, 1u);
    app_request_stop(&app); /* nothing to stop */
    isr_quiet(&s);
    assert_int_equal(app.state, APP_STATE_INIT);
}

/* main.c builds the cfg in app->cfg itself and passes it: app_init then
 * ends in the state a separate copy gives (cfg and controller alike). */
static void init_with_its_own_cfg_in_place(void **state)
{
    (void)state;
    static app_t in_place; /* large: not on the test's stack */
    const app_cfg_t cfg = make_cfg(false, false);
    init_app();
    in_place.cfg = cfg;
    expect_function_call(hal_pwm_disable);
    app_init(&in_place, &in_place.cfg);
    assert_memory_equal(&in_place.cfg, &app.cfg, sizeof cfg);
    assert_memory_equal(probe_ctrl_kept(&in_place), probe_ctrl_kept(&app), sizeof *probe_ctrl_kept(&app));
    assert_int_equal(ctrl_status(app_ctrl(&in_place)), ctrl_status(app_ctrl(&app)));
    assert_int_equal(in_place.state, APP_STATE_INIT);
}

/* INIT -> RUN -> IDLE -> RUN with both sequence steps off; a start while
 * running is ignored. */
static void start_runs_and_stop_idles(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(0.5f, -0.2f, VDC);
    start(&s);
    isr_run(&s);
    assert_true(isfinite(mock_hal_duty[0]) && mock_hal_duty[0] >= 0.0f && mock_hal_duty[0] <= 1.0f);
    assert_float_equal(mock_hal_duty[1], app.out.duty[1], 0.0); /* the controller's duties */
    app_request_start(&app);
    isr_run(&s);
    assert_int_equal(app.state, APP_STATE_RUN);
    assert_int_equal(app.req_start, 0u);

    isr_stop(&s);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_float_equal(mock_hal_duty[0], 0.5, 0.0);
    isr_quiet(&s);
    assert_int_equal(app.state, APP_STATE_IDLE);
    start(&s); /* IDLE -> RUN, outputs on again after the first duties */
}


/* INIT -> CALIBRATE -> ALIGN -> RUN: offsets from the hand values, the
 * alignment's two vectors period by period (hand duties), then the
 * aligned count reads 0 rad and RUN uses the corrected currents. */
static void sequence_calibrates_aligns_runs(void **state)
{
    (void)state;
    init_with(true, true);
    run_calibration(CAL_IA, CAL_IB, VDC);
    assert_int_equal(app.state, APP_STATE_ALIGN);
    assert_float_equal(app.offset_ia_A, 0.11, 1e-6);
    assert_float_equal(app.offset_ib_A, -0.04, 1e-6);
    assert_true(app.prot.uv_armed);

    hal_sample_t s = sample(0.5f, -0.25f, VDC);
    for (int k = 0; k <= ALIGN_END; k++) {
        if (k == 0) {
            isr_first_write(&s);
        } else {
            isr_run(&s);
        }
        float ua;
        float ub;
        float d[3];
        align_u(k, &ua, &ub);
        minmax_duty(ua, ub, VDC, d);
        for (int j = 0; j < 3; j++) {
            assert_float_equal(mock_hal_duty[j], d[j], 1e-6);
        }
        if (k < ALIGN_END) {
            assert_int_equal(app.state, APP_STATE_ALIGN);
        }
    }
    assert_int_equal(app.state, APP_STATE_RUN);
    assert_true(app.aligned);
    /* offset = -(electrical angle of COUNT0) = -((1234 * 3 mod 10000) + 1.5) * 2 pi / 10000:
     * 3702 electrical counts plus the centre of the count's interval (p/2) */
    assert_true(wrap_dist(ctrl_enc_offset_el_rad(app_ctrl(&app)), -3703.5f * 2.0f * PI_F / CPR) < 1e-5f);

    /* RUN: the aligned count reads 0 rad; the controller gets ia - 0.11, ib + 0.04 */
    hal_sample_t r = sample(0.61f, -0.34f, VDC);
    isr_run(&r);
    assert_int_equal(app.state, APP_STATE_RUN);
    assert_true(wrap_dist(app_monitor(&app)->theta_el_rad, 0.0f) < 1e-5f);
    assert_float_equal(app_monitor(&app)->id_A, 0.5, 1e-4); /* Park at 0 rad: id = ia */
}

/* A stop in CALIBRATE or ALIGN ends in IDLE with the outputs off. */
static void stop_during_calibrate_and_align(void **state)
{
    (void)state;
    init_with(true, true);
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    app_request_start(&app);
    isr_quiet(&s);
    assert_int_equal(app.state, APP_STATE_CALIBRATE);
    isr_stop(&s);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_float_equal(app.offset_ia_A, 0.0, 0.0); /* aborted: nothing taken */

    run_calibration(CAL_IA, CAL_IB, VDC);
    isr_first_write(&s);
    assert_int_equal(app.state, APP_STATE_ALIGN);
    isr_stop(&s);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_false(app.aligned);
}

/* ---- ISR call order ---------------------------------------------------- */

/* read -> protection (trip poll) -> ctrl_step -> write -> ack: the duties
 * written are the ones this call's ctrl_step computed from this call's
 * samples; a protection fault stops before ctrl_step and the write. */
static void isr_call_order(void **state)
{
    (void)state;
    init_app();
    count_now = 0u; /* angle 0 with offset 0: id = ia */
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    start(&s);
    hal_sample_t r = sample(2.0f, -1.0f, VDC);
    expect_function_call(hal_sample_read);
    will_return(hal_sample_read, &r);
    expect_function_call(hal_trip_active);
    will_return(hal_trip_active, 0);
    expect_function_call(hal_pwm_write);
    expect_function_call(hal_isr_ack);
    app_isr(&app);
    assert_float_equal(app_monitor(&app)->id_A, 2.0, 1e-3); /* ctrl_step saw this call's sample */
    for (int j = 0; j < 3; j++) {
        assert_float_equal(mock_hal_duty[j], app.out.duty[j], 0.0);
    }
    hal_sample_t bad = sample(5.0f, 0.0f, 500.0f);
    isr_fault(&bad, 0);
    /* no ctrl_step (no write, no reference): the monitor has this sample's readings all the same */
    assert_float_equal(app_monitor(&app)->id_A, 5.0, 1e-2); /* at the encoder's angle, about 0 */
    assert_float_equal(app_monitor(&app)->te_ref_Nm, 0.0, 0.0);
    assert_float_equal(app.vdc_V, 500.0, 0.0);
}

static void background_kicks_watchdog(void **state)
{
    (void)state;
    init_app();
    expect_function_call(hal_watchdog_kick);
    app_background(&app);
}

/* A new configuration (the link's parameters): due only while stopped; taken by
 * app_reconfigure_now, which rebuilds the controller from app->cfg (the speed PI's gain and the
 * model's L as written), keeps the operator's request and the encoder's offset in use, and
 * clears the request; in RUN it waits (not due), the running controller untouched. */
static void reconfigure_while_stopped(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(0.5f, -0.2f, VDC);
    start(&s);
    assert_int_equal(app.state, APP_STATE_RUN);
    const float kp0 = probe_speed_pi_cfg(&app)->Kp;
    app.cfg.ctrl.speed_kp_Nms_rad = 2.0f * kp0;
    app.cfg.ctrl.L_H = 1.5f * app.cfg.ctrl.L_H;
    app_request_reconfigure(&app, 0u);
    assert_false(app_reconfigure_due(&app));
    app_reconfigure_now(&app);                                  /* not due: nothing */
    assert_true(probe_speed_pi_cfg(&app)->Kp == kp0);
    isr_stop(&s);
    assert_int_equal(app.state, APP_STATE_IDLE);
    assert_true(app_reconfigure_due(&app));
    const float offset = ctrl_enc_offset_el_rad(app_ctrl(&app));
    const app_op_t op = app.op_taken;
    app_reconfigure_now(&app);
    assert_false(app_reconfigure_due(&app));
    assert_int_equal(app.req_reconfigure, 0u);
    assert_true(probe_speed_pi_cfg(&app)->Kp == 2.0f * kp0);
    assert_true(probe_model(&app)->L_H == app.cfg.ctrl.L_H);
    assert_true(ctrl_enc_offset_el_rad(app_ctrl(&app)) == offset);
    assert_int_equal(ctrl_mode(app_ctrl(&app)), op.mode);
    assert_int_equal(app.state, APP_STATE_IDLE);
}

/* A refused block the conventional method needs (the encoder's PLL at
 * 6000 rad/s: bandwidth x Ts 0.6 > 0.5) faults CONFIG at the start, in
 * the request's own call, with ctrl_init's refusals as the snapshot's
 * value and the PWM never enabled (isr_fault: no write, no enable). */
static void refused_block_faults_config_at_start(void **state)
{
    (void)state;
    for (int align = 0; align <= 1; align++) {
        app_cfg_t cfg = make_cfg(align != 0, align != 0);
        cfg.ctrl.enc_pll_bw_rad_s = 6000.0f;
        init_cfg(&cfg);
        assert_int_equal(ctrl_status(app_ctrl(&app)) & CTRL_CFG_ENCODER, CTRL_CFG_ENCODER);
        hal_sample_t s = sample(0.0f, 0.0f, VDC);
        app_request_start(&app);
        for (int k = 0; align != 0 && k < CAL_SETTLE + CAL_N - 1; k++) {
            isr_quiet(&s); /* calibration first (PWM off); the check after it */
        }
        isr_fault(&s, 0);
        assert_int_equal(app.fault, APP_FAULT_CONFIG);
        assert_float_equal(app.snapshot.value, (float)ctrl_status(app_ctrl(&app)), 0.0);
        assert_false(app.pwm_on);
    }
}

/* Ratings the drive cannot run (a rated current beyond the ADC range:
 * i_limit reaches the trip) fault CONFIG at the start, the refusal in the
 * snapshot's value above ctrl_init's bits, PWM never enabled. */
static void refused_ratings_fault_config_at_start(void **state)
{
    (void)state;
    app_cfg_t cfg = make_cfg(false, false);
    drive_params_t p;
    drive_params_board(&p);
    p.rating.i_rated_A = 10.0f;
    p.rating.i_peak_A = 20.0f;
    drive_params_to_app_cfg(&p, &cfg);
    assert_int_equal(cfg.params_refused, DRIVE_DERIVE_ADC_RANGE);
    init_cfg(&cfg);
    hal_sample_t s = sample(0.0f, 0.0f, VDC);
    app_request_start(&app);
    isr_fault(&s, 0);
    assert_int_equal(app.fault, APP_FAULT_CONFIG);
    assert_float_equal(app.snapshot.value,
                       (float)(ctrl_status(app_ctrl(&app)) | (DRIVE_DERIVE_ADC_RANGE << APP_PARAMS_REFUSED_SHIFT)), 0.0);
    assert_false(app.pwm_on);
}

/* Level 4: torque mode, the conventional method and 0.3 x the board's
 * current limit from its start; a start at level 5 gives back the
 * operator's speed mode (taken in the level-4 start's call, then
 * overridden by the level) and the configured limit (make_cfg: none, so i_max_A). Another level than 1..5
 * is not taken. */
static void level4_own_limit_and_mode_then_restored(void **state)
{
    (void)state;
    init_app();
    hal_sample_t s = sample(0.5f, -0.2f, VDC);
    app_op_t op = app.op_taken;
    op.mode = CTRL_MODE_SPEED; /* the operator's, taken in the start's ISR call before the start */
    app_request_op(&app, &op);
    app_request_level(&app, 7u);
    assert_int_equal(app.req_level, app.cfg.lvl.level);
    app_request_level(&app, LEVEL_TORQUE);
    start(&s);
    assert_int_equal(app.level, LEVEL_TORQUE);
    drive_params_t p;
    drive_params_board(&p);
    (void)drive_params_derive(&p);
    assert_float_equal(ctrl_i_lim_A(app_ctrl(&app)), BOARD_LEVEL4_I_LIMIT_PER_LIMIT * p.limits.i_limit_A, 1e-6);
    assert_int_equal(ctrl_mode(app_ctrl(&app)), CTRL_MODE_TORQUE);
    assert_int_equal(ctrl_method(app_ctrl(&app)), CTRL_METHOD_CONVENTIONAL);
    isr_stop(&s);
    app_request_level(&app, LEVEL_FULL);
    start(&s);
    assert_float_equal(ctrl_i_lim_A(app_ctrl(&app)), app.cfg.ctrl.i_max_A, 0.0);
    assert_int_equal(ctrl_mode(app_ctrl(&app)), CTRL_MODE_SPEED);
}

/* The board's image starts at build level 1, as TI's motor kits ship, and
 * levels 1-2 refuse a bus above 30 V (board_cfg.h: IEC 60364-4-41's SELV
 * limit for touchable parts outside dry conditions). */
static void board_starts_at_level_1_with_an_extra_low_bus_limit(void **state)
{
    (void)state;
    app_cfg_t cfg;
    app_cfg_default(&cfg);
    assert_int_equal(cfg.lvl.level, LEVEL_PWM);
    assert_float_equal(cfg.lvl.vdc_max_12_V, 30.0, 0.0);
    expect_function_call(hal_pwm_disable);
    app_init(&app, &cfg);
    assert_int_equal(app.req_level, LEVEL_PWM);
}

#define BUS_12_MAX_V 30.0f   /* app_cfg_default's, kept by make_cfg */

/* Levels 1 and 2 started on a charged bus: BUS_CHARGED in the start's own
 * ISR call, before any gate switches (no duty written, no enable), with
 * the bus and the limit in the snapshot; at the limit itself they start. */
static void levels_1_and_2_refuse_to_start_on_a_charged_bus(void **state)
{
    (void)state;
    for (uint16_t lvl = LEVEL_PWM; lvl <= LEVEL_ADC; lvl++) {
        init_app();
        const hal_sample_t s = sample(0.0f, 0.0f, VDC);
        app_request_level(&app, lvl);
        app_request_start(&app);
        isr_fault(&s, 0);
        assert_int_equal(app.fault, APP_FAULT_BUS_CHARGED);
        assert_float_equal(app.snapshot.value, VDC, 0.0);
        assert_float_equal(app.snapshot.limit, BUS_12_MAX_V, 0.0);
        assert_snapshot(&s, APP_STATE_INIT);
    }
    init_app();
    const hal_sample_t at = sample(0.0f, 0.0f, BUS_12_MAX_V);
    app_request_level(&app, LEVEL_PWM);
    app_request_start(&app);
    isr_first_write(&at);
    assert_int_equal(app.state, APP_STATE_PWM_CHECK);
}

/* A bus charged while level 1 switches (12 V, then 30.5 V) or level 2
 * reports: BUS_CHARGED in that period, level 1's duties not written. */
static void levels_1_and_2_stop_when_the_bus_charges(void **state)
{
    (void)state;
    const hal_sample_t low = sample(0.0f, 0.0f, 12.0f);
    const hal_sample_t high = sample(0.0f, 0.0f, BUS_12_MAX_V + 0.5f);
    init_app();
    app_request_level(&app, LEVEL_PWM);
    app_request_start(&app);
    isr_first_write(&low);
    isr_run(&low);
    isr_fault(&high, 0);
    assert_int_equal(app.fault, APP_FAULT_BUS_CHARGED);
    assert_snapshot(&high, APP_STATE_PWM_CHECK);

    init_with(true, false);
    app_request_level(&app, LEVEL_ADC);
    run_calibration(CAL_IA, CAL_IB, 12.0f);
    assert_int_equal(app.state, APP_STATE_ADC_CHECK);
    isr_quiet(&low);
    assert_float_equal(app.adc.vdc_V, 12.0, 0.0);
    isr_fault(&high, 0);
    assert_int_equal(app.fault, APP_FAULT_BUS_CHARGED);
    assert_snapshot(&high, APP_STATE_ADC_CHECK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cfg_default_is_the_board),
        cmocka_unit_test(refused_ratings_fault_config_at_start),
        cmocka_unit_test(init_is_init_with_pwm_off),
        cmocka_unit_test(init_with_its_own_cfg_in_place),
        cmocka_unit_test(start_runs_and_stop_idles),
        cmocka_unit_test(level4_own_limit_and_mode_then_restored),
        cmocka_unit_test(board_starts_at_level_1_with_an_extra_low_bus_limit),
        cmocka_unit_test(levels_1_and_2_refuse_to_start_on_a_charged_bus),
        cmocka_unit_test(levels_1_and_2_stop_when_the_bus_charges),
        cmocka_unit_test(sequence_calibrates_aligns_runs),
        cmocka_unit_test(stop_during_calibrate_and_align),
        cmocka_unit_test(isr_call_order),
        cmocka_unit_test(background_kicks_watchdog),
        cmocka_unit_test(reconfigure_while_stopped),
        cmocka_unit_test(refused_block_faults_config_at_start),
    };
    return cmocka_run_group_tests_name("app", tests, NULL, NULL);
}
