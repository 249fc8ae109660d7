/*
 * hal_f28335_nv.c - hal.h's parameter sector on the F28335: flash sector B
 * (F28335_NV_SECTOR_*, reserved in firmware/f28335/f28335_flash.cmd), read
 * as memory and written through TI's Flash2833x API (SPRC539; C2000Ware
 * libraries/flash_api/f2833x) by its documented names: Flash_Erase,
 * Flash_Program and Flash_Verify, with the two globals the caller
 * provides, Flash_CPUScaleFactor (TI's SCALE_FACTOR for this SYSCLKOUT,
 * F28335_FLASH_API_SCALE) and Flash_CallbackPtr (here: the watchdog
 * serviced between the API's erase pulses; its reset timeout is 35 ms).
 *
 * The API must run from RAM, and while it erases or programs no code may
 * read the flash. Its section Flash28_API is stored in flash and run, for
 * a write only, over the start of ramfuncs (a UNION in f28335_flash.cmd:
 * about 1.5K words the control ISR's code holds the rest of the time, not
 * needed while every interrupt is held off), then that start is copied
 * back from flash. This file's writer and callback run from RAM where
 * the API does not reach (section nvfuncs, the end of ramfuncs). The order
 * of a write: the outputs forced off (hal_pwm_disable, RAM code still in
 * place), every interrupt held off, the API copied in, erase, program,
 * verify, ramfuncs' start copied back, interrupts on again. On the host
 * the API is the register fake's (tests/c2000_fake/flash_api_fake.c) and
 * the sector an array; the copies are the target's only.
 */
#include <stddef.h>

#include "DSP2833x_Device.h"
#include "Flash2833x_API_Library.h"
#include "hal.h"
#include "hal_f28335.h"
#include "hal_f28335_cfg.h"
#include "hal_f28335_internal.h"

#if defined(__TMS320C28XX__)
#include <string.h>
/* firmware/f28335/f28335_flash.cmd: the API's load image, its run address
 * (ramfuncs' start), and ramfuncs' load image. */
extern Uint16 Flash28_API_LoadStart;
extern Uint16 Flash28_API_LoadEnd;
extern Uint16 Flash28_API_RunStart;
extern Uint16 RamfuncsLoadStart;
extern Uint16 RamfuncsRunStart;
#define NV_SECTOR ((volatile Uint16 *)F28335_NV_SECTOR_ADDR)
#pragma CODE_SECTION(hal_nv_write, "nvfuncs")
#pragma CODE_SECTION(nv_api_callback, "nvfuncs")
#else
#include "c2000_fake.h"
#define NV_SECTOR ((volatile Uint16 *)c2000_fake_flash_b)
#endif

F28335_STATIC_ASSERT(nv_sector_is_the_fakes, F28335_NV_SECTOR_WORDS == 0x8000UL);

/* The API's globals, defined by its caller (Flash2833x_API_Library.h); in
 * M0 with the other objects .ebss (RAML5L7) keeps its margin without, set
 * before every use (nothing zeroes M0). */
#if defined(__TMS320C28XX__)
#pragma DATA_SECTION(Flash_CPUScaleFactor, "m0data")
#pragma DATA_SECTION(Flash_CallbackPtr, "m0data")
#endif
Uint32 Flash_CPUScaleFactor;
void (*Flash_CallbackPtr)(void);

uint32_t hal_nv_words(void)
{
    return F28335_NV_SECTOR_WORDS;
}

/* off .. off + n within the sector, without an overflow. */
static bool in_sector(uint32_t off, uint16_t n)
{
    return (off <= F28335_NV_SECTOR_WORDS) && ((uint32_t)n <= F28335_NV_SECTOR_WORDS - off);
}

bool hal_nv_read(uint32_t off, uint16_t *dst, uint16_t n)
{
    uint16_t k;

    if (!in_sector(off, n)) {
        return false;
    }
    for (k = 0U; k < n; k++) {
        dst[k] = NV_SECTOR[off + k];
    }
    return true;
}

/* Flash_CallbackPtr: the watchdog's key sequence, written here (RAM):
 * hal_watchdog_kick is flash code, unreadable while the API works. */
static void nv_api_callback(void)
{
    EALLOW;
    SysCtrlRegs.WDKEY = F28335_WDKEY_1;
    SysCtrlRegs.WDKEY = F28335_WDKEY_2;
    EDIS;
}

bool hal_nv_write(uint32_t off, const uint16_t *src, uint16_t n, bool erase_first)
{
    FLASH_ST st;
    bool ok = in_sector(off, n);

    if (!ok) {
        return false;
    }
    hal_pwm_disable();   /* RAM code, still in place: both gates of every leg low */
    DINT;
#if defined(__TMS320C28XX__)
    memcpy(&Flash28_API_RunStart, &Flash28_API_LoadStart, (size_t)(&Flash28_API_LoadEnd - &Flash28_API_LoadStart));
#endif
    Flash_CPUScaleFactor = F28335_FLASH_API_SCALE;
    Flash_CallbackPtr = &nv_api_callback;
    if (erase_first) {
        ok = (Flash_Erase(SECTORB, &st) == STATUS_SUCCESS);
    }
    if (ok) {
        ok = (Flash_Program((Uint16 *)&NV_SECTOR[off], (Uint16 *)src, (Uint32)n, &st) == STATUS_SUCCESS);
    }
    if (ok) {
        ok = (Flash_Verify((Uint16 *)&NV_SECTOR[off], (Uint16 *)src, (Uint32)n, &st) == STATUS_SUCCESS);
    }
    Flash_CallbackPtr = NULL;
#if defined(__TMS320C28XX__)
    /* the ISR's code back where the API ran (the flash readable again) */
    memcpy(&RamfuncsRunStart, &RamfuncsLoadStart, (size_t)(&Flash28_API_LoadEnd - &Flash28_API_LoadStart));
#endif
    EINT;
    return ok;
}
