/* SIL: the app's commissioning (firmware/commission/commission.h) through
 * sil_run_ctl() on the paper's motor (Table I, ideal board), the
 * controller told no encoder offset (run.align = on) and R, L, psi_f
 * 1.5x, 0.7x, 1.2x off: the run ends in IDLE with the gates off, the
 * results valid and within the commissioning's tolerances, and the
 * measured offset taken by the controller as an alignment would. The
 * wrong boards of build level 3 end in the same faults from the same
 * module (enc_check.h), with the gates off: an encoder counting down
 * (ENCODER_DIRECTION, about -10000 counts over the mechanical turn of the
 * ENCODER sweep), told 4 or 2 pole pairs (POLE_PAIRS, p^ = 3), legs b and
 * c swapped (PHASE_ORDER in WIRING, before any current loop is closed).
 * The three motors and the refusals: tests/cli/test_commission.py. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>

#include "app.h"
#include "sil.h"

#define OFFSET_EL_RAD 2.0
#define TOL_REL 0.03               /* R, L, psi_f */
#define TOL_J_REL 0.10
#define TOL_OFFSET_EL_RAD 0.0349   /* 2 deg */
#define PI_D 3.141592653589793

static double last_pwm = -1.0;

static int on_row(const sil_row_t *row, void *user)
{
    (void)user;
    last_pwm = row->pwm;
    return 0;
}

static double wrapped_diff(double a, double b)
{
    double d = fmod(a - b + PI_D, 2.0 * PI_D);
    return (d < 0.0 ? d + 2.0 * PI_D : d) - PI_D;
}

static void commissions_the_paper_motor(void **state)
{
    static scenario_t sc;
    char err[SCENARIO_ERR_LEN];
    const char *sets[] = { "plant.encoder_offset_el_rad=2.0", "run.align=on", "run.log_every=1",
                           "controller.R_factor=1.5", "controller.L_factor=0.7", "controller.psif_factor=1.2" };
    sil_ctl_t ctl = { NULL, NULL, NULL, 0u, NULL, 1 };
    sil_result_t res;
    (void)state;
    scenario_defaults(&sc);
    for (size_t k = 0; k < sizeof sets / sizeof sets[0]; k++) {
        assert_int_equal(scenario_set(&sc, sets[k], err, sizeof err), 0);
    }
    assert_int_equal(scenario_finish(&sc, err, sizeof err), 0);
    assert_int_equal(sil_run_ctl(&sc, on_row, NULL, &ctl, &res), 0);
    assert_int_equal(res.comm_valid, 1);
    assert_int_equal(res.final_state, APP_STATE_IDLE);
    assert_int_equal(res.comm_stage, COMM_STAGE_DONE);
    assert_true(res.pwm_periods > 0u);
    assert_true(last_pwm == 0.0);                 /* gates off in the last period */
    assert_true(fabs(res.comm_R_ohm / sc.plant.R_ohm - 1.0) < TOL_REL);
    assert_true(fabs(res.comm_L_H / sc.plant.L_H - 1.0) < TOL_REL);
    assert_true(fabs(res.comm_psif_Wb / sc.plant.psif_Wb - 1.0) < TOL_REL);
    assert_true(fabs(res.comm_J_kgm2 / sc.plant.J_kgm2 - 1.0) < TOL_J_REL);
    assert_int_equal(res.comm_pole_pairs, sc.plant.pole_pairs);
    assert_true(fabs(wrapped_diff(res.comm_enc_offset_el_rad, OFFSET_EL_RAD)) < TOL_OFFSET_EL_RAD);
    /* the controller, told 0, now uses the measured offset */
    assert_true(fabs(wrapped_diff(res.enc_offset_el_rad, res.comm_enc_offset_el_rad)) < 1e-6);
    printf("  R %.4f L %.6f psi_f %.4f J %.6f p %u offset %.4f rad, %u periods\n", res.comm_R_ohm, res.comm_L_H,
           res.comm_psif_Wb, res.comm_J_kgm2, res.comm_pole_pairs, res.comm_enc_offset_el_rad, res.periods);
}

/* A commissioning of the paper motor's default scenario with one wrong part. */
static void wrong_board(const char *set, sil_result_t *res)
{
    static scenario_t sc;
    char err[SCENARIO_ERR_LEN];
    sil_ctl_t ctl = { NULL, NULL, NULL, 0u, NULL, 1 };
    scenario_defaults(&sc);
    assert_int_equal(scenario_set(&sc, "run.log_every=1", err, sizeof err), 0);
    assert_int_equal(scenario_set(&sc, set, err, sizeof err), 0);
    assert_int_equal(scenario_finish(&sc, err, sizeof err), 0);
    assert_int_equal(sil_run_ctl(&sc, on_row, NULL, &ctl, res), 0);
    printf("  %-28s fault %2d in stage %d: value %.4g, limit %.4g\n", set, res->final_fault, res->comm_stage,
           res->fault_value, res->fault_limit);
    assert_int_equal(res->comm_valid, 0);
    assert_int_equal(res->final_state, APP_STATE_FAULT);
    assert_int_equal(res->fault_state, APP_STATE_COMMISSION);
    assert_int_equal(res->gates_on_in_fault, 0u);
    assert_true(last_pwm == 0.0);
}

static void reversed_encoder_is_named(void **state)
{
    sil_result_t res;
    (void)state;
    wrong_board("plant.encoder_direction=-1", &res);
    assert_int_equal(res.final_fault, APP_FAULT_ENCODER_DIRECTION);
    assert_int_equal(res.comm_stage, COMM_STAGE_ENCODER);
    assert_float_equal(res.fault_value, -10000.0, 100.0);
}

static void wrong_pole_pairs_are_named(void **state)
{
    sil_result_t res;
    (void)state;
    wrong_board("controller.pole_pairs=4", &res);
    assert_int_equal(res.final_fault, APP_FAULT_POLE_PAIRS);
    assert_int_equal(res.comm_stage, COMM_STAGE_ENCODER);
    assert_float_equal(res.fault_value, 3.0, 0.01);
    assert_float_equal(res.fault_limit, 4.0, 0.0);
    wrong_board("controller.pole_pairs=2", &res);
    assert_int_equal(res.final_fault, APP_FAULT_POLE_PAIRS);
    assert_float_equal(res.fault_value, 3.0, 0.01);
    assert_float_equal(res.fault_limit, 2.0, 0.0);
}

static void swapped_phase_pair_is_named(void **state)
{
    sil_result_t res;
    (void)state;
    wrong_board("plant.phase_order=acb", &res);
    assert_int_equal(res.final_fault, APP_FAULT_PHASE_ORDER);
    assert_int_equal(res.comm_stage, COMM_STAGE_WIRING);
    assert_true(res.fault_value > 10.0 * res.fault_limit);   /* negative sequence against positive */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(commissions_the_paper_motor),
        cmocka_unit_test(reversed_encoder_is_named),
        cmocka_unit_test(wrong_pole_pairs_are_named),
        cmocka_unit_test(swapped_phase_pair_is_named),
    };
    return cmocka_run_group_tests_name("sil_commission", tests, NULL, NULL);
}
