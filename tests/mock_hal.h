/* mock_hal.h - what tests/mock_hal.c exposes besides hal.h. */
#ifndef MOCK_HAL_H
#define MOCK_HAL_H

#include <stdint.h>

/* The duties of the last hal_pwm_write() call. */
extern float mock_hal_duty[3];

/* hal_cycles() returns mock_hal_cycles, then adds mock_hal_cycles_step to
 * it (not recorded with function_called(): tests set the time instead). */
extern uint32_t mock_hal_cycles;
extern uint32_t mock_hal_cycles_step;

#endif /* MOCK_HAL_H */
