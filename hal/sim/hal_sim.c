/* hal_sim.c - hal/hal.h on the simulated board; see hal_sim.h. */
#include "hal_sim.h"
#include "sim_units.h"

#include <math.h>
#include <string.h>

#define PWM_PERIOD_S 1.0e-4          /* 10 kHz, the paper's sampling frequency */
/* Longest time the plant solves at once: by default the whole period
 * (hal/sim/plant_design.md: exact at a held speed, 1e-7 A against a fine
 * RK4 with the shaft free); tests/test_inverter.c checks it against 1 us. */
#define DEFAULT_SUBSTEP_S PWM_PERIOD_S
#define DEFAULT_TRIP_A 15.0          /* comparators at the end of the current ADC range */
#define DUTY_ZERO_VOLTAGE 0.5        /* all legs at half duty: zero line-to-line voltage */
#define CPU_CLOCK_HZ 150.0e6         /* F28335 SYSCLKOUT: hal_cycles() counts simulated time in it */
#define CYCLE_COUNTER_BITS 32
#define N_PHASES 3
#define SQRT3_2 0.8660254037844386
/* A fault time t_f starts the fault at the first t_k >= t_f; t_k is a sum of
 * periods, so t_f = k Ts must not miss period k by rounding. */
#define FAULT_TIME_TOL_PER_TS 1.0e-6
/* Defaults of the injected faults (hal_sim_faults_none). */
#define DEFAULT_SHORT_OHM 0.1        /* a bolted short through a cable loop */
#define DEFAULT_SHORT_H 10.0e-6
#define DEFAULT_ENC_JUMP_COUNTS 2500 /* a quarter turn of the 2500-line encoder */
#define DEFAULT_VDC_SAG_V 150.0      /* below the board's 200 V undervoltage trip */
#define DEFAULT_VDC_SURGE_V 450.0    /* above its 400 V overvoltage trip */
#define DEFAULT_ISR_OVERRUN_RUN_S 1.2e-4   /* longer than a period */

static struct {
    hal_sim_cfg_t cfg;
    plant_t plant;
    sensors_t sens;
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
    float vdc_reading_V;            /* the bus ADC's reading of cfg.inv.vdc_V (set_bus) */
    hal_sim_truth_t truth;          /* the derived fields NaN (truth_derive) */
    plant_state_t x_k;              /* the plant's state at t_k */
    plant_t probe;                  /* the motor's constants (never R) with x_k, for truth_derive */
    bool stepped;                   /* a period ran since hal_sim_configure() */
    /* fault injection */
    hal_sim_faults_t faults;
    uint32_t faults_active;
    uint32_t faults_new;            /* the bits that started at this t_k */
    double faults_next_s;           /* the earliest time of a fault not yet due (faults_due) */
    float stuck_value_A;            /* ADC_STUCK: the frozen reading */
    uint32_t enc_frozen;            /* ENC_LOST: the frozen count */
    double i_short_A;               /* SHORT: current from the first output into the second */
    uint32_t cycles_extra;          /* hal_cycles(): added to its next answer ... */
    uint32_t cycles_extra_later;    /* ... and to every one after it (the ISR's overrun) */
    uint32_t overrun_cycles;        /* isr_overrun_run_s in hal_cycles() counts */
} g_sim;

void hal_sim_default_cfg(hal_sim_cfg_t *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    /* the motor and the bus: the caller's (hal_sim.h) */
    cfg->plant.R_Ohm = NAN;
    cfg->plant.L_H = NAN;
    cfg->plant.psi_f_Wb = NAN;
    cfg->plant.J_kgm2 = NAN;
    cfg->enc_offset_el_rad = 0.0;
    cfg->inv.model = INV_AVERAGED;
    cfg->inv.vdc_V = NAN;
    cfg->inv.Ts_s = PWM_PERIOD_S;
    cfg->inv.deadtime_s = 0.0;
    cfg->inv.substep_max_s = DEFAULT_SUBSTEP_S;
    sensors_default_cfg(&cfg->sens);
    cfg->trip_current_A = DEFAULT_TRIP_A;
}

/* The bus steps to vdc_V (power-on, an injected sag or surge); the bus ADC reads it. */
static void set_bus(double vdc_V)
{
    g_sim.cfg.inv.vdc_V = vdc_V;
    g_sim.vdc_reading_V = (float)sensor_adc_vdc_V(&g_sim.sens, vdc_V);
}

void hal_sim_configure(const hal_sim_cfg_t *cfg)
{
    hal_sim_truth_t *tr = &g_sim.truth;
    memset(&g_sim, 0, sizeof g_sim);
    g_sim.cfg = *cfg;
    plant_cfg_t shaft = cfg->plant;
    shaft.B_Nms += cfg->load_B_Nms;   /* the load's viscous friction acts as the shaft's own */
    plant_init(&g_sim.plant, &shaft, cfg->enc_offset_el_rad);
    g_sim.probe = g_sim.plant;
    sensors_init(&g_sim.sens, &cfg->sens);
    prng_seed(&g_sim.prng, cfg->sens.seed);
    set_bus(cfg->inv.vdc_V);
    tr->theta_el_rad = NAN;
    tr->te_Nm = NAN;
    tr->psi_s_Wb = NAN;
    tr->ud_mean_V = NAN;
    tr->uq_mean_V = NAN;
    tr->id_mean_A = NAN;
    tr->iq_mean_A = NAN;
    g_sim.cycles_per_period = (uint32_t)llround(fmod(cfg->inv.Ts_s * CPU_CLOCK_HZ, ldexp(1.0, CYCLE_COUNTER_BITS)));
    for (int k = 0; k < N_PHASES; k++) {
        g_sim.duty_shadow[k] = DUTY_ZERO_VOLTAGE;
        g_sim.duty_active[k] = DUTY_ZERO_VOLTAGE;
    }
    hal_sim_faults_t none;
    hal_sim_faults_none(&none);
    hal_sim_set_faults(&none);
}

void hal_sim_set_load(double TL_Nm)
{
    g_sim.load_Nm = TL_Nm;
}

void hal_sim_set_R_Ohm(double R_Ohm)
{
    plant_set_R_Ohm(&g_sim.plant, R_Ohm);
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

/* ---- fault injection -------------------------------------------------- */

void hal_sim_faults_none(hal_sim_faults_t *f)
{
    memset(f, 0, sizeof *f);
    f->open_phase_s = NAN;
    f->short_s = NAN;
    f->short_ohm = DEFAULT_SHORT_OHM;
    f->short_H = DEFAULT_SHORT_H;
    f->adc_stuck_s = NAN;
    f->enc_lost_s = NAN;
    f->enc_jump_s = NAN;
    f->enc_jump_counts = DEFAULT_ENC_JUMP_COUNTS;
    f->vdc_sag_s = NAN;
    f->vdc_sag_V = DEFAULT_VDC_SAG_V;
    f->vdc_surge_s = NAN;
    f->vdc_surge_V = DEFAULT_VDC_SURGE_V;
    f->gate_trip_s = NAN;
    f->isr_overrun_s = NAN;
    f->isr_overrun_run_s = DEFAULT_ISR_OVERRUN_RUN_S;
}

void hal_sim_set_faults(const hal_sim_faults_t *f)
{
    g_sim.faults = *f;
    g_sim.faults_active = 0u;
    g_sim.overrun_cycles = (uint32_t)llround(f->isr_overrun_run_s * CPU_CLOCK_HZ);
    g_sim.faults_next_s = -INFINITY;   /* judged at the next t_k */
}

/* Fault time f_s is due at t (NaN never comes); if not, it bounds *next_s. */
static uint32_t fault_due(double t, double f_s, uint32_t bit, double *next_s)
{
    if (t >= f_s) {
        return bit;
    }
    if (f_s < *next_s) {
        *next_s = f_s;
    }
    return 0u;
}

/* The bits of the faults whose time has come by t (t_k with its rounding
 * tolerance), and in faults_next_s the earliest time of one that has not
 * (+inf: none). */
static uint32_t faults_due(double t)
{
    const hal_sim_faults_t *f = &g_sim.faults;
    double next_s = INFINITY;
    uint32_t m = 0u;
    m |= fault_due(t, f->open_phase_s, SIM_FAULT_OPEN_PHASE, &next_s);
    m |= fault_due(t, f->short_s, SIM_FAULT_SHORT, &next_s);
    m |= fault_due(t, f->adc_stuck_s, SIM_FAULT_ADC_STUCK, &next_s);
    m |= fault_due(t, f->enc_lost_s, SIM_FAULT_ENC_LOST, &next_s);
    m |= fault_due(t, f->enc_jump_s, SIM_FAULT_ENC_JUMP, &next_s);
    m |= fault_due(t, f->vdc_sag_s, SIM_FAULT_VDC_SAG, &next_s);
    m |= fault_due(t, f->vdc_surge_s, SIM_FAULT_VDC_SURGE, &next_s);
    m |= fault_due(t, f->gate_trip_s, SIM_FAULT_GATE_TRIP, &next_s);
    m |= fault_due(t, f->isr_overrun_s, SIM_FAULT_ISR_OVERRUN, &next_s);
    g_sim.faults_next_s = next_s;
    return m;
}

/* At t_k, before the samples: the faults that start now change the board.
 * Time only grows, so the due set changes only once faults_next_s is reached. */
static void faults_start(void)
{
    const double t = g_sim.t_s + FAULT_TIME_TOL_PER_TS * g_sim.cfg.inv.Ts_s;
    if (!(t >= g_sim.faults_next_s)) {
        g_sim.faults_new = 0u;
        return;
    }
    const uint32_t due = faults_due(t);
    const uint32_t new_bits = due & ~g_sim.faults_active;
    g_sim.faults_active = due;
    g_sim.faults_new = new_bits;
    if ((new_bits & SIM_FAULT_VDC_SAG) != 0u) {
        set_bus(g_sim.faults.vdc_sag_V);
    }
    if ((new_bits & SIM_FAULT_VDC_SURGE) != 0u) {
        set_bus(g_sim.faults.vdc_surge_V);
    }
    if ((new_bits & SIM_FAULT_GATE_TRIP) != 0u) {
        hal_sim_force_trip();
    }
}

/* The inverter output currents the sensors and comparators see: the motor's plus the short's. */
static void faults_leg_currents(double i_abc[N_PHASES])
{
    if ((g_sim.faults_active & SIM_FAULT_SHORT) != 0u) {
        const uint32_t x = g_sim.faults.short_pair % N_PHASES;
        i_abc[x] += g_sim.i_short_A;
        i_abc[(x + 1u) % N_PHASES] -= g_sim.i_short_A;
    }
}

/* The samples after the sensors: a stuck channel, a lost or jumping count. */
static void faults_samples(hal_sample_t *s, uint32_t new_bits)
{
    if (g_sim.faults_active == 0u) {
        return;   /* new_bits are active ones */
    }
    const uint32_t cpr = g_sim.sens.enc_cpr;
    float *ch = (g_sim.faults.adc_stuck_channel == 0u) ? &s->ia_A : &s->ib_A;

    if ((new_bits & SIM_FAULT_ADC_STUCK) != 0u) {
        g_sim.stuck_value_A = *ch;
    }
    if ((g_sim.faults_active & SIM_FAULT_ADC_STUCK) != 0u) {
        *ch = g_sim.stuck_value_A;
    }
    if ((g_sim.faults_active & SIM_FAULT_ENC_JUMP) != 0u) {
        int64_t c = ((int64_t)s->enc_count + g_sim.faults.enc_jump_counts) % (int64_t)cpr;
        s->enc_count = (uint32_t)((c < 0) ? c + (int64_t)cpr : c);
    }
    if ((new_bits & SIM_FAULT_ENC_LOST) != 0u) {
        g_sim.enc_frozen = s->enc_count;
    }
    if ((g_sim.faults_active & SIM_FAULT_ENC_LOST) != 0u) {
        s->enc_count = g_sim.enc_frozen;
    }
}

/* After the plant's period: an open phase carries no current (the component
 * of the stator current along its axis is removed, once per period: exact
 * with the period solved at once, as the SPMSM's alpha and beta
 * equations do not couple); the short's current over the period. */
static void faults_after_period(bool gates_on)
{
    if (g_sim.faults_active == 0u) {
        return;
    }
    if ((g_sim.faults_active & SIM_FAULT_OPEN_PHASE) != 0u) {
        plant_t *p = &g_sim.plant;
        const double th = plant_theta_el_rad(p);
        const double ax = SIM_TWO_PI / 3.0 * (double)(g_sim.faults.open_phase % N_PHASES);
        const double c = cos(th), s = sin(th);
        double ia = p->x.id_A * c - p->x.iq_A * s;   /* alpha-beta */
        double ib = p->x.id_A * s + p->x.iq_A * c;
        const double along = ia * cos(ax) + ib * sin(ax);
        ia -= along * cos(ax);
        ib -= along * sin(ax);
        p->x.id_A = ia * c + ib * s;
        p->x.iq_A = -ia * s + ib * c;
    }
    if ((g_sim.faults_active & SIM_FAULT_SHORT) != 0u) {
        /* L di/dt = v - R i over the period with the period-mean line voltage; outputs off: zero at once */
        const uint32_t x = g_sim.faults.short_pair % N_PHASES;
        const double v = (g_sim.duty_active[x] - g_sim.duty_active[(x + 1u) % N_PHASES]) * g_sim.cfg.inv.vdc_V;
        const double R = g_sim.faults.short_ohm;
        const double e = exp(-R * g_sim.cfg.inv.Ts_s / g_sim.faults.short_H);
        g_sim.i_short_A = gates_on ? (g_sim.i_short_A * e + v / R * (1.0 - e)) : 0.0;
    }
}

/* Step 1 of hal_sim_period(): shadow load, samples, comparator, truth at
 * t_k (what truth_derive() needs of it: the state). */
static void sample_at_period_start(void)
{
    const hal_sim_cfg_t *c = &g_sim.cfg;
    hal_sim_truth_t *tr = &g_sim.truth;
    memcpy(g_sim.duty_active, g_sim.duty_shadow, sizeof g_sim.duty_active);
    if (c->phases_acb) {
        /* the motor's phases b and c driven by legs c and b */
        const double d = g_sim.duty_active[1];
        g_sim.duty_active[1] = g_sim.duty_active[2];
        g_sim.duty_active[2] = d;
    }
    faults_start();

    double i_abc[N_PHASES];
    double i_leg[N_PHASES];
    g_sim.x_k = g_sim.plant.x;
    plant_iabc_A(&g_sim.plant, i_abc);
    memcpy(i_leg, i_abc, sizeof i_leg);
    faults_leg_currents(i_leg);
    for (int k = 0; k < N_PHASES; k++) {
        if (fabs(i_leg[k]) > c->trip_current_A) {
            hal_sim_force_trip();
        }
    }
    g_sim.sample.ia_A = (float)sensor_adc_current_A(&g_sim.sens, &g_sim.prng, i_leg[0], c->sens.adc_offset_a_A);
    g_sim.sample.ib_A = (float)sensor_adc_current_A(&g_sim.sens, &g_sim.prng, i_leg[1], c->sens.adc_offset_b_A);
    g_sim.sample.vdc_V = g_sim.vdc_reading_V;
    g_sim.sample.enc_count = sensor_encoder_count(&g_sim.sens, g_sim.plant.x.theta_m_rad);
    if (c->enc_reversed && (g_sim.sample.enc_count != 0u)) {
        g_sim.sample.enc_count = g_sim.sens.enc_cpr - g_sim.sample.enc_count; /* A and B swapped */
    }
    faults_samples(&g_sim.sample, g_sim.faults_new);

    tr->t_s = g_sim.t_s;
    tr->i_short_A = g_sim.i_short_A;
    tr->id_A = g_sim.plant.x.id_A;
    tr->iq_A = g_sim.plant.x.iq_A;
    tr->R_Ohm = g_sim.plant.cfg.R_Ohm;
    tr->ia_A = i_abc[0];
    tr->ib_A = i_abc[1];
    tr->ic_A = i_abc[2];
    tr->speed_m_rad_s = g_sim.plant.x.omega_m_rad_s;
}

/* The truth's fields derived on demand (hal_sim_truth): at t_k from the
 * state then (x_k) and the motor's constants (R, which may change, is not
 * among their inputs); the period means from the plant's integrals, kept
 * until the next period clears them. */
static void truth_derive(hal_sim_truth_t *tr)
{
    const plant_acc_t *acc = &g_sim.plant.acc;
    g_sim.probe.x = g_sim.x_k;
    tr->theta_el_rad = plant_theta_el_rad(&g_sim.probe);
    tr->te_Nm = plant_te_Nm(&g_sim.probe);
    tr->psi_s_Wb = plant_psi_s_Wb(&g_sim.probe);
    tr->ud_mean_V = acc->ud_Vs / acc->time_s;
    tr->uq_mean_V = acc->uq_Vs / acc->time_s;
    tr->id_mean_A = acc->id_As / acc->time_s;
    tr->iq_mean_A = acc->iq_As / acc->time_s;
}

/* The load's Coulomb friction on a shaft turning at w [N m, against the motion]; at rest none
 * here: coulomb_stop() holds the shaft up to it. */
static double coulomb_Nm(double w_m_rad_s)
{
    const double fc = g_sim.cfg.load_coulomb_Nm;
    return (w_m_rad_s > 0.0) ? fc : ((w_m_rad_s < 0.0) ? -fc : 0.0);
}

/* After a period that began at w0: a turning shaft the friction stopped within the period stays at
 * rest (the speed would cross zero); a shaft at rest moves only by what the torque left beyond the
 * friction's impulse fc Ts / J (hal/sim/plant_design.md sec. 10). */
static void coulomb_stop(double w0)
{
    const double fc = g_sim.cfg.load_coulomb_Nm;
    const double w1 = g_sim.plant.x.omega_m_rad_s;
    if (!(fc > 0.0) || g_sim.cfg.plant.speed_held) {
        return;
    }
    if ((w0 > 0.0 && !(w1 > 0.0)) || (w0 < 0.0 && !(w1 < 0.0))) {
        plant_set_speed(&g_sim.plant, 0.0);
    } else if (!(w0 > 0.0) && !(w0 < 0.0)) {
        const double dw = fc * g_sim.cfg.inv.Ts_s / g_sim.cfg.plant.J_kgm2;
        plant_set_speed(&g_sim.plant, (fabs(w1) <= dw) ? 0.0 : w1 - copysign(dw, w1));
    }
}

void hal_sim_period(void)
{
    const hal_sim_cfg_t *c = &g_sim.cfg;
    hal_sim_truth_t *tr = &g_sim.truth;
    sample_at_period_start();

    if (g_sim.isr != NULL && !g_sim.isr_stalled) {
        g_sim.ack_pending = true;
        g_sim.isr_calls++;
        /* an injected overrun: every hal_cycles() call after the ISR's first is later */
        g_sim.cycles_extra_later = ((g_sim.faults_new & SIM_FAULT_ISR_OVERRUN) != 0u) ? g_sim.overrun_cycles : 0u;
        g_sim.isr();
        g_sim.cycles_extra = 0u;
        g_sim.cycles_extra_later = 0u;
        g_sim.isr_stalled = g_sim.ack_pending;
    }

    plant_acc_clear(&g_sim.plant);
    bool gates_on = g_sim.pwm_enabled && !g_sim.trip;
    const double w0 = g_sim.plant.x.omega_m_rad_s;
    const double TL = g_sim.load_Nm + coulomb_Nm(w0);
    if (gates_on) {
        inv_period(&c->inv, g_sim.duty_active, TL, &g_sim.plant);
    } else {
        plant_step_rectified(&g_sim.plant, c->inv.vdc_V, c->inv.device_drop_V, TL, c->inv.Ts_s);
    }
    coulomb_stop(w0);
    faults_after_period(gates_on);
    tr->load_Nm = g_sim.load_Nm;
    memcpy(tr->duty, g_sim.duty_active, sizeof tr->duty);
    tr->pwm_enabled = gates_on;
    tr->trip = g_sim.trip;
    tr->isr_stalled = g_sim.isr_stalled;
    tr->isr_calls = g_sim.isr_calls;
    tr->faults_active = g_sim.faults_active;
    g_sim.t_s += c->inv.Ts_s;
    g_sim.cycles += g_sim.cycles_per_period;
    g_sim.stepped = true;
}

void hal_sim_truth(hal_sim_truth_t *out)
{
    *out = g_sim.truth;
    if (g_sim.stepped) {
        truth_derive(out);
    } else {
        out->theta_el_rad = 0.0;   /* power-on: all zero */
        out->te_Nm = 0.0;
        out->psi_s_Wb = 0.0;
        out->ud_mean_V = 0.0;
        out->uq_mean_V = 0.0;
        out->id_mean_A = 0.0;
        out->iq_mean_A = 0.0;
    }
}

const hal_sim_truth_t *hal_sim_truth_view(void)
{
    return &g_sim.truth;
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

/* The SIL's background runs between periods: nothing interrupts it. */
void hal_isr_pause(void)
{
}

void hal_isr_resume(void)
{
}

void hal_sample_read(hal_sample_t *out)
{
    *out = g_sim.sample;
}

/* A duty into [0, 1]; NaN maps to 0. */
static double duty_clamp(float duty)
{
    const double d = (double)duty;
    const double lo = (d >= 0.0) ? d : 0.0;
    return (lo <= 1.0) ? lo : 1.0;
}

void hal_pwm_write(const float duty[3])
{
    g_sim.duty_shadow[0] = duty_clamp(duty[0]);
    g_sim.duty_shadow[1] = duty_clamp(duty[1]);
    g_sim.duty_shadow[2] = duty_clamp(duty[2]);
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
     * (unsigned arithmetic of the period count). It stands still inside the
     * ISR, except in an injected overrun: every call after the ISR's first
     * is isr_overrun_run_s later. */
    const uint32_t now = g_sim.cycles + g_sim.cycles_extra;
    g_sim.cycles_extra = g_sim.cycles_extra_later;
    return now;
}

void hal_watchdog_kick(void)
{
    g_sim.watchdog_kicks++;
}
