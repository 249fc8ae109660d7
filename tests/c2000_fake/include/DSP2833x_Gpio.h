/* DSP2833x_Gpio.h - host stand-in: GPIO control registers (SPRUFB0,
 * "GPIO MUX"; GpioCtrlRegs at 0x6F80). Only port A is modelled. */
#ifndef DSP2833x_GPIO_H
#define DSP2833x_GPIO_H

struct GPA1_BITS {             /* two bits per pin, GPIO0..15 */
    Uint16 GPIO0:2;  Uint16 GPIO1:2;  Uint16 GPIO2:2;  Uint16 GPIO3:2;
    Uint16 GPIO4:2;  Uint16 GPIO5:2;  Uint16 GPIO6:2;  Uint16 GPIO7:2;
    Uint16 GPIO8:2;  Uint16 GPIO9:2;  Uint16 GPIO10:2; Uint16 GPIO11:2;
    Uint16 GPIO12:2; Uint16 GPIO13:2; Uint16 GPIO14:2; Uint16 GPIO15:2;
};
union GPA1_REG { Uint32 all; struct GPA1_BITS bit; };

struct GPA2_BITS {             /* two bits per pin, GPIO16..31 */
    Uint16 GPIO16:2; Uint16 GPIO17:2; Uint16 GPIO18:2; Uint16 GPIO19:2;
    Uint16 GPIO20:2; Uint16 GPIO21:2; Uint16 GPIO22:2; Uint16 GPIO23:2;
    Uint16 GPIO24:2; Uint16 GPIO25:2; Uint16 GPIO26:2; Uint16 GPIO27:2;
    Uint16 GPIO28:2; Uint16 GPIO29:2; Uint16 GPIO30:2; Uint16 GPIO31:2;
};
union GPA2_REG { Uint32 all; struct GPA2_BITS bit; };

struct GPADAT_BITS {           /* one bit per pin, GPIO0..31 */
    Uint16 GPIO0:1;  Uint16 GPIO1:1;  Uint16 GPIO2:1;  Uint16 GPIO3:1;
    Uint16 GPIO4:1;  Uint16 GPIO5:1;  Uint16 GPIO6:1;  Uint16 GPIO7:1;
    Uint16 GPIO8:1;  Uint16 GPIO9:1;  Uint16 GPIO10:1; Uint16 GPIO11:1;
    Uint16 GPIO12:1; Uint16 GPIO13:1; Uint16 GPIO14:1; Uint16 GPIO15:1;
    Uint16 GPIO16:1; Uint16 GPIO17:1; Uint16 GPIO18:1; Uint16 GPIO19:1;
    Uint16 GPIO20:1; Uint16 GPIO21:1; Uint16 GPIO22:1; Uint16 GPIO23:1;
    Uint16 GPIO24:1; Uint16 GPIO25:1; Uint16 GPIO26:1; Uint16 GPIO27:1;
    Uint16 GPIO28:1; Uint16 GPIO29:1; Uint16 GPIO30:1; Uint16 GPIO31:1;
};
union GPADAT_REG { Uint32 all; struct GPADAT_BITS bit; };

struct GPIO_CTRL_REGS {                /* word offset */
    Uint32            GPACTRL;         /* 0x00 (unused here) */
    union GPA1_REG    GPAQSEL1;        /* 0x02 input qualification 0..15 */
    union GPA2_REG    GPAQSEL2;        /* 0x04 input qualification 16..31 */
    union GPA1_REG    GPAMUX1;         /* 0x06 pin function 0..15 */
    union GPA2_REG    GPAMUX2;         /* 0x08 pin function 16..31 */
    union GPADAT_REG  GPADIR;          /* 0x0A */
    union GPADAT_REG  GPAPUD;          /* 0x0C 1 = pull-up disabled */
};

extern volatile struct GPIO_CTRL_REGS GpioCtrlRegs;

#endif /* DSP2833x_GPIO_H */
