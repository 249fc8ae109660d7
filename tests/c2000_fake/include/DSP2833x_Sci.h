/* DSP2833x_Sci.h - host stand-in: SCI registers (SPRUG03, section 2
 * "SCI Registers"; SciaRegs at 0x7050). */
#ifndef DSP2833x_SCI_H
#define DSP2833x_SCI_H

struct SCICCR_BITS {
    Uint16 SCICHAR:3;          /* 2:0 character length - 1 */
    Uint16 ADDRIDLE_MODE:1;    /* 3 */
    Uint16 LOOPBKENA:1;        /* 4 */
    Uint16 PARITYENA:1;        /* 5 */
    Uint16 PARITY:1;           /* 6 */
    Uint16 STOPBITS:1;         /* 7 */
    Uint16 rsvd1:8;            /* 15:8 */
};
union SCICCR_REG { Uint16 all; struct SCICCR_BITS bit; };

struct SCICTL1_BITS {
    Uint16 RXENA:1;            /* 0 */
    Uint16 TXENA:1;            /* 1 */
    Uint16 SLEEP:1;            /* 2 */
    Uint16 TXWAKE:1;           /* 3 */
    Uint16 rsvd:1;             /* 4 */
    Uint16 SWRESET:1;          /* 5  0 = held in reset */
    Uint16 RXERRINTENA:1;      /* 6 */
    Uint16 rsvd1:9;            /* 15:7 */
};
union SCICTL1_REG { Uint16 all; struct SCICTL1_BITS bit; };

struct SCICTL2_BITS {
    Uint16 TXINTENA:1;         /* 0 */
    Uint16 RXBKINTENA:1;       /* 1 */
    Uint16 rsvd:4;             /* 5:2 */
    Uint16 TXEMPTY:1;          /* 6 */
    Uint16 TXRDY:1;            /* 7 */
    Uint16 rsvd1:8;            /* 15:8 */
};
union SCICTL2_REG { Uint16 all; struct SCICTL2_BITS bit; };

struct SCIFFTX_BITS {
    Uint16 TXFFIL:5;           /* 4:0 */
    Uint16 TXFFIENA:1;         /* 5 */
    Uint16 TXFFINTCLR:1;       /* 6 */
    Uint16 TXFFINT:1;          /* 7 */
    Uint16 TXFFST:5;           /* 12:8 words in the transmit FIFO */
    Uint16 TXFIFOXRESET:1;     /* 13 */
    Uint16 SCIFFENA:1;         /* 14 */
    Uint16 SCIRST:1;           /* 15 */
};
union SCIFFTX_REG { Uint16 all; struct SCIFFTX_BITS bit; };

struct SCIFFCT_BITS {
    Uint16 FFTXDLY:8;          /* 7:0 delay between FIFO words, in baud clocks */
    Uint16 rsvd:5;             /* 12:8 */
    Uint16 CDC:1;              /* 13 */
    Uint16 ABDCLR:1;           /* 14 */
    Uint16 ABD:1;              /* 15 */
};
union SCIFFCT_REG { Uint16 all; struct SCIFFCT_BITS bit; };

struct SCI_REGS {                      /* word offset */
    union SCICCR_REG   SCICCR;         /* 0x0 */
    union SCICTL1_REG  SCICTL1;        /* 0x1 */
    Uint16             SCIHBAUD;       /* 0x2 BRR high byte */
    Uint16             SCILBAUD;       /* 0x3 BRR low byte */
    union SCICTL2_REG  SCICTL2;        /* 0x4 */
    Uint16             SCIRXST;        /* 0x5 (unused here) */
    Uint16             SCIRXEMU;       /* 0x6 */
    Uint16             SCIRXBUF;       /* 0x7 (unused here) */
    Uint16             rsvd1;          /* 0x8 */
    Uint16             SCITXBUF;       /* 0x9 */
    union SCIFFTX_REG  SCIFFTX;        /* 0xA */
    Uint16             SCIFFRX;        /* 0xB (unused here) */
    union SCIFFCT_REG  SCIFFCT;        /* 0xC */
    Uint16             rsvd2;          /* 0xD */
    Uint16             rsvd3;          /* 0xE */
    Uint16             SCIPRI;         /* 0xF (unused here) */
};

extern volatile struct SCI_REGS SciaRegs;

#endif /* DSP2833x_SCI_H */
