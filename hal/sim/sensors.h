/*
 * sensors.h - the simulated board's measurement chain: incremental encoder
 * (x4 decoding), 12-bit current ADC with offset and Gaussian noise, DC-bus
 * ADC. Host-only. The noise comes from an own seeded PRNG (xorshift64*
 * and Box-Muller), so a seed reproduces a run bit for bit on any libc.
 */
#ifndef SENSORS_H
#define SENSORS_H

#include <math.h>
#include <stdint.h>

typedef struct {
    uint32_t enc_lines;        /* encoder lines per revolution; counts = 4 x lines */
    uint32_t adc_bits;         /* ADC resolution */
    double adc_full_scale_A;   /* current range is [-full scale, +full scale) */
    double adc_offset_a_A;     /* offset error of the phase-a channel */
    double adc_offset_b_A;
    double adc_noise_A;        /* standard deviation of the Gaussian noise, 0 = off */
    double vdc_full_scale_V;   /* DC-bus channel range [0, full scale) */
    uint64_t seed;             /* PRNG seed, any value (0 is remapped) */
} sensors_cfg_t;

/* A measurement chain ready to sample: its cfg and the scales derived from
 * it once (sensors_init), so a sample divides once and shifts nothing. */
typedef struct {
    sensors_cfg_t cfg;
    uint32_t enc_cpr;          /* counts per turn, 4 x lines */
    double i_lsb_A;            /* current ADC step */
    double i_code_min;         /* its code range, zero current at code 0 */
    double i_code_max;
    double vdc_lsb_V;          /* DC-bus ADC step */
    double vdc_code_max;       /* its code range starts at 0 */
} sensors_t;

typedef struct {
    uint64_t s;                /* xorshift64* state, never 0 */
    double spare;              /* second Box-Muller deviate */
    int has_spare;
} prng_t;

/* Seed the generator; the same seed gives the same sequence. */
void prng_seed(prng_t *g, uint64_t seed);

/* Uniform deviate in (0, 1). */
double prng_uniform(prng_t *g);

/* Standard normal deviate. */
double prng_gauss(prng_t *g);

/* Board defaults: 2500 lines, 12 bits over +-15 A, no offset, no noise, 600 V bus range, seed 1. */
void sensors_default_cfg(sensors_cfg_t *cfg);

/* The chain of *cfg (copied) with its scales derived; the PRNG is the caller's. */
void sensors_init(sensors_t *s, const sensors_cfg_t *cfg);

/* Encoder count 0 .. 4 lines - 1 at mechanical angle theta_m_rad (any value, wrapped). */
uint32_t sensor_encoder_count(const sensors_t *s, double theta_m_rad);

/* Round x / lsb to the nearest code in [lo_code, hi_code], return code x lsb. */
static inline double sensor_quantize(double x, double lsb, double lo_code, double hi_code)
{
    double code = floor(x / lsb + 0.5);
    if (code < lo_code) {
        code = lo_code;
    } else if (code > hi_code) {
        code = hi_code;
    }
    return code * lsb;
}

/* The ADC's reading [A] of current i_A: offset, noise from *g, 12-bit rounding, range clamp.
 * Inline: twice a period, the noise's call the exception. */
static inline double sensor_adc_current_A(const sensors_t *s, prng_t *g, double i_A, double offset_A)
{
    double x = i_A + offset_A;
    if (s->cfg.adc_noise_A > 0.0) {
        x += s->cfg.adc_noise_A * prng_gauss(g);
    }
    return sensor_quantize(x, s->i_lsb_A, s->i_code_min, s->i_code_max);
}

/* The ADC's reading [V] of the DC-bus voltage vdc_V: rounding to the bus channel's LSB, range clamp. */
double sensor_adc_vdc_V(const sensors_t *s, double vdc_V);

#endif /* SENSORS_H */
