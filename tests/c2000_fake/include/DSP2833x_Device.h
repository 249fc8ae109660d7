/*
 * DSP2833x_Device.h - host stand-in for TI C2000Ware's header of the same
 * name (device_support/f2833x/headers/include). Written from the documented
 * register maps, not copied: same type, struct, union, field and object
 * names, same bit layouts and word offsets, only the registers the drive
 * uses. On the target the real header replaces it with no source change.
 *
 * Host data model: Uint16 = uint16_t, Uint32 = uint32_t; gcc allocates
 * uint16_t bit-fields LSB first in 16-bit units, as cl2000 does, so the
 * layouts match (tests/test_c2000_fake.c checks sizes and offsets).
 */
#ifndef DSP2833x_DEVICE_H
#define DSP2833x_DEVICE_H

#include <stdint.h>

typedef int16_t  int16;
typedef int32_t  int32;
typedef uint16_t Uint16;
typedef uint32_t Uint32;
typedef float    float32;

/* CPU core: on the C28x these are instructions and core registers.  On the
 * host they only record state, so tests can see e.g. that EALLOW was closed. */
extern volatile Uint16 c2000_fake_eallow;  /* 1 between EALLOW and EDIS */
extern volatile Uint16 c2000_fake_intm;    /* 1 = global interrupts masked */
extern volatile Uint16 IER;                /* CPU interrupt enable register */
extern volatile Uint16 IFR;                /* CPU interrupt flag register */
extern volatile Uint16 c2000_fake_estop0;  /* ESTOP0 instructions executed */

/* EDIS closes the protected-register window and then runs the test's EDIS
 * hook, if any (c2000_fake.h): every protected write sequence ends there,
 * so a test can check an invariant after each one. */
void c2000_fake_edis(void);

#define EALLOW (c2000_fake_eallow = 1U)
#define EDIS   c2000_fake_edis()
#define EINT   (c2000_fake_intm = 0U)
#define DINT   (c2000_fake_intm = 1U)
#define ERTM   ((void)0)
#define ESTOP0 (c2000_fake_estop0++)   /* emulation stop (breakpoint); a NOP without a debugger */

/* CPU interrupt lines (IER/IFR bits). */
#define M_INT1  0x0001U
#define M_INT2  0x0002U
#define M_INT3  0x0004U
#define M_INT9  0x0100U
#define M_INT13 0x1000U
#define M_INT14 0x2000U

/* PIEACK group bits. */
#define PIEACK_GROUP1  0x0001U
#define PIEACK_GROUP2  0x0002U
#define PIEACK_GROUP3  0x0004U
#define PIEACK_GROUP4  0x0008U
#define PIEACK_GROUP5  0x0010U
#define PIEACK_GROUP6  0x0020U
#define PIEACK_GROUP7  0x0040U
#define PIEACK_GROUP8  0x0080U
#define PIEACK_GROUP9  0x0100U
#define PIEACK_GROUP10 0x0200U
#define PIEACK_GROUP11 0x0400U
#define PIEACK_GROUP12 0x0800U

#include "DSP2833x_Adc.h"
#include "DSP2833x_CpuTimers.h"
#include "DSP2833x_EPwm.h"
#include "DSP2833x_EQep.h"
#include "DSP2833x_Gpio.h"
#include "DSP2833x_PieCtrl.h"
#include "DSP2833x_PieVect.h"
#include "DSP2833x_Sci.h"
#include "DSP2833x_SysCtrl.h"

#endif /* DSP2833x_DEVICE_H */
