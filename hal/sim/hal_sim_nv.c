/* hal_sim_nv.c - hal.h's parameter sector on the simulated board: an
 * image of HAL_SIM_NV_WORDS words kept across runs in one process (a
 * board's flash outlives its power-off), with the flash's rules (an erase
 * sets every word to 0xFFFF, a program only clears bits and refuses to
 * set one, as TI's API does); see hal_sim.h. */
#include "hal_sim.h"

#include <stddef.h>

static uint16_t g_nv[HAL_SIM_NV_WORDS];
static bool g_nv_ready;              /* erased once, at the first use */
static hal_sim_nv_hook_t g_hook;
static void *g_hook_user;

uint16_t *hal_sim_nv_image(void)
{
    if (!g_nv_ready) {
        hal_sim_nv_erase();
    }
    return g_nv;
}

void hal_sim_nv_erase(void)
{
    for (uint32_t k = 0; k < HAL_SIM_NV_WORDS; k++) {
        g_nv[k] = 0xFFFFu;
    }
    g_nv_ready = true;
}

void hal_sim_nv_on_write(hal_sim_nv_hook_t hook, void *user)
{
    g_hook = hook;
    g_hook_user = user;
}

uint32_t hal_nv_words(void)
{
    return HAL_SIM_NV_WORDS;
}

static bool in_sector(uint32_t off, uint16_t n)
{
    return (off <= HAL_SIM_NV_WORDS) && ((uint32_t)n <= HAL_SIM_NV_WORDS - off);
}

bool hal_nv_read(uint32_t off, uint16_t *dst, uint16_t n)
{
    const uint16_t *img = hal_sim_nv_image();
    if (!in_sector(off, n)) {
        return false;
    }
    for (uint16_t k = 0; k < n; k++) {
        dst[k] = img[off + k];
    }
    return true;
}

bool hal_nv_write(uint32_t off, const uint16_t *src, uint16_t n, bool erase_first)
{
    uint16_t *img = hal_sim_nv_image();
    bool ok = in_sector(off, n);
    if (!ok) {
        return false;
    }
    hal_pwm_disable();   /* as the board's: the outputs off while the flash is written */
    if (erase_first) {
        hal_sim_nv_erase();
    }
    for (uint16_t k = 0; k < n && ok; k++) {
        ok = (src[k] & (uint16_t)~img[off + k]) == 0u;   /* a 1 where the flash holds a 0: no erase was asked */
        img[off + k] &= src[k];
    }
    if (g_hook != NULL && (erase_first || n > 0u)) {
        g_hook(g_hook_user);
    }
    return ok;
}
