/*
 * hal_f28335_cfg.h - register values of the F28335 HAL, derived from
 * board_hw.h (the board's hardware facts). Kept apart so the unit tests can check them.
 * Document references: SPRUG04 (ePWM), SPRU812 (ADC), SPRUG05 (eQEP),
 * SPRUFB0 (system control, PIE), SPRUG03 (SCI), SPRS439 (data sheet).
 */
#ifndef HAL_F28335_CFG_H
#define HAL_F28335_CFG_H

#include <stdint.h>

#include "board_hw.h"

/* ---- clocks (SPRUFB0 "Clocking") -------------------------------------- */
#define F28335_PLL_DIVSEL_2      2U   /* PLLSTS.DIVSEL: CLKIN = VCOCLK / 2 */
#define F28335_HISPCP            3U   /* HSPCLK = SYSCLKOUT / (2 * 3) = 25 MHz */
#define F28335_HSPCLK_HZ         (BOARD_SYSCLK_HZ / (2UL * F28335_HISPCP))
#define F28335_LOSPCP            2U   /* LSPCLK = SYSCLKOUT / (2 * 2) = 37.5 MHz */
#define F28335_LSPCLK_HZ         (BOARD_SYSCLK_HZ / (2UL * F28335_LOSPCP))
/* PLL lock takes 131072 OSCCLK cycles (SPRUFB0); the poll loop runs at
 * most at OSCCLK and each pass takes at least one cycle, so twice that many
 * passes bound the wait without hanging (host fake, dead PLL). */
#define F28335_PLL_LOCK_POLLS    262144UL

/* ---- flash wait states at 150 MHz (SPRS439 flash timing table) -------- */
/* wait = ceil(t_access / t_SYSCLKOUT) - 1 with t = 6.67 ns:
 * paged and random 37 ns -> 5, OTP 60 ns -> 8. */
#define F28335_FLASH_PAGEWAIT    5U
#define F28335_FLASH_RANDWAIT    5U
#define F28335_FLASH_OTPWAIT     8U
#define F28335_FLASH_FALLBACK_WAIT 0x01FFU  /* STDBYWAIT / ACTIVEWAIT: reset value, the maximum */

/* ---- watchdog (SPRUFB0 "Watchdog Block") ------------------------------ */
/* WDCR: WDCHK (bits 5:3) must be written as 101b; WDDIS is bit 6; WDPS bits 2:0. */
#define F28335_WDCR_DISABLE      0x0068U   /* WDDIS = 1, WDCHK = 101b */
#define F28335_WDCR_ENABLE_DIV8  0x002CU   /* WDDIS = 0, WDCHK = 101b, WDPS = 100b (/8) */
/* Timeout = 256 * 8 * 512 / 30 MHz = 35 ms without a hal_watchdog_kick(). */
#define F28335_WDKEY_1           0x0055U
#define F28335_WDKEY_2           0x00AAU
/* WDCR.WDFLAG (bit 7): set by a watchdog reset, write 1 to clear. */
#define F28335_WDCR_WDFLAG       0x0080U
/* SCSR: WDOVERRIDE (bit 0, write 1 to clear) = 0 locks WDDIS, so nothing can
 * turn the watchdog off again; WDENINT (bit 1) = 0 keeps it a reset. */
#define F28335_SCSR_WD_LOCK      0x0001U

/* ---- PIE (SPRUFB0 "PIE") ------------------------------------------------ */
#define F28335_PIEACK_ALL        0xFFFFU  /* acknowledge every group: all may deliver */

/* ---- ePWM (SPRUG04 "Time-Base", "Dead-Band") -------------------------- */
#define F28335_TBCLK_HZ          BOARD_SYSCLK_HZ   /* HSPCLKDIV = CLKDIV = /1 */
/* Up-down count: f_pwm = TBCLK / (2 * TBPRD) -> 150 MHz / (2 * 10 kHz) = 7500. */
#define F28335_TBPRD             ((uint16_t)(F28335_TBCLK_HZ / (2UL * BOARD_PWM_FREQ_HZ)))
/* Dead band in TBCLK counts, rounded up: 1000 ns * 150 MHz = 150. */
#define F28335_DB_COUNTS         ((uint16_t)((BOARD_DEADTIME_NS * (F28335_TBCLK_HZ / 1000000UL) + 999UL) / 1000UL))
#define F28335_DB_MAX_COUNTS     1023U             /* DBRED/DBFED are 10 bits */
/* SPRUG04 "Action-Qualifier", symmetric up-down PWM: with CMPA loaded at
 * TBCTR = 0, CMPA must be >= 1 (at 0 the compare event can coincide with the
 * load and an edge is lost or doubled). Duty 1 is therefore CMPA = 1: the
 * high side is off for 2 TBCLK (13 ns) around zero, well inside the dead band. */
#define F28335_CMPA_MIN          1U

/* ---- ADC (SPRU812) ----------------------------------------------------- */
#define F28335_ADC_CLKPS         1U   /* FCLK = HSPCLK / (2 * 1) = 12.5 MHz, CPS = 0 */
#define F28335_ADC_ACQ_PS        7U   /* S/H window = 8 ADCCLK = 640 ns */
#define F28335_ADC_POWERUP_US    5000UL /* after powering bandgap, reference, core */
#define F28335_ADC_RESULT_SHIFT  4U   /* ADCRESULTn holds the 12-bit value left-justified */
#define F28335_ADC_V_PER_COUNT   (BOARD_ADC_FULL_SCALE_V / BOARD_ADC_COUNTS)
#define F28335_I_A_PER_COUNT     (F28335_ADC_V_PER_COUNT * BOARD_I_GAIN_A_PER_V)
#define F28335_I_OFFSET_A        (BOARD_I_OFFSET_V * BOARD_I_GAIN_A_PER_V)
#define F28335_VDC_V_PER_COUNT   (F28335_ADC_V_PER_COUNT * BOARD_VDC_GAIN_V_PER_V)
#define F28335_VDC_OFFSET_V      (BOARD_VDC_OFFSET_V * BOARD_VDC_GAIN_V_PER_V)

/* ---- eQEP (SPRUG05) ----------------------------------------------------- */
#define F28335_QPOSMAX           (4UL * BOARD_ENC_LINES - 1UL)   /* 9999 for 2500 lines */

/* ---- SCI-A (SPRUG03 "Baud rate") ---------------------------------------- */
/* The link's rate (firmware/link/link_protocol.md). Set at build time, e.g.
 * -DF28335_SCI_BAUD=937500UL: exact (BRR 4); 115200 is -0.76 %; 921600 is
 * not reachable (BRR 4.09 -> 4 gives 937500, +1.7 %); the top is
 * LSPCLK / 16 = 2.34 Mbaud (BRR 1). */
#ifndef F28335_SCI_BAUD
#define F28335_SCI_BAUD          115200UL
#endif
/* BRR = LSPCLK / (baud * 8) - 1 = 37.5 MHz / 921600 - 1 = 39.69 -> 40
 * (rounded); actual 37.5 MHz / (41 * 8) = 114329 baud, -0.76 %. */
#define F28335_SCI_BRR           ((uint16_t)((F28335_LSPCLK_HZ + 4UL * F28335_SCI_BAUD) / (8UL * F28335_SCI_BAUD) - 1UL))
/* The rate BRR gives, and its error in parts per 10000 of the asked one (-76 at 115200) */
#define F28335_SCI_BAUD_ACTUAL   (F28335_LSPCLK_HZ / (8UL * ((uint32_t)F28335_SCI_BRR + 1UL)))
#define F28335_SCI_ERROR_PER_10K (((int32_t)F28335_SCI_BAUD_ACTUAL - (int32_t)F28335_SCI_BAUD) * 10000L / (int32_t)F28335_SCI_BAUD)
#define F28335_SCI_ERROR_MAX_PER_10K 200L   /* +-2 %: both ends' errors add up within 8N1's ~4.5 % */
#define F28335_SCI_FIFO_DEPTH    16U
/* Above this rate the transmit FIFO is fed by its interrupt (PIE INT9.2, SCITXINTA) instead of
 * the background's pump: at 2.34 Mbaud the 16 words last 16 x 10 / 2.34 MHz = 68 us, less than
 * a background loop pass may take beside a busy control ISR; at 937500 they last 171 us. */
#define F28335_SCI_TX_IRQ_MIN_BAUD 1500000UL
#define F28335_SCI_TX_IRQ        (F28335_SCI_BAUD > F28335_SCI_TX_IRQ_MIN_BAUD)
/* The transmit interrupt comes when the FIFO holds this many words or fewer (TXFFIL): 8 words
 * are 34 us of line at 2.34 Mbaud, more than the control ISR (about 16 us) that may delay it,
 * so the line does not idle; each interrupt then moves 8 or more words. */
#define F28335_SCI_TX_FIFO_LEVEL 8U

/* ---- the parameter store's sector (hal.h hal_nv_*, hal_f28335_nv.c) ------- */
/* Flash sector B (SPRS439 "Memory Maps": 0x330000-0x337FFF), reserved in
 * firmware/f28335/f28335_flash.cmd (FLASHB_NV: no section placed, no CRC
 * record; tools/check/target_cfg.sh checks the two agree). */
#define F28335_NV_SECTOR_ADDR    0x330000UL
#define F28335_NV_SECTOR_WORDS   0x8000UL     /* 32K words */
/* The Flash2833x API's timing, TI's SCALE_FACTOR (Flash2833x_API_Config.h:
 * 1048576 x 200 / CPU_RATE, CPU_RATE the SYSCLKOUT period in ns): for
 * SYSCLKOUT in MHz, 1048576 x 200 x f / 1000 = 1048576 x f / 5; 31457280
 * at 150 MHz. */
#define F28335_FLASH_API_SCALE   (1048576UL * (BOARD_SYSCLK_HZ / 1000000UL) / 5UL)

#endif /* HAL_F28335_CFG_H */
