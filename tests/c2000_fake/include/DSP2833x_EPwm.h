/* DSP2833x_EPwm.h - host stand-in: ePWM registers (SPRUG04, section 4
 * "Registers"; ePWM1 at 0x6800, ePWM2 0x6840, ePWM3 0x6880). */
#ifndef DSP2833x_EPWM_H
#define DSP2833x_EPWM_H

struct TBCTL_BITS {            /* bits */
    Uint16 CTRMODE:2;          /* 1:0   counter mode (2 = up-down) */
    Uint16 PHSEN:1;            /* 2     load TBCTR from TBPHS on sync */
    Uint16 PRDLD:1;            /* 3     0 = TBPRD shadowed */
    Uint16 SYNCOSEL:2;         /* 5:4   sync-out select */
    Uint16 SWFSYNC:1;          /* 6     software sync */
    Uint16 HSPCLKDIV:3;        /* 9:7   high-speed prescale */
    Uint16 CLKDIV:3;           /* 12:10 prescale */
    Uint16 PHSDIR:1;           /* 13    count direction after sync */
    Uint16 FREE_SOFT:2;        /* 15:14 emulation mode */
};
union TBCTL_REG { Uint16 all; struct TBCTL_BITS bit; };

struct TBSTS_BITS {
    Uint16 CTRDIR:1;           /* 0 */
    Uint16 SYNCI:1;            /* 1 */
    Uint16 CTRMAX:1;           /* 2 */
    Uint16 rsvd1:13;           /* 15:3 */
};
union TBSTS_REG { Uint16 all; struct TBSTS_BITS bit; };

struct TBPHS_HRPWM_REG {
    Uint16 TBPHSHR;            /* 15:0  high-resolution extension */
    Uint16 TBPHS;              /* 31:16 phase offset */
};
union TBPHS_HRPWM_GROUP { Uint32 all; struct TBPHS_HRPWM_REG half; };

struct CMPCTL_BITS {
    Uint16 LOADAMODE:2;        /* 1:0  0 = load CMPA at CTR = 0 */
    Uint16 LOADBMODE:2;        /* 3:2 */
    Uint16 SHDWAMODE:1;        /* 4    0 = shadowed */
    Uint16 rsvd1:1;            /* 5 */
    Uint16 SHDWBMODE:1;        /* 6 */
    Uint16 rsvd2:1;            /* 7 */
    Uint16 SHDWAFULL:1;        /* 8 */
    Uint16 SHDWBFULL:1;        /* 9 */
    Uint16 rsvd3:6;            /* 15:10 */
};
union CMPCTL_REG { Uint16 all; struct CMPCTL_BITS bit; };

struct CMPA_HRPWM_REG {
    Uint16 CMPAHR;             /* 15:0  high-resolution extension */
    Uint16 CMPA;               /* 31:16 compare A */
};
union CMPA_HRPWM_GROUP { Uint32 all; struct CMPA_HRPWM_REG half; };

struct AQCTL_BITS {            /* each: 0 none, 1 clear, 2 set, 3 toggle */
    Uint16 ZRO:2;              /* 1:0 */
    Uint16 PRD:2;              /* 3:2 */
    Uint16 CAU:2;              /* 5:4 */
    Uint16 CAD:2;              /* 7:6 */
    Uint16 CBU:2;              /* 9:8 */
    Uint16 CBD:2;              /* 11:10 */
    Uint16 rsvd:4;             /* 15:12 */
};
union AQCTL_REG { Uint16 all; struct AQCTL_BITS bit; };

struct AQSFRC_BITS {
    Uint16 ACTSFA:2;           /* 1:0 */
    Uint16 OTSFA:1;            /* 2 */
    Uint16 ACTSFB:2;           /* 4:3 */
    Uint16 OTSFB:1;            /* 5 */
    Uint16 RLDCSF:2;           /* 7:6 */
    Uint16 rsvd1:8;            /* 15:8 */
};
union AQSFRC_REG { Uint16 all; struct AQSFRC_BITS bit; };

struct AQCSFRC_BITS {
    Uint16 CSFA:2;             /* 1:0 */
    Uint16 CSFB:2;             /* 3:2 */
    Uint16 rsvd1:12;           /* 15:4 */
};
union AQCSFRC_REG { Uint16 all; struct AQCSFRC_BITS bit; };

struct DBCTL_BITS {
    Uint16 OUT_MODE:2;         /* 1:0  3 = both edges delayed */
    Uint16 POLSEL:2;           /* 3:2  2 = active high complementary */
    Uint16 IN_MODE:2;          /* 5:4  0 = ePWMxA drives both delays */
    Uint16 rsvd1:10;           /* 15:6 */
};
union DBCTL_REG { Uint16 all; struct DBCTL_BITS bit; };

struct TZSEL_BITS {
    Uint16 CBC1:1;             /* 0 */
    Uint16 CBC2:1;             /* 1 */
    Uint16 CBC3:1;             /* 2 */
    Uint16 CBC4:1;             /* 3 */
    Uint16 CBC5:1;             /* 4 */
    Uint16 CBC6:1;             /* 5 */
    Uint16 rsvd1:2;            /* 7:6 */
    Uint16 OSHT1:1;            /* 8  TZ1 one-shot */
    Uint16 OSHT2:1;            /* 9 */
    Uint16 OSHT3:1;            /* 10 */
    Uint16 OSHT4:1;            /* 11 */
    Uint16 OSHT5:1;            /* 12 */
    Uint16 OSHT6:1;            /* 13 */
    Uint16 rsvd2:2;            /* 15:14 */
};
union TZSEL_REG { Uint16 all; struct TZSEL_BITS bit; };

struct TZCTL_BITS {            /* 0 high-Z, 1 high, 2 low, 3 no action */
    Uint16 TZA:2;              /* 1:0 */
    Uint16 TZB:2;              /* 3:2 */
    Uint16 rsvd:12;            /* 15:4 */
};
union TZCTL_REG { Uint16 all; struct TZCTL_BITS bit; };

struct TZEINT_BITS {
    Uint16 rsvd1:1;            /* 0 */
    Uint16 CBC:1;              /* 1 */
    Uint16 OST:1;              /* 2 */
    Uint16 rsvd2:13;           /* 15:3 */
};
union TZEINT_REG { Uint16 all; struct TZEINT_BITS bit; };

struct TZFLG_BITS {
    Uint16 INT:1;              /* 0 */
    Uint16 CBC:1;              /* 1 */
    Uint16 OST:1;              /* 2 */
    Uint16 rsvd2:13;           /* 15:3 */
};
union TZFLG_REG { Uint16 all; struct TZFLG_BITS bit; };

struct TZCLR_BITS {
    Uint16 INT:1;              /* 0 */
    Uint16 CBC:1;              /* 1 */
    Uint16 OST:1;              /* 2 */
    Uint16 rsvd2:13;           /* 15:3 */
};
union TZCLR_REG { Uint16 all; struct TZCLR_BITS bit; };

struct TZFRC_BITS {
    Uint16 rsvd1:1;            /* 0 */
    Uint16 CBC:1;              /* 1 */
    Uint16 OST:1;              /* 2 */
    Uint16 rsvd2:13;           /* 15:3 */
};
union TZFRC_REG { Uint16 all; struct TZFRC_BITS bit; };

struct ETSEL_BITS {
    Uint16 INTSEL:3;           /* 2:0 */
    Uint16 INTEN:1;            /* 3 */
    Uint16 rsvd1:4;            /* 7:4 */
    Uint16 SOCASEL:3;          /* 10:8  1 = CTR = 0 */
    Uint16 SOCAEN:1;           /* 11 */
    Uint16 SOCBSEL:3;          /* 14:12 */
    Uint16 SOCBEN:1;           /* 15 */
};
union ETSEL_REG { Uint16 all; struct ETSEL_BITS bit; };

struct ETPS_BITS {
    Uint16 INTPRD:2;           /* 1:0 */
    Uint16 INTCNT:2;           /* 3:2 */
    Uint16 rsvd1:4;            /* 7:4 */
    Uint16 SOCAPRD:2;          /* 9:8  1 = every event */
    Uint16 SOCACNT:2;          /* 11:10 */
    Uint16 SOCBPRD:2;          /* 13:12 */
    Uint16 SOCBCNT:2;          /* 15:14 */
};
union ETPS_REG { Uint16 all; struct ETPS_BITS bit; };

struct ETFLG_BITS {
    Uint16 INT:1;              /* 0 */
    Uint16 rsvd1:1;            /* 1 */
    Uint16 SOCA:1;             /* 2 */
    Uint16 SOCB:1;             /* 3 */
    Uint16 rsvd2:12;           /* 15:4 */
};
union ETFLG_REG { Uint16 all; struct ETFLG_BITS bit; };
union ETCLR_REG { Uint16 all; struct ETFLG_BITS bit; };
union ETFRC_REG { Uint16 all; struct ETFLG_BITS bit; };

struct EPWM_REGS {                        /* word offset */
    union  TBCTL_REG         TBCTL;       /* 0x00 */
    union  TBSTS_REG         TBSTS;       /* 0x01 */
    union  TBPHS_HRPWM_GROUP TBPHS;       /* 0x02 */
    Uint16                   TBCTR;       /* 0x04 */
    Uint16                   TBPRD;       /* 0x05 */
    Uint16                   rsvd1;       /* 0x06 */
    union  CMPCTL_REG        CMPCTL;      /* 0x07 */
    union  CMPA_HRPWM_GROUP  CMPA;        /* 0x08 */
    Uint16                   CMPB;        /* 0x0A */
    union  AQCTL_REG         AQCTLA;      /* 0x0B */
    union  AQCTL_REG         AQCTLB;      /* 0x0C */
    union  AQSFRC_REG        AQSFRC;      /* 0x0D */
    union  AQCSFRC_REG       AQCSFRC;     /* 0x0E */
    union  DBCTL_REG         DBCTL;       /* 0x0F */
    Uint16                   DBRED;       /* 0x10 */
    Uint16                   DBFED;       /* 0x11 */
    union  TZSEL_REG         TZSEL;       /* 0x12 */
    Uint16                   rsvd2;       /* 0x13 */
    union  TZCTL_REG         TZCTL;       /* 0x14 */
    union  TZEINT_REG        TZEINT;      /* 0x15 */
    union  TZFLG_REG         TZFLG;       /* 0x16 */
    union  TZCLR_REG         TZCLR;       /* 0x17 */
    union  TZFRC_REG         TZFRC;       /* 0x18 */
    union  ETSEL_REG         ETSEL;       /* 0x19 */
    union  ETPS_REG          ETPS;        /* 0x1A */
    union  ETFLG_REG         ETFLG;       /* 0x1B */
    union  ETCLR_REG         ETCLR;       /* 0x1C */
    union  ETFRC_REG         ETFRC;       /* 0x1D */
    Uint16                   PCCTL;       /* 0x1E chopper (unused here) */
    Uint16                   rsvd3;       /* 0x1F */
    Uint16                   HRCNFG;      /* 0x20 HRPWM (unused here) */
};

extern volatile struct EPWM_REGS EPwm1Regs;
extern volatile struct EPWM_REGS EPwm2Regs;
extern volatile struct EPWM_REGS EPwm3Regs;

#endif /* DSP2833x_EPWM_H */
