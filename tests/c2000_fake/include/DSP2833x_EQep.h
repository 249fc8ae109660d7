/* DSP2833x_EQep.h - host stand-in: eQEP registers (SPRUG05, section 5
 * "eQEP Registers"; EQep1Regs at 0x6B00). */
#ifndef DSP2833x_EQEP_H
#define DSP2833x_EQEP_H

struct QDECCTL_BITS {
    Uint16 rsvd1:5;            /* 4:0 */
    Uint16 QSP:1;              /* 5 */
    Uint16 QIP:1;              /* 6 */
    Uint16 QBP:1;              /* 7 */
    Uint16 QAP:1;              /* 8 */
    Uint16 IGATE:1;            /* 9 */
    Uint16 SWAP:1;             /* 10 */
    Uint16 XCR:1;              /* 11 */
    Uint16 SPSEL:1;            /* 12 */
    Uint16 SOEN:1;             /* 13 */
    Uint16 QSRC:2;             /* 15:14 0 = quadrature count mode */
};
union QDECCTL_REG { Uint16 all; struct QDECCTL_BITS bit; };

struct QEPCTL_BITS {
    Uint16 WDE:1;              /* 0 */
    Uint16 UTE:1;              /* 1 */
    Uint16 QCLM:1;             /* 2 */
    Uint16 QPEN:1;             /* 3  counter enable */
    Uint16 IEL:2;              /* 5:4 index event latch (1 = rising) */
    Uint16 SEL:1;              /* 6 */
    Uint16 SWI:1;              /* 7 */
    Uint16 IEI:2;              /* 9:8 */
    Uint16 SEI:2;              /* 11:10 */
    Uint16 PCRM:2;             /* 13:12 counter reset mode (1 = at max) */
    Uint16 FREE_SOFT:2;        /* 15:14 */
};
union QEPCTL_REG { Uint16 all; struct QEPCTL_BITS bit; };

struct EQEP_REGS {                     /* word offset */
    Uint32             QPOSCNT;        /* 0x00 */
    Uint32             QPOSINIT;       /* 0x02 */
    Uint32             QPOSMAX;        /* 0x04 */
    Uint32             QPOSCMP;        /* 0x06 */
    Uint32             QPOSILAT;       /* 0x08 */
    Uint32             QPOSSLAT;       /* 0x0A */
    Uint32             QPOSLAT;        /* 0x0C */
    Uint32             QUTMR;          /* 0x0E */
    Uint32             QUPRD;          /* 0x10 */
    Uint16             QWDTMR;         /* 0x12 */
    Uint16             QWDPRD;         /* 0x13 */
    union QDECCTL_REG  QDECCTL;        /* 0x14 */
    union QEPCTL_REG   QEPCTL;         /* 0x15 */
};

extern volatile struct EQEP_REGS EQep1Regs;

#endif /* DSP2833x_EQEP_H */
