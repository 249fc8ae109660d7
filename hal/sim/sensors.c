/* sensors.c - encoder, ADC and PRNG of the simulated board; see sensors.h. */
#include "sensors.h"
#include "sim_units.h"

#include <math.h>

#define QUAD_COUNTS_PER_LINE 4u

#define DEFAULT_ENC_LINES 2500u
#define DEFAULT_ADC_BITS 12u
/* As the board's front end (hal/f28335/board_hw.h): 10 A/V around 1.5 V on a
 * 0..3 V ADC gives +-15 A; the bus divider 200 V/V gives 0..600 V. */
#define DEFAULT_ADC_FULL_SCALE_A 15.0
#define DEFAULT_VDC_FULL_SCALE_V 600.0
#define DEFAULT_SEED 1u

/* xorshift64* (Vigna 2016): shifts and multiplier of the published generator. */
#define XS_A 12
#define XS_B 25
#define XS_C 27
#define XS_MULT 2685821657736338717ull
#define XS_ZERO_SEED_REPLACEMENT 0x9E3779B97F4A7C15ull
#define MANTISSA_BITS 53
#define U64_TO_53 11   /* 64 - 53: keep the top 53 bits */

void prng_seed(prng_t *g, uint64_t seed)
{
    g->s = (seed != 0u) ? seed : XS_ZERO_SEED_REPLACEMENT;   /* xorshift state must not be 0 */
    g->has_spare = 0;
    g->spare = 0.0;
}

double prng_uniform(prng_t *g)
{
    g->s ^= g->s >> XS_A;
    g->s ^= g->s << XS_B;
    g->s ^= g->s >> XS_C;
    uint64_t r = (g->s * XS_MULT) >> U64_TO_53;
    /* (r + 0.5) / 2^53 never hits 0 or 1, so log() below stays finite. */
    return ((double)r + 0.5) / (double)((uint64_t)1u << MANTISSA_BITS);
}

double prng_gauss(prng_t *g)
{
    if (g->has_spare) {
        g->has_spare = 0;
        return g->spare;
    }
    double r = sqrt(-2.0 * log(prng_uniform(g)));
    double phi = SIM_TWO_PI * prng_uniform(g);
    g->spare = r * sin(phi);
    g->has_spare = 1;
    return r * cos(phi);
}

void sensors_default_cfg(sensors_cfg_t *cfg)
{
    cfg->enc_lines = DEFAULT_ENC_LINES;
    cfg->adc_bits = DEFAULT_ADC_BITS;
    cfg->adc_full_scale_A = DEFAULT_ADC_FULL_SCALE_A;
    cfg->adc_offset_a_A = 0.0;
    cfg->adc_offset_b_A = 0.0;
    cfg->adc_noise_A = 0.0;
    cfg->vdc_full_scale_V = DEFAULT_VDC_FULL_SCALE_V;
    cfg->seed = DEFAULT_SEED;
}

void sensors_init(sensors_t *s, const sensors_cfg_t *cfg)
{
    const double half_codes = (double)((uint64_t)1u << (cfg->adc_bits - 1u));   /* mid-scale code = zero current */
    const double codes = (double)((uint64_t)1u << cfg->adc_bits);

    s->cfg = *cfg;
    s->enc_cpr = QUAD_COUNTS_PER_LINE * cfg->enc_lines;
    s->i_lsb_A = cfg->adc_full_scale_A / half_codes;
    s->i_code_min = -half_codes;
    s->i_code_max = half_codes - 1.0;
    s->vdc_lsb_V = cfg->vdc_full_scale_V / codes;
    s->vdc_code_max = codes - 1.0;
}

uint32_t sensor_encoder_count(const sensors_t *s, double theta_m_rad)
{
    const uint32_t cpr = s->enc_cpr;
    double frac = theta_m_rad / SIM_TWO_PI;   /* turns */
    if (!((frac >= 0.0) && (frac < 1.0))) {
        frac -= floor(frac);                  /* the plant's angle is in [0, 2 pi): seldom */
    }
    uint32_t n = (uint32_t)(frac * (double)cpr);   /* >= 0: truncation is floor() */
    return (n >= cpr) ? n - cpr : n;   /* frac * cpr may round up to cpr */
}

double sensor_adc_vdc_V(const sensors_t *s, double vdc_V)
{
    return sensor_quantize(vdc_V, s->vdc_lsb_V, 0.0, s->vdc_code_max);
}
