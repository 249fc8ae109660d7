/* DSP2833x_PieCtrl.h - host stand-in: PIE control registers (SPRUFB0,
 * "Peripheral Interrupt Expansion (PIE)"; PieCtrlRegs at 0x0CE0). */
#ifndef DSP2833x_PIE_CTRL_H
#define DSP2833x_PIE_CTRL_H

struct PIECTRL_BITS {
    Uint16 ENPIE:1;            /* 0 */
    Uint16 PIEVECT:15;         /* 15:1 */
};
union PIECTRL_REG { Uint16 all; struct PIECTRL_BITS bit; };

struct PIEACK_BITS {
    Uint16 ACK1:1;  Uint16 ACK2:1;  Uint16 ACK3:1;  Uint16 ACK4:1;
    Uint16 ACK5:1;  Uint16 ACK6:1;  Uint16 ACK7:1;  Uint16 ACK8:1;
    Uint16 ACK9:1;  Uint16 ACK10:1; Uint16 ACK11:1; Uint16 ACK12:1;
    Uint16 rsvd:4;
};
union PIEACK_REG { Uint16 all; struct PIEACK_BITS bit; };

struct PIEIER_BITS {
    Uint16 INTx1:1; Uint16 INTx2:1; Uint16 INTx3:1; Uint16 INTx4:1;
    Uint16 INTx5:1; Uint16 INTx6:1; Uint16 INTx7:1; Uint16 INTx8:1;
    Uint16 rsvd:8;
};
union PIEIER_REG { Uint16 all; struct PIEIER_BITS bit; };

struct PIEIFR_BITS {
    Uint16 INTx1:1; Uint16 INTx2:1; Uint16 INTx3:1; Uint16 INTx4:1;
    Uint16 INTx5:1; Uint16 INTx6:1; Uint16 INTx7:1; Uint16 INTx8:1;
    Uint16 rsvd:8;
};
union PIEIFR_REG { Uint16 all; struct PIEIFR_BITS bit; };

struct PIE_CTRL_REGS {                 /* word offset */
    union PIECTRL_REG PIECTRL;         /* 0x00 */
    union PIEACK_REG  PIEACK;          /* 0x01 */
    union PIEIER_REG  PIEIER1;         /* 0x02 */
    union PIEIFR_REG  PIEIFR1;         /* 0x03 */
    union PIEIER_REG  PIEIER2;         /* 0x04 */
    union PIEIFR_REG  PIEIFR2;         /* 0x05 */
    union PIEIER_REG  PIEIER3;         /* 0x06 */
    union PIEIFR_REG  PIEIFR3;         /* 0x07 */
    union PIEIER_REG  PIEIER4;         /* 0x08 */
    union PIEIFR_REG  PIEIFR4;         /* 0x09 */
    union PIEIER_REG  PIEIER5;         /* 0x0A */
    union PIEIFR_REG  PIEIFR5;         /* 0x0B */
    union PIEIER_REG  PIEIER6;         /* 0x0C */
    union PIEIFR_REG  PIEIFR6;         /* 0x0D */
    union PIEIER_REG  PIEIER7;         /* 0x0E */
    union PIEIFR_REG  PIEIFR7;         /* 0x0F */
    union PIEIER_REG  PIEIER8;         /* 0x10 */
    union PIEIFR_REG  PIEIFR8;         /* 0x11 */
    union PIEIER_REG  PIEIER9;         /* 0x12 */
    union PIEIFR_REG  PIEIFR9;         /* 0x13 */
    union PIEIER_REG  PIEIER10;        /* 0x14 */
    union PIEIFR_REG  PIEIFR10;        /* 0x15 */
    union PIEIER_REG  PIEIER11;        /* 0x16 */
    union PIEIFR_REG  PIEIFR11;        /* 0x17 */
    union PIEIER_REG  PIEIER12;        /* 0x18 */
    union PIEIFR_REG  PIEIFR12;        /* 0x19 */
};

extern volatile struct PIE_CTRL_REGS PieCtrlRegs;

#endif /* DSP2833x_PIE_CTRL_H */
