/* protect.c - protection checks and the fault snapshot; see protect.h. */
#include "protect.h"

#include "mathx.h"

void protect_init(protect_t *p, const protect_cfg_t *cfg)
{
    p->cfg = *cfg;
    p->enc_cpr = (cfg->enc_cpr > 0u) ? cfg->enc_cpr : 1u;
    p->enc_jump_max = PROTECT_ENC_JUMP_MARGIN * cfg->speed_max_rad_s * cfg->Ts_s * (float)p->enc_cpr /
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
}

/* Count change from prev to now (both < cpr), the shortest way round; no
 * 32-bit % (an RTS call from flash on the C28x). */
static int32_t count_delta(uint32_t now, uint32_t prev, uint32_t cpr)
{
    const uint32_t d = (now >= prev) ? (now - prev) : (now + cpr - prev);
    return (d > (cpr / 2u)) ? ((int32_t)d - (int32_t)cpr) : (int32_t)d;
}

void protect_track(protect_t *p, uint32_t enc_count, uint32_t t_entry_cycles)
{
    const uint32_t count = mathx_umod_u32(enc_count, p->enc_cpr);

    if (p->seeded) {
        p->enc_delta = count_delta(count, p->enc_prev, p->enc_cpr);
        p->isr_interval_cycles = t_entry_cycles - p->isr_entry; /* modulo 2^32, wrap-safe */
    }
    p->enc_prev = count;
    p->isr_entry = t_entry_cycles;
    p->seeded = true;
}

void protect_arm_uv(protect_t *p)
{
    p->uv_armed = true;
}

app_step_t protect_check(const protect_t *p, const hal_sample_t *s, float offset_ia_A, float offset_ib_A,
                         float speed_m_rad_s)
{
    const protect_cfg_t *cfg = &p->cfg;
    const float ia = s->ia_A - offset_ia_A;
    const float ib = s->ib_A - offset_ib_A;
    const float ic = -ia - ib;
    float i_peak;

    if (hal_trip_active()) {
        return app_step_fault(APP_FAULT_HW_TRIP, 0.0f, 0.0f);
    }
    if (!mathx_isfinitef(s->ia_A) || !mathx_isfinitef(s->ib_A) || !mathx_isfinitef(s->vdc_V)) {
        return app_step_fault(APP_FAULT_NONFINITE_SAMPLE, 0.0f, 0.0f);
    }
    i_peak = mathx_fabsf(ia);
    i_peak = (mathx_fabsf(ib) > i_peak) ? mathx_fabsf(ib) : i_peak;
    i_peak = (mathx_fabsf(ic) > i_peak) ? mathx_fabsf(ic) : i_peak;
    if (!(i_peak <= cfg->i_max_A)) { /* !(x <= max): a NaN limit trips too */
        return app_step_fault(APP_FAULT_OVERCURRENT, i_peak, cfg->i_max_A);
    }
    if (!(s->vdc_V <= cfg->vdc_max_V)) {
        return app_step_fault(APP_FAULT_OVERVOLTAGE, s->vdc_V, cfg->vdc_max_V);
    }
    if (p->uv_armed && (s->vdc_V < cfg->vdc_min_V)) {
        return app_step_fault(APP_FAULT_UNDERVOLTAGE, s->vdc_V, cfg->vdc_min_V);
    }
    if (mathx_fabsf((float)p->enc_delta) > p->enc_jump_max) {
        return app_step_fault(APP_FAULT_ENCODER, mathx_fabsf((float)p->enc_delta), p->enc_jump_max);
    }
    if (!(mathx_fabsf(speed_m_rad_s) <= cfg->speed_max_rad_s)) {
        return app_step_fault(APP_FAULT_OVERSPEED, mathx_fabsf(speed_m_rad_s), cfg->speed_max_rad_s);
    }
    if (p->isr_interval_cycles > p->isr_late_cycles) {
        return app_step_fault(APP_FAULT_OVERRUN, (float)p->isr_interval_cycles, (float)p->isr_late_cycles);
    }
    if (p->isr_run_cycles > cfg->isr_budget_cycles) { /* the last call's: for a fault reset's check */
        return app_step_fault(APP_FAULT_OVERRUN, (float)p->isr_run_cycles, (float)cfg->isr_budget_cycles);
    }
    return app_step_running();
}

app_step_t protect_run_time(protect_t *p, uint32_t t_entry_cycles, uint32_t now_cycles)
{
    p->isr_run_cycles = now_cycles - t_entry_cycles;
    if (p->isr_run_cycles > p->cfg.isr_budget_cycles) {
        return app_step_fault(APP_FAULT_OVERRUN, (float)p->isr_run_cycles, (float)p->cfg.isr_budget_cycles);
    }
    return app_step_running();
}

void protect_snapshot(app_snapshot_t *snap, app_state_t state, const hal_sample_t *s, const app_step_t *f)
{
    snap->sample = *s;
    snap->state = state;
    snap->value = f->value;
    snap->limit = f->limit;
}
