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

struct SCIRXST_BITS {
    Uint16 rsvd:1;             /* 0 */
    Uint16 RXWAKE:1;           /* 1 */
    Uint16 PE:1;               /* 2 parity error */
    Uint16 OE:1;               /* 3 overrun error */
    Uint16 FE:1;               /* 4 framing error */
    Uint16 BRKDT:1;            /* 5 break detected */
    Uint16 RXRDY:1;            /* 6 */
    Uint16 RXERROR:1;          /* 7 any of BRKDT, FE, OE, PE */
    Uint16 rsvd1:8;            /* 15:8 */
};
union SCIRXST_REG { Uint16 all; struct SCIRXST_BITS bit; };

struct SCIRXBUF_BITS {
    Uint16 RXDT:8;             /* 7:0 received character */
    Uint16 rsvd:6;             /* 13:8 */
    Uint16 SCIFFPE:1;          /* 14 parity error of this FIFO word */
    Uint16 SCIFFFE:1;          /* 15 framing error of this FIFO word */
};
union SCIRXBUF_REG { Uint16 all; struct SCIRXBUF_BITS bit; };

struct SCIFFRX_BITS {
    Uint16 RXFFIL:5;           /* 4:0 interrupt level */
    Uint16 RXFFIENA:1;         /* 5 */
    Uint16 RXFFINTCLR:1;       /* 6 */
    Uint16 RXFFINT:1;          /* 7 */
    Uint16 RXFFST:5;           /* 12:8 words in the receive FIFO */
    Uint16 RXFIFORESET:1;      /* 13 0 = held in reset */
    Uint16 RXFFOVRCLR:1;       /* 14 write 1: clear RXFFOVF */
    Uint16 RXFFOVF:1;          /* 15 a word was lost: the FIFO was full */
};
union SCIFFRX_REG { Uint16 all; struct SCIFFRX_BITS bit; };

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
    union SCIRXST_REG  SCIRXST;        /* 0x5 */
    Uint16             SCIRXEMU;       /* 0x6 */
    union SCIRXBUF_REG SCIRXBUF;       /* 0x7 */
    Uint16             rsvd1;          /* 0x8 */
    Uint16             SCITXBUF;       /* 0x9 */
    union SCIFFTX_REG  SCIFFTX;        /* 0xA */
    union SCIFFRX_REG  SCIFFRX;        /* 0xB */
    union SCIFFCT_REG  SCIFFCT;        /* 0xC */
    Uint16             rsvd2;          /* 0xD */
    Uint16             rsvd3;          /* 0xE */
    Uint16             SCIPRI;         /* 0xF (unused here) */
};

extern volatile struct SCI_REGS SciaRegs;

#endif /* DSP2833x_SCI_H */
