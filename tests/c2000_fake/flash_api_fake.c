/* flash_api_fake.c - the F2833x flash API on the host (Flash2833x_API_Library.h's
 * fake): sector B only, a program clears bits, an erase sets every word,
 * each call recorded in c2000_fake_flash (c2000_fake.h). */
#include <stddef.h>

#include "DSP2833x_Device.h"
#include "Flash2833x_API_Library.h"
#include "c2000_fake.h"

Uint16 c2000_fake_flash_b[C2000_FAKE_FLASH_B_WORDS];
c2000_fake_flash_t c2000_fake_flash;

/* The call recorded with the CPU's and the ePWMs' state during it; true
 * when a test asked this op to fail. */
static int record(c2000_fake_flash_op_t op, Uint16 mask, Uint32 off, Uint32 len)
{
    c2000_fake_flash_call_t *c = &c2000_fake_flash.call[c2000_fake_flash.n % C2000_FAKE_FLASH_CALLS_MAX];
    c2000_fake_flash.n++;
    c->op = op;
    c->sector_mask = mask;
    c->offset = off;
    c->length = len;
    c->ints_masked = c2000_fake_intm;
    c->pwm_forced_off = (Uint16)((EPwm1Regs.TZFRC.bit.OST != 0U) && (EPwm2Regs.TZFRC.bit.OST != 0U) &&
                                 (EPwm3Regs.TZFRC.bit.OST != 0U));
    c->scale_factor = Flash_CPUScaleFactor;
    c->callback_kicks = 0U;
    if (c2000_fake_flash.fail_next == (Uint16)op) {
        c2000_fake_flash.fail_next = 0U;
        return 1;
    }
    return 0;
}

/* A pointer into sector B as its word offset, or -1 outside it. */
static long offset_of(const Uint16 *p, Uint32 len)
{
    const ptrdiff_t d = p - c2000_fake_flash_b;
    return (d >= 0 && (Uint32)d + len <= C2000_FAKE_FLASH_B_WORDS) ? (long)d : -1;
}

/* A program's or verify's call recorded: its word offset in sector B (-1
 * outside it) and in *fail whether a test asked it to fail. */
static long range_call(c2000_fake_flash_op_t op, const Uint16 *p, Uint32 len, int *fail)
{
    const long off = offset_of(p, len);
    *fail = record(op, 0U, (off < 0) ? 0U : (Uint32)off, len);
    return off;
}

Uint16 Flash_Erase(Uint16 SectorMask, FLASH_ST *FEraseStat)
{
    c2000_fake_flash_call_t *c = &c2000_fake_flash.call[c2000_fake_flash.n % C2000_FAKE_FLASH_CALLS_MAX];
    const int fail = record(C2000_FAKE_ERASE, SectorMask, 0U, 0U);
    FEraseStat->FirstFailAddr = 0U;
    if (SectorMask == 0U) {
        return STATUS_FAIL_NO_SECTOR_SPECIFIED;
    }
    for (Uint16 k = 0U; k < c2000_fake_flash.callbacks_per_erase; k++) {
        if (Flash_CallbackPtr != NULL) {
            SysCtrlRegs.WDKEY = 0U;
            Flash_CallbackPtr();
            c->callback_kicks = (Uint16)(c->callback_kicks + ((SysCtrlRegs.WDKEY == 0x00AAU) ? 1U : 0U));
        }
    }
    if (fail) {
        return STATUS_FAIL_ERASE;
    }
    if ((SectorMask & SECTORB) != 0U) {
        for (Uint32 k = 0U; k < C2000_FAKE_FLASH_B_WORDS; k++) {
            c2000_fake_flash_b[k] = 0xFFFFU;
        }
    }
    return STATUS_SUCCESS;
}

Uint16 Flash_Program(Uint16 *FlashAddr, Uint16 *BufAddr, Uint32 Length, FLASH_ST *FProgStatus)
{
    int fail;
    const long off = range_call(C2000_FAKE_PROGRAM, FlashAddr, Length, &fail);
    if (off < 0) {
        return STATUS_FAIL_ADDR_INVALID;
    }
    if (fail) {
        FProgStatus->FirstFailAddr = (Uint32)off;
        return STATUS_FAIL_PROGRAM;
    }
    for (Uint32 k = 0U; k < Length; k++) {
        if ((BufAddr[k] & (Uint16)~c2000_fake_flash_b[off + k]) != 0U) {
            FProgStatus->FirstFailAddr = (Uint32)(off + (long)k);
            return STATUS_FAIL_ZERO_BIT_ERROR;   /* a 1 asked where the flash holds a 0: no erase */
        }
        c2000_fake_flash_b[off + k] &= BufAddr[k];
    }
    return STATUS_SUCCESS;
}

Uint16 Flash_Verify(Uint16 *StartAddr, Uint16 *BufAddr, Uint32 Length, FLASH_ST *FVerifyStat)
{
    int fail;
    const long off = range_call(C2000_FAKE_VERIFY, StartAddr, Length, &fail);
    if (off < 0) {
        return STATUS_FAIL_ADDR_INVALID;
    }
    for (Uint32 k = 0U; k < Length; k++) {
        if (fail || (c2000_fake_flash_b[off + k] != BufAddr[k])) {
            FVerifyStat->FirstFailAddr = (Uint32)(off + (long)k);
            FVerifyStat->ExpectedData = BufAddr[k];
            FVerifyStat->ActualData = c2000_fake_flash_b[off + k];
            return STATUS_FAIL_VERIFY;
        }
    }
    return STATUS_SUCCESS;
}
