/*
 * board_hw.h - hardware facts of the F28335 drive board: clocks, PWM,
 * gate-driver dead time, ADC front end and encoder. The HAL derives its
 * register values from them (hal_f28335_cfg.h); the drive configuration
 * (firmware/params/board_cfg.h: limits, start-up, tuning, motor) reads the few it
 * needs. Change the board's hardware here, nowhere else, or through a motor
 * file: `make board MOTOR=FILE.ini` (tools/sil/board_config.h) generates
 * drive_config.h with the file's board facts ([plant] deadtime_s,
 * encoder_lines, adc_full_scale_A, trip_A) and builds with DRIVE_CONFIG
 * defined, which puts them in place of the defaults marked "motor file".
 */
#ifndef BOARD_HW_H
#define BOARD_HW_H

#if defined(DRIVE_CONFIG)
#include "drive_config.h"
#endif

/* ---- clocks ----------------------------------------------------------- */
#define BOARD_XTAL_HZ            30000000UL   /* crystal on X1/X2 [Hz] */
#define BOARD_PLL_MULT           10U          /* PLLCR.DIV: VCOCLK = 300 MHz */
#define BOARD_SYSCLK_HZ          150000000UL  /* 30 MHz * 10 / 2 (PLLSTS.DIVSEL = /2) [Hz] */

/* ---- PWM -------------------------------------------------------------- */
#define BOARD_PWM_FREQ_HZ        10000UL      /* switching = control frequency [Hz] */
/* Gate-driver dead time, both edges (ePWM dead band, DBRED = DBFED): the
 * switches' turn-off time and the driver's propagation skew, with margin,
 * measured at the gates (hal/f28335/README.md, level 1). 1 us for this
 * board's switches; TI's high-voltage kit (HVMTRPFCKIT, HVPM_Sensored)
 * runs 2 us for its IGBT module: a board with slower switches needs its
 * own, never less. Motor file: [plant] deadtime_s. */
#ifndef BOARD_DEADTIME_NS
#define BOARD_DEADTIME_NS        1000UL       /* [ns] */
#endif

/* ---- ADC front end (F28335 ADC: 0..3 V, 12 bit) ----------------------- */
#define BOARD_ADC_FULL_SCALE_V   3.0f         /* ADC input range [V] */
#define BOARD_ADC_COUNTS         4096.0f      /* 12-bit full scale [counts] */
/* Phase current: i = (v_pin - offset) * gain, +-BOARD_I_FULL_SCALE_A over
 * the input range around its middle: 10 A/V around 1.5 V for +-15 A.
 * Motor file: [plant] adc_full_scale_A. */
#ifndef BOARD_I_FULL_SCALE_A
#define BOARD_I_FULL_SCALE_A     15.0f        /* current ADC range, +- [A] */
#endif
#define BOARD_I_OFFSET_V         1.5f         /* pin voltage at zero current [V] */
#define BOARD_I_SENSE_SIGN       1.0f         /* -1.0f: a sensor mounted the other way (positive current flows into the motor) */
#define BOARD_I_GAIN_A_PER_V     (BOARD_I_SENSE_SIGN * BOARD_I_FULL_SCALE_A / BOARD_I_OFFSET_V) /* [A/V] */
/* The gate driver's overcurrent comparator, which pulls TZ1 low: set by the
 * board's parts, not by the firmware; above the software trip the
 * parameter set derives (params_design.md sec. 3). Motor file: [plant]
 * trip_A (what drive_sil's simulated board trips at). */
#ifndef BOARD_HW_TRIP_A
#define BOARD_HW_TRIP_A          15.0f        /* [A] */
#endif
/* DC bus: resistive divider, 200 V per volt at the pin: 0..600 V. */
#define BOARD_VDC_GAIN_V_PER_V   200.0f       /* [V bus / V pin] */
#define BOARD_VDC_OFFSET_V       0.0f         /* pin voltage at 0 V bus [V] */

/* ---- encoder ---------------------------------------------------------- */
#ifndef BOARD_ENC_LINES
#define BOARD_ENC_LINES          2500UL       /* lines per revolution; x4 counts; motor file: [plant] encoder_lines */
#endif

#endif /* BOARD_HW_H */
