/*
 * hal_f28335_timer.c - CPU timer 2 as a free-running SYSCLKOUT cycle
 * counter (hal_cycles) and the control-ISR timing record. Reference:
 * SPRUFB0 "CPU Timers" (TIM counts down from PRD at SYSCLKOUT / (TDDR+1)).
 *
 * PRD = 0xFFFFFFFF and prescale /1: TIM runs 0xFFFFFFFF -> 0 and reloads,
 * a period of exactly 2^32 cycles, so 0xFFFFFFFF - TIM counts up and
 * differences of hal_cycles() are right modulo 2^32 (28.6 s at 150 MHz).
 */
#include "DSP2833x_Device.h"
#include "hal.h"
#include "hal_f28335.h"
#include "hal_f28335_internal.h"

#define TIMER_PRD_FREE_RUN 0xFFFFFFFFUL
#define TIMING_MIN_NONE    0xFFFFFFFFUL

volatile hal_f28335_isr_timing_t hal_f28335_isr_timing = { 0U, TIMING_MIN_NONE, 0U, 0U };

static uint32_t s_isr_start;

void f28335_timer_init(void)
{
    CpuTimer2Regs.TCR.bit.TSS = 1U;
    CpuTimer2Regs.PRD.all = TIMER_PRD_FREE_RUN;
    CpuTimer2Regs.TPR.all = 0U;   /* prescale /1 */
    CpuTimer2Regs.TPRH.all = 0U;
    CpuTimer2Regs.TCR.bit.TIE = 0U;
    CpuTimer2Regs.TCR.bit.FREE = 0U;  /* stop on an emulation halt: times stay CPU times */
    CpuTimer2Regs.TCR.bit.SOFT = 0U;
    CpuTimer2Regs.TCR.bit.TRB = 1U;   /* TIM = PRD */
    CpuTimer2Regs.TCR.bit.TSS = 0U;
    hal_f28335_isr_timing_reset();
}

RAMFUNC uint32_t hal_cycles(void)
{
    return TIMER_PRD_FREE_RUN - CpuTimer2Regs.TIM.all;
}

RAMFUNC void hal_f28335_isr_timing_begin(void)
{
    s_isr_start = hal_cycles();
}

RAMFUNC void hal_f28335_isr_timing_end(void)
{
    const uint32_t dt = hal_cycles() - s_isr_start;

    hal_f28335_isr_timing.last_cycles = dt;
    if (dt < hal_f28335_isr_timing.min_cycles) {
        hal_f28335_isr_timing.min_cycles = dt;
    }
    if (dt > hal_f28335_isr_timing.max_cycles) {
        hal_f28335_isr_timing.max_cycles = dt;
    }
    hal_f28335_isr_timing.count++;
}

void hal_f28335_isr_timing_reset(void)
{
    hal_f28335_isr_timing.last_cycles = 0U;
    hal_f28335_isr_timing.min_cycles = TIMING_MIN_NONE;
    hal_f28335_isr_timing.max_cycles = 0U;
    hal_f28335_isr_timing.count = 0U;
}
