/* enc_check.c - encoder and wiring checked against a commanded rotation; see enc_check.h. */
#include "enc_check.h"

#include "mathx.h"

void enc_check_init(enc_check_t *e, const enc_check_cfg_t *cfg)
{
    e->cfg = *cfg;
    enc_check_start(e, 0u);
}

FLASHFUNC void enc_check_start(enc_check_t *e, uint32_t enc_count)
{
    e->count_last = enc_count;
    e->counts = 0;
    e->angle_el_rad = 0.0f;
    e->i_pos_A[0] = 0.0f;
    e->i_pos_A[1] = 0.0f;
    e->i_neg_A[0] = 0.0f;
    e->i_neg_A[1] = 0.0f;
    e->n = 0u;
}

FLASHFUNC void enc_check_step(enc_check_t *e, float dangle_el_rad, float cos_el, float sin_el, float i_alpha_A,
                    float i_beta_A, uint32_t enc_count)
{
    /* the count's step, across the wrap at counts_per_turn: less than half a turn per period */
    const int32_t cpr = (int32_t)e->cfg.counts_per_turn;
    int32_t d = (int32_t)enc_count - (int32_t)e->count_last;
    if (d > cpr / 2) {
        d -= cpr;
    } else if (d < -(cpr / 2)) {
        d += cpr;
    }
    e->count_last = enc_count;
    e->counts += d;
    e->angle_el_rad += dangle_el_rad;
    /* i e^(-j theta) and i e^(+j theta) */
    e->i_pos_A[0] += i_alpha_A * cos_el + i_beta_A * sin_el;
    e->i_pos_A[1] += i_beta_A * cos_el - i_alpha_A * sin_el;
    e->i_neg_A[0] += i_alpha_A * cos_el - i_beta_A * sin_el;
    e->i_neg_A[1] += i_beta_A * cos_el + i_alpha_A * sin_el;
    e->n++;
}

FLASHFUNC app_step_t enc_check_phase_order(const enc_check_t *e, enc_check_out_t *out)
{
    const float inv_n = (e->n > 0u) ? 1.0f / (float)e->n : 0.0f;
    const float abs_counts = (float)((e->counts >= 0) ? e->counts : -e->counts);

    out->counts = e->counts;
    out->angle_el_rad = e->angle_el_rad;
    out->i_pos_A = inv_n * mathx_sqrtf(e->i_pos_A[0] * e->i_pos_A[0] + e->i_pos_A[1] * e->i_pos_A[1]);
    out->i_neg_A = inv_n * mathx_sqrtf(e->i_neg_A[0] * e->i_neg_A[0] + e->i_neg_A[1] * e->i_neg_A[1]);
    out->pole_pairs_est = (abs_counts > 0.0f) ? mathx_fabsf(e->angle_el_rad) * (1.0f / MATHX_TWO_PI_F) *
                                                    (float)e->cfg.counts_per_turn / abs_counts
                                              : 0.0f;
    if (!(out->i_neg_A <= out->i_pos_A)) {
        return app_step_fault(APP_FAULT_PHASE_ORDER, out->i_neg_A, out->i_pos_A);
    }
    return app_step_done();
}

FLASHFUNC app_step_t enc_check_verdict(const enc_check_t *e, enc_check_out_t *out)
{
    const float p = (float)e->cfg.pole_pairs;
    const float angle = e->angle_el_rad;
    const app_step_t order = enc_check_phase_order(e, out);

    if (order.status != APP_STEP_DONE) {
        return order;
    }
    if (!((float)e->counts * angle > 0.0f)) {
        return app_step_fault(APP_FAULT_ENCODER_DIRECTION, (float)e->counts, 0.0f);
    }
    /* half an electrical turn of lag over the travelled angle */
    if (!(mathx_fabsf(out->pole_pairs_est - p) * mathx_fabsf(angle) <= p * MATHX_PI_F)) {
        return app_step_fault(APP_FAULT_POLE_PAIRS, out->pole_pairs_est, p);
    }
    return app_step_done();
}
