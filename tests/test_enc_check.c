/* Unit tests for firmware/enc_check: the encoder and the wiring judged
 * against a commanded rotation, on hand-made periods: 100 periods per
 * electrical turn, a 10000-count encoder, a current of 2 A turning with
 * (or against) the commanded vector. Expected figures by hand:
 *   one mechanical turn of a 3-pole-pair motor told 3: 3 electrical turns
 *   (6 pi), 10000 counts, p^ = (6 pi / 2 pi) x 10000 / 10000 = 3;
 *   told 4: 4 electrical turns (8 pi) turn the 3-pole-pair rotor 4/3 of a
 *   turn, 13333 counts, p^ = 4 x 10000 / 13333 = 3.0001 -> POLE_PAIRS;
 *   the band over 6 pi: |p^ - 3| <= 3 pi / (6 pi) = 0.5. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>

#include "enc_check.h"

#define CPR        10000u
#define TURN       100          /* periods per electrical turn */
#define I_A        2.0
#define PI_D       3.14159265358979323846

typedef struct {
    uint16_t p_told;            /* the controller's pole pairs */
    int el_turns;               /* commanded electrical turns */
    double counts_total;        /* the count's travel over them (signed) */
    uint32_t count0;            /* the count at the start */
    int current_sign;           /* +1: i turns with the vector, -1: against it */
} run_t;

/* The check over the run; the verdict and *out. */
static app_step_t check(const run_t *r, enc_check_out_t *out)
{
    const enc_check_cfg_t cfg = { CPR, r->p_told };
    const int n = r->el_turns * TURN;
    const double dth = 2.0 * PI_D / TURN;
    enc_check_t e;
    enc_check_init(&e, &cfg);
    enc_check_start(&e, r->count0);
    for (int k = 1; k <= n; k++) {
        const double th = dth * (double)(k - 1);   /* the vector the currents answer */
        const double travel = floor(r->counts_total * (double)k / (double)n + 0.5);
        const long long c = ((long long)r->count0 + (long long)travel) % CPR;
        const uint32_t count = (uint32_t)((c < 0) ? c + CPR : c);
        const double ia = I_A * cos(r->current_sign * th);
        const double ib = I_A * sin(r->current_sign * th);
        enc_check_step(&e, (float)dth, (float)cos(th), (float)sin(th), (float)ia, (float)ib, count);
    }
    return enc_check_verdict(&e, out);
}

static void right_board_passes(void **state)
{
    (void)state;
    const run_t r = { 3u, 3, 10000.0, 9990u, 1 }; /* through the wrap at 10000 */
    enc_check_out_t o;
    const app_step_t v = check(&r, &o);
    assert_int_equal(v.status, APP_STEP_DONE);
    assert_int_equal(o.counts, 10000);
    assert_float_equal(o.angle_el_rad, 6.0 * PI_D, 1e-4);
    assert_float_equal(o.pole_pairs_est, 3.0, 1e-4);
    assert_float_equal(o.i_pos_A, I_A, 1e-4);
    assert_float_equal(o.i_neg_A, 0.0, 1e-4);
}

static void reversed_encoder_is_named(void **state)
{
    (void)state;
    const run_t r = { 3u, 3, -10000.0, 5u, 1 };
    enc_check_out_t o;
    const app_step_t v = check(&r, &o);
    assert_int_equal(v.status, APP_STEP_FAULT);
    assert_int_equal(v.fault, APP_FAULT_ENCODER_DIRECTION);
    assert_float_equal(v.value, -10000.0, 0.0);
    assert_float_equal(v.limit, 0.0, 0.0);
}

static void still_encoder_is_a_direction_fault(void **state)
{
    (void)state;
    const run_t r = { 3u, 3, 0.0, 1234u, 1 };
    enc_check_out_t o;
    const app_step_t v = check(&r, &o);
    assert_int_equal(v.fault, APP_FAULT_ENCODER_DIRECTION);
    assert_float_equal(o.pole_pairs_est, 0.0, 0.0);
}

static void wrong_pole_pairs_are_named(void **state)
{
    (void)state;
    const run_t r = { 4u, 4, 40000.0 / 3.0, 0u, 1 };
    enc_check_out_t o;
    const app_step_t v = check(&r, &o);
    assert_int_equal(v.status, APP_STEP_FAULT);
    assert_int_equal(v.fault, APP_FAULT_POLE_PAIRS);
    assert_float_equal(v.value, 4.0 * 10000.0 / 13333.0, 1e-4);
    assert_float_equal(v.limit, 4.0, 0.0);
}

/* The band's edges: p^ 3.4 passes, 3.6 does not (counts 30000 / p^). */
static void pole_pair_band_is_half_a_pair_over_a_turn(void **state)
{
    (void)state;
    enc_check_out_t o;
    const run_t in = { 3u, 3, 30000.0 / 3.4, 0u, 1 };
    assert_int_equal(check(&in, &o).status, APP_STEP_DONE);
    assert_float_equal(o.pole_pairs_est, 3.4, 1e-3);
    const run_t out = { 3u, 3, 30000.0 / 3.6, 0u, 1 };
    assert_int_equal(check(&out, &o).fault, APP_FAULT_POLE_PAIRS);
    assert_float_equal(o.pole_pairs_est, 3.6, 1e-3);
}

/* Legs swapped before the sensors: the current turns against the vector
 * (and the rotor with it); the phase order is named, not the encoder. */
static void swapped_phases_are_named_first(void **state)
{
    (void)state;
    const run_t r = { 3u, 3, -10000.0, 0u, -1 };
    enc_check_out_t o;
    const app_step_t v = check(&r, &o);
    assert_int_equal(v.status, APP_STEP_FAULT);
    assert_int_equal(v.fault, APP_FAULT_PHASE_ORDER);
    assert_float_equal(v.value, I_A, 1e-4);   /* negative sequence */
    assert_float_equal(v.limit, 0.0, 1e-4);   /* positive sequence */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(right_board_passes),
        cmocka_unit_test(reversed_encoder_is_named),
        cmocka_unit_test(still_encoder_is_a_direction_fault),
        cmocka_unit_test(wrong_pole_pairs_are_named),
        cmocka_unit_test(pole_pair_band_is_half_a_pair_over_a_turn),
        cmocka_unit_test(swapped_phases_are_named_first),
    };
    return cmocka_run_group_tests_name("enc_check", tests, NULL, NULL);
}
