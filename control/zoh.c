/* zoh.c - the model's decay over a period; see zoh.h. */
#include "zoh.h"

uint32_t zoh_turn_seq = 0u;

/* (1 - e^-x)/x by its series up to x^7: error below x^8/9! = 1.1e-8 for
 * x <= ZOH_SERIES_MAX; beyond, x is halved until it is within (e^-x
 * squared back). ZOH_HALVINGS_MAX halvings cover x up to 2^15 (e^-x is 0
 * in float long before). */
#define ZOH_SERIES_MAX  0.5f
#define ZOH_HALVINGS_MAX 16u

/* (1 - e^-x)/x, 0 <= x <= ZOH_SERIES_MAX. */
static float one_m_exp_over_x(float x)
{
    return 1.0f - x * 0.5f *
                      (1.0f - x * (1.0f / 3.0f) *
                                  (1.0f - x * 0.25f *
                                              (1.0f - x * 0.2f *
                                                          (1.0f - x * (1.0f / 6.0f) *
                                                                      (1.0f - x * (1.0f / 7.0f) * (1.0f - x * 0.125f))))));
}

bool zoh_model(float R_Ohm, float L_H, float Ts_s, zoh_model_t *m)
{
    if (!(mathx_isfinitef(R_Ohm + L_H + Ts_s) && (R_Ohm > 0.0f) && (L_H > 0.0f) && (Ts_s > 0.0f))) {
        return false;
    }
    zoh_model_of(R_Ohm, L_H, Ts_s, m);
    return true;
}

void zoh_model_of(float R_Ohm, float L_H, float Ts_s, zoh_model_t *m)
{
    const float inv_R = 1.0f / R_Ohm;
    const float x = Ts_s * R_Ohm / L_H;
    /* beyond the series' range x halved n times, e^-x squared back n times */
    float y = x;
    uint16_t n = 0u;
    while ((y > ZOH_SERIES_MAX) && (n < ZOH_HALVINGS_MAX)) {
        y *= 0.5f;
        n++;
    }
    const float p = y * one_m_exp_over_x(y); /* the series once: 1 - e^-y */
    float one_m_rho;
    float rho;
    if (n == 0u) {
        one_m_rho = p;
        rho = 1.0f - one_m_rho;
    } else {
        rho = 1.0f - p;
        for (uint16_t k = 0u; k < n; k++) {
            rho *= rho;
        }
        one_m_rho = 1.0f - rho;
    }
    m->R_Ohm = R_Ohm;
    m->L_H = L_H;
    m->tau_s = L_H * inv_R;
    m->rho = rho;
    m->one_m_rho = one_m_rho;
    m->gamma_A_V = one_m_rho * inv_R;
    m->kappa_1_s = 1.0f / (L_H * m->gamma_A_V);
}
