/* DSP2833x_PieVect.h - host stand-in: PIE vector table (SPRUFB0, "PIE
 * Vector Table"; PieVectTable at 0x0D00, 128 32-bit vectors: 13 reserved,
 * the CPU's own interrupts and traps, then groups 1..12 of eight PIE
 * interrupts each, INTx.1 first). On the host a vector is a plain function
 * pointer; tests/test_c2000_fake.c checks every entry's index. */
#ifndef DSP2833x_PIE_VECT_H
#define DSP2833x_PIE_VECT_H

typedef void (*PINT)(void);

struct PIE_VECT_TABLE {                /* entry index (word offset / 2) */
    PINT PIE1_RESERVED;  PINT PIE2_RESERVED;  PINT PIE3_RESERVED;
    PINT PIE4_RESERVED;  PINT PIE5_RESERVED;  PINT PIE6_RESERVED;
    PINT PIE7_RESERVED;  PINT PIE8_RESERVED;  PINT PIE9_RESERVED;
    PINT PIE10_RESERVED; PINT PIE11_RESERVED; PINT PIE12_RESERVED;
    PINT PIE13_RESERVED;               /* 0..12 (reset is fetched from boot ROM) */
    PINT XINT13;                       /* 13  INT13: XINT13 / CPU timer 1 */
    PINT TINT2;                        /* 14  INT14: CPU timer 2 */
    PINT DATALOG;                      /* 15 */
    PINT RTOSINT;                      /* 16 */
    PINT EMUINT;                       /* 17 */
    PINT XNMI;                         /* 18  non-maskable interrupt */
    PINT ILLEGAL;                      /* 19  illegal-instruction trap (ITRAP) */
    PINT USER1;  PINT USER2;  PINT USER3;  PINT USER4;
    PINT USER5;  PINT USER6;  PINT USER7;  PINT USER8;
    PINT USER9;  PINT USER10; PINT USER11; PINT USER12;   /* 20..31 TRAP #20..#31 */
    /* group 1 (CPU INT1): entries 32..39 */
    PINT SEQ1INT; PINT SEQ2INT; PINT rsvd1_3; PINT XINT1;
    PINT XINT2; PINT ADCINT; PINT TINT0; PINT WAKEINT;
    /* group 2 (CPU INT2): entries 40..47 */
    PINT EPWM1_TZINT; PINT EPWM2_TZINT; PINT EPWM3_TZINT; PINT EPWM4_TZINT;
    PINT EPWM5_TZINT; PINT EPWM6_TZINT; PINT rsvd2_7; PINT rsvd2_8;
    /* group 3 (CPU INT3): entries 48..55 */
    PINT EPWM1_INT; PINT EPWM2_INT; PINT EPWM3_INT; PINT EPWM4_INT;
    PINT EPWM5_INT; PINT EPWM6_INT; PINT rsvd3_7; PINT rsvd3_8;
    /* group 4 (CPU INT4): entries 56..63 */
    PINT ECAP1_INT; PINT ECAP2_INT; PINT ECAP3_INT; PINT ECAP4_INT;
    PINT ECAP5_INT; PINT ECAP6_INT; PINT rsvd4_7; PINT rsvd4_8;
    /* group 5 (CPU INT5): entries 64..71 */
    PINT EQEP1_INT; PINT EQEP2_INT; PINT rsvd5_3; PINT rsvd5_4;
    PINT rsvd5_5; PINT rsvd5_6; PINT rsvd5_7; PINT rsvd5_8;
    /* group 6 (CPU INT6): entries 72..79 */
    PINT SPIRXINTA; PINT SPITXINTA; PINT MRINTB; PINT MXINTB;
    PINT MRINTA; PINT MXINTA; PINT rsvd6_7; PINT rsvd6_8;
    /* group 7 (CPU INT7): entries 80..87 */
    PINT DINTCH1; PINT DINTCH2; PINT DINTCH3; PINT DINTCH4;
    PINT DINTCH5; PINT DINTCH6; PINT rsvd7_7; PINT rsvd7_8;
    /* group 8 (CPU INT8): entries 88..95 */
    PINT I2CINT1A; PINT I2CINT2A; PINT rsvd8_3; PINT rsvd8_4;
    PINT SCIRXINTC; PINT SCITXINTC; PINT rsvd8_7; PINT rsvd8_8;
    /* group 9 (CPU INT9): entries 96..103 */
    PINT SCIRXINTA; PINT SCITXINTA; PINT SCIRXINTB; PINT SCITXINTB;
    PINT ECAN0INTA; PINT ECAN1INTA; PINT ECAN0INTB; PINT ECAN1INTB;
    /* group 10 (CPU INT10): entries 104..111 */
    PINT rsvd10_1; PINT rsvd10_2; PINT rsvd10_3; PINT rsvd10_4;
    PINT rsvd10_5; PINT rsvd10_6; PINT rsvd10_7; PINT rsvd10_8;
    /* group 11 (CPU INT11): entries 112..119 */
    PINT rsvd11_1; PINT rsvd11_2; PINT rsvd11_3; PINT rsvd11_4;
    PINT rsvd11_5; PINT rsvd11_6; PINT rsvd11_7; PINT rsvd11_8;
    /* group 12 (CPU INT12): entries 120..127 */
    PINT XINT3; PINT XINT4; PINT XINT5; PINT XINT6;
    PINT XINT7; PINT rsvd12_6; PINT LVF; PINT LUF;
};

extern struct PIE_VECT_TABLE PieVectTable;

#endif /* DSP2833x_PIE_VECT_H */
