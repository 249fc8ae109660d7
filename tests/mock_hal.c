/* mock_hal.c - cmocka mock of hal/hal.h for the firmware tests.
 * Every call but hal_cycles() is recorded with function_called(), so a
 * test states the exact order with expect_function_call();
 * hal_sample_read() returns the
 * sample queued with will_return(hal_sample_read, &sample) and
 * hal_trip_active() the value queued with will_return(hal_trip_active, b).
 * The last duties written are kept in mock_hal_duty for inspection;
 * hal_cycles() follows mock_hal_cycles (see mock_hal.h). */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include "hal.h"
#include "mock_hal.h"

float mock_hal_duty[3];
uint32_t mock_hal_cycles;
uint32_t mock_hal_cycles_step;

void hal_init(void)
{
    function_called();
}

void hal_isr_attach(hal_isr_fn isr)
{
    function_called();
    check_expected_ptr(isr);
}

void hal_sample_read(hal_sample_t *out)
{
    function_called();
    *out = *mock_ptr_type(const hal_sample_t *);
}

void hal_pwm_write(const float duty[3])
{
    function_called();
    for (int j = 0; j < 3; j++) {
        mock_hal_duty[j] = duty[j];
    }
}

void hal_pwm_enable(void)
{
    function_called();
}

void hal_pwm_disable(void)
{
    function_called();
}

bool hal_trip_active(void)
{
    function_called();
    return mock_type(int) != 0;
}

void hal_trip_clear(void)
{
    function_called();
}

void hal_isr_ack(void)
{
    function_called();
}

uint32_t hal_cycles(void)
{
    uint32_t now = mock_hal_cycles;
    mock_hal_cycles += mock_hal_cycles_step;
    return now;
}

void hal_watchdog_kick(void)
{
    function_called();
}
