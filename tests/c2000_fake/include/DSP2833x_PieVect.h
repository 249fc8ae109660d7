/* DSP2833x_PieVect.h - host stand-in: PIE vector table (SPRUFB0, "PIE
 * Vector Table"; PieVectTable at 0x0D00, one 32-bit vector per entry).
 * Modelled up to group 2; on the host a vector is a plain function pointer. */
#ifndef DSP2833x_PIE_VECT_H
#define DSP2833x_PIE_VECT_H

typedef void (*PINT)(void);

struct PIE_VECT_TABLE {                /* entry index (word offset / 2) */
    PINT PIE1_RESERVED;  PINT PIE2_RESERVED;  PINT PIE3_RESERVED;
    PINT PIE4_RESERVED;  PINT PIE5_RESERVED;  PINT PIE6_RESERVED;
    PINT PIE7_RESERVED;  PINT PIE8_RESERVED;  PINT PIE9_RESERVED;
    PINT PIE10_RESERVED; PINT PIE11_RESERVED; PINT PIE12_RESERVED;
    PINT PIE13_RESERVED;               /* 0..12 */
    PINT XINT13;                       /* 13 */
    PINT TINT2;                        /* 14 */
    PINT DATALOG;                      /* 15 */
    PINT RTOSINT;                      /* 16 */
    PINT EMUINT;                       /* 17 */
    PINT XNMI;                         /* 18 */
    PINT ILLEGAL;                      /* 19 */
    PINT USER1;  PINT USER2;  PINT USER3;  PINT USER4;
    PINT USER5;  PINT USER6;  PINT USER7;  PINT USER8;
    PINT USER9;  PINT USER10; PINT USER11; PINT USER12;   /* 20..31 */
    /* group 1 (CPU INT1) */
    PINT SEQ1INT;                      /* 32  INT1.1 ADC sequencer 1 */
    PINT SEQ2INT;                      /* 33  INT1.2 */
    PINT rsvd1_3;                      /* 34  INT1.3 */
    PINT XINT1;                        /* 35  INT1.4 */
    PINT XINT2;                        /* 36  INT1.5 */
    PINT ADCINT;                       /* 37  INT1.6 */
    PINT TINT0;                        /* 38  INT1.7 */
    PINT WAKEINT;                      /* 39  INT1.8 */
    /* group 2 (CPU INT2) */
    PINT EPWM1_TZINT;                  /* 40  INT2.1 */
    PINT EPWM2_TZINT;                  /* 41  INT2.2 */
    PINT EPWM3_TZINT;                  /* 42  INT2.3 */
    PINT EPWM4_TZINT;                  /* 43  INT2.4 */
    PINT EPWM5_TZINT;                  /* 44  INT2.5 */
    PINT EPWM6_TZINT;                  /* 45  INT2.6 */
    PINT rsvd2_7;                      /* 46  INT2.7 */
    PINT rsvd2_8;                      /* 47  INT2.8 */
};

extern struct PIE_VECT_TABLE PieVectTable;

#endif /* DSP2833x_PIE_VECT_H */
