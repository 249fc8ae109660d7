/* DSP2833x_CpuTimers.h - host stand-in: CPU timer registers (SPRUFB0,
 * "CPU Timers"; timer 0/1/2 at 0x0C00/0x0C08/0x0C10). */
#ifndef DSP2833x_CPU_TIMERS_H
#define DSP2833x_CPU_TIMERS_H

struct TIM_REG { Uint16 LSW; Uint16 MSW; };
union TIM_GROUP { Uint32 all; struct TIM_REG half; };

struct PRD_REG { Uint16 LSW; Uint16 MSW; };
union PRD_GROUP { Uint32 all; struct PRD_REG half; };

struct TCR_BITS {
    Uint16 rsvd1:4;            /* 3:0 */
    Uint16 TSS:1;              /* 4  1 = stop */
    Uint16 TRB:1;              /* 5  reload TIM from PRD */
    Uint16 rsvd2:4;            /* 9:6 */
    Uint16 SOFT:1;             /* 10 */
    Uint16 FREE:1;             /* 11 */
    Uint16 rsvd3:2;            /* 13:12 */
    Uint16 TIE:1;              /* 14 */
    Uint16 TIF:1;              /* 15 */
};
union TCR_REG { Uint16 all; struct TCR_BITS bit; };

struct TPR_BITS { Uint16 TDDR:8; Uint16 PSC:8; };
union TPR_REG { Uint16 all; struct TPR_BITS bit; };

struct TPRH_BITS { Uint16 TDDRH:8; Uint16 PSCH:8; };
union TPRH_REG { Uint16 all; struct TPRH_BITS bit; };

struct CPUTIMER_REGS {                 /* word offset */
    union TIM_GROUP  TIM;              /* 0 counter (counts down) */
    union PRD_GROUP  PRD;              /* 2 period */
    union TCR_REG    TCR;              /* 4 control */
    Uint16           rsvd1;            /* 5 */
    union TPR_REG    TPR;              /* 6 prescale low */
    union TPRH_REG   TPRH;             /* 7 prescale high */
};

extern volatile struct CPUTIMER_REGS CpuTimer2Regs;

#endif /* DSP2833x_CPU_TIMERS_H */
