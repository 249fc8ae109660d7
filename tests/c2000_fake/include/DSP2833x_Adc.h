/* DSP2833x_Adc.h - host stand-in: ADC registers (SPRU812, section 2
 * "ADC Registers"; AdcRegs at 0x7100). */
#ifndef DSP2833x_ADC_H
#define DSP2833x_ADC_H

struct ADCTRL1_BITS {
    Uint16 rsvd1:4;            /* 3:0 */
    Uint16 SEQ_CASC:1;         /* 4   0 = dual sequencers */
    Uint16 SEQ_OVRD:1;         /* 5 */
    Uint16 CONT_RUN:1;         /* 6   0 = start-stop */
    Uint16 CPS:1;              /* 7   core clock prescale */
    Uint16 ACQ_PS:4;           /* 11:8 S/H window = ACQ_PS + 1 ADCCLK */
    Uint16 SUSMOD:2;           /* 13:12 */
    Uint16 RESET:1;            /* 14 */
    Uint16 rsvd2:1;            /* 15 */
};
union ADCTRL1_REG { Uint16 all; struct ADCTRL1_BITS bit; };

struct ADCTRL2_BITS {
    Uint16 EPWM_SOCB_SEQ2:1;   /* 0 */
    Uint16 rsvd1:1;            /* 1 */
    Uint16 INT_MOD_SEQ2:1;     /* 2 */
    Uint16 INT_ENA_SEQ2:1;     /* 3 */
    Uint16 rsvd2:1;            /* 4 */
    Uint16 SOC_SEQ2:1;         /* 5 */
    Uint16 RST_SEQ2:1;         /* 6 */
    Uint16 EXT_SOC_SEQ1:1;     /* 7 */
    Uint16 EPWM_SOCA_SEQ1:1;   /* 8 */
    Uint16 rsvd3:1;            /* 9 */
    Uint16 INT_MOD_SEQ1:1;     /* 10 */
    Uint16 INT_ENA_SEQ1:1;     /* 11 */
    Uint16 rsvd4:1;            /* 12 */
    Uint16 SOC_SEQ1:1;         /* 13 */
    Uint16 RST_SEQ1:1;         /* 14 */
    Uint16 EPWM_SOCB_SEQ:1;    /* 15 */
};
union ADCTRL2_REG { Uint16 all; struct ADCTRL2_BITS bit; };

struct ADCMAXCONV_BITS {
    Uint16 MAX_CONV1:4;        /* 3:0 */
    Uint16 MAX_CONV2:3;        /* 6:4 */
    Uint16 rsvd1:9;            /* 15:7 */
};
union ADCMAXCONV_REG { Uint16 all; struct ADCMAXCONV_BITS bit; };

struct ADCCHSELSEQ1_BITS {
    Uint16 CONV00:4;           /* 3:0 */
    Uint16 CONV01:4;           /* 7:4 */
    Uint16 CONV02:4;           /* 11:8 */
    Uint16 CONV03:4;           /* 15:12 */
};
union ADCCHSELSEQ1_REG { Uint16 all; struct ADCCHSELSEQ1_BITS bit; };

struct ADCTRL3_BITS {
    Uint16 SMODE_SEL:1;        /* 0   1 = simultaneous sampling */
    Uint16 ADCCLKPS:4;         /* 4:1 */
    Uint16 ADCPWDN:1;          /* 5 */
    Uint16 ADCBGRFDN:2;        /* 7:6 */
    Uint16 rsvd1:8;            /* 15:8 */
};
union ADCTRL3_REG { Uint16 all; struct ADCTRL3_BITS bit; };

struct ADCST_BITS {
    Uint16 INT_SEQ1:1;         /* 0 */
    Uint16 INT_SEQ2:1;         /* 1 */
    Uint16 SEQ1_BSY:1;         /* 2 */
    Uint16 SEQ2_BSY:1;         /* 3 */
    Uint16 INT_SEQ1_CLR:1;     /* 4 */
    Uint16 INT_SEQ2_CLR:1;     /* 5 */
    Uint16 EOS_BUF1:1;         /* 6 */
    Uint16 EOS_BUF2:1;         /* 7 */
    Uint16 rsvd1:8;            /* 15:8 */
};
union ADCST_REG { Uint16 all; struct ADCST_BITS bit; };

struct ADC_REGS {                           /* word offset */
    union ADCTRL1_REG      ADCTRL1;         /* 0x00 */
    union ADCTRL2_REG      ADCTRL2;         /* 0x01 */
    union ADCMAXCONV_REG   ADCMAXCONV;      /* 0x02 */
    union ADCCHSELSEQ1_REG ADCCHSELSEQ1;    /* 0x03 */
    Uint16                 ADCCHSELSEQ2;    /* 0x04 (unused here) */
    Uint16                 ADCCHSELSEQ3;    /* 0x05 (unused here) */
    Uint16                 ADCCHSELSEQ4;    /* 0x06 (unused here) */
    Uint16                 ADCASEQSR;       /* 0x07 (unused here) */
    Uint16                 ADCRESULT0;      /* 0x08 left-justified: value << 4 */
    Uint16                 ADCRESULT1;      /* 0x09 */
    Uint16                 ADCRESULT2;      /* 0x0A */
    Uint16                 ADCRESULT3;      /* 0x0B */
    Uint16                 ADCRESULT4;      /* 0x0C */
    Uint16                 ADCRESULT5;      /* 0x0D */
    Uint16                 ADCRESULT6;      /* 0x0E */
    Uint16                 ADCRESULT7;      /* 0x0F */
    Uint16                 ADCRESULT8;      /* 0x10 */
    Uint16                 ADCRESULT9;      /* 0x11 */
    Uint16                 ADCRESULT10;     /* 0x12 */
    Uint16                 ADCRESULT11;     /* 0x13 */
    Uint16                 ADCRESULT12;     /* 0x14 */
    Uint16                 ADCRESULT13;     /* 0x15 */
    Uint16                 ADCRESULT14;     /* 0x16 */
    Uint16                 ADCRESULT15;     /* 0x17 */
    union ADCTRL3_REG      ADCTRL3;         /* 0x18 */
    union ADCST_REG        ADCST;           /* 0x19 */
    Uint16                 rsvd1;           /* 0x1A */
    Uint16                 rsvd2;           /* 0x1B */
    Uint16                 ADCREFSEL;       /* 0x1C (set by ADC_cal) */
    Uint16                 ADCOFFTRIM;      /* 0x1D (set by ADC_cal) */
};

extern volatile struct ADC_REGS AdcRegs;

#endif /* DSP2833x_ADC_H */
