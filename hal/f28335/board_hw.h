/*
 * board_hw.h - hardware facts of the F28335 drive board: clocks, PWM,
 * gate-driver dead time, ADC front end and encoder. The HAL derives its
 * register values from them (hal_f28335_cfg.h); the drive configuration
 * (firmware/params/board_cfg.h: limits, start-up, tuning, motor) reads the few it
 * needs. Change the board's hardware here, nowhere else.
 */
#ifndef BOARD_HW_H
#define BOARD_HW_H

/* ---- clocks ----------------------------------------------------------- */
#define BOARD_XTAL_HZ            30000000UL   /* crystal on X1/X2 [Hz] */
#define BOARD_PLL_MULT           10U          /* PLLCR.DIV: VCOCLK = 300 MHz */
#define BOARD_SYSCLK_HZ          150000000UL  /* 30 MHz * 10 / 2 (PLLSTS.DIVSEL = /2) [Hz] */

/* ---- PWM -------------------------------------------------------------- */
#define BOARD_PWM_FREQ_HZ        10000UL      /* switching = control frequency [Hz] */
#define BOARD_DEADTIME_NS        1000UL       /* gate-driver dead time, both edges [ns] */

/* ---- ADC front end (F28335 ADC: 0..3 V, 12 bit) ----------------------- */
#define BOARD_ADC_FULL_SCALE_V   3.0f         /* ADC input range [V] */
#define BOARD_ADC_COUNTS         4096.0f      /* 12-bit full scale [counts] */
/* Phase current: i = (v_pin - offset) * gain; the sign of the gain makes
 * positive current flow into the motor. 10 A/V around 1.5 V: +/-15 A. */
#define BOARD_I_GAIN_A_PER_V     10.0f        /* current sensor + conditioning [A/V] */
#define BOARD_I_OFFSET_V         1.5f         /* pin voltage at zero current [V] */
/* DC bus: resistive divider, 200 V per volt at the pin: 0..600 V. */
#define BOARD_VDC_GAIN_V_PER_V   200.0f       /* [V bus / V pin] */
#define BOARD_VDC_OFFSET_V       0.0f         /* pin voltage at 0 V bus [V] */

/* ---- encoder ---------------------------------------------------------- */
#define BOARD_ENC_LINES          2500UL       /* lines per revolution; x4 counts */

#endif /* BOARD_HW_H */
