/* est_gate.c - pause and hold of step 2's laws; see est_gate.h. */
#include "est_gate.h"

#include "mathx.h"

/* Longest hold / snap in periods (uint16_t counters). */
#define EST_GATE_PERIODS_MAX 65535.0f
#define ROUND_HALF 0.5f
/* w_floor when accel_per_speed is 0: the floor applies at every speed */
#define EST_GATE_W_FLOOR_NONE 3.0e38f

void est_gate_cfg_defaults(est_gate_cfg_t *cfg, float Ts_s)
{
    cfg->Ts_s = Ts_s;
    cfg->accel_per_speed_1_s = EST_GATE_ACCEL_PER_SPEED_DEFAULT_1_S;
    cfg->accel_floor_rad_s2 = EST_GATE_ACCEL_FLOOR_DEFAULT_RAD_S2;
    cfg->settled = EST_GATE_SETTLED_DEFAULT;
    cfg->di_max_A = EST_GATE_DI_MAX_DEFAULT_A;
    cfg->dte_max_Nm = EST_GATE_DTE_MAX_DEFAULT_NM;
    cfg->tau_s = EST_GATE_TAU_DEFAULT_S;
    cfg->tau_accel_s = EST_GATE_TAU_ACCEL_DEFAULT_S;
    cfg->hold_s = EST_GATE_HOLD_DEFAULT_S;
    cfg->snap_s = EST_GATE_SNAP_DEFAULT_S;
    cfg->f_hold_s = EST_GATE_F_HOLD_DEFAULT_S;
}

float est_gate_accel_floor_rad_s2(uint32_t counts_per_rev, uint16_t pole_pairs, float pll_bw_rad_s)
{
    /* the PLL's integrator takes bw^2 Ts e per period: one count of e is bw^2 counts/s^2 */
    const float count_el_rad =
        (counts_per_rev > 0u) ? (MATHX_TWO_PI_F * (float)pole_pairs / (float)counts_per_rev) : 0.0f;
    const float floor_rad_s2 = EST_GATE_ACCEL_FLOOR_PER_COUNT * pll_bw_rad_s * pll_bw_rad_s * count_el_rad;
    return (floor_rad_s2 > EST_GATE_ACCEL_FLOOR_DEFAULT_RAD_S2) ? floor_rad_s2 : EST_GATE_ACCEL_FLOOR_DEFAULT_RAD_S2;
}

static bool periods_ok(float t_s, float Ts_s)
{
    const float n = t_s / Ts_s;
    return (n >= 1.0f) && (n <= EST_GATE_PERIODS_MAX);
}

bool est_gate_init(est_gate_t *g, const est_gate_cfg_t *cfg)
{
    const float sum = cfg->Ts_s + cfg->accel_per_speed_1_s + cfg->accel_floor_rad_s2 + cfg->settled + cfg->di_max_A + cfg->dte_max_Nm +
                      cfg->tau_s + cfg->tau_accel_s + cfg->hold_s + cfg->snap_s + cfg->f_hold_s;
    g->cfg = *cfg;
    g->valid = mathx_isfinitef(sum) && (cfg->Ts_s > 0.0f) && (cfg->accel_per_speed_1_s >= 0.0f) &&
               (cfg->accel_floor_rad_s2 > 0.0f) && (cfg->settled > 0.0f) &&
               (cfg->di_max_A > 0.0f) && (cfg->dte_max_Nm > 0.0f) && (cfg->tau_s >= cfg->Ts_s) &&
               (cfg->tau_accel_s >= cfg->Ts_s) && periods_ok(cfg->hold_s, cfg->Ts_s) &&
               periods_ok(cfg->snap_s, cfg->Ts_s) && periods_ok(cfg->f_hold_s, cfg->Ts_s);
    if (g->valid) {
        g->k_lp = cfg->Ts_s / cfg->tau_s;
        g->k_acc = cfg->Ts_s / cfg->tau_accel_s;
        /* thresholds on the change of speed per period: a Ts */
        g->k_dw = cfg->accel_per_speed_1_s * cfg->Ts_s;
        g->dw_floor = cfg->accel_floor_rad_s2 * cfg->Ts_s;
        g->w_floor = (cfg->accel_per_speed_1_s > 0.0f) ? (cfg->accel_floor_rad_s2 / cfg->accel_per_speed_1_s)
                                                       : EST_GATE_W_FLOOR_NONE;
        g->hold_n = (uint16_t)(cfg->hold_s / cfg->Ts_s + ROUND_HALF);
        g->snap_n = (uint16_t)(cfg->snap_s / cfg->Ts_s + ROUND_HALF);
        g->f_hold_n = (uint16_t)(cfg->f_hold_s / cfg->Ts_s + ROUND_HALF);
    } else {
        g->k_lp = 0.0f;
        g->k_acc = 0.0f;
        g->k_dw = 0.0f;
        g->dw_floor = 0.0f;
        g->w_floor = 0.0f;
        g->hold_n = 1u;
        g->snap_n = 1u;
        g->f_hold_n = 1u;
    }
    g->seeded = false;
    g->hold_cnt = g->hold_n;
    g->snap_cnt = 0u;
    g->reasons = EST_GATE_HOLD;
    g->di_cnt = 0u;
    g->w_prev = 0.0f;
    g->dw_lp = 0.0f;
    g->i_lp.d = 0.0f;
    g->i_lp.q = 0.0f;
    g->te_lp = 0.0f;
    g->L_old = 0.0f;
    g->psi_old = 0.0f;
    g->L_new = 0.0f;
    g->psi_new = 0.0f;
    g->settled = false;
    return g->valid;
}

RAMFUNC void est_gate_reset(est_gate_t *g, const smo_t *smo)
{
    g->seeded = false;
    g->hold_cnt = 0u; /* step 2 starts learning at once */
    g->snap_cnt = 0u;
    g->reasons = 0u;
    g->di_cnt = 0u;
    g->dw_lp = 0.0f;
    g->L_old = 0.0f; /* no old copy yet: unsettled until two copies agree */
    g->psi_old = 0.0f;
    g->L_new = smo->L_H;
    g->psi_new = smo->psi_f_Wb;
    g->settled = false;
}

RAMFUNC void est_gate_take_L(est_gate_t *g, float L_H)
{
    g->L_old = L_H;
    g->L_new = L_H;
}
