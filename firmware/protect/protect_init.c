/* protect_init.c - protection's derived limits (protect_init; see protect.h): start-up and
 * background code, in flash (off the ISR path: no placement marker, control/c28x_portable.h);
 * the checks are protect.c's. */
#include "protect.h"

#include "mathx.h"

#define OP_WHOLE_PARTS (PROTECT_OP_SUBWINDOWS - 1u) /* the window's parts before the part so far */

/* OPEN_PHASE's voltage rule's top speed as the net count change of a part of part_ticks periods:
 * the back-EMF's peak w_el psi_f at PROTECT_OP_EMF_SHARE x op_u_min_V (protect_design.md). */
static float op_slow_counts(const protect_cfg_t *cfg, const protect_drive_t *drv, uint32_t cpr, uint32_t part_ticks)
{
    const float w_el = PROTECT_OP_EMF_SHARE * cfg->watch.op_u_min_V / drv->psi_f_Wb;
    const float counts = w_el / (float)drv->pole_pairs * drv->Ts_s * (float)part_ticks * (float)cpr / MATHX_TWO_PI_F;
    return (mathx_isfinitef(counts) && (counts > 0.0f)) ? counts : 0.0f;
}

void protect_init(protect_t *p, const protect_cfg_t *cfg, const protect_drive_t *drv)
{
    p->cfg = *cfg;
    p->drv = *drv;
    p->enc_cpr = (drv->enc_cpr > 0u) ? drv->enc_cpr : 1u;
    p->enc_jump_max = PROTECT_ENC_JUMP_MARGIN * cfg->speed_max_rad_s * drv->Ts_s * (float)p->enc_cpr /
                          MATHX_TWO_PI_F +
                      1.0f; /* + one count of quantisation */
    /* 1.5 periods: the entry jitter is a few cycles, a missed period adds a whole one */
    p->isr_late_cycles = cfg->isr_period_cycles + cfg->isr_period_cycles / 2u;
    p->enc_prev = 0u;
    p->enc_delta = 0;
    p->seeded = false;
    p->isr_entry = 0u;
    p->isr_interval_cycles = 0u;
    p->isr_run_cycles = 0u;
    p->uv_armed = false;
    p->op_part_ticks = app_periods_of(cfg->watch.op_window_s / (float)PROTECT_OP_SUBWINDOWS, drv->Ts_s);
    /* a whole window is PROTECT_OP_SUBWINDOWS whole parts of op_part_ticks periods */
    p->op_i_min_sum_A = cfg->watch.op_i_min_A * (float)(PROTECT_OP_SUBWINDOWS * p->op_part_ticks);
    p->op_u_min_sum_V = cfg->watch.op_u_min_V * (float)(PROTECT_OP_SUBWINDOWS * p->op_part_ticks);
    p->op_cone_min = (uint16_t)(PROTECT_OP_CONE_MIN * (float)(PROTECT_OP_SUBWINDOWS * p->op_part_ticks));
    p->op_slow_counts = op_slow_counts(cfg, drv, p->enc_cpr, p->op_part_ticks);
    p->stall_ticks_max = app_periods_of(cfg->watch.enc_stall_s, drv->Ts_s);
    p->el_rad_per_count = MATHX_TWO_PI_F * (float)drv->pole_pairs / (float)p->enc_cpr;
    p->counts_per_rad = (float)p->enc_cpr / MATHX_TWO_PI_F;
    p->op_phase = 0u;
    /* the ring's parts are summed (op_prep_step) before the ring is full: start from zero sums */
    for (uint32_t k = 0u; k < OP_WHOLE_PARTS; k++) {
        protect_op_sums_clear(&p->op_parts[k]);
    }
    protect_watch_reset(p);
}

