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
#include "spmsm.h"

/* ---- encoder mounting ------------------------------------------------ */
#define BOARD_ENC_OFFSET_EL_RAD  0.0f         /* electrical angle at count 0: measure by d-axis alignment [rad] */

/* ---- the inverter's voltage error beyond its dead time ----------------- */
#define BOARD_DEVICE_DROP_V      0.0f         /* on-state drop the controller compensates: 0 until commissioning measures it [V] */

/* ---- protection limits (used by the application) ---------------------- */
#define BOARD_VDC_NOMINAL_V      311.0f       /* rectified 220 V AC [V] (assumed; paper gives none) */
/* ---- the reference design: the paper motor on this board -------------
 * Values that scale with one quantity of the motor or the board are
 * given here at the reference and scaled in proportion by
 * drive_params_derive() (params_design.md: each rule and its reason);
 * for the reference itself they are these constants to the bit. */
#define REF_I_RATED_A            (6.0f / (SPMSM_TORQUE_PER_P_PSI_I * 3.0f * 0.24f)) /* 5.56 A: 6 N m (Table I) */
#define REF_I_PEAK_A             (2.0f * REF_I_RATED_A)  /* 11.1 A: 12 N m */
#define REF_T_RATED_NM           6.0f         /* [N m] */
#define REF_VDC_V                311.0f       /* [V] */
#define REF_J_KGM2               0.00129f     /* [kg m^2] */
#define REF_SPEED_BW_RAD_S       387.596899f  /* speed-loop crossover: 0.5 / 0.00129 [rad/s] */
#define REF_PSI_F_WB             0.24f        /* [Wb] */
#define REF_R_OHM                3.0f         /* [Ohm] */
/* limits (params_design.md sec. 3): the targets' current limit i_peak;
 * the software trip 14 A at i_peak 11.1 A (1.26 i_peak: the reversals'
 * 5 % of deadbeat overshoot and the switching ripple above the limit),
 * at most the largest current the ADC reads (the range less the accepted
 * offset, BOARD_I_OFFSET_MAX_A's share of it) and at least the limit plus
 * the noise a sample at it reads (drive_trip_margin_A()); overspeed 1.2 x n_max */
#define REF_I_TRIP_A             14.0f        /* at REF_I_PEAK_A [A] */
/* The current ADC's noise (assumed, as for the frozen-reading check below)
 * and how far above the limit a sample at it may read: 6 sigma, once in
 * 1e9 samples (9 h of three readings at 10 kHz; 4 sigma: twice a second). */
#define BOARD_ADC_NOISE_CODES_RMS 2.0f        /* [codes rms] */
#define BOARD_TRIP_NOISE_SIGMAS  6.0f         /* [-] */
#define LIM_OVERSPEED_PER_MAX    1.2f         /* overspeed trip / n_max [-] */
#define BOARD_VDC_MIN_V          200.0f       /* undervoltage trip [V] */
#define BOARD_VDC_MAX_V          400.0f       /* overvoltage trip [V] */
/* Control ISR: 15000 CPU cycles per period; the rest is the background
 * loop's (watchdog, telemetry) and the interrupt entry/exit. */
#define BOARD_ISR_PERIOD_CYCLES  (BOARD_SYSCLK_HZ / BOARD_PWM_FREQ_HZ) /* [cycles] */
#define BOARD_ISR_BUDGET_CYCLES  12000UL      /* 80 % of the period for app_isr [cycles] */
/* Checks on the periods' history (firmware/protect/protect.h derives each rule;
 * detection times measured in SIL: tests/test_sil_faults.c). */
/* Open phase (protect.h, protect_design.md): a phase counts as carrying
 * nothing below 0.2 of the current the controller aimed at it (a healthy
 * one carries cos(30 deg + the current's lag) of it: 0.2 leaves 48 deg);
 * slow, the voltage on the phase decides: with i_x < 0.2 |i| (< 2.4 A) a
 * healthy phase gets R i_x + back-EMF (held below 12.5 V) + the dead-time
 * feedforward (3 V), below 25 V. The window slides by a quarter
 * (PROTECT_OP_SUBWINDOWS): SIL 25-100 ms, noise 0-0.15 A, 0-2000 r/min. */
#define BOARD_OPEN_PHASE_WINDOW_S  0.1f       /* [s] */
#define REF_OPEN_PHASE_I_MIN_A   1.0f       /* mean |i|, and a period's aimed |i*|, to judge by, at REF_I_RATED_A [A] */
#define BOARD_OPEN_PHASE_RATIO     0.2f       /* |i_x| / |i*| (mean |i_x| / mean |i|) below it: no current in x [-] */
#define REF_OPEN_PHASE_U_MIN_V   25.0f      /* ... while phase x was given this mean |u_x|, at REF_VDC_V [V] */
/* Frozen current reading: half an ADC step of the range is "unchanged"
 * (drive_params.c, from the ADC range). In a net turn
 * of 15 deg el a field-oriented current |i| moves each reading by at least
 * |i| (1 - cos 7.5 deg) = 0.0086 |i| and the other by at most
 * 2 |i| sin 7.5 deg = 0.26 |i|: the other sweeping 0.5 A means |i| >= 1.9 A,
 * and a healthy reading then moves >= 16 mA, two ADC steps. 15 deg: at
 * 100 r/min the frozen reading's runaway reaches the overcurrent trip in
 * 13-21 ms, 15 deg takes 8 ms. A reading frozen near zero is what an open
 * phase gives too: OPEN_PHASE judges that one. */
#define BOARD_I_STUCK_ANGLE_EL_DEG 15.0f      /* net rotor turn with one reading unchanged [deg el] */
#define BOARD_I_STUCK_SPAN_A     0.5f         /* ... while the other reading swept this [A] */
#define BOARD_I_STUCK_ZERO_A     0.1f         /* ... and the frozen reading is beyond +- this [A] */
/* ... for at least 16 periods: ADC noise of 2 codes rms keeps a code
 * 0.2 of the periods, 16 in a row 1e-11 (4 periods at 4 pole pairs,
 * 1500 r/min: 1e-3, a false trip within seconds); at Table I's 100 r/min
 * the 15 deg take 83 periods, at 2000 r/min 4 (then 1.6 ms). */
#define BOARD_I_STUCK_MIN_PERIODS 16U         /* [periods] */
/* Lost encoder: the PLL (500 rad/s) runs on past a count that stops from
 * speed; a healthy count lags the estimate by a few counts (a full-torque
 * reversal: about 16), so 100 counts (3.6 deg) is a lost signal. At low
 * speed the PLL stops first: no count for 0.3 s at 0.9 x the torque limit
 * is no motion where the controller asks for all it has. */
#define BOARD_ENC_LOST_COUNTS    100.0f       /* [counts] */
#define BOARD_ENC_STALL_S        0.3f         /* [s] */
#define BOARD_ENC_STALL_TE_FRAC  0.9f         /* x te_max [-] */

/* ---- the link (firmware/link/link.h) ---------------------------------- */
/* Host timeout: once a host wrote a reference or started the drive, no
 * valid frame for this long ramps the drive to zero and stops it. Off, as
 * ODrive's watchdog (watchdog_timeout 0, enable_watchdog false): a
 * reference set by one `drivetool set` must outlive that command's
 * connection; a host program that feeds the link turns it on
 * (link_protocol.md, "Host timeout": VESC's 1 s). */
#define BOARD_HOST_TIMEOUT_S     0.0f         /* [s]; 0: off */

/* ---- start-up sequence (used by the application) ---------------------- */
/* Current-offset calibration, PWM off, at every start. */
#define BOARD_CAL_SETTLE_S       0.01f        /* wait before averaging: a current decays through the diodes in L/R = 3.7 ms [s] */
#define BOARD_CAL_SAMPLES        1024U        /* periods averaged (0.1 s): noise / 32 [-] */
#define BOARD_I_OFFSET_MAX_A     0.75f        /* accepted |offset| of ia, ib: 75 mV at the pin, 5 % of the range (assumed); another range: the same share [A] */
/* Rotor alignment (d axis onto phase a), once per power-up, in two steps:
 * a vector at the pre-position angle first, then the one on phase a (a
 * rotor 180 deg from the last vector gets no torque; app.h derives why
 * the two never both leave it there). */
#define BOARD_ENC_OFFSET_KNOWN   0U           /* 1: BOARD_ENC_OFFSET_EL_RAD is measured, no alignment [-] */
#define REF_ALIGN_CURRENT_A      3.0f         /* d-axis current aimed at, about half rated, at REF_I_RATED_A; voltage = it x told R [A] */
#define BOARD_ALIGN_PREPOS_EL_DEG 90.0f       /* pre-position vector from phase a: 90 gives the most torque on the turn to phase a [deg el] */
#define BOARD_ALIGN_RAMP_S       0.2f         /* voltage ramp from 0, and the turn onto phase a: no torque jerk [s] */
/* The two holds: SIL (Table I, 1 us dead time, no friction; 36 start
 * angles 10 deg apart and both dead points) within a count of the true
 * offset from 0.1 s and 0.3 s on; twice that, for a load's inertia. */
#define BOARD_ALIGN_PREPOS_S     0.2f         /* hold at the pre-position: the rotor is off phase a's dead point before the turn [s] */
#define BOARD_ALIGN_SETTLE_S     0.6f         /* hold on phase a: the rotor settles [s] */

/* Commissioning (commission.h; methods and error budget in
 * firmware/commission/commission_design.md). Currents as shares of the motor's rated
 * current, speeds of its rated speed (drive_params_to_app_cfg). */
#define COMM_U_FRAC              0.9f         /* |u| / (vdc/sqrt 3) beyond which a stage is implausible (SPIN: a sweep's end) [-] */
#define COMM_R_I1_FRAC           0.35f        /* R: first DC current / bound (INVERTER: reversed, second) [-] */
#define COMM_R_I2_FRAC           0.7f         /* R: second DC current / bound: overshoot of the integral loop stays below 1 (INVERTER: reversed, first) [-] */
/* R: the first current's pre-position: any angle with sin != 0 leaves no
 * start angle a dead point of both vectors; 60 deg (0.87 of 90 deg's
 * torque) keeps every phase at half the current or more, so the open-phase
 * check (ratio 0.2) never sees a phase idle, as at 90 deg (phase a: 0). */
#define COMM_R_PREPOS_EL_DEG     60.0f        /* [deg el] */
#define COMM_R_RAMP_S            0.3f         /* WIRING and R: ramp of the first current at the pre-position, and its turn onto phase a: slower than the rotor's swing [s] */
#define COMM_R_KP_FRAC           0.05f        /* R: virtual resistance / (vdc / bound): the swing's induced current 5x smaller on the 540 V motor [-] */
#define COMM_R_SEEK_S            1.0f         /* R (WIRING: the amplitude on |i|): first regulator, a full-bound error ramps the voltage through vdc in this [s] */
#define COMM_R_BW_RAD_S          200.0f       /* R: alpha's integral regulator from R0: faster than the rotor's swing [rad/s] */
#define COMM_R_SETTLE_S          0.15f        /* R, INVERTER: settling after a current change, with the rotor still [s] */
#define COMM_R_STILL_MECH_DEG    0.5f         /* R, INVERTER, ENCODER's first hold: still = within this of the settling's start: the back-EMF on alpha is second order in the swing [deg] */
#define COMM_R_WINDOW_S          0.1f         /* R, INVERTER: averaging window, 1000 periods; WIRING: its measurement [s] */
#define COMM_R_MAX_S             3.0f         /* R: stage timeout [s] */
#define COMM_L_STEP_FRAC         0.3f         /* L: current step / bound (voltage step R^ x this) [-] */
#define COMM_L_RISE_FRAC         0.7f         /* L: a step ends at this share of its final change [-] */
#define COMM_L_CYCLES            8U           /* L: down-and-up steps [-] */
#define COMM_L_MAX_S             1.0f         /* L: stage timeout [s] */
#define COMM_I_BW_RAD_S          1500.0f      /* INVERTER, ENCODER, SPIN: current PI from R^, L^; 0.15 / Ts [rad/s] */
#define COMM_ENC_FRAC            0.5f         /* WIRING, ENCODER: swept current / bound [-] */
#define COMM_ENC_SPEED_EL_DEG_S  720.0f       /* ENCODER: sweep speed, two electrical turns a second (INVERTER: its half turn's top speed) [deg/s el] */
#define COMM_ENC_HOLD_S          0.1f         /* WIRING: hold after the ramp; ENCODER: hold before, between, after the sweeps [s] */
#define COMM_POLE_PAIRS_MAX      32U          /* ENCODER: fewer counts than half an electrical turn at this many: no rotation [-] */
#define COMM_ENC_MAX_S           2.0f         /* WIRING, INVERTER, ENCODER: timeout beyond the stage's planned length [s] */
#define COMM_WIRING_EL_HZ        200.0f       /* WIRING: the vector's frequency; the rotor's swing and back-EMF at it are 1/f^2 and 1/f^3 of a slow one's [Hz el] */
#define COMM_SPIN_FRAC           0.5f         /* SPIN: |i_q| / bound in the three sweeps: the current's ripple a small share of it (commission_design.md sec. 5) [-] */
#define COMM_SPIN_TOP_FRAC       0.4f         /* SPIN: bound on |speed| / rated speed; the sweeps turn before it [-] */
#define COMM_SPIN_LO_FRAC        0.2f         /* SPIN: fits above this share of the top speed [-] */
#define COMM_SPIN_SKIP_S         0.02f        /* SPIN: fits skip this after a current change: 10 / PLL bandwidth [s] */
#define COMM_SPIN_MAX_S          2.0f         /* SPIN: stage timeout [s] */

/* Build levels of the first power-up (level.h); the app starts at
 * BOARD_LEVEL, 1 as TI's motor kits ship: a first `run` only switches the
 * gates at fixed duties (a motor file's [run] level sets another,
 * `make board`). */
#define BOARD_LEVEL              1U           /* 1 PWM, 2 ADC, 3 open-loop rotation, 4 torque control, 5 the drive [-] */
/* Levels 1-2 run without the DC bus: above this bus they refuse to start
 * (BUS_CHARGED). 30 V ripple-free DC: IEC 60364-4-41 (414.4.5), SELV whose
 * live parts may be touched outside normal dry conditions (12 V AC / 30 V
 * DC; 25 V AC / 60 V DC in dry ones): a bench with the power stage open. */
#define BOARD_LEVEL12_VDC_MAX_V  30.0f        /* [V] */
#define BOARD_LEVEL1_DUTY_A      0.25f        /* level 1's duties: each leg its own on the scope [-] */
#define BOARD_LEVEL1_DUTY_B      0.50f
#define BOARD_LEVEL1_DUTY_C      0.75f
#define BOARD_LEVEL3_SPEED_RPM   60.0f        /* level 3's rotation: slow enough for the rotor to follow the vector [r/min] */
#define BOARD_LEVEL4_I_LIMIT_PER_LIMIT 0.3f   /* level 4's current limit, x the drive's current limit [-] */

/* ---- controller tuning: the SIL scenario defaults (tools/sil/scenario_keys.h) */
/* Speed PI (params_design.md sec. 4): kp = J w_c, ki = kp w_c x 0.103;
 * w_c = 0.5 / 0.00129 = 388 rad/s, the paper motor's kp 0.5 and ki 20. */
#define TUNE_SPEED_BW_RAD_S      REF_SPEED_BW_RAD_S /* speed-loop crossover w_c [rad/s] */
#define TUNE_ENC_PLL_BW_RAD_S    500.0f       /* speed estimator bandwidth [rad/s] */
#define TUNE_U_MARGIN            0.92f        /* steady-state share of Vdc/sqrt(3) for flux weakening (oplim.h) [-] */

/* Step 1 of the proposed method (IDENTIFY_R, app.h). Off by default (the
 * conventional method); with the proposed one, 2: the board commands two
 * speeds at the load present (a dyno or the driven machine must load it). */
#define BOARD_RSID_MODE          0U           /* app_rsid_mode_t: 0 off, 1 windows, 2 speeds, 3 trusted R [-] */
/* Speeds, ramp and settle times from the ratings and the speed loop
 * (params_design.md sec. 5; the paper motor's in brackets). */
#define RSID_SPEED_1_PER_RATED   0.25f        /* first point, x n_rated (500 r/min) [-] */
#define RSID_SPEED_2_PER_RATED   0.5f         /* second point: (41) needs w1 iq2 != w2 iq1 (1000 r/min) [-] */
#define REF_RSID_ACCEL_RPM_S     2500.0f      /* ramp: the first point in 0.2 s, at REF's n_rated [r/min/s] */
#define RSID_RAMP_TORQUE_PER_RATED 0.25f      /* ... at most this x T_rated accelerating J [-] */
#define REF_RSID_SETTLE_2_S      0.14f        /* window 1 to 2: 5.6 / w_i, the PI's integral corner, at REF_SPEED_BW [s] */
#define RSID_SETTLE_1_PER_2      2.0f         /* settle_1 = this x settle_2: the start's transient too (0.28 s) [-] */
#define BOARD_RSID_WINDOW_S      0.06f        /* averaging window, 600 periods [s] */
#define BOARD_RSID_WINDOW_MAX_S  0.3f         /* window 2 lengthened up to this while se(R^) is too large [s] */
#define BOARD_RSID_REPEATS_MAX   2U           /* speeds mode: both windows repeated at most this often [-] */
#define BOARD_RSID_ON_REFUSAL    2U           /* app_rsid_refusal_t: 0 fault (PWM off), 1 conventional + warning, 2 step 2 from the told R + warning (R^ learned by injection) [-] */
#define BOARD_TRACK_R            2U           /* EST_TRACK_R_*: 0 off, 1 on, 2 auto (1 s after step 2): R^ tracked in service by a 0.5 A i_d injection (control/r_tracking_design.md sec. 3; held while the field is weakened or the voltage at its limit) [-] */

/* The proposed method's amplitudes and thresholds (params_design.md
 * sec. 6), at the reference; scaled by the rated current (I), the rated
 * torque (T) or the bus (V). */
#define REF_OBS_EF_MAX_V         50.0f        /* (V) |f^ - f| the observer must dominate, (36) [V] */
#define REF_EST_DI_MAX_A         0.5f         /* (I) est_gate: current step that pauses step 2 [A] */
#define REF_EST_DTE_MAX_NM       0.3f         /* (T) est_gate: torque-reference step [N m] */
#define REF_RT_I_IDENT_A         1.0f         /* (I) r_track: injection identifying the inverter error [A] */
#define REF_RT_I_TRACK_A         0.5f         /* r_track: injection tracking R: R I (1.5 V) in proportion to the bus [A] */
#define RT_I_TRACK_MAX_PER_RATED 0.2f         /* ... at most this x i_rated: copper loss <= 4 % of the rated [-] */
#define REF_RT_IQ_MIN_A          1.0f         /* (I) r_track: |iq| below: cycle held [A] */
#define REF_RT_IQ_STEP_A         0.2f         /* (I) r_track: iq change within a cycle: held [A] */
#define REF_RT_VE_MAX_V          20.0f        /* (V) r_track: |Ve| beyond: no inverter error [V] */
/* The estimator's speed floor: w psi_f against the voltage the drive
 * cannot explain, (4/pi) bus (dead-time uncertainty x f_s + device drop
 * per bus): 30 rad/s el for psi_f 0.24 Wb at 311 V; scaled by that
 * voltage over psi_f. |w iq| floor of L^: w_min x 1 A at the rated current. */
#define EST_DT_UNC_S             0.1e-6f      /* dead time left unknown once measured [s] */
#define EST_DROP_UNC_PER_VDC     (1.0f / 311.0f) /* device on-state drop left unknown, x bus: 1 V at 311 V (the devices' voltage class follows the bus) [-] */
#define REF_EST_W_MIN_RAD_S      30.0f        /* [rad/s el] */
#define REF_EST_WIQ_MIN_A_RAD_S  30.0f        /* (I, x w_min) [A rad/s] */
/* Speed PI: kp = J w_c; its integral corner w_i = ki/kp in proportion to
 * w_c (40 rad/s at the reference: ki 20). */
#define REF_SPEED_KP_NMS_RAD     0.5f         /* at REF_J, REF_SPEED_BW [N m s/rad] */
#define REF_SPEED_KI_NM_RAD      20.0f        /* at REF_J, REF_SPEED_BW (x J w_c^2) [N m/rad] */

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
#define MOTOR_B_NMS              0.0f         /* viscous friction [N m s/rad] (the paper gives none) */
#define MOTOR_RATED_SPEED_RPM    2000.0f      /* [r/min] */
#define MOTOR_RATED_TORQUE_NM    6.0f         /* [N m]; iq = 6 / (1.5 * 3 * 0.24) = 5.56 A */
/* The paper's ratings as the [motor] section states them (firmware/params/params_design.md):
 * the rated current is the rated torque's, T = 1.5 p psi_f i; the short-time
 * current twice that for 1 s (the paper gives no figure: assumed); the
 * highest speed the rated one (overspeed trips at 1.2x it). */
#define MOTOR_I_RATED_A          (MOTOR_RATED_TORQUE_NM / (SPMSM_TORQUE_PER_P_PSI_I * (float)MOTOR_POLE_PAIRS * MOTOR_PSI_F_WB)) /* 5.56 A */
#define MOTOR_I_PEAK_A           (2.0f * MOTOR_I_RATED_A)  /* [A]: 12 N m */
#define MOTOR_T_PEAK_S           1.0f         /* [s] */
#define MOTOR_MAX_SPEED_RPM      MOTOR_RATED_SPEED_RPM     /* [r/min] */

/* ---- a motor file's configuration (`make board MOTOR=FILE.ini`) ----------
 * With DRIVE_CONFIG, the generated drive_config.h (through board_hw.h)
 * sets every field of the parameter set at the end of drive_params_board()
 * and the app's settings the scenario keys name at the end of
 * app_cfg_default() (tools/sil/board_config.h); without it, the values
 * above. */
#ifndef DRIVE_CONFIG_PARAMS
#define DRIVE_CONFIG_PARAMS(p) ((void)(p))
#endif
#ifndef DRIVE_CONFIG_APP
#define DRIVE_CONFIG_APP(cfg) ((void)(cfg))
#endif

#endif /* BOARD_CFG_H */
