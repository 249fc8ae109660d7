/* hal_sim.c - hal/hal.h on the simulated board; see hal_sim.h. */
#include "hal_sim.h"

#include <math.h>
#include <string.h>

#define TABLE1_VDC_V 311.0
#define PWM_PERIOD_S 1.0e-4          /* 10 kHz, the paper's sampling frequency */
/* RK4 step bound inside a constant-voltage piece: by default a piece (at most
 * one period) is one step. Its error is below 1e-8 of the current at the
 * paper's speeds (|omega_el| Ts, R Ts / L < 0.07), and tests/test_inverter.c
 * checks it against 1 us steps; the bench targets need the long step. */
#define DEFAULT_SUBSTEP_S PWM_PERIOD_S
#define DEFAULT_TRIP_A 15.0          /* comparators at the end of the current ADC range */
#define DUTY_ZERO_VOLTAGE 0.5        /* all legs at half duty: zero line-to-line voltage */
#define CPU_CLOCK_HZ 150.0e6         /* F28335 SYSCLKOUT: hal_cycles() counts simulated time in it */
#define CYCLE_COUNTER_BITS 32
#define N_PHASES 3

static struct {
    hal_sim_cfg_t cfg;
    plant_t plant;
    prng_t prng;
    double t_s;
    double load_Nm;
    double duty_shadow[N_PHASES];   /* written by the ISR, active from the next period */
    double duty_active[N_PHASES];
    bool pwm_enabled;
    bool trip;
    hal_isr_fn isr;
    bool ack_pending;
    bool isr_stalled;
    uint32_t isr_calls;
    uint32_t watchdog_kicks;
    uint32_t cycles;                /* hal_cycles(): CPU clock cycles of simulated time, mod 2^32 */
    uint32_t cycles_per_period;
    hal_sample_t sample;
    hal_sim_truth_t truth;
} g_sim;

void hal_sim_default_cfg(hal_sim_cfg_t *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    plant_default_cfg(&cfg->plant);
    cfg->theta_offset_el_rad = 0.0;
    cfg->inv.model = INV_AVERAGED;
    cfg->inv.vdc_V = TABLE1_VDC_V;
    cfg->inv.Ts_s = PWM_PERIOD_S;
    cfg->inv.deadtime_s = 0.0;
    cfg->inv.substep_max_s = DEFAULT_SUBSTEP_S;
    sensors_default_cfg(&cfg->sens);
    cfg->trip_current_A = DEFAULT_TRIP_A;
}

void hal_sim_configure(const hal_sim_cfg_t *cfg)
{
    memset(&g_sim, 0, sizeof g_sim);
    g_sim.cfg = *cfg;
    plant_init(&g_sim.plant, &cfg->plant, cfg->theta_offset_el_rad);
    prng_seed(&g_sim.prng, cfg->sens.seed);
    g_sim.cycles_per_period = (uint32_t)llround(fmod(cfg->inv.Ts_s * CPU_CLOCK_HZ, ldexp(1.0, CYCLE_COUNTER_BITS)));
    for (int k = 0; k < N_PHASES; k++) {
        g_sim.duty_shadow[k] = DUTY_ZERO_VOLTAGE;
        g_sim.duty_active[k] = DUTY_ZERO_VOLTAGE;
    }
}

void hal_sim_set_load(double TL_Nm)
{
    g_sim.load_Nm = TL_Nm;
}

void hal_sim_set_R_ohm(double R_ohm)
{
    plant_set_R_ohm(&g_sim.plant, R_ohm);
}

void hal_sim_force_trip(void)
{
    g_sim.trip = true;
    g_sim.pwm_enabled = false;
}

uint32_t hal_sim_watchdog_kicks(void)
{
    return g_sim.watchdog_kicks;
}

/* Step 1 of hal_sim_period(): shadow load, samples, comparator, truth at t_k. */
static void sample_at_period_start(void)
{
    const hal_sim_cfg_t *c = &g_sim.cfg;
    hal_sim_truth_t *tr = &g_sim.truth;
    memcpy(g_sim.duty_active, g_sim.duty_shadow, sizeof g_sim.duty_active);

    double i_abc[N_PHASES];
    const double th_el = plant_theta_el_rad(&g_sim.plant);
    plant_iabc_at_A(&g_sim.plant, th_el, i_abc);
    for (int k = 0; k < N_PHASES; k++) {
        if (fabs(i_abc[k]) > c->trip_current_A) {
            hal_sim_force_trip();
        }
    }
    g_sim.sample.ia_A = (float)sensor_adc_current_A(&c->sens, &g_sim.prng, i_abc[0], c->sens.adc_offset_a_A);
    g_sim.sample.ib_A = (float)sensor_adc_current_A(&c->sens, &g_sim.prng, i_abc[1], c->sens.adc_offset_b_A);
    g_sim.sample.vdc_V = (float)sensor_adc_vdc_V(&c->sens, c->inv.vdc_V);
    g_sim.sample.enc_count = sensor_encoder_count(&c->sens, g_sim.plant.x.theta_m_rad);

    tr->t_s = g_sim.t_s;
    tr->id_A = g_sim.plant.x.id_A;
    tr->iq_A = g_sim.plant.x.iq_A;
    tr->R_ohm = g_sim.plant.cfg.R_ohm;
    tr->ia_A = i_abc[0];
    tr->ib_A = i_abc[1];
    tr->ic_A = i_abc[2];
    tr->speed_m_rad_s = g_sim.plant.x.omega_m_rad_s;
    tr->theta_el_rad = th_el;
    tr->te_Nm = plant_te_Nm(&g_sim.plant);
    tr->psi_s_Wb = plant_psi_s_Wb(&g_sim.plant);
}

void hal_sim_period(void)
{
    const hal_sim_cfg_t *c = &g_sim.cfg;
    hal_sim_truth_t *tr = &g_sim.truth;
    sample_at_period_start();

    if (g_sim.isr != NULL && !g_sim.isr_stalled) {
        g_sim.ack_pending = true;
        g_sim.isr_calls++;
        g_sim.isr();
        g_sim.isr_stalled = g_sim.ack_pending;
    }

    plant_acc_clear(&g_sim.plant);
    bool gates_on = g_sim.pwm_enabled && !g_sim.trip;
    if (gates_on) {
        inv_period(&c->inv, g_sim.duty_active, g_sim.load_Nm, &g_sim.plant);
    } else {
        plant_step_open(&g_sim.plant, g_sim.load_Nm, c->inv.Ts_s);
    }
    const plant_acc_t *acc = &g_sim.plant.acc;
    tr->ud_mean_V = acc->ud_Vs / acc->time_s;
    tr->uq_mean_V = acc->uq_Vs / acc->time_s;
    tr->id_mean_A = acc->id_As / acc->time_s;
    tr->iq_mean_A = acc->iq_As / acc->time_s;
    tr->load_Nm = g_sim.load_Nm;
    memcpy(tr->duty, g_sim.duty_active, sizeof tr->duty);
    tr->pwm_enabled = gates_on;
    tr->trip = g_sim.trip;
    tr->isr_stalled = g_sim.isr_stalled;
    tr->isr_calls = g_sim.isr_calls;
    g_sim.t_s += c->inv.Ts_s;
    g_sim.cycles += g_sim.cycles_per_period;
}

void hal_sim_truth(hal_sim_truth_t *out)
{
    *out = g_sim.truth;
}

/* ---- hal.h ---------------------------------------------------------------- */

void hal_init(void)
{
    g_sim.pwm_enabled = false;
    g_sim.isr = NULL;
}

void hal_isr_attach(hal_isr_fn isr)
{
    g_sim.isr = isr;
    g_sim.isr_stalled = false;
}

void hal_sample_read(hal_sample_t *out)
{
    *out = g_sim.sample;
}

void hal_pwm_write(const float duty[3])
{
    for (int k = 0; k < N_PHASES; k++) {
        double d = (double)duty[k];
        g_sim.duty_shadow[k] = (d > 1.0) ? 1.0 : ((d >= 0.0) ? d : 0.0);   /* NaN maps to 0 */
    }
}

void hal_pwm_enable(void)
{
    if (!g_sim.trip) {
        g_sim.pwm_enabled = true;
    }
}

void hal_pwm_disable(void)
{
    g_sim.pwm_enabled = false;
}

bool hal_trip_active(void)
{
    return g_sim.trip;
}

void hal_trip_clear(void)
{
    g_sim.trip = false;
}

void hal_isr_ack(void)
{
    g_sim.ack_pending = false;
}

uint32_t hal_cycles(void)
{
    /* Simulated time, so runs stay reproducible; wraps like the 32-bit counter
     * (unsigned arithmetic of the period count). */
    return g_sim.cycles;
}

void hal_watchdog_kick(void)
{
    g_sim.watchdog_kicks++;
}
