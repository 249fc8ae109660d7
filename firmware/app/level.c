/* level.c - level 3's open-loop rotation; see level.h. */
#include "level.h"

#include "mathx.h"

void level_rot_init(level_rot_t *r, const level_cfg_t *cfg, const ctrl_cfg_t *c, float Ts_s)
{
    const enc_check_cfg_t ecfg = { APP_ENC_COUNTS_PER_LINE * c->enc_lines, c->pole_pairs };
    const float w_el = (float)c->pole_pairs * cfg->speed_m_rad_s;
    const float ri = c->R_Ohm * cfg->i_A;
    const float wpsi = w_el * (c->L_H * cfg->i_A + c->psi_f_Wb);
    const uint32_t ramp_ticks = app_periods_of(cfg->ramp_s, Ts_s);

    r->u_V = mathx_sqrtf(ri * ri + wpsi * wpsi);
    r->turn_ticks = (w_el > 0.0f) ? app_periods_of(MATHX_TWO_PI_F / w_el, Ts_s) : 0u;
    /* whole turns in whole periods: the check's sums cover whole turns */
    r->dangle_el_rad = (r->turn_ticks > 0u) ? MATHX_TWO_PI_F / (float)r->turn_ticks : 0.0f;
    r->du_V = (ramp_ticks > 0u) ? r->u_V / (float)ramp_ticks : r->u_V;
    r->pole_pairs = c->pole_pairs;
    enc_check_init(&r->chk, &ecfg);
    (void)enc_check_verdict(&r->chk, &r->out); /* the empty figures */
    level_rot_start(r);
}

FLASHFUNC void level_rot_start(level_rot_t *r)
{
    r->phase = ROT_RAMP;
    r->ticks = 0u;
    r->u_now_V = 0.0f;
    r->angle_el_rad = 0.0f;
}

FLASHFUNC app_step_t level_rot_step(level_rot_t *r, float i_alpha_A, float i_beta_A, uint32_t enc_count, ab_t *u_ab_V)
{
    float s;
    float c;
    app_step_t res = app_step_running();

    /* the currents sampled now answer the vector applied over the last period */
    mathx_sincosf(r->angle_el_rad, &s, &c);
    r->ticks++;
    switch (r->phase) {
    case ROT_RAMP:
        r->u_now_V = (r->u_now_V + r->du_V < r->u_V) ? r->u_now_V + r->du_V : r->u_V;
        if (!(r->u_now_V < r->u_V)) {
            r->phase = ROT_SETTLE;
            r->ticks = 0u;
        }
        break;
    case ROT_SETTLE:
        r->angle_el_rad = mathx_wrap_2pi(r->angle_el_rad + r->dangle_el_rad);
        if (r->ticks >= r->turn_ticks) {
            r->phase = ROT_MEASURE;
            r->ticks = 0u;
            enc_check_start(&r->chk, enc_count);
        }
        break;
    case ROT_MEASURE:
    default:
        enc_check_step(&r->chk, r->dangle_el_rad, c, s, i_alpha_A, i_beta_A, enc_count);
        r->angle_el_rad = mathx_wrap_2pi(r->angle_el_rad + r->dangle_el_rad);
        if (r->ticks >= (uint32_t)r->pole_pairs * r->turn_ticks) {
            res = enc_check_verdict(&r->chk, &r->out);
        }
        break;
    }
    mathx_sincosf(r->angle_el_rad, &s, &c);
    u_ab_V->a = r->u_now_V * c;
    u_ab_V->b = r->u_now_V * s;
    return res;
}
