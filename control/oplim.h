/*
 * oplim.h - the torque and flux targets of the deadbeat step inside the
 * drive's operating limits: stator current |i| <= i_lim and, above base
 * speed, the inverter voltage (flux weakening). Derivation and figures:
 * limits_design.md. Both methods use it, with the parameters in
 * use (dbdtc_par_t: nominal, or the observer's estimates).
 *
 * Current limit. Surface PMSM, psi_d = psi_f + L id, psi_q = L iq
 * (eq. 11). The deadbeat step (eq. 17) puts psi_q = psi_q* = Te* /
 * te_per_Wb and psi_d = sqrt(psi_s*^2 - psi_q*^2), so the current it aims
 * at follows from (Te*, psi_s*):
 *   |i|^2 <= i_lim^2  <=>  psi_s*^2 - 2 psi_f psi_d + psi_f^2 <= (L i_lim)^2
 *                     <=>  psi_d >= psi_d,min = (psi_s*^2 + psi_f^2 - (L i_lim)^2) / (2 psi_f)
 *   hence |Te*| <= te_per_Wb sqrt(psi_s*^2 - max(psi_d,min, 0)^2).
 * At psi_s* = MTPA's (id = 0) this is |Te*| <= kt i_lim.
 *
 * Voltage limit (flux weakening). psi_s* = MTPA's - dpsi, not below
 * psi_f - L i_lim (all the current on -d), and Te* limited by the current
 * limit at that flux: negative i_d, |i| <= i_lim. dpsi >= 0 is a
 * voltage-feedback loop: it rises at rate_Wb_s while the deadbeat asks
 * for more than u_lim = margin Vdc/sqrt(3) (the hexagon's inscribed
 * circle: any angle; the margin is the deadbeat's headroom) and falls at
 * the same rate when it asks for less than hyst u_lim. A feedforward
 * psi_v = u_lim/|w| would act on the model's flux, which is not the
 * motor's while the parameters are off (conventional method, step 1):
 * with psi_f = 1.5 psi_f0 it weakened at 1350 r/min and drove id to the
 * limit in the SIL. The loop sees the voltage the motor really needs.
 */
#ifndef OPLIM_H
#define OPLIM_H

#include "dbdtc.h"
#include "mathx.h"
#include "mtpa.h"

/* Design defaults (limits_design.md sec. 2). */
#define OPLIM_FW_RATE_DEFAULT_WB_S 5.0f  /* follows 3x the 2050 r/min in 0.2 s ramp's flux change */
#define OPLIM_FW_HYST_DEFAULT      0.97f /* dpsi falls below 0.97 u_lim */
#define OPLIM_HALF 0.5f

typedef struct {
    float dpsi_step_Wb;   /* rate_Wb_s * Ts: change of dpsi per period [Wb] */
    float hyst_sq;        /* hyst^2 */
    float dpsi_Wb;        /* flux reduction below MTPA [Wb], >= 0 */
    float dpsi_max_Wb;    /* MTPA's flux - (psi_f - L i_lim) of the last targets [Wb] */
} oplim_t;

typedef struct {
    float te_Nm;        /* torque target, limited */
    float psi_Wb;       /* stator-flux target */
} oplim_out_t;

/* Weakening loop rate rate_Wb_s [Wb/s] (> 0) and hysteresis hyst (0..1],
 * period Ts_s [s]; dpsi = 0. Background. */
void oplim_init(oplim_t *o, float Ts_s, float rate_Wb_s, float hyst);

/* dpsi = 0. Background or ISR. */
void oplim_reset(oplim_t *o);

/*
 * Targets for a requested torque te_req_Nm [N m] (already within
 * +-te_max): MTPA flux (sec. III) less dpsi, and the current limit
 * i_lim_A [A] above, with the parameters *p (their kt and 1/psi_f).
 * 1 division (MTPA's q flux) and 1 square root; while weakening 1 square
 * root more. ISR (inline: once a period).
 */
static inline oplim_out_t oplim_targets(oplim_t *o, const dbdtc_par_t *p, float i_lim_A, float te_req_Nm)
{
    oplim_out_t out;
    /* current limit at id = 0 (MTPA): |Te*| <= kt i_lim */
    const float te_i = p->kt_Nm_per_A * i_lim_A;
    const float Li = p->L_H * i_lim_A;

    out.te_Nm = mathx_clampf(te_req_Nm, -te_i, te_i);
    /* L Te* / kt, not psiq_per_Nm Te* without the division: a last-bit
     * change of the flux target moves the figures of make sil
     * (ctrl_step_design.md sec. 4) */
    out.psi_Wb = mtpa_psi_s_of_psi_q(p->psi_f_Wb, (p->L_H * out.te_Nm) / p->kt_Nm_per_A); /* sec. III */
    o->dpsi_max_Wb = out.psi_Wb - (p->psi_f_Wb - Li);
    if (o->dpsi_Wb > 0.0f) {
        /* weakening: the flux the voltage allows, then the torque the current allows there */
        const float psi = mathx_clampf(out.psi_Wb - o->dpsi_Wb, p->psi_f_Wb - Li, out.psi_Wb);
        const float psid_min = (psi * psi + p->psi_f_Wb * p->psi_f_Wb - Li * Li) * OPLIM_HALF * p->inv_psi_f_1_Wb;
        const float psid_lo = (psid_min > 0.0f) ? psid_min : 0.0f;
        const float te_fw = p->te_per_Wb * mathx_sqrtf(psi * psi - psid_lo * psid_lo);
        out.te_Nm = mathx_clampf(out.te_Nm, -te_fw, te_fw);
        out.psi_Wb = psi;
    }
    return out;
}

/* The weakening loop, after the deadbeat step: u_req_V [V] = its voltage
 * before the hexagon, u_lim_V [V] = the steady-state limit. ISR, no
 * division; inline (every period). */
static inline void oplim_fw_update(oplim_t *o, dq_t u_req_V, float u_lim_V)
{
    const float u_sq = u_req_V.d * u_req_V.d + u_req_V.q * u_req_V.q;
    const float lim_sq = u_lim_V * u_lim_V;
    float d = o->dpsi_Wb;

    if (u_sq > lim_sq) {
        d += o->dpsi_step_Wb;
    } else if (u_sq < o->hyst_sq * lim_sq) {
        d -= o->dpsi_step_Wb;
    }
    /* a NaN stays out: the bounds win */
    o->dpsi_Wb = mathx_clampf(d, 0.0f, o->dpsi_max_Wb);
}

#endif /* OPLIM_H */
