/* DSP2833x_SysCtrl.h - host stand-in: system control (SysCtrlRegs at
 * 0x7010) and flash wait-state registers (FlashRegs at 0x0A80), SPRUFB0
 * "Clocking" and "Watchdog Block", SPRUFB0/SPRS439 "Flash and OTP". */
#ifndef DSP2833x_SYS_CTRL_H
#define DSP2833x_SYS_CTRL_H

struct PLLSTS_BITS {
    Uint16 PLLLOCKS:1;         /* 0   PLL locked */
    Uint16 rsvd1:1;            /* 1 */
    Uint16 PLLOFF:1;           /* 2 */
    Uint16 MCLKSTS:1;          /* 3   missing clock (limp mode) */
    Uint16 MCLKCLR:1;          /* 4 */
    Uint16 OSCOFF:1;           /* 5 */
    Uint16 MCLKOFF:1;          /* 6   missing-clock detect off */
    Uint16 DIVSEL:2;           /* 8:7 CLKIN divider (2 = /2) */
    Uint16 rsvd2:7;            /* 15:9 */
};
union PLLSTS_REG { Uint16 all; struct PLLSTS_BITS bit; };

struct HISPCP_BITS { Uint16 HSPCLK:3; Uint16 rsvd1:13; };
union HISPCP_REG { Uint16 all; struct HISPCP_BITS bit; };

struct LOSPCP_BITS { Uint16 LSPCLK:3; Uint16 rsvd1:13; };
union LOSPCP_REG { Uint16 all; struct LOSPCP_BITS bit; };

struct PCLKCR0_BITS {
    Uint16 rsvd1:2;            /* 1:0 */
    Uint16 TBCLKSYNC:1;        /* 2 */
    Uint16 ADCENCLK:1;         /* 3 */
    Uint16 I2CAENCLK:1;        /* 4 */
    Uint16 SCICENCLK:1;        /* 5 */
    Uint16 rsvd2:2;            /* 7:6 */
    Uint16 SPIAENCLK:1;        /* 8 */
    Uint16 rsvd3:1;            /* 9 */
    Uint16 SCIAENCLK:1;        /* 10 */
    Uint16 SCIBENCLK:1;        /* 11 */
    Uint16 MCBSPAENCLK:1;      /* 12 */
    Uint16 MCBSPBENCLK:1;      /* 13 */
    Uint16 ECANAENCLK:1;       /* 14 */
    Uint16 ECANBENCLK:1;       /* 15 */
};
union PCLKCR0_REG { Uint16 all; struct PCLKCR0_BITS bit; };

struct PCLKCR1_BITS {
    Uint16 EPWM1ENCLK:1;       /* 0 */
    Uint16 EPWM2ENCLK:1;       /* 1 */
    Uint16 EPWM3ENCLK:1;       /* 2 */
    Uint16 EPWM4ENCLK:1;       /* 3 */
    Uint16 EPWM5ENCLK:1;       /* 4 */
    Uint16 EPWM6ENCLK:1;       /* 5 */
    Uint16 rsvd1:2;            /* 7:6 */
    Uint16 ECAP1ENCLK:1;       /* 8 */
    Uint16 ECAP2ENCLK:1;       /* 9 */
    Uint16 ECAP3ENCLK:1;       /* 10 */
    Uint16 ECAP4ENCLK:1;       /* 11 */
    Uint16 ECAP5ENCLK:1;       /* 12 */
    Uint16 ECAP6ENCLK:1;       /* 13 */
    Uint16 EQEP1ENCLK:1;       /* 14 */
    Uint16 EQEP2ENCLK:1;       /* 15 */
};
union PCLKCR1_REG { Uint16 all; struct PCLKCR1_BITS bit; };

struct PCLKCR3_BITS {
    Uint16 rsvd1:8;            /* 7:0 */
    Uint16 CPUTIMER0ENCLK:1;   /* 8 */
    Uint16 CPUTIMER1ENCLK:1;   /* 9 */
    Uint16 CPUTIMER2ENCLK:1;   /* 10 */
    Uint16 DMAENCLK:1;         /* 11 */
    Uint16 XINTFENCLK:1;       /* 12 */
    Uint16 GPIOINENCLK:1;      /* 13 */
    Uint16 rsvd2:2;            /* 15:14 */
};
union PCLKCR3_REG { Uint16 all; struct PCLKCR3_BITS bit; };

struct PLLCR_BITS { Uint16 DIV:4; Uint16 rsvd1:12; };
union PLLCR_REG { Uint16 all; struct PLLCR_BITS bit; };

struct SYS_CTRL_REGS {                 /* word offset */
    Uint16             rsvd7;          /* 0 */
    union PLLSTS_REG   PLLSTS;         /* 1 */
    Uint16             rsvd1[8];       /* 2-9 */
    union HISPCP_REG   HISPCP;         /* 10 */
    union LOSPCP_REG   LOSPCP;         /* 11 */
    union PCLKCR0_REG  PCLKCR0;        /* 12 */
    union PCLKCR1_REG  PCLKCR1;        /* 13 */
    Uint16             LPMCR0;         /* 14 (unused here) */
    Uint16             rsvd2;          /* 15 */
    union PCLKCR3_REG  PCLKCR3;        /* 16 */
    union PLLCR_REG    PLLCR;          /* 17 */
    Uint16             SCSR;           /* 18 */
    Uint16             WDCNTR;         /* 19 */
    Uint16             rsvd4;          /* 20 */
    Uint16             WDKEY;          /* 21 */
    Uint16             rsvd5[3];       /* 22-24 */
    Uint16             WDCR;           /* 25 */
    Uint16             rsvd6[6];       /* 26-31 */
};

struct FOPT_BITS { Uint16 ENPIPE:1; Uint16 rsvd:15; };
union FOPT_REG { Uint16 all; struct FOPT_BITS bit; };

struct FSTDBYWAIT_BITS { Uint16 STDBYWAIT:9; Uint16 rsvd:7; };
union FSTDBYWAIT_REG { Uint16 all; struct FSTDBYWAIT_BITS bit; };

struct FACTIVEWAIT_BITS { Uint16 ACTIVEWAIT:9; Uint16 rsvd:7; };
union FACTIVEWAIT_REG { Uint16 all; struct FACTIVEWAIT_BITS bit; };

struct FBANKWAIT_BITS {
    Uint16 RANDWAIT:4;         /* 3:0 */
    Uint16 rsvd1:4;            /* 7:4 */
    Uint16 PAGEWAIT:4;         /* 11:8 */
    Uint16 rsvd2:4;            /* 15:12 */
};
union FBANKWAIT_REG { Uint16 all; struct FBANKWAIT_BITS bit; };

struct FOTPWAIT_BITS { Uint16 OTPWAIT:5; Uint16 rsvd:11; };
union FOTPWAIT_REG { Uint16 all; struct FOTPWAIT_BITS bit; };

struct FLASH_REGS {                    /* word offset */
    union FOPT_REG         FOPT;       /* 0 */
    Uint16                 rsvd1;      /* 1 */
    Uint16                 FPWR;       /* 2 (unused here) */
    Uint16                 FSTATUS;    /* 3 (unused here) */
    union FSTDBYWAIT_REG   FSTDBYWAIT; /* 4 */
    union FACTIVEWAIT_REG  FACTIVEWAIT;/* 5 */
    union FBANKWAIT_REG    FBANKWAIT;  /* 6 */
    union FOTPWAIT_REG     FOTPWAIT;   /* 7 */
};

extern volatile struct SYS_CTRL_REGS SysCtrlRegs;
extern volatile struct FLASH_REGS FlashRegs;

#endif /* DSP2833x_SYS_CTRL_H */
