/*
 * board_cfg.h - the drive configuration of the F28335 board: protection
 * limits, start-up sequence, controller tuning, step-1 settings and the
 * motor defaults. Named constants with units, used by the application
 * only. The board's hardware facts (clocks, PWM, dead time, sensor
 * scaling, encoder lines) are in hal/f28335/board_hw.h, which the HAL
 * reads too; the HAL never reads this file.
 */
#ifndef BOARD_CFG_H
#define BOARD_CFG_H

#include "board_hw.h"

/* ---- encoder mounting ------------------------------------------------ */
#define BOARD_ENC_OFFSET_EL_RAD  0.0f         /* electrical angle at count 0: measure by d-axis alignment [rad] */

/* ---- protection limits (used by the application) ---------------------- */
#define BOARD_VDC_NOMINAL_V      311.0f       /* rectified 220 V AC [V] (assumed; paper gives none) */
/* Software trip on any phase current: above the 11.1 A that the 12 N m
 * torque limit asks for (12 / (1.5 p psi_f)), with room for one period of
 * deadbeat overshoot, below the sensors' 15 A full scale and hardware trip. */
#define BOARD_OVERCURRENT_A      14.0f        /* [A] */
/* Stator-current limit the controller's targets respect (oplim.h): the
 * 11.1 A of the 12 N m torque limit plus margin, below the trip with room
 * for a period of deadbeat overshoot and the switching ripple. */
#define BOARD_I_LIMIT_A          12.0f        /* [A] */
#define BOARD_VDC_MIN_V          200.0f       /* undervoltage trip [V] */
#define BOARD_VDC_MAX_V          400.0f       /* overvoltage trip [V] */
#define BOARD_OVERSPEED_RPM      2400.0f      /* 1.2 x rated speed [r/min] */
/* Control ISR: 15000 CPU cycles per period; the rest is the background
 * loop's (watchdog, telemetry) and the interrupt entry/exit. */
#define BOARD_ISR_PERIOD_CYCLES  (BOARD_SYSCLK_HZ / BOARD_PWM_FREQ_HZ) /* [cycles] */
#define BOARD_ISR_BUDGET_CYCLES  12000UL      /* 80 % of the period for app_isr [cycles] */
/* Checks on the periods' history (firmware/protect.h derives each rule;
 * detection times measured in SIL: tests/test_sil_faults.c). */
/* Open phase (protect.h): a window of 0.1 s covers half an electrical
 * turn (where a healthy phase carries 2/pi = 0.64 of |i|) from 100 r/min;
 * slower, the voltage on the phase decides: with i_x < 0.2 |i| (< 2.8 A)
 * a healthy phase gets R i_x + back-EMF (7.5 V peak at 100 r/min) + the
 * dead-time feedforward (3 V), below 25 V. The window slides by a quarter
 * (PROTECT_OP_SUBWINDOWS): SIL 65-100 ms, noise 0-0.15 A, 0-2000 r/min. */
#define BOARD_OPEN_PHASE_WINDOW_S  0.1f       /* [s] */
#define BOARD_OPEN_PHASE_I_MIN_A   1.0f       /* mean |i| to judge by [A] */
#define BOARD_OPEN_PHASE_RATIO     0.2f       /* mean |i_x| / mean |i| below it: no current in phase x [-] */
#define BOARD_OPEN_PHASE_U_MIN_V   25.0f      /* ... while phase x was given this mean |u_x| (below half a turn) [V] */
/* Frozen current reading: half an ADC step is "unchanged". In a net turn
 * of 15 deg el a field-oriented current |i| moves each reading by at least
 * |i| (1 - cos 7.5 deg) = 0.0086 |i| and the other by at most
 * 2 |i| sin 7.5 deg = 0.26 |i|: the other sweeping 0.5 A means |i| >= 1.9 A,
 * and a healthy reading then moves >= 16 mA, two ADC steps. 15 deg: at
 * 100 r/min the frozen reading's runaway reaches the overcurrent trip in
 * 13-21 ms, 15 deg takes 8 ms. A reading frozen near zero is what an open
 * phase gives too: OPEN_PHASE judges that one. */
#define BOARD_I_STUCK_DELTA_A    (0.5f * BOARD_I_GAIN_A_PER_V * BOARD_ADC_FULL_SCALE_V / BOARD_ADC_COUNTS) /* [A] */
#define BOARD_I_STUCK_ANGLE_EL_DEG 15.0f      /* net rotor turn with one reading unchanged [deg el] */
#define BOARD_I_STUCK_SPAN_A     0.5f         /* ... while the other reading swept this [A] */
#define BOARD_I_STUCK_ZERO_A     0.1f         /* ... and the frozen reading is beyond +- this [A] */
/* Lost encoder: the PLL (500 rad/s) runs on past a count that stops from
 * speed; a healthy count lags the estimate by a few counts (a full-torque
 * reversal: about 16), so 100 counts (3.6 deg) is a lost signal. At low
 * speed the PLL stops first: no count for 0.3 s at 0.9 x the torque limit
 * is no motion where the controller asks for all it has. */
#define BOARD_ENC_LOST_COUNTS    100.0f       /* [counts] */
#define BOARD_ENC_STALL_S        0.3f         /* [s] */
#define BOARD_ENC_STALL_TE_FRAC  0.9f         /* x te_max [-] */

/* ---- start-up sequence (used by the application) ---------------------- */
/* Current-offset calibration, PWM off, at every start. */
#define BOARD_CAL_SETTLE_S       0.01f        /* wait before averaging: a current decays through the diodes in L/R = 3.7 ms [s] */
#define BOARD_CAL_SAMPLES        1024U        /* periods averaged (0.1 s): noise / 32 [-] */
#define BOARD_I_OFFSET_MAX_A     0.75f        /* accepted |offset| of ia, ib: 75 mV at the pin, 5 % of the range (assumed) [A] */
/* Rotor alignment (d axis onto phase a), once per power-up, in two steps:
 * a vector at the pre-position angle first, then the one on phase a (a
 * rotor 180 deg from the last vector gets no torque; app.h derives why
 * the two never both leave it there). */
#define BOARD_ENC_OFFSET_KNOWN   0U           /* 1: BOARD_ENC_OFFSET_EL_RAD is measured, no alignment [-] */
#define BOARD_ALIGN_CURRENT_A    3.0f         /* d-axis current aimed at, about half rated; voltage = this x MOTOR_R_OHM [A] */
#define BOARD_ALIGN_PREPOS_EL_DEG 90.0f       /* pre-position vector from phase a: 90 gives the most torque on the turn to phase a [deg el] */
#define BOARD_ALIGN_RAMP_S       0.2f         /* voltage ramp from 0, and the turn onto phase a: no torque jerk [s] */
/* The two holds: SIL (Table I, 1 us dead time, no friction; 36 start
 * angles 10 deg apart and both dead points) within a count of the true
 * offset from 0.1 s and 0.3 s on; twice that, for a load's inertia. */
#define BOARD_ALIGN_PREPOS_S     0.2f         /* hold at the pre-position: the rotor is off phase a's dead point before the turn [s] */
#define BOARD_ALIGN_SETTLE_S     0.6f         /* hold on phase a: the rotor settles [s] */

/* Commissioning (commission.h; methods and error budget in
 * firmware/commission_design.md). Currents as shares of the commissioning
 * current bound (the board: BOARD_I_LIMIT_A until the motor's rated current
 * is a setting), speeds of the rated speed. */
#define COMM_U_FRAC              0.9f         /* |u| / (vdc/sqrt 3) beyond which a stage is implausible (SPIN: top speed) [-] */
#define COMM_R_I1_FRAC           0.35f        /* R: first DC current / bound [-] */
#define COMM_R_I2_FRAC           0.7f         /* R: second DC current / bound: overshoot of the integral loop stays below 1 [-] */
/* R: the first current's pre-position: any angle with sin != 0 leaves no
 * start angle a dead point of both vectors; 60 deg (0.87 of 90 deg's
 * torque) keeps every phase at half the current or more, so the open-phase
 * check (ratio 0.2) never sees a phase idle, as at 90 deg (phase a: 0). */
#define COMM_R_PREPOS_EL_DEG     60.0f        /* [deg el] */
#define COMM_R_RAMP_S            0.3f         /* R: ramp of the first current at the pre-position, and its turn onto phase a: slower than the rotor's swing [s] */
#define COMM_R_KP_FRAC           0.05f        /* R: virtual resistance / (vdc / bound): the swing's induced current 5x smaller on the 540 V motor [-] */
#define COMM_R_SEEK_S            1.0f         /* R: first regulator, a full-bound error ramps the voltage through vdc in this [s] */
#define COMM_R_BW_RAD_S          200.0f       /* R: alpha's integral regulator from R0: faster than the rotor's swing [rad/s] */
#define COMM_R_SETTLE_S          0.15f        /* R: settling after a current change, with the rotor still [s] */
#define COMM_R_STILL_MECH_DEG    0.5f         /* R: still = within this of the settling's start: the back-EMF on alpha is second order in the swing [deg] */
#define COMM_R_WINDOW_S          0.1f         /* R: averaging window, 1000 periods [s] */
#define COMM_R_MAX_S             3.0f         /* R: stage timeout [s] */
#define COMM_L_STEP_FRAC         0.3f         /* L: current step / bound (voltage step R^ x this) [-] */
#define COMM_L_RISE_FRAC         0.7f         /* L: a step ends at this share of its final change [-] */
#define COMM_L_CYCLES            8U           /* L: down-and-up steps [-] */
#define COMM_L_MAX_S             1.0f         /* L: stage timeout [s] */
#define COMM_I_BW_RAD_S          1500.0f      /* ENCODER, SPIN: current PI from R^, L^; 0.15 / Ts [rad/s] */
#define COMM_ENC_FRAC            0.5f         /* ENCODER: swept current / bound [-] */
#define COMM_ENC_SPEED_EL_DEG_S  720.0f       /* ENCODER: sweep speed, two electrical turns a second [deg/s el] */
#define COMM_ENC_HOLD_S          0.1f         /* ENCODER: hold before, between, after the sweeps [s] */
#define COMM_P_TOL               0.2f         /* ENCODER: |counts-derived pole pairs - integer| accepted [-] */
#define COMM_POLE_PAIRS_MAX      32U          /* ENCODER: most pole pairs accepted [-] */
#define COMM_ENC_MAX_S           2.0f         /* ENCODER: stage timeout [s] */
#define COMM_SPIN_FRAC           0.2f         /* SPIN: |i_q| / bound accelerating and braking [-] */
#define COMM_SPIN_TOP_FRAC       0.4f         /* SPIN: top speed / rated speed [-] */
#define COMM_SPIN_LO_FRAC        0.2f         /* SPIN: fits above this share of the top speed [-] */
#define COMM_SPIN_SKIP_S         0.02f        /* SPIN: fits skip this after a current change: 10 / PLL bandwidth [s] */
#define COMM_SPIN_MAX_S          2.0f         /* SPIN: stage timeout [s] */

/* ---- controller tuning: the SIL scenario defaults (tools/sil/scenario.c) - */
#define TUNE_SPEED_KP_NMS_RAD    0.5f         /* speed PI [N m / (rad/s)] */
#define TUNE_SPEED_KI_NM_RAD     20.0f        /* speed PI [N m / rad] */
#define TUNE_ENC_PLL_BW_RAD_S    500.0f       /* speed estimator bandwidth [rad/s] */
#define TUNE_TE_MAX_PER_RATED    2.0f         /* torque limit / rated torque: 12 N m [-] */
#define TUNE_U_MARGIN            0.92f        /* steady-state share of Vdc/sqrt(3) for flux weakening (oplim.h) [-] */

/* Step 1 of the proposed method (IDENTIFY_R, app.h). Off by default (the
 * conventional method); with the proposed one, 2: the board commands two
 * speeds at the load present (a dyno or the driven machine must load it). */
#define BOARD_RSID_MODE          0U           /* app_rsid_mode_t: 0 off, 1 windows, 2 speeds, 3 trusted R [-] */
#define BOARD_RSID_SPEED_1_RPM   500.0f       /* first point [r/min] */
#define BOARD_RSID_SPEED_2_RPM   1000.0f      /* second point: (41) needs w1 iq2 != w2 iq1 [r/min] */
#define BOARD_RSID_ACCEL_RPM_S   2500.0f      /* ramp of the commanded speed: 500 r/min in 0.2 s [r/min/s] */
#define BOARD_RSID_SETTLE_1_S    0.28f        /* entry to window 1: ramp + speed loop settled (SIL, Table I) [s] */
#define BOARD_RSID_WINDOW_S      0.06f        /* averaging window, 600 periods [s] */
#define BOARD_RSID_SETTLE_2_S    0.14f        /* window 1 to window 2: the speed loop settles after the change [s] */
#define BOARD_RSID_WINDOW_MAX_S  0.3f         /* window 2 lengthened up to this while se(R^) is too large [s] */
#define BOARD_RSID_REPEATS_MAX   2U           /* speeds mode: both windows repeated at most this often [-] */
#define BOARD_RSID_ON_REFUSAL    0U           /* app_rsid_refusal_t: 0 fault (PWM off), 1 conventional + warning [-] */
#define BOARD_TRACK_R            0U           /* 1: R^ tracked in service by a 0.5 A i_d injection (observer_design.md sec. 9) [-] */

/* Bounds on what the controller's model may see (as in tools/sil/sil.c). */
#define MODEL_I_BOUND_PER_TRIP   5.0f         /* x software overcurrent threshold [-] */
#define MODEL_SPEED_BOUND_RPM    6000.0f      /* 3x rated speed [r/min] */
#define MODEL_PSI_BOUND_PER_PSIF 4.0f         /* x psi_f [-] */

/* ---- motor defaults: paper Table I ------------------------------------ */
#define MOTOR_R_OHM              3.0f         /* stator phase resistance [Ohm] */
#define MOTOR_L_H                0.011f       /* Ld = Lq [H] */
#define MOTOR_PSI_F_WB           0.24f        /* permanent-magnet flux linkage [Wb] */
#define MOTOR_POLE_PAIRS         3U           /* pole pairs [-] */
#define MOTOR_J_KGM2             0.00129f     /* rotor inertia [kg m^2] */
#define MOTOR_RATED_SPEED_RPM    2000.0f      /* [r/min] */
#define MOTOR_RATED_TORQUE_NM    6.0f         /* [N m]; iq = 6 / (1.5 * 3 * 0.24) = 5.56 A */

#endif /* BOARD_CFG_H */
