/* mock_hal.h - what tests/mock_hal.c exposes besides hal.h. */
#ifndef MOCK_HAL_H
#define MOCK_HAL_H

/* The duties of the last hal_pwm_write() call. */
extern float mock_hal_duty[3];

#endif /* MOCK_HAL_H */
