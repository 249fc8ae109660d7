/*
 * hal_sim.h - configuration, stepping and ground truth of the simulated
 * board that implements hal/hal.h on the host (plant.h, inverter.h,
 * sensors.h behind it). Host-only; one board per process (the HAL is a
 * set of free functions, as on the DSP).
 *
 * Timing (the DSP's, see hal.h): hal_sim_period() simulates period k:
 *   1. t_k: the duties written during period k-1 become active (shadow
 *      load at counter zero); currents, DC bus and encoder are sampled;
 *      the hardware overcurrent comparator is checked;
 *   2. the attached ISR runs once (it reads those samples and writes the
 *      duties for period k+1);
 *   3. the plant is integrated over [t_k, t_k + Ts] with the active
 *      duties, or with the stator open while the outputs are off.
 * An ISR that returns without hal_isr_ack() is not called again, as the
 * PIE would not take the interrupt again.
 */
#ifndef HAL_SIM_H
#define HAL_SIM_H

#include <stdbool.h>
#include <stdint.h>

#include "hal.h"
#include "inverter.h"
#include "plant.h"
#include "sensors.h"

typedef struct {
    plant_cfg_t plant;           /* the TRUE motor and shaft */
    double enc_offset_el_rad;  /* electrical angle of the d axis at encoder count 0 */
    inv_cfg_t inv;               /* inverter model, bus, period, dead time */
    sensors_cfg_t sens;          /* encoder, ADC */
    double trip_current_A;       /* hardware overcurrent comparator on |ia|, |ib|, |ic| */
    bool enc_reversed;           /* a wrong board: the count runs down as the rotor turns forward */
    bool phases_acb;             /* a wrong board: legs b and c swapped before the current sensors and the motor */
    /* the load's passive part, beside the active torque (hal_sim_set_load): opposing the motion */
    double load_coulomb_Nm;      /* Coulomb friction: holds a shaft at rest up to it, brakes one turning by it */
    double load_B_Nms;           /* viscous friction, added to the shaft's own B */
} hal_sim_cfg_t;

/* Fault injection (the scenario's [faults] section, hal/sim/README.md):
 * each fault starts at the first period whose sample instant t_k >= its
 * time and stays (NaN: never). Bits of hal_sim_truth_t.faults_active. */
typedef enum {
    SIM_FAULT_OPEN_PHASE = 1u << 0,   /* one phase conducts no current */
    SIM_FAULT_SHORT = 1u << 1,        /* two inverter outputs shorted through short_ohm, short_H */
    SIM_FAULT_ADC_STUCK = 1u << 2,    /* one current channel repeats its reading of the first faulted period */
    SIM_FAULT_ENC_LOST = 1u << 3,     /* the count stops (A/B signals lost) */
    SIM_FAULT_ENC_JUMP = 1u << 4,     /* the count jumps by enc_jump_counts (noise on A/B) */
    SIM_FAULT_VDC_SAG = 1u << 5,      /* the bus steps to vdc_sag_V */
    SIM_FAULT_VDC_SURGE = 1u << 6,    /* the bus steps to vdc_surge_V */
    SIM_FAULT_GATE_TRIP = 1u << 7,    /* the gate driver pulls the trip input */
    SIM_FAULT_ISR_OVERRUN = 1u << 8   /* the ISR call of that period runs isr_overrun_run_s (one call) */
} hal_sim_fault_bit_t;

typedef struct {
    double open_phase_s;
    uint32_t open_phase;         /* 0 a, 1 b, 2 c */
    double short_s;
    uint32_t short_pair;         /* 0 a-b, 1 b-c, 2 c-a: current from the first output into the second */
    double short_ohm, short_H;   /* the short's loop resistance and inductance */
    double adc_stuck_s;
    uint32_t adc_stuck_channel;  /* 0 ia, 1 ib */
    double enc_lost_s;
    double enc_jump_s;
    int32_t enc_jump_counts;
    double vdc_sag_s, vdc_sag_V;
    double vdc_surge_s, vdc_surge_V;
    double gate_trip_s;
    double isr_overrun_s;
    double isr_overrun_run_s;    /* run time of the overrunning ISR call, as hal_cycles() counts it */
} hal_sim_faults_t;

/* Ground truth of the last simulated period. */
typedef struct {
    double t_s;                  /* t_k, the period's start and sample instant */
    /* at t_k */
    double id_A, iq_A;           /* true rotor frame */
    double R_Ohm;                /* stator resistance in the plant */
    double ia_A, ib_A, ic_A;
    double speed_m_rad_s;        /* mechanical */
    double theta_el_rad;
    double te_Nm;
    double psi_s_Wb;
    /* over [t_k, t_k + Ts] */
    double ud_mean_V, uq_mean_V; /* applied voltage in the true rotor frame (0 with outputs off) */
    double id_mean_A, iq_mean_A;
    double load_Nm;
    double duty[3];              /* duties active in this period */
    bool pwm_enabled;            /* gates on during this period */
    bool trip;                   /* hardware trip latched */
    bool isr_stalled;            /* an ISR returned without hal_isr_ack() */
    uint32_t isr_calls;
    uint32_t faults_active;      /* hal_sim_fault_bit_t of the injected faults active in this period */
    double i_short_A;            /* current in the injected short at t_k (0 without one) */
} hal_sim_truth_t;

/* Defaults of the board around the motor: shaft at rest and free, averaged
 * inverter at 10 kHz, no dead time, the period solved at once,
 * 2500-line encoder aligned (offset 0), ideal 12-bit ADC over +-15 A,
 * trip at 15 A. The motor (plant R_Ohm, L_H, psi_f_Wb, pole_pairs,
 * J_kgm2) and the bus (inv.vdc_V) are the caller's: NaN and
 * 0 here. tools/sil/sil_board.h fills them from the drive's parameter
 * set (the paper's Table I); hal/sim keeps no copy of the motor data. */
void hal_sim_default_cfg(hal_sim_cfg_t *cfg);

/* Power-on state of the board with *cfg: plant at omega0 and angle 0, t = 0, outputs off,
 * duties 0.5, no trip, no ISR attached, PRNG seeded. Call before hal_init(). */
void hal_sim_configure(const hal_sim_cfg_t *cfg);

/* Load torque [N m] opposing positive speed, from the next period on. */
void hal_sim_set_load(double TL_Nm);

/* Stator resistance of the plant [ohm] from the next period on (plant_set_R_Ohm). */
void hal_sim_set_R_Ohm(double R_Ohm);

/* No fault: every time NaN, the other fields at their defaults. */
void hal_sim_faults_none(hal_sim_faults_t *f);

/* Inject the faults of *f from their times on; after hal_sim_configure(). */
void hal_sim_set_faults(const hal_sim_faults_t *f);

/* Simulate one PWM period (see the timing above). */
void hal_sim_period(void);

/* Ground truth of the last simulated period into *out. */
void hal_sim_truth(hal_sim_truth_t *out);

/* The same in place, for a check every period: no copy, and the fields
 * hal_sim_truth() derives on demand (theta_el_rad, te_Nm, psi_s_Wb and
 * the period means ud/uq_mean_V, id/iq_mean_A) read NaN. */
const hal_sim_truth_t *hal_sim_truth_view(void);

/* Latch a hardware trip now, as the trip-zone input would (fault-injection for tests). */
void hal_sim_force_trip(void);

/* Number of hal_watchdog_kick() calls since hal_sim_configure(). */
uint32_t hal_sim_watchdog_kicks(void);

/* ---- the parameter store's sector (hal.h hal_nv_*, hal_sim_nv.c) ----------
 * As the board's flash sector B: HAL_SIM_NV_WORDS words, erased at the
 * first use, kept across runs of one process (hal_sim_configure leaves it:
 * a board's flash outlives a power cycle); an erase sets every word to
 * 0xFFFF, a program only clears bits (one asked to set a bit fails, as
 * TI's API does without an erase). drive_sil --nv FILE loads it from FILE
 * before a run and writes FILE after every write. */
#define HAL_SIM_NV_WORDS 0x8000u

/* The sector's words, HAL_SIM_NV_WORDS of them: read or filled by the caller between runs. */
uint16_t *hal_sim_nv_image(void);

/* Every word erased (0xFFFF). */
void hal_sim_nv_erase(void);

/* hook(user) after every hal_nv_write, the image changed (NULL: none). */
typedef void (*hal_sim_nv_hook_t)(void *user);
void hal_sim_nv_on_write(hal_sim_nv_hook_t hook, void *user);

#endif /* HAL_SIM_H */
