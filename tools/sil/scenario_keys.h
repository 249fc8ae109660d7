/*
 * scenario_keys.h - the scenario keys: one table, one line per key. It
 * generates scenario_t's fields (scenario.h), the parser's key table with
 * its types, ranges and defaults, the mapping of each value into the
 * drive's configuration (scenario.c), drive_sil --help and --list-keys
 * (the documented list, tools/sil/SCENARIO_KEYS.md), the "derived" and
 * "keys" objects of OUT.resolved.json (sil.c). Adding a key is one line
 * here (firmware/params/params_design.md, "Adding a parameter").
 *
 * One list per section: SC_KEYS_<section>(X), each line
 *   X(section, key, KIND, RANGE, DEFAULT, FROM, TO, help)
 * KIND    REAL (double) | UINT (uint32_t) | ENUM (uint32_t, index into the
 *         names) | PROF (profile_t) | RPROF (a positive profile from t = 0:
 *         the double <key> takes its value at t = 0, <key>_profile the profile)
 * RANGE   what the parser accepts: SC_GT0 (> 0), SC_GE0 (>= 0), SC_ANY (finite),
 *         SC_IN(lo, hi) (a whole number), SC_NAMES(names), SC_NONE (profiles)
 * DEFAULT SC_TEXT("text") | SC_PARAMS (read from FROM: the configuration the
 *         target starts from) | SC_DERIVED("keys it comes from": derived from
 *         the motor's data by drive_params_derive() unless set) | SC_UNSET
 *         (NaN: resolved by scenario_finish, or never for a fault's time)
 * FROM    where a SC_PARAMS default is read: SC_P (drive_params_t, from
 *         drive_params_board()), SC_A (app_cfg_t, app_cfg_default()),
 *         SC_S (hal_sim_cfg_t, hal_sim_default_cfg()), SC_L (link_cfg_t,
 *         link_cfg_default()); SC_NO otherwise
 * TO      where the value goes: SC_P (scenario_params), SC_A (the SIL's app
 *         configuration, after drive_params_to_app_cfg), SC_S (the simulated
 *         board, sil_board_from), SC_F (hal_sim_faults_t), SC_L (the link's
 *         configuration, drive_sil --link); SC_SAME: where
 *         FROM reads; SC_NO: scenario.c or sil.c reads it by name (method,
 *         references, the controller's factors). A NaN value leaves the
 *         target as it is. Each location: (field, conversion, key unit per
 *         field unit); the conversions are sc_conv_t's (scenario.h).
 */
#ifndef SCENARIO_KEYS_H
#define SCENARIO_KEYS_H

#define SC_KEYS_plant(X) \
    X(plant, R_ohm, RPROF, SC_GT0, SC_PARAMS, SC_P(motor.R_Ohm, F32, 1.0), SC_S(plant.R_Ohm, F64, 1.0), \
      "true stator resistance R0 [ohm]; a profile from t = 0 warms the winding (\"0:3.0, 2:3.9~\")") \
    X(plant, L_H, REAL, SC_GT0, SC_PARAMS, SC_P(motor.L_H, F32, 1.0), SC_S(plant.L_H, F64, 1.0), \
      "true inductance L0 = Ld = Lq [H]") \
    X(plant, psif_Wb, REAL, SC_GT0, SC_PARAMS, SC_P(motor.psi_f_Wb, F32, 1.0), SC_S(plant.psi_f_Wb, F64, 1.0), \
      "true PM flux linkage psi_f0 [Wb]") \
    X(plant, pole_pairs, UINT, SC_IN(1.0, SC_UINT16_MAX_D), SC_PARAMS, SC_P(motor.pole_pairs, U16, 1.0), \
      SC_S(plant.pole_pairs, U32, 1.0), "pole pairs") \
    X(plant, J_kgm2, REAL, SC_GT0, SC_PARAMS, SC_P(motor.J_kgm2, F32, 1.0), SC_S(plant.J_kgm2, F64, 1.0), \
      "inertia [kg m^2]") \
    X(plant, B_Nms, REAL, SC_GE0, SC_PARAMS, SC_S(plant.B_Nms, F64, 1.0), SC_SAME, "viscous friction [N m s/rad]") \
    X(plant, speed_held, UINT, SC_IN(0.0, 1.0), SC_PARAMS, SC_S(plant.speed_held, BOOL, 1.0), SC_SAME, \
      "1: shaft held at speed0_rpm (0: free)") \
    X(plant, speed0_rpm, REAL, SC_ANY, SC_PARAMS, SC_S(plant.omega0_m_rad_s, F64, SIM_RPM_PER_RAD_S), SC_SAME, \
      "initial (or held) speed [r/min]") \
    X(plant, vdc_V, REAL, SC_GT0, SC_PARAMS, SC_P(board.vdc_nominal_V, F32, 1.0), SC_S(inv.vdc_V, F64, 1.0), \
      "DC-bus voltage [V]") \
    X(plant, model, ENUM, SC_NAMES(SC_MODEL_NAMES), SC_PARAMS, SC_S(inv.model, ENUM, 1.0), SC_SAME, \
      "inverter model: averaged | switching") \
    X(plant, deadtime_s, REAL, SC_GE0, SC_PARAMS, SC_S(inv.deadtime_s, F64, 1.0), SC_SAME, "inverter dead time [s]") \
    X(plant, device_drop_V, REAL, SC_GE0, SC_PARAMS, SC_S(inv.device_drop_V, F64, 1.0), SC_SAME, \
      "on-state drop of the conducting switch or diode [V], by the current's sign") \
    X(plant, substep_s, REAL, SC_GT0, SC_PARAMS, SC_S(inv.substep_max_s, F64, 1.0), SC_SAME, \
      "longest time the plant solves at once; below the PWM period it splits it [s]") \
    X(plant, encoder_lines, UINT, SC_IN(1.0, 1.0e6), SC_PARAMS, SC_P(board.enc_lines, U32, 1.0), \
      SC_S(sens.enc_lines, U32, 1.0), "encoder lines (x4 counts)") \
    X(plant, encoder_offset_el_rad, REAL, SC_ANY, SC_PARAMS, SC_P(board.enc_offset_el_rad, F32, 1.0), \
      SC_S(enc_offset_el_rad, F64, 1.0), \
      "electrical angle of the d axis at count 0 [rad]; the controller is told the same unless run.align = on") \
    X(plant, encoder_direction, ENUM, SC_NAMES(SC_DIRECTION_NAMES), SC_TEXT("1"), SC_NO, SC_S(enc_reversed, BOOL, 1.0), \
      "1 | -1: the encoder counts up (1) or down (-1, A and B swapped) as the rotor turns forward") \
    X(plant, phase_order, ENUM, SC_NAMES(SC_ORDER_NAMES), SC_TEXT("abc"), SC_NO, SC_S(phases_acb, BOOL, 1.0), \
      "abc | acb: acb swaps the inverter's legs b and c on their way to the current sensors and the motor") \
    X(plant, adc_full_scale_A, REAL, SC_GT0, SC_PARAMS, SC_S(sens.adc_full_scale_A, F64, 1.0), SC_SAME, \
      "current ADC range +-[A] (12 bit)") \
    X(plant, adc_offset_a_A, REAL, SC_ANY, SC_PARAMS, SC_S(sens.adc_offset_a_A, F64, 1.0), SC_SAME, \
      "phase-a ADC offset [A]") \
    X(plant, adc_offset_b_A, REAL, SC_ANY, SC_PARAMS, SC_S(sens.adc_offset_b_A, F64, 1.0), SC_SAME, \
      "phase-b ADC offset [A]") \
    X(plant, adc_noise_A, REAL, SC_GE0, SC_PARAMS, SC_S(sens.adc_noise_A, F64, 1.0), SC_SAME, \
      "current ADC Gaussian noise, std dev [A]") \
    X(plant, seed, UINT, SC_IN(0.0, SC_UINT32_MAX_D), SC_PARAMS, SC_S(sens.seed, U64, 1.0), SC_SAME, "noise seed") \
    X(plant, trip_A, REAL, SC_GT0, SC_PARAMS, SC_S(trip_current_A, F64, 1.0), SC_SAME, \
      "hardware overcurrent trip level [A]")

#define SC_KEYS_motor(X) \
    X(motor, i_rated_A, REAL, SC_GT0, SC_PARAMS, SC_P(rating.i_rated_A, F32, 1.0), SC_SAME, \
      "continuous current, peak of the phase current [A]; T_rated = 1.5 p psi_f i_rated") \
    X(motor, i_peak_A, REAL, SC_GT0, SC_UNSET, SC_NO, SC_P(rating.i_peak_A, F32, 1.0), \
      "short-time current [A] (default 2 x i_rated_A)") \
    X(motor, t_peak_s, REAL, SC_GT0, SC_PARAMS, SC_P(rating.t_peak_s, F32, 1.0), SC_SAME, \
      "how long i_peak_A may last [s]") \
    X(motor, n_rated_rpm, REAL, SC_GT0, SC_PARAMS, SC_P(rating.n_rated_rad_s, F32, SIM_RPM_PER_RAD_S), SC_SAME, \
      "rated speed [r/min]") \
    X(motor, n_max_rpm, REAL, SC_GT0, SC_UNSET, SC_NO, SC_P(rating.n_max_rad_s, F32, SIM_RPM_PER_RAD_S), \
      "highest speed [r/min] (default n_rated_rpm)")

/* The derived keys' order is OUT.resolved.json's "derived" object's. */
#define SC_KEYS_controller(X) \
    X(controller, R_ohm, REAL, SC_GT0, SC_UNSET, SC_NO, SC_P(motor.R_Ohm, F32, 1.0), \
      "controller's R [ohm] (default R_factor x plant)") \
    X(controller, L_H, REAL, SC_GT0, SC_UNSET, SC_NO, SC_P(motor.L_H, F32, 1.0), \
      "controller's L [H] (default L_factor x plant)") \
    X(controller, psif_Wb, REAL, SC_GT0, SC_UNSET, SC_NO, SC_P(motor.psi_f_Wb, F32, 1.0), \
      "controller's psi_f [Wb] (default psif_factor x plant)") \
    X(controller, R_factor, REAL, SC_GT0, SC_UNSET, SC_NO, SC_NO, "controller's R / plant R (default 1)") \
    X(controller, L_factor, REAL, SC_GT0, SC_UNSET, SC_NO, SC_NO, "controller's L / plant L (default 1)") \
    X(controller, psif_factor, REAL, SC_GT0, SC_UNSET, SC_NO, SC_NO, "controller's psi_f / plant psi_f (default 1)") \
    X(controller, J_kgm2, REAL, SC_GT0, SC_UNSET, SC_NO, SC_P(motor.J_kgm2, F32, 1.0), \
      "controller's inertia [kg m^2] (default the plant's)") \
    X(controller, B_Nms, REAL, SC_GE0, SC_UNSET, SC_NO, SC_P(motor.B_Nms, F32, 1.0), \
      "controller's viscous friction [N m s/rad] (default the plant's)") \
    X(controller, speed_bw_rad_s, REAL, SC_GT0, SC_PARAMS, SC_P(tuning.speed_bw_rad_s, F32, 1.0), SC_SAME, \
      "speed-loop crossover [rad/s]: speed_kp = J w_c, speed_ki = kp w_c 0.103") \
    X(controller, pole_pairs, UINT, SC_IN(0.0, 64.0), SC_TEXT("0"), SC_NO, SC_P(motor.pole_pairs, U16, 1.0), \
      "pole pairs the controller is told (0: the plant's)") \
    X(controller, method, ENUM, SC_NAMES(SC_METHOD_NAMES), SC_TEXT("conventional"), SC_NO, SC_NO, \
      "conventional | proposed") \
    X(controller, mode, ENUM, SC_NAMES(SC_MODE_NAMES), SC_TEXT("speed"), SC_NO, SC_NO, "speed | torque | open_loop") \
    X(controller, speed_kp_Nms_rad, REAL, SC_GT0, SC_DERIVED("controller.J_kgm2 controller.speed_bw_rad_s"), SC_NO, \
      SC_P(tuning.speed_kp_Nms_rad, F32, 1.0), "speed PI proportional gain (J_kgm2 x speed_bw_rad_s)") \
    X(controller, speed_ki_Nm_rad, REAL, SC_GT0, SC_DERIVED("controller.J_kgm2 controller.speed_bw_rad_s"), SC_NO, \
      SC_P(tuning.speed_ki_Nm_rad, F32, 1.0), "speed PI integral gain (speed_kp x speed_bw_rad_s x 0.103)") \
    X(controller, pll_bw_rad_s, REAL, SC_GT0, SC_PARAMS, SC_P(tuning.pll_bw_rad_s, F32, 1.0), SC_SAME, \
      "speed estimator bandwidth [rad/s]") \
    X(controller, te_max_Nm, REAL, SC_GT0, SC_DERIVED("motor.i_peak_A controller.psif_Wb plant.pole_pairs"), SC_NO, \
      SC_P(limits.te_max_Nm, F32, 1.0), "torque reference limit [N m] (1.5 p psi_f i_peak_A; derived, it follows the learned psi_f)") \
    X(controller, i_limit_A, REAL, SC_GT0, SC_DERIVED("motor.i_peak_A"), SC_NO, SC_P(limits.i_limit_A, F32, 1.0), \
      "stator-current limit the targets respect [A] (i_peak_A; never above it)") \
    X(controller, i_max_A, REAL, SC_GT0, SC_DERIVED("motor.i_peak_A plant.adc_full_scale_A"), SC_NO, \
      SC_P(limits.i_trip_A, F32, 1.0), \
      "software overcurrent threshold [A] (1.26 i_peak_A, at most 0.95 adc_full_scale_A: what the ADC reads)") \
    X(controller, overspeed_rpm, REAL, SC_GT0, SC_DERIVED("motor.n_max_rpm"), SC_NO, \
      SC_P(limits.speed_max_rad_s, F32, DRIVE_RPM_PER_RAD_S), "overspeed trip [r/min] (1.2 n_max_rpm)") \
    X(controller, deadtime_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_P(board.deadtime_s, F32, 1.0), \
      "dead time the controller compensates [s] (default the plant's, >= 0)") \
    X(controller, device_drop_V, REAL, SC_GE0, SC_UNSET, SC_NO, SC_P(board.device_drop_V, F32, 1.0), \
      "on-state drop of a leg's conducting device the controller compensates, on top of the dead time, " \
      "both methods [V] (default 0: none; --commission writes what it measured)") \
    X(controller, untold_deadtime_s, REAL, SC_IN(0.0, 1e-5), SC_UNSET, SC_NO, SC_A(ctrl.est_cfg.untold_deadtime_s, F32, 1.0), \
      "proposed: until the inverter error is identified, the least error nobody told, as a dead time [s] " \
      "(the speed floor's prior, and with identify.mode = trusted what the measurement leaves in the final " \
      "bound; step 1's inverter check; default 0.15e-6: EST_UNTOLD_DEADTIME_DEFAULT_S, >= 0; --commission " \
      "writes what its measurement of the inverter leaves uncertain)") \
    X(controller, encoder_offset_el_rad, REAL, SC_ANY, SC_UNSET, SC_NO, SC_NO, \
      "encoder offset the controller is told [rad, electrical], sign as plant.encoder_offset_el_rad " \
      "(default the plant's; run.align = on: the alignment's measurement replaces it)") \
    X(controller, R_min_ohm, REAL, SC_GT0, SC_UNSET, SC_NO, SC_P(tuning.R_min_Ohm, F32, 1.0), \
      "accepted R^ band, low end [ohm] (default 0.1 x controller's R: est_rsid_band)") \
    X(controller, R_max_ohm, REAL, SC_GT0, SC_UNSET, SC_NO, SC_P(tuning.R_max_Ohm, F32, 1.0), \
      "accepted R^ band, high end [ohm] (default 6 x controller's R, at most the observer's eq. (36) bound)")

#define SC_KEYS_identify(X) \
    X(identify, mode, ENUM, SC_NAMES(SC_RSID_NAMES), SC_PARAMS, SC_A(rsid.mode, ENUM, 1.0), SC_SAME, \
      "step 1 of the proposed method: off | windows | speeds | trusted (no step 1: the controller's R_ohm " \
      "is measured, as --commission writes it; R then tracked in service by track_R)") \
    X(identify, speed_1_rpm, REAL, SC_ANY, SC_DERIVED("motor.n_rated_rpm"), SC_NO, \
      SC_P(step1.speed_1_rad_s, F32, DRIVE_RPM_PER_RAD_S), "speeds mode: speed of point 1 [r/min] (0.25 n_rated_rpm)") \
    X(identify, speed_2_rpm, REAL, SC_ANY, SC_DERIVED("motor.n_rated_rpm"), SC_NO, \
      SC_P(step1.speed_2_rad_s, F32, DRIVE_RPM_PER_RAD_S), "speeds mode: speed of point 2 [r/min] (0.5 n_rated_rpm)") \
    X(identify, accel_rpm_s, REAL, SC_GT0, SC_DERIVED("motor.n_rated_rpm motor.i_rated_A controller.J_kgm2"), SC_NO, \
      SC_P(step1.accel_rad_s2, F32, DRIVE_RPM_PER_RAD_S), \
      "speeds mode: ramp of the commanded speed [r/min/s] (speed_1 in 0.2 s, at most 0.25 T_rated / J)") \
    X(identify, settle_2_s, REAL, SC_GE0, SC_DERIVED("controller.speed_bw_rad_s"), SC_NO, \
      SC_P(step1.settle_2_s, F32, 1.0), "end of window 1 to window 2 [s] (5.6 / w_i, the speed PI's integral corner)") \
    X(identify, settle_1_s, REAL, SC_GE0, SC_DERIVED("controller.speed_bw_rad_s"), SC_NO, \
      SC_P(step1.settle_1_s, F32, 1.0), "start of IDENTIFY_R to window 1 [s] (2 x settle_2_s)") \
    X(identify, window_s, REAL, SC_GT0, SC_PARAMS, SC_A(rsid.window_s, F32, 1.0), SC_SAME, "each averaging window [s]") \
    X(identify, R_se_max_rel, REAL, SC_GT0, SC_PARAMS, SC_A(ctrl.est_cfg.rsid.R_se_max_rel, F32, 1.0), SC_SAME, \
      "largest standard error of R^ accepted, x R^") \
    X(identify, batch_s, REAL, SC_GT0, SC_PARAMS, SC_A(ctrl.est_cfg.rsid.n_batch, PERIODS, 1.0), SC_SAME, \
      "batch of the standard error's batch means [s] (more than the staged check's 16 periods, else CONFIG)") \
    X(identify, window_max_s, REAL, SC_GE0, SC_PARAMS, SC_A(rsid.window_max_s, F32, 1.0), SC_SAME, \
      "window 2 is lengthened up to this while the standard error of R^ is too large [s]") \
    X(identify, repeats_max, UINT, SC_IN(0.0, 100.0), SC_PARAMS, SC_A(rsid.repeats_max, U16, 1.0), SC_SAME, \
      "speeds mode: both windows repeated at most this often while window 1's share of se(R^) is too large") \
    X(identify, on_refusal, ENUM, SC_NAMES(SC_REFUSAL_NAMES), SC_PARAMS, SC_A(rsid.on_refusal, ENUM, 1.0), SC_SAME, \
      "a refused step 1: fault (PWM off, RSID_* fault) | conventional (runs on, warning STEP1_REFUSED) | told " \
      "(default: runs on with step 2 from the told R, the inverter error identified, R^ learned by the injection; " \
      "warning STEP1_REFUSED)") \
    X(identify, track_R, ENUM, SC_NAMES(SC_TRACK_NAMES), SC_PARAMS, SC_A(ctrl.est_cfg.track_R, U16, 1.0), SC_SAME, \
      "off | on | auto: R^ tracked in step 2 by a d-current injection (a warming winding); auto: from 1 s after " \
      "step 2; both held while the field is weakened or the voltage at its limit")

#define SC_KEYS_reference(X) \
    X(reference, speed_rpm, PROF, SC_NONE, SC_TEXT(""), SC_NO, SC_NO, "speed reference [r/min] (speed mode)") \
    X(reference, torque_Nm, PROF, SC_NONE, SC_TEXT(""), SC_NO, SC_NO, "torque reference [N m] (torque mode)") \
    X(reference, ud_V, PROF, SC_NONE, SC_TEXT(""), SC_NO, SC_NO, "d voltage [V] (open_loop mode)") \
    X(reference, uq_V, PROF, SC_NONE, SC_TEXT(""), SC_NO, SC_NO, "q voltage [V] (open_loop mode)")

#define SC_KEYS_load(X) \
    X(load, torque_Nm, PROF, SC_NONE, SC_TEXT(""), SC_NO, SC_NO, \
      "active load torque [N m], opposing positive speed (it drives a shaft at rest: a hanging mass, a dyno)") \
    X(load, friction_Nm, REAL, SC_GE0, SC_PARAMS, SC_S(load_coulomb_Nm, F64, 1.0), SC_SAME, \
      "passive load: Coulomb friction [N m], opposing the motion (holds a shaft at rest up to it)") \
    X(load, viscous_Nms, REAL, SC_GE0, SC_PARAMS, SC_S(load_B_Nms, F64, 1.0), SC_SAME, \
      "passive load: viscous friction [N m s/rad], opposing the motion, beside [plant] B_Nms")

#define SC_KEYS_run(X) \
    X(run, duration_s, REAL, SC_GT0, SC_TEXT("1.2"), SC_NO, SC_NO, "simulated time [s]") \
    X(run, log_every, UINT, SC_IN(1.0, SC_UINT32_MAX_D), SC_TEXT("10"), SC_NO, SC_NO, "periods between CSV rows") \
    X(run, calibrate, ENUM, SC_NAMES(SC_ONOFF_NAMES), SC_TEXT("off"), SC_NO, SC_A(calibrate, BOOL, 1.0), \
      "off | on: current-offset calibration at start (both off: RUN at t = 0)") \
    X(run, align, ENUM, SC_NAMES(SC_ONOFF_NAMES), SC_TEXT("off"), SC_NO, SC_A(align, BOOL, 1.0), \
      "off | on: rotor alignment identifies the encoder offset (off: the controller is told it)") \
    X(run, level, UINT, SC_IN(1.0, 5.0), SC_TEXT("5"), SC_NO, SC_A(lvl.level, U16, 1.0), \
      "build level (app.h): 1 PWM pattern, 2 ADC readings, 3 open-loop rotation and encoder check, " \
      "4 torque control at level4_i_limit_A, 5 the full drive") \
    X(run, level4_i_limit_A, REAL, SC_GT0, SC_UNSET, SC_NO, SC_A(lvl.i_lim_4_A, F32, 1.0), \
      "level 4's current limit [A] (default 0.3 x [controller] i_limit_A)") \
    X(run, level12_vdc_max_V, REAL, SC_GT0, SC_PARAMS, SC_A(lvl.vdc_max_12_V, F32, 1.0), SC_SAME, \
      "levels 1-2 run without the DC bus: above this bus a start, or a running level 1 or 2, latches " \
      "BUS_CHARGED (PWM off) [V]: a safe extra-low voltage")

/* [faults]: fault injection on the simulated board (hal_sim.h); each from its time on */
#define SC_KEYS_faults(X) \
    X(faults, open_phase_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_F(open_phase_s, F64, 1.0), \
      "time the phase `open_phase` opens [s] (default never)") \
    X(faults, open_phase, ENUM, SC_NAMES(SC_PHASE_NAMES), SC_TEXT("a"), SC_NO, SC_F(open_phase, U32, 1.0), \
      "the open phase: a | b | c") \
    X(faults, short_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_F(short_s, F64, 1.0), \
      "time the outputs `short_phases` short together [s] (default never)") \
    X(faults, short_phases, ENUM, SC_NAMES(SC_PAIR_NAMES), SC_TEXT("bc"), SC_NO, SC_F(short_pair, U32, 1.0), \
      "the shorted pair: ab | bc | ca") \
    X(faults, short_ohm, REAL, SC_GT0, SC_TEXT("0.1"), SC_NO, SC_F(short_ohm, F64, 1.0), \
      "the short's loop resistance [ohm]") \
    X(faults, short_H, REAL, SC_GT0, SC_TEXT("1e-5"), SC_NO, SC_F(short_H, F64, 1.0), "the short's loop inductance [H]") \
    X(faults, adc_stuck_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_F(adc_stuck_s, F64, 1.0), \
      "time the current channel `adc_stuck` freezes at its reading [s] (default never)") \
    X(faults, adc_stuck, ENUM, SC_NAMES(SC_CHANNEL_NAMES), SC_TEXT("a"), SC_NO, SC_F(adc_stuck_channel, U32, 1.0), \
      "the stuck channel: a | b") \
    X(faults, encoder_lost_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_F(enc_lost_s, F64, 1.0), \
      "time the encoder count stops (A/B lost) [s] (default never)") \
    X(faults, encoder_jump_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_F(enc_jump_s, F64, 1.0), \
      "time the encoder count jumps by encoder_jump_counts [s] (default never)") \
    X(faults, encoder_jump_counts, REAL, SC_ANY, SC_TEXT("2500"), SC_NO, SC_F(enc_jump_counts, I32, 1.0), \
      "the jump [counts] (whole)") \
    X(faults, vdc_sag_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_F(vdc_sag_s, F64, 1.0), \
      "time the DC bus steps to vdc_sag_V [s] (default never)") \
    X(faults, vdc_sag_V, REAL, SC_GT0, SC_TEXT("150"), SC_NO, SC_F(vdc_sag_V, F64, 1.0), "bus after the sag [V]") \
    X(faults, vdc_surge_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_F(vdc_surge_s, F64, 1.0), \
      "time the DC bus steps to vdc_surge_V [s] (default never)") \
    X(faults, vdc_surge_V, REAL, SC_GT0, SC_TEXT("450"), SC_NO, SC_F(vdc_surge_V, F64, 1.0), "bus after the surge [V]") \
    X(faults, gate_trip_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_F(gate_trip_s, F64, 1.0), \
      "time the gate driver pulls the trip input [s] (default never)") \
    X(faults, isr_overrun_s, REAL, SC_GE0, SC_UNSET, SC_NO, SC_F(isr_overrun_s, F64, 1.0), \
      "time of the control ISR call that overruns [s] (default never)") \
    X(faults, isr_overrun_run_s, REAL, SC_GT0, SC_TEXT("1.2e-4"), SC_NO, SC_F(isr_overrun_run_s, F64, 1.0), \
      "run time of that ISR call [s]")

/* [link]: drive_sil --link (tools/sil/link_sil.h) */
#define SC_KEYS_link(X) \
    X(link, idle_timeout_s, REAL, SC_GE0, SC_TEXT("10"), SC_NO, SC_NO, \
      "--link: a client that sends nothing this long (wall time) is told so and closed [s]; 0: never") \
    X(link, host_timeout_s, REAL, SC_IN(0.0, LINK_HOST_TIMEOUT_MAX_S), SC_PARAMS, SC_L(host_timeout_s, F32, 1.0), \
      SC_SAME, "the link's host timeout (the variable host_timeout_s): once a host wrote a reference or " \
      "started the drive, no valid frame this long (the drive's time) ramps it to zero and stops it, warning " \
      "HOST_TIMEOUT [s]; 0: off")

/* Every key, in the order of --help, --list-keys and the resolved JSON. */
#define SC_KEYS(X) \
    SC_KEYS_plant(X) SC_KEYS_motor(X) SC_KEYS_controller(X) SC_KEYS_identify(X) SC_KEYS_reference(X) \
    SC_KEYS_load(X) SC_KEYS_run(X) SC_KEYS_faults(X) SC_KEYS_link(X)

/* scenario_t's field of a key (scenario.h) */
#define SC_FIELD(sec, key, KIND, ...) SC_FIELD_##KIND(key)
#define SC_FIELD_REAL(key) double key;
#define SC_FIELD_UINT(key) uint32_t key;
#define SC_FIELD_ENUM(key) uint32_t key;
#define SC_FIELD_PROF(key) profile_t key;
#define SC_FIELD_RPROF(key) double key; profile_t key##_profile;

#endif /* SCENARIO_KEYS_H */
