/*
 * mtpa.h - stator-flux reference for a surface-mounted PMSM (paper sec. III):
 *
 *   psi_s* = sqrt(psi_f^2 + (L*Te* / (1.5*p*psi_f))^2)
 *
 * i.e. id = 0 (MTPA for Ld = Lq) and iq = Te_ref / (1.5*p*psi_f). L and psi_f
 * are arguments because the proposed method feeds online estimates.
 */
#ifndef MTPA_H
#define MTPA_H

#include <stdint.h>

#include "mathx.h"
#include "spmsm.h"

/* An estimated magnet flux below this [Wb] (or non-finite) is replaced by
 * it: the torque term then stays finite instead of dividing by ~0. */
#define MTPA_PSI_F_MIN_WB 1.0e-3f
/* Ceiling of both flux terms and of the result [Wb]: far above any machine
 * this drive runs (Table I: 0.24 Wb); only keeps the reference finite. */
#define MTPA_PSI_MAX_WB 100.0f

/* psi_f_Wb [Wb] as the reference uses it: within [MTPA_PSI_F_MIN_WB,
 * MTPA_PSI_MAX_WB], non-finite -> the floor. Any context. */
static inline float mtpa_psi_f_bounded(float psi_f_Wb)
{
    return (mathx_isfinitef(psi_f_Wb) && (psi_f_Wb > MTPA_PSI_F_MIN_WB))
               ? mathx_clampf(psi_f_Wb, MTPA_PSI_F_MIN_WB, MTPA_PSI_MAX_WB)
               : MTPA_PSI_F_MIN_WB;
}

/*
 * Stator-flux reference [Wb] from the q flux psi_q_Wb = L*iq [Wb] the
 * torque reference needs (sign ignored) and the magnet flux psi_f_Wb
 * [Wb], for a caller that has the torque constant (oplim: the model's
 * dbdtc_par_t.kt_Nm_per_A). Result in [MTPA_PSI_F_MIN_WB,
 * MTPA_PSI_MAX_WB]. Any context.
 */
static inline float mtpa_psi_s_of_psi_q(float psi_f_Wb, float psi_q_Wb)
{
    const float psi_f = mtpa_psi_f_bounded(psi_f_Wb);
    /* NaN (from NaN inputs) clamps to 0, Inf to the ceiling. */
    const float psi_q = mathx_clampf(mathx_fabsf(psi_q_Wb), 0.0f, MTPA_PSI_MAX_WB);
    return mathx_clampf(mathx_sqrtf(psi_f * psi_f + psi_q * psi_q), MTPA_PSI_F_MIN_WB,
                        MTPA_PSI_MAX_WB);
}

/*
 * Stator-flux reference [Wb] for torque reference Te_ref_Nm [N*m], with
 * inductance L_H [H], magnet flux psi_f_Wb [Wb] and pole_pairs (0 counts
 * as 1). Non-finite L or Te drop the torque term (result psi_f). Result in
 * [MTPA_PSI_F_MIN_WB, MTPA_PSI_MAX_WB]. 1 division. Any context.
 */
static inline float mtpa_psi_s_ref(float L_H, float psi_f_Wb, uint16_t pole_pairs, float Te_ref_Nm)
{
    const float psi_f = mtpa_psi_f_bounded(psi_f_Wb);
    const uint16_t p = (pole_pairs > 0u) ? pole_pairs : 1u;
    return mtpa_psi_s_of_psi_q(psi_f, L_H * Te_ref_Nm / spmsm_kt_Nm_A(p, psi_f)); /* psi_q = L*iq, eq. (3) */
}

#endif /* MTPA_H */
