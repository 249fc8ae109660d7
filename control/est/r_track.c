/* r_track.c - d-axis square-wave injection, synchronous demodulation; see r_track.h. */
#include "r_track.h"

#include "mathx.h"

/* Segments per cycle: signs + - - + (a linear drift of z cancels). */
#define SEGMENTS 4u
/* The inverter error's square waves leave a ripple at 6 w (and its
 * multiples) in the rotor frame (inverter_error_design.md sec. 4) */
#define RIPPLE_HARMONIC 6.0f
#define TWO_PI 6.28318531f
/* r_track_step shifts a two-entry delay line */
typedef char r_track_delay_line_fits[(R_TRACK_RESPONSE_PERIODS == 2u) ? 1 : -1];

void r_track_cfg_defaults(r_track_cfg_t *cfg)
{
    cfg->Ts_s = 0.0f;
    cfg->i_ident_A = R_TRACK_I_IDENT_DEFAULT_A;
    cfg->i_track_A = R_TRACK_I_TRACK_DEFAULT_A;
    cfg->seg_periods = R_TRACK_SEG_DEFAULT;
    cfg->blank_periods = R_TRACK_BLANK_DEFAULT;
    cfg->sync_max_periods = R_TRACK_SYNC_MAX_DEFAULT;
    cfg->ident_cycles = R_TRACK_IDENT_CYCLES_DEFAULT;
    cfg->ident_delay_periods = R_TRACK_IDENT_DELAY_DEFAULT;
    cfg->auto_delay_periods = R_TRACK_AUTO_DELAY_DEFAULT;
    cfg->iq_min_A = R_TRACK_IQ_MIN_DEFAULT_A;
    cfg->iq_step_max_A = R_TRACK_IQ_STEP_DEFAULT_A;
    cfg->k_R = R_TRACK_K_R_DEFAULT;
    cfg->k_I = R_TRACK_K_I_DEFAULT;
    cfg->ve_max_V = R_TRACK_VE_MAX_DEFAULT_V;
    cfg->ve_unc_frac = R_TRACK_VE_UNC_FRAC_DEFAULT;
    cfg->ve_unc_abs_V = R_TRACK_VE_UNC_ABS_DEFAULT_V;
    cfg->psi_tol = R_TRACK_PSI_TOL_DEFAULT;
    cfg->inv_unc_frac = R_TRACK_INV_UNC_FRAC_DEFAULT;
    cfg->ripple_unc = R_TRACK_RIPPLE_UNC_DEFAULT;
    cfg->R_res_max = R_TRACK_R_RES_MAX_DEFAULT;
    cfg->unresolved_wait_periods = R_TRACK_UNRESOLVED_WAIT_DEFAULT;
}

RAMFUNC static void clear_cycle(r_track_t *rt)
{
    rt->seg = 0u;
    rt->j = 0u;
    rt->seg_len = rt->cfg.seg_periods;
    rt->blank_len = rt->cfg.blank_periods;
    rt->sync = false;
    rt->s_now = 1.0f;
    rt->n = 0u;
    rt->L_c_H = 0.0f;
    rt->s_zs = 0.0f;
    rt->s_is = 0.0f;
    rt->s_iq = 0.0f;
    rt->s_iqs = 0.0f;
}

bool r_track_init(r_track_t *rt, const r_track_cfg_t *cfg)
{
    const float sum = cfg->Ts_s + cfg->i_ident_A + cfg->i_track_A + cfg->iq_min_A + cfg->iq_step_max_A + cfg->k_R + cfg->k_I +
                      cfg->ve_max_V + cfg->ve_unc_frac + cfg->ve_unc_abs_V + cfg->psi_tol + cfg->inv_unc_frac +
                      cfg->ripple_unc + cfg->R_res_max;
    rt->cfg = *cfg;
    rt->valid = mathx_isfinitef(sum) && (cfg->Ts_s >= 0.0f) && (cfg->i_ident_A > 0.0f) && (cfg->i_track_A > 0.0f) &&
                (cfg->blank_periods > 0u) && (cfg->blank_periods < cfg->seg_periods) &&
                (cfg->seg_periods <= (uint16_t)(UINT16_MAX / SEGMENTS)) && (cfg->sync_max_periods > 0u) &&
                ((uint32_t)cfg->blank_periods + cfg->sync_max_periods <= (uint32_t)(UINT16_MAX / SEGMENTS)) &&
                (cfg->ident_cycles >= 1u) &&
                (cfg->iq_min_A > 0.0f) && (cfg->iq_step_max_A > 0.0f) && (cfg->k_R > 0.0f) &&
                (cfg->k_R <= 1.0f) && (cfg->k_I >= 0.0f) && (cfg->k_I < cfg->k_R) && (cfg->ve_max_V > 0.0f) && (cfg->ve_unc_frac >= 0.0f) &&
                (cfg->ve_unc_abs_V >= 0.0f) && (cfg->psi_tol > 0.0f) && (cfg->inv_unc_frac >= 0.0f) &&
                (cfg->ripple_unc >= 0.0f) && (cfg->R_res_max > 0.0f);
    r_track_reset(rt);
    return rt->valid;
}

RAMFUNC void r_track_reset(r_track_t *rt)
{
    rt->phase = R_TRACK_OFF;
    rt->i_inj_A = 0.0f;
    rt->wait = 0u;
    rt->ref_q[0] = 0.0f;
    rt->ref_q[1] = 0.0f;
    rt->id_expect_A = 0.0f;
    rt->cycles = 0u;
    rt->tried = 0u;
    rt->ident_sync = false;
    rt->ident_need = rt->cfg.ident_cycles;
    rt->id_zs = 0.0f;
    rt->id_is = 0.0f;
    rt->id_iq = 0.0f;
    rt->rho_Ohm = 0.0f;
    rt->rate_Ohm = 0.0f;
    rt->dR_step_Ohm = 0.0f;
    rt->Ve_V = 0.0f;
    clear_cycle(rt);
}

RAMFUNC void r_track_start(r_track_t *rt, r_track_phase_t phase)
{
    const float Ve = rt->Ve_V; /* an identification survives the start of tracking */
    const bool sync = rt->ident_sync;
    r_track_reset(rt);
    rt->Ve_V = Ve;
    rt->ident_sync = sync;
    if (!rt->valid || (phase == R_TRACK_OFF)) {
        return;
    }
    rt->phase = phase;
    rt->i_inj_A = (phase == R_TRACK_IDENT) ? rt->cfg.i_ident_A : rt->cfg.i_track_A;
    rt->wait = (phase == R_TRACK_IDENT) ? rt->cfg.ident_delay_periods : 0u;
}

/* IDENT, at a cycle's start: segments that sum whole periods of the 6 w
 * ripple, as many as fit in seg_periods after the blanking (the segment's
 * last ones; the blanking longer), or one longer one up to sync_max_periods; a
 * synchronous sum cancels the ripple whatever its phase, where a fixed
 * 70-period sum aliases it into Ve (inverter_error_design.md sec. 4). Slower: the fixed
 * segments, not synchronous. 4 float divisions, once per cycle. */
RAMFUNC static void cycle_length(r_track_t *rt, float omega_el_rad_s)
{
    const r_track_cfg_t *c = &rt->cfg;
    const float w6 = RIPPLE_HARMONIC * mathx_fabsf(omega_el_rad_s) * c->Ts_s; /* rad per period */
    const float ripple = (w6 > TWO_PI / (float)c->sync_max_periods) ? (TWO_PI / w6) : 0.0f; /* periods */
    const float avail = (float)(c->seg_periods - c->blank_periods);
    rt->seg_len = c->seg_periods;
    rt->blank_len = c->blank_periods;
    rt->sync = false;
    if (ripple > 0.0f) {
        const float whole = (ripple < avail) ? (ripple * (float)(uint16_t)(avail / ripple)) : ripple;
        const uint16_t m = (uint16_t)(whole + 0.5f);
        /* the segment's timing as configured where the sum fits in it; the sum is its last m periods */
        const uint16_t len = (uint16_t)(c->blank_periods + m);
        rt->seg_len = (len > c->seg_periods) ? len : c->seg_periods;
        rt->blank_len = (uint16_t)(rt->seg_len - m);
        rt->sync = true;
    }
    /* float: no integer division in the ISR (a library call from flash on the target) */
    const float need = (float)c->ident_cycles * (float)c->seg_periods / (float)rt->seg_len;
    rt->ident_need = (need >= 1.0f) ? (uint16_t)need : 1u;
}

RAMFUNC void r_track_restart_cycle(r_track_t *rt, float omega_el_rad_s)
{
    if ((rt->phase == R_TRACK_IDENT) && (rt->wait == 0u)) {
        clear_cycle(rt);
        cycle_length(rt, omega_el_rad_s);
    }
}

RAMFUNC void r_track_delay(r_track_t *rt, uint16_t periods)
{
    if ((rt->phase == R_TRACK_TRACK) && (rt->wait < periods)) {
        rt->wait = periods;
    }
}

RAMFUNC void r_track_hold(r_track_t *rt)
{
    if (rt->phase != R_TRACK_TRACK) {
        return;
    }
    clear_cycle(rt);
    rt->ref_q[0] = 0.0f;
    rt->ref_q[1] = 0.0f;
    rt->id_expect_A = 0.0f;
    r_track_delay(rt, rt->cfg.seg_periods);
}

/* Sign of the reference in segment seg: + - - +. */
RAMFUNC static float seg_sign(uint16_t seg)
{
    return ((seg == 0u) || (seg == (SEGMENTS - 1u))) ? 1.0f : -1.0f;
}

RAMFUNC float r_track_w_psi_min(const r_track_t *rt, float psi_f_Wb)
{
    const float unc = rt->cfg.ve_unc_frac * mathx_fabsf(rt->Ve_V) + rt->cfg.ve_unc_abs_V;
    return (psi_f_Wb > 0.0f) ? unc / (rt->cfg.psi_tol * psi_f_Wb) : 0.0f;
}

RAMFUNC bool r_track_resolves(const r_track_t *rt, float ve_comp_V, float ripple_A, float i_abs_A, float R_Ohm)
{
    /* (inv_unc_frac + ripple_unc r/|i|) Ve_comp/|i| <= R_res_max R, times |i|^2 (no division) */
    const float unc_x_i2 = (rt->cfg.inv_unc_frac * i_abs_A + rt->cfg.ripple_unc * ripple_A) * ve_comp_V;
    return (i_abs_A > 0.0f) && (unc_x_i2 <= rt->cfg.R_res_max * R_Ohm * i_abs_A * i_abs_A);
}

RAMFUNC void r_track_discard(r_track_t *rt)
{
    rt->rate_Ohm += rt->cfg.k_I * rt->rho_Ohm; /* end_cycle's integration undone */
    rt->dR_step_Ohm = 0.0f;
    r_track_delay(rt, rt->cfg.unresolved_wait_periods);
}

/* End of a cycle: rho, or a hold. IDENT also sums the valid cycles and
 * ends after ident_cycles of them (or twice that many tried). */
RAMFUNC static r_track_event_t end_cycle(r_track_t *rt)
{
    const r_track_cfg_t *c = &rt->cfg;
    const float inv_n = 1.0f / (float)rt->n;
    const float iq_mean = rt->s_iq * inv_n;
    const float iq_step = 2.0f * rt->s_iqs * inv_n; /* mean iq(+) - mean iq(-): equal counts */
    /* a demodulated current well below the injection: the current did not follow */
    const bool followed = (rt->s_is > 0.5f * rt->i_inj_A * (float)rt->n);
    /* identifying, any load: the injection's +-I is the current's direction, and
     * rho = -Ve/|i| holds for the square wave itself (|i| = sqrt(I^2 + iq^2)); tracking
     * reads dR on a tilt that needs a load current */
    const bool loaded = (rt->phase == R_TRACK_IDENT) || (mathx_fabsf(iq_mean) >= c->iq_min_A);
    const bool ok = followed && loaded && (mathx_fabsf(iq_step) <= c->iq_step_max_A);
    r_track_event_t ev = R_TRACK_HELD;

    if (ok) {
        rt->rho_Ohm = -rt->s_zs / rt->s_is;
        /* type 2: the rate integrates rho, so a steady warm-up leaves no lag */
        rt->rate_Ohm -= c->k_I * rt->rho_Ohm;
        rt->dR_step_Ohm = -c->k_R * rt->rho_Ohm + rt->rate_Ohm;
        ev = R_TRACK_CYCLE;
    }
    if (rt->phase == R_TRACK_IDENT) {
        rt->tried++;
        if (ok) {
            rt->ident_sync = (rt->cycles == 0u) ? rt->sync : (rt->ident_sync && rt->sync);
            rt->cycles++;
            rt->id_zs += rt->s_zs;
            rt->id_is += rt->s_is;
            rt->id_iq += iq_mean;
        }
        ev = R_TRACK_NONE;
        if (rt->cycles >= rt->ident_need) {
            /* Ve = -rho |i| with R^ = R0 (inverter_error_design.md sec. 5) */
            const float iq = rt->id_iq / (float)rt->cycles;
            const float i_abs = mathx_sqrtf(rt->i_inj_A * rt->i_inj_A + iq * iq);
            const float Ve = (rt->id_zs / rt->id_is) * i_abs;
            const bool plausible = mathx_isfinitef(Ve) && (mathx_fabsf(Ve) <= c->ve_max_V);
            rt->Ve_V = plausible ? Ve : 0.0f;
            rt->ident_sync = rt->ident_sync && plausible;
            ev = plausible ? R_TRACK_IDENT_DONE : R_TRACK_IDENT_REFUSED;
        } else if (rt->tried >= (uint16_t)(2u * rt->ident_need)) {
            rt->Ve_V = 0.0f;
            rt->ident_sync = false;
            ev = R_TRACK_IDENT_REFUSED;
        }
        if (ev != R_TRACK_NONE) {
            rt->phase = R_TRACK_OFF;
            rt->ref_q[0] = 0.0f;
            rt->ref_q[1] = 0.0f;
            rt->id_expect_A = 0.0f;
            rt->i_inj_A = 0.0f;
        }
    }
    clear_cycle(rt);
    return ev;
}

RAMFUNC void r_track_wait_over(r_track_t *rt, float omega_el_rad_s)
{
    if (rt->phase == R_TRACK_IDENT) {
        cycle_length(rt, omega_el_rad_s); /* the first cycle */
    }
}

RAMFUNC r_track_event_t r_track_segment_end(r_track_t *rt, float omega_el_rad_s)
{
    r_track_event_t ev = R_TRACK_NONE;
    rt->j = 0u;
    rt->seg++;
    if (rt->seg >= SEGMENTS) {
        ev = end_cycle(rt); /* back to segment 0 */
        if (rt->phase == R_TRACK_IDENT) {
            cycle_length(rt, omega_el_rad_s); /* the next cycle */
        }
    }
    rt->s_now = seg_sign(rt->seg);
    return ev;
}
