/*
 * Layout of the host register fake (tests/c2000_fake/include) against the
 * documented register maps: struct sizes and field offsets in 16-bit words
 * (the C28x addressing unit), and bit positions of the fields the HAL uses.
 * Sources: SPRUG04 (ePWM), SPRU812 (ADC), SPRUG05 (eQEP), SPRUFB0 (system
 * control, PIE, CPU timers, GPIO), SPRUG03 (SCI).
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "DSP2833x_Device.h"

#define WORDS(type, member) (offsetof(struct type, member) / sizeof(Uint16))
#define SIZE_WORDS(type)    (sizeof(struct type) / sizeof(Uint16))

/* Bit position of a field: set it to 1 through .bit, find it in .all. */
#define BIT_OF(reg_union, field, expected_all)          \
    do {                                                \
        union reg_union r_;                             \
        r_.all = 0U;                                    \
        r_.bit.field = 1U;                              \
        assert_int_equal(r_.all, (expected_all));       \
    } while (0)

static void bitfields_pack_in_16_bit_words(void **state)
{
    (void)state;
    assert_int_equal(sizeof(union TBCTL_REG), 2);
    assert_int_equal(sizeof(union CMPA_HRPWM_GROUP), 4);
    assert_int_equal(sizeof(union GPA1_REG), 4);
    assert_int_equal(sizeof(union GPADAT_REG), 4);
    /* A field straddling a byte boundary stays where TI puts it: DIVSEL is bits 8:7. */
    {
        union PLLSTS_REG r;
        r.all = 0U;
        r.bit.DIVSEL = 2U;
        assert_int_equal(r.all, 0x0100);
    }
    /* Upper half of a 32-bit group: GPIO12 mux is bits 25:24 of GPAMUX1. */
    {
        union GPA1_REG r;
        r.all = 0UL;
        r.bit.GPIO12 = 1U;
        assert_int_equal(r.all, 0x01000000UL);
    }
    /* CMPA is the high word of the CMPA:CMPAHR pair. */
    {
        union CMPA_HRPWM_GROUP r;
        r.all = 0UL;
        r.half.CMPA = 0x1234U;
        assert_int_equal(r.all, 0x12340000UL);
    }
}

static void epwm_register_map(void **state)
{
    (void)state;
    assert_int_equal(WORDS(EPWM_REGS, TBCTL), 0x00);
    assert_int_equal(WORDS(EPWM_REGS, TBSTS), 0x01);
    assert_int_equal(WORDS(EPWM_REGS, TBPHS), 0x02);
    assert_int_equal(WORDS(EPWM_REGS, TBCTR), 0x04);
    assert_int_equal(WORDS(EPWM_REGS, TBPRD), 0x05);
    assert_int_equal(WORDS(EPWM_REGS, CMPCTL), 0x07);
    assert_int_equal(WORDS(EPWM_REGS, CMPA), 0x08);
    assert_int_equal(WORDS(EPWM_REGS, CMPB), 0x0A);
    assert_int_equal(WORDS(EPWM_REGS, AQCTLA), 0x0B);
    assert_int_equal(WORDS(EPWM_REGS, AQCTLB), 0x0C);
    assert_int_equal(WORDS(EPWM_REGS, AQSFRC), 0x0D);
    assert_int_equal(WORDS(EPWM_REGS, AQCSFRC), 0x0E);
    assert_int_equal(WORDS(EPWM_REGS, DBCTL), 0x0F);
    assert_int_equal(WORDS(EPWM_REGS, DBRED), 0x10);
    assert_int_equal(WORDS(EPWM_REGS, DBFED), 0x11);
    assert_int_equal(WORDS(EPWM_REGS, TZSEL), 0x12);
    assert_int_equal(WORDS(EPWM_REGS, TZCTL), 0x14);
    assert_int_equal(WORDS(EPWM_REGS, TZEINT), 0x15);
    assert_int_equal(WORDS(EPWM_REGS, TZFLG), 0x16);
    assert_int_equal(WORDS(EPWM_REGS, TZCLR), 0x17);
    assert_int_equal(WORDS(EPWM_REGS, TZFRC), 0x18);
    assert_int_equal(WORDS(EPWM_REGS, ETSEL), 0x19);
    assert_int_equal(WORDS(EPWM_REGS, ETPS), 0x1A);
    assert_int_equal(WORDS(EPWM_REGS, ETFLG), 0x1B);
    assert_int_equal(WORDS(EPWM_REGS, ETCLR), 0x1C);
    assert_int_equal(WORDS(EPWM_REGS, PCCTL), 0x1E);
    assert_int_equal(WORDS(EPWM_REGS, HRCNFG), 0x20);
    /* 0x21 words, padded to the 32-bit alignment of the CMPA/TBPHS groups. */
    assert_int_equal(SIZE_WORDS(EPWM_REGS), 0x22);
}

static void epwm_bit_fields(void **state)
{
    (void)state;
    BIT_OF(TBCTL_REG, PHSEN, 0x0004);
    BIT_OF(TBCTL_REG, SYNCOSEL, 0x0010);
    BIT_OF(TBCTL_REG, HSPCLKDIV, 0x0080);
    BIT_OF(TBCTL_REG, CLKDIV, 0x0400);
    BIT_OF(TBCTL_REG, PHSDIR, 0x2000);
    BIT_OF(TBCTL_REG, FREE_SOFT, 0x4000);
    BIT_OF(CMPCTL_REG, SHDWAMODE, 0x0010);
    BIT_OF(AQCTL_REG, CAU, 0x0010);
    BIT_OF(AQCTL_REG, CAD, 0x0040);
    BIT_OF(DBCTL_REG, POLSEL, 0x0004);
    BIT_OF(DBCTL_REG, IN_MODE, 0x0010);
    BIT_OF(TZSEL_REG, OSHT1, 0x0100);
    BIT_OF(TZCTL_REG, TZB, 0x0004);
    BIT_OF(TZEINT_REG, OST, 0x0004);
    BIT_OF(TZFLG_REG, OST, 0x0004);
    BIT_OF(TZCLR_REG, INT, 0x0001);
    BIT_OF(TZFRC_REG, OST, 0x0004);
    BIT_OF(ETSEL_REG, SOCASEL, 0x0100);
    BIT_OF(ETSEL_REG, SOCAEN, 0x0800);
    BIT_OF(ETPS_REG, SOCAPRD, 0x0100);
}

static void adc_register_map(void **state)
{
    (void)state;
    assert_int_equal(WORDS(ADC_REGS, ADCTRL1), 0x00);
    assert_int_equal(WORDS(ADC_REGS, ADCTRL2), 0x01);
    assert_int_equal(WORDS(ADC_REGS, ADCMAXCONV), 0x02);
    assert_int_equal(WORDS(ADC_REGS, ADCCHSELSEQ1), 0x03);
    assert_int_equal(WORDS(ADC_REGS, ADCASEQSR), 0x07);
    assert_int_equal(WORDS(ADC_REGS, ADCRESULT0), 0x08);
    assert_int_equal(WORDS(ADC_REGS, ADCRESULT15), 0x17);
    assert_int_equal(WORDS(ADC_REGS, ADCTRL3), 0x18);
    assert_int_equal(WORDS(ADC_REGS, ADCST), 0x19);
    assert_int_equal(WORDS(ADC_REGS, ADCREFSEL), 0x1C);
    assert_int_equal(WORDS(ADC_REGS, ADCOFFTRIM), 0x1D);
    assert_int_equal(SIZE_WORDS(ADC_REGS), 0x1E);
    BIT_OF(ADCTRL1_REG, ACQ_PS, 0x0100);
    BIT_OF(ADCTRL1_REG, SEQ_CASC, 0x0010);
    BIT_OF(ADCTRL2_REG, EPWM_SOCA_SEQ1, 0x0100);
    BIT_OF(ADCTRL2_REG, INT_ENA_SEQ1, 0x0800);
    BIT_OF(ADCTRL2_REG, RST_SEQ1, 0x4000);
    BIT_OF(ADCTRL3_REG, SMODE_SEL, 0x0001);
    BIT_OF(ADCTRL3_REG, ADCCLKPS, 0x0002);
    BIT_OF(ADCTRL3_REG, ADCPWDN, 0x0020);
    BIT_OF(ADCTRL3_REG, ADCBGRFDN, 0x0040);
    BIT_OF(ADCST_REG, INT_SEQ1_CLR, 0x0010);
    BIT_OF(ADCCHSELSEQ1_REG, CONV01, 0x0010);
}

static void eqep_register_map(void **state)
{
    (void)state;
    assert_int_equal(WORDS(EQEP_REGS, QPOSCNT), 0x00);
    assert_int_equal(WORDS(EQEP_REGS, QPOSINIT), 0x02);
    assert_int_equal(WORDS(EQEP_REGS, QPOSMAX), 0x04);
    assert_int_equal(WORDS(EQEP_REGS, QPOSILAT), 0x08);
    assert_int_equal(WORDS(EQEP_REGS, QUPRD), 0x10);
    assert_int_equal(WORDS(EQEP_REGS, QWDTMR), 0x12);
    assert_int_equal(WORDS(EQEP_REGS, QDECCTL), 0x14);
    assert_int_equal(WORDS(EQEP_REGS, QEPCTL), 0x15);
    BIT_OF(QDECCTL_REG, QSRC, 0x4000);
    BIT_OF(QEPCTL_REG, QPEN, 0x0008);
    BIT_OF(QEPCTL_REG, IEL, 0x0010);
    BIT_OF(QEPCTL_REG, PCRM, 0x1000);
    BIT_OF(QEPCTL_REG, FREE_SOFT, 0x4000);
}

static void sysctrl_and_flash_register_map(void **state)
{
    (void)state;
    /* SysCtrlRegs at 0x7010: PLLSTS 0x7011, HISPCP 0x701A, PCLKCR0 0x701C,
     * PCLKCR3 0x7020, PLLCR 0x7021, WDKEY 0x7025, WDCR 0x7029. */
    assert_int_equal(WORDS(SYS_CTRL_REGS, PLLSTS), 0x01);
    assert_int_equal(WORDS(SYS_CTRL_REGS, HISPCP), 0x0A);
    assert_int_equal(WORDS(SYS_CTRL_REGS, LOSPCP), 0x0B);
    assert_int_equal(WORDS(SYS_CTRL_REGS, PCLKCR0), 0x0C);
    assert_int_equal(WORDS(SYS_CTRL_REGS, PCLKCR1), 0x0D);
    assert_int_equal(WORDS(SYS_CTRL_REGS, PCLKCR3), 0x10);
    assert_int_equal(WORDS(SYS_CTRL_REGS, PLLCR), 0x11);
    assert_int_equal(WORDS(SYS_CTRL_REGS, SCSR), 0x12);
    assert_int_equal(WORDS(SYS_CTRL_REGS, WDKEY), 0x15);
    assert_int_equal(WORDS(SYS_CTRL_REGS, WDCR), 0x19);
    assert_int_equal(SIZE_WORDS(SYS_CTRL_REGS), 0x20);
    BIT_OF(PLLSTS_REG, MCLKSTS, 0x0008);
    BIT_OF(PLLSTS_REG, MCLKCLR, 0x0010);
    BIT_OF(PLLSTS_REG, MCLKOFF, 0x0040);
    BIT_OF(PCLKCR0_REG, TBCLKSYNC, 0x0004);
    BIT_OF(PCLKCR0_REG, ADCENCLK, 0x0008);
    BIT_OF(PCLKCR0_REG, SCIAENCLK, 0x0400);
    BIT_OF(PCLKCR1_REG, EQEP1ENCLK, 0x4000);
    BIT_OF(PCLKCR3_REG, CPUTIMER2ENCLK, 0x0400);
    BIT_OF(PCLKCR3_REG, GPIOINENCLK, 0x2000);
    /* FlashRegs at 0x0A80: FBANKWAIT 0x0A86, FOTPWAIT 0x0A87. */
    assert_int_equal(WORDS(FLASH_REGS, FSTDBYWAIT), 0x04);
    assert_int_equal(WORDS(FLASH_REGS, FACTIVEWAIT), 0x05);
    assert_int_equal(WORDS(FLASH_REGS, FBANKWAIT), 0x06);
    assert_int_equal(WORDS(FLASH_REGS, FOTPWAIT), 0x07);
    BIT_OF(FBANKWAIT_REG, PAGEWAIT, 0x0100);
}

static void pie_register_map(void **state)
{
    (void)state;
    /* PieCtrlRegs at 0x0CE0: PIEACK 0x0CE1, PIEIER1 0x0CE2 ... PIEIFR12 0x0CF9. */
    assert_int_equal(WORDS(PIE_CTRL_REGS, PIEACK), 0x01);
    assert_int_equal(WORDS(PIE_CTRL_REGS, PIEIER1), 0x02);
    assert_int_equal(WORDS(PIE_CTRL_REGS, PIEIFR1), 0x03);
    assert_int_equal(WORDS(PIE_CTRL_REGS, PIEIER2), 0x04);
    assert_int_equal(WORDS(PIE_CTRL_REGS, PIEIFR12), 0x19);
    assert_int_equal(SIZE_WORDS(PIE_CTRL_REGS), 0x1A);
    /* Vector table at 0x0D00, 32-bit entries: INT1.1 at 0x0D40, INT2.1 at 0x0D50.
     * Host pointers are wider, so the check is by entry index. */
    assert_int_equal(offsetof(struct PIE_VECT_TABLE, SEQ1INT) / sizeof(PINT), 32);
    assert_int_equal(offsetof(struct PIE_VECT_TABLE, TINT0) / sizeof(PINT), 38);
    assert_int_equal(offsetof(struct PIE_VECT_TABLE, EPWM1_TZINT) / sizeof(PINT), 40);
}

/* The whole table (SPRUFB0 "PIE Vector Table Mapping"): 0x0D00 + 2 * index.
 * The CPU's own vectors, then group g's INTg.1 at 32 + 8 (g - 1). */
#define VEC(member) (offsetof(struct PIE_VECT_TABLE, member) / sizeof(PINT))
static void pie_vector_table_covers_all_128_entries(void **state)
{
    (void)state;
    assert_int_equal(sizeof(struct PIE_VECT_TABLE) / sizeof(PINT), 128);
    assert_int_equal(VEC(PIE13_RESERVED), 12);
    assert_int_equal(VEC(XINT13), 13);       /* 0x0D1A INT13 */
    assert_int_equal(VEC(TINT2), 14);        /* 0x0D1C INT14 */
    assert_int_equal(VEC(XNMI), 18);         /* 0x0D24 NMI */
    assert_int_equal(VEC(ILLEGAL), 19);      /* 0x0D26 ITRAP */
    assert_int_equal(VEC(USER1), 20);        /* 0x0D28 */
    assert_int_equal(VEC(USER12), 31);       /* 0x0D3E */
    assert_int_equal(VEC(WAKEINT), 39);      /* INT1.8 */
    assert_int_equal(VEC(EPWM1_INT), 48);    /* INT3.1 0x0D60 */
    assert_int_equal(VEC(ECAP1_INT), 56);    /* INT4.1 0x0D70 */
    assert_int_equal(VEC(EQEP1_INT), 64);    /* INT5.1 0x0D80 */
    assert_int_equal(VEC(SPIRXINTA), 72);    /* INT6.1 0x0D90 */
    assert_int_equal(VEC(MRINTA), 76);       /* INT6.5 */
    assert_int_equal(VEC(DINTCH1), 80);      /* INT7.1 0x0DA0 */
    assert_int_equal(VEC(I2CINT1A), 88);     /* INT8.1 0x0DB0 */
    assert_int_equal(VEC(SCIRXINTC), 92);    /* INT8.5 */
    assert_int_equal(VEC(SCIRXINTA), 96);    /* INT9.1 0x0DC0 */
    assert_int_equal(VEC(ECAN1INTB), 103);   /* INT9.8 */
    assert_int_equal(VEC(rsvd10_1), 104);    /* INT10.1 0x0DD0 */
    assert_int_equal(VEC(rsvd11_1), 112);    /* INT11.1 0x0DE0 */
    assert_int_equal(VEC(XINT3), 120);       /* INT12.1 0x0DF0 */
    assert_int_equal(VEC(LVF), 126);         /* INT12.7 */
    assert_int_equal(VEC(LUF), 127);         /* INT12.8 0x0DFE */
}

static void timer_gpio_sci_register_maps(void **state)
{
    (void)state;
    assert_int_equal(WORDS(CPUTIMER_REGS, TIM), 0);
    assert_int_equal(WORDS(CPUTIMER_REGS, PRD), 2);
    assert_int_equal(WORDS(CPUTIMER_REGS, TCR), 4);
    assert_int_equal(WORDS(CPUTIMER_REGS, TPR), 6);
    assert_int_equal(WORDS(CPUTIMER_REGS, TPRH), 7);
    assert_int_equal(SIZE_WORDS(CPUTIMER_REGS), 8);
    BIT_OF(TCR_REG, TSS, 0x0010);
    BIT_OF(TCR_REG, TRB, 0x0020);
    BIT_OF(TCR_REG, FREE, 0x0800);
    /* GpioCtrlRegs at 0x6F80: GPAQSEL1 0x6F82, GPAMUX1 0x6F86, GPAMUX2 0x6F88, GPAPUD 0x6F8C. */
    assert_int_equal(WORDS(GPIO_CTRL_REGS, GPAQSEL1), 0x02);
    assert_int_equal(WORDS(GPIO_CTRL_REGS, GPAQSEL2), 0x04);
    assert_int_equal(WORDS(GPIO_CTRL_REGS, GPAMUX1), 0x06);
    assert_int_equal(WORDS(GPIO_CTRL_REGS, GPAMUX2), 0x08);
    assert_int_equal(WORDS(GPIO_CTRL_REGS, GPADIR), 0x0A);
    assert_int_equal(WORDS(GPIO_CTRL_REGS, GPAPUD), 0x0C);
    /* SciaRegs at 0x7050: SCILBAUD 0x7053, SCITXBUF 0x7059, SCIFFTX 0x705A. */
    assert_int_equal(WORDS(SCI_REGS, SCIHBAUD), 0x2);
    assert_int_equal(WORDS(SCI_REGS, SCILBAUD), 0x3);
    assert_int_equal(WORDS(SCI_REGS, SCICTL2), 0x4);
    assert_int_equal(WORDS(SCI_REGS, SCITXBUF), 0x9);
    assert_int_equal(WORDS(SCI_REGS, SCIFFTX), 0xA);
    assert_int_equal(WORDS(SCI_REGS, SCIPRI), 0xF);
    assert_int_equal(SIZE_WORDS(SCI_REGS), 0x10);
    BIT_OF(SCICTL1_REG, SWRESET, 0x0020);
    BIT_OF(SCIFFTX_REG, TXFFST, 0x0100);
    BIT_OF(SCIFFTX_REG, SCIRST, 0x8000);
    /* the receive side: SCIRXST 0x7055, SCIRXBUF 0x7057, SCIFFRX 0x705B */
    assert_int_equal(WORDS(SCI_REGS, SCIRXST), 0x5);
    assert_int_equal(WORDS(SCI_REGS, SCIRXBUF), 0x7);
    assert_int_equal(WORDS(SCI_REGS, SCIFFRX), 0xB);
    BIT_OF(SCIRXST_REG, RXERROR, 0x0080);
    BIT_OF(SCIRXST_REG, OE, 0x0008);
    BIT_OF(SCIRXBUF_REG, SCIFFFE, 0x8000);
    BIT_OF(SCIRXBUF_REG, SCIFFPE, 0x4000);
    BIT_OF(SCIFFRX_REG, RXFFST, 0x0100);
    BIT_OF(SCIFFRX_REG, RXFIFORESET, 0x2000);
    BIT_OF(SCIFFRX_REG, RXFFOVRCLR, 0x4000);
    BIT_OF(SCIFFRX_REG, RXFFOVF, 0x8000);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bitfields_pack_in_16_bit_words),
        cmocka_unit_test(epwm_register_map),
        cmocka_unit_test(epwm_bit_fields),
        cmocka_unit_test(adc_register_map),
        cmocka_unit_test(eqep_register_map),
        cmocka_unit_test(sysctrl_and_flash_register_map),
        cmocka_unit_test(pie_register_map),
        cmocka_unit_test(pie_vector_table_covers_all_128_entries),
        cmocka_unit_test(timer_gpio_sci_register_maps),
    };
    return cmocka_run_group_tests_name("c2000_fake", tests, NULL, NULL);
}
