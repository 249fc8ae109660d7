/*
 * Flash2833x_API_Library.h - host stand-in for TI's F2833x flash API
 * header of the same name (the Flash2833x API, SPRC539; C2000Ware
 * libraries/flash_api/f2833x). Written from the API's documented
 * interface, not copied: the names the HAL calls (Flash_Erase,
 * Flash_Program, Flash_Verify), their status codes and sector masks, the
 * status structure and the two globals the caller provides
 * (Flash_CPUScaleFactor, Flash_CallbackPtr). The fake (flash_api_fake.c)
 * erases and programs a host array standing for the sector, calls the
 * callback during an erase as the API does between its pulses, and
 * records what a test checks (c2000_fake.h). On the target the real
 * header and Flash28335_API library replace it with no source change.
 */
#ifndef FLASH2833X_API_LIBRARY_H
#define FLASH2833X_API_LIBRARY_H

#include "DSP2833x_Device.h"

#define STATUS_SUCCESS 0
#define STATUS_FAIL_CSM_LOCKED 10
#define STATUS_FAIL_ADDR_INVALID 12
#define STATUS_FAIL_NO_SECTOR_SPECIFIED 20
#define STATUS_FAIL_ERASE 22
#define STATUS_FAIL_PROGRAM 30
#define STATUS_FAIL_ZERO_BIT_ERROR 31
#define STATUS_FAIL_VERIFY 40

#define SECTORA (Uint16)0x0001
#define SECTORB (Uint16)0x0002
#define SECTORC (Uint16)0x0004
#define SECTORD (Uint16)0x0008
#define SECTORE (Uint16)0x0010
#define SECTORF (Uint16)0x0020
#define SECTORG (Uint16)0x0040
#define SECTORH (Uint16)0x0080

typedef struct {
    Uint32 FirstFailAddr;
    Uint16 ExpectedData;
    Uint16 ActualData;
} FLASH_ST;

extern Uint16 Flash_Erase(Uint16 SectorMask, FLASH_ST *FEraseStat);
extern Uint16 Flash_Program(Uint16 *FlashAddr, Uint16 *BufAddr, Uint32 Length, FLASH_ST *FProgStatus);
extern Uint16 Flash_Verify(Uint16 *StartAddr, Uint16 *BufAddr, Uint32 Length, FLASH_ST *FVerifyStat);

/* Provided by the caller: the API's timing for SYSCLKOUT, and a function
 * it calls between its operations (flash unreadable meanwhile). */
extern Uint32 Flash_CPUScaleFactor;
extern void (*Flash_CallbackPtr)(void);

#endif /* FLASH2833X_API_LIBRARY_H */
