/*
 * encoder.c - count to electrical angle, PLL speed estimate.
 *
 * PLL per period:  pos += Ts*vel;  e = count - pos (shortest way round);
 *                  pos += 2*bw*Ts*e;  vel += bw^2*Ts*e.
 * Working on the shortest-way error makes the wrap 9999 -> 0 (and back)
 * invisible; pos is kept in [0, cpr) so its float resolution stays fine.
 */
#include "encoder.h"

#include "mathx.h"

/* Half a turn [1 / turn]: the shortest-way error lies in [-cpr/2, cpr/2). */
#define ENCODER_HALF 0.5f
/* Centre of a count's interval, from its start [counts]. */
#define ENCODER_COUNT_CENTRE 0.5f

/* Position [counts] into [0, cpr); inputs lie within one turn of it. */
RAMFUNC static float encoder_wrap_counts(float x, float cpr)
{
    if (x >= cpr) {
        x -= cpr;
    } else if (x < 0.0f) {
        x += cpr;
    }
    /* -tiny + cpr rounds to cpr. */
    return (x < cpr) ? x : 0.0f;
}

RAMFUNC static void encoder_outputs_zero(encoder_t *enc)
{
    enc->theta_e_rad = 0.0f;
    enc->omega_m_rad_s = 0.0f;
    enc->omega_e_rad_s = 0.0f;
}

/* Electrical angle of a count before the offset [rad], in [0, 2*pi]: the
 * centre of the count's interval. The x4 count is the floor of the shaft
 * position, so the interval's start lags by half a count on average (0.94
 * mrad electrical at 2500 lines, p = 3: enough to bias the observer's L^
 * by 0.8 % through the back-EMF it sees on d); the centre is unbiased. */
RAMFUNC static float encoder_elec_angle(const encoder_t *enc, uint32_t count)
{
    /* Integer product mod cpr: exact, and init checked it cannot overflow.
     * count < cpr, so fewer than pole_pairs subtractions bring it into
     * [0, cpr): no 32-bit % (an RTS call on the C28x). */
    uint32_t elec = count * (uint32_t)enc->cfg.pole_pairs;
    uint16_t k;

    for (k = 1u; (k < enc->cfg.pole_pairs) && (elec >= enc->cfg.counts_per_rev); k++) {
        elec -= enc->cfg.counts_per_rev;
    }
    return ((float)elec + enc->centre_el) * enc->rad_per_count;
}

static bool encoder_cfg_valid(const encoder_cfg_t *cfg)
{
    if ((cfg->counts_per_rev == 0u) || (cfg->counts_per_rev > ENCODER_CPR_MAX)
        || (cfg->pole_pairs == 0u)) {
        return false;
    }
    if (cfg->counts_per_rev > (UINT32_MAX / (uint32_t)cfg->pole_pairs)) {
        return false;
    }
    if (!mathx_isfinitef(cfg->offset_el_rad) || !mathx_isfinitef(cfg->Ts_s)
        || !mathx_isfinitef(cfg->pll_bw_rad_s) || !(cfg->Ts_s > 0.0f)
        || !(cfg->pll_bw_rad_s > 0.0f)) {
        return false;
    }
    return (cfg->pll_bw_rad_s * cfg->Ts_s) <= ENCODER_PLL_BW_TS_MAX;
}

bool encoder_init(encoder_t *enc, const encoder_cfg_t *cfg)
{
    enc->valid = encoder_cfg_valid(cfg);
    enc->cfg = *cfg;
    if (enc->valid) {
        const float bw = cfg->pll_bw_rad_s;
        enc->cpr = (float)cfg->counts_per_rev;
        enc->rad_per_count = MATHX_TWO_PI_F / enc->cpr;
        enc->kp_Ts = ENCODER_KP_PER_BW * bw * cfg->Ts_s;
        enc->ki_Ts = bw * bw * cfg->Ts_s;
        enc->vel_max = ENCODER_HALF * enc->cpr / cfg->Ts_s;
        enc->offset_el_rad = mathx_wrap_2pi(cfg->offset_el_rad);
        enc->pole_pairs_f = (float)cfg->pole_pairs;
        enc->centre_el = ENCODER_COUNT_CENTRE * enc->pole_pairs_f;
    } else {
        enc->cpr = 0.0f;
        enc->rad_per_count = 0.0f;
        enc->kp_Ts = 0.0f;
        enc->ki_Ts = 0.0f;
        enc->vel_max = 0.0f;
        enc->offset_el_rad = 0.0f;
        enc->pole_pairs_f = 0.0f;
        enc->centre_el = 0.0f;
    }
    encoder_reset(enc);
    return enc->valid;
}

RAMFUNC void encoder_reset(encoder_t *enc)
{
    enc->seeded = false;
    enc->pos = 0.0f;
    enc->vel = 0.0f;
    encoder_outputs_zero(enc);
}

RAMFUNC void encoder_step(encoder_t *enc, uint32_t count)
{
    if (!enc->valid) {
        encoder_outputs_zero(enc);
        return;
    }
    const uint32_t c = mathx_umod_u32(count, enc->cfg.counts_per_rev);
    const float cf = (float)c;
    enc->theta_e_rad = mathx_wrap_2pi(encoder_elec_angle(enc, c) + enc->offset_el_rad);

    if (!enc->seeded) {
        /* Start where the rotor is, at rest: no step in position, no spike. */
        enc->pos = cf;
        enc->vel = 0.0f;
        enc->seeded = true;
    } else {
        const float half = ENCODER_HALF * enc->cpr;
        enc->pos = encoder_wrap_counts(enc->pos + enc->cfg.Ts_s * enc->vel, enc->cpr);
        float e = cf - enc->pos;
        if (e >= half) {
            e -= enc->cpr;
        } else if (e < -half) {
            e += enc->cpr;
        }
        enc->pos = encoder_wrap_counts(enc->pos + enc->kp_Ts * e, enc->cpr);
        enc->vel = mathx_clampf(enc->vel + enc->ki_Ts * e, -enc->vel_max, enc->vel_max);
    }
    enc->omega_m_rad_s = enc->vel * enc->rad_per_count;
    enc->omega_e_rad_s = enc->omega_m_rad_s * enc->pole_pairs_f;
}

RAMFUNC void encoder_set_offset(encoder_t *enc, float offset_el_rad)
{
    if (mathx_isfinitef(offset_el_rad)) {
        enc->offset_el_rad = mathx_wrap_2pi(offset_el_rad);
    }
}

FLASHFUNC void encoder_align(encoder_t *enc, uint32_t count)
{
    if (!enc->valid) {
        return;
    }
    const float theta = encoder_elec_angle(enc, mathx_umod_u32(count, enc->cfg.counts_per_rev));
    enc->offset_el_rad = mathx_wrap_2pi(-theta);
}
