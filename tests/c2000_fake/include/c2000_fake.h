/* c2000_fake.h - host-only controls of the register fake (tests only). */
#ifndef C2000_FAKE_H
#define C2000_FAKE_H

#include <stdint.h>

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

#endif /* C2000_FAKE_H */
