/* c2000_fake.h - host-only controls of the register fake (tests only). */
#ifndef C2000_FAKE_H
#define C2000_FAKE_H

#include <stdint.h>

#include "DSP2833x_Device.h"

/* Zero every fake register and the fake CPU state (power-on state for the
 * tests); forgets the EDIS hook and the ADC_cal record. */
void c2000_fake_reset(void);

/* Called after every EDIS until reset (NULL: none). */
void c2000_fake_set_edis_hook(void (*hook)(void));

/* TI's ADC_cal (factory code in TI-reserved OTP at 0x380080, run by the boot
 * ROM; C2000Ware's DSP2833x_ADC_cal.asm calls it): writes the device's
 * reference and offset trims. The fake writes the values below and records
 * the call, and whether the ADC clock (PCLKCR0.ADCENCLK) was on at the time. */
void ADC_cal(void);

#define C2000_FAKE_ADCREFSEL_TRIM  0x0000U   /* internal reference */
#define C2000_FAKE_ADCOFFTRIM_TRIM 0x01F3U   /* a device's offset trim */

typedef struct {
    uint16_t calls;             /* ADC_cal() calls since reset */
    uint16_t adc_clock_on;      /* ADCENCLK was 1 at every call */
} c2000_fake_adc_cal_t;

extern c2000_fake_adc_cal_t c2000_fake_adc_cal;

/* The F28335's flash sector B (0x330000, 32K words: hal_f28335_cfg.h's
 * F28335_NV_SECTOR_*), the parameter store's, on the host; erased (0xFFFF)
 * by c2000_fake_reset. Flash2833x_API_Library.h's fake erases and programs
 * it. */
#define C2000_FAKE_FLASH_B_WORDS 0x8000UL
extern Uint16 c2000_fake_flash_b[]; /* C2000_FAKE_FLASH_B_WORDS of them (no size here: the 16-bit-int gate) */

/* What the flash API's fake saw, call by call (reset by c2000_fake_reset). */
typedef enum { C2000_FAKE_ERASE = 1, C2000_FAKE_PROGRAM = 2, C2000_FAKE_VERIFY = 3 } c2000_fake_flash_op_t;
#define C2000_FAKE_FLASH_CALLS_MAX 8
typedef struct {
    c2000_fake_flash_op_t op;
    Uint16 sector_mask;         /* ERASE */
    Uint32 offset, length;      /* PROGRAM, VERIFY: in sector B [words] */
    Uint16 ints_masked;         /* INTM set during the call */
    Uint16 pwm_forced_off;      /* TZFRC.OST set on ePWM1-3 */
    Uint32 scale_factor;        /* Flash_CPUScaleFactor */
    Uint16 callback_kicks;      /* ERASE: callbacks whose watchdog key sequence ended in 0xAA */
} c2000_fake_flash_call_t;
typedef struct {
    Uint16 n;
    c2000_fake_flash_call_t call[C2000_FAKE_FLASH_CALLS_MAX];
    Uint16 fail_next;           /* set by a test: the next call of that op fails (0: none) */
    Uint16 callbacks_per_erase; /* how often an erase calls Flash_CallbackPtr (3 after reset) */
} c2000_fake_flash_t;
extern c2000_fake_flash_t c2000_fake_flash;

#endif /* C2000_FAKE_H */
