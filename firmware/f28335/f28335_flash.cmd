/*
 * f28335_flash.cmd - memory map and section placement of the drive image
 * for the TMS320F28335, running from flash (boot mode "jump to flash").
 * Linked together with C2000Ware's DSP2833x_Headers_nonBIOS.cmd, which
 * places the peripheral register structures. COFF ABI (C symbols carry a
 * leading underscore here). Addresses: SPRS439 "Memory Maps" (F28335),
 * boot ROM layout: SPRU963 / the F2833x boot ROM map.
 *
 * PAGE 0 = program space, PAGE 1 = data space. On the F28335 the SARAM
 * blocks are unified (one physical memory seen on both pages), so a block
 * is listed on one page only.
 */

MEMORY
{
PAGE 0 :
   /* L0-L5 for ramfuncs but L5's last 0x80 words, which .ebss takes
    * (RAML5L7): the RAM code left L0-L5 about 3K words free once the blocks'
    * set-up ran from flash, .ebss had under 10 % of L6-L7 (the current
    * offsets' state, control/observer_log.md 2026-12-02). The L-blocks are
    * alike (zero-wait SARAM, L4-L7 outside the CSM's secure zone), so the
    * boundary is the map's; .ebss stays 64-word aligned (its pages). What
    * each RAM range holds and its margin: `make check`
    * (tools/check/ram_budget.py, from drive.map once there is one), which
    * fails under 10 % free; it reads the lengths below. */
   RAML0L5    : origin = 0x008000, length = 0x005F80   /* L0-L5 SARAM less L5's last 0x80 words: run address of ramfuncs */
   FLASHHC    : origin = 0x300000, length = 0x030000   /* flash sectors H..C, 32K words each: the image */
   /* Flash sector B, the parameter store's (hal/f28335/hal_f28335_nv.c,
    * hal_f28335_cfg.h F28335_NV_SECTOR_*): nothing is placed here, so no
    * CRC record covers it and an image leaves it alone. */
   FLASHB_NV  : origin = 0x330000, length = 0x008000
   FLASHA     : origin = 0x338000, length = 0x007F80   /* flash sector A, up to the CSM reserved words */
   CSM_RSVD   : origin = 0x33FF80, length = 0x000076   /* must be 0x0000 when the CSM is used */
   BEGIN      : origin = 0x33FFF6, length = 0x000002   /* boot ROM "jump to flash" entry */
   CSM_PWL    : origin = 0x33FFF8, length = 0x000008   /* code security passwords */
   ADC_CAL    : origin = 0x380080, length = 0x000009   /* ADC_cal in TI-reserved OTP (factory trims) */
   FPUTABLES  : origin = 0x3FEBDC, length = 0x0006A0   /* boot ROM FPU math tables (FPUfastRTS) */
   RESET      : origin = 0x3FFFC0, length = 0x000002   /* reset vector, in boot ROM */

PAGE 1 :
   BOOT_RSVD  : origin = 0x000000, length = 0x000050   /* M0 part used by the boot ROM stack */
   RAMM0      : origin = 0x000050, length = 0x0003B0   /* M0 SARAM */
   RAMM1      : origin = 0x000400, length = 0x000400   /* M1 SARAM: the stack */
   RAML5L7    : origin = 0x00DF80, length = 0x002080   /* L5's last 0x80 words and L6-L7 SARAM: .ebss */
}

SECTIONS
{
   /* Boot: the boot ROM jumps to BEGIN, where f28335_codestart.asm turns
    * the watchdog off, zeroes .ebss and branches to _c_int00. */
   codestart     : > BEGIN,     PAGE = 0, crc_table(_flash_crc_table, algorithm = CRC32_PRIME)

   /* Code and constants in flash. The program sections carry CRC records
    * (CRC32_PRIME, firmware/f28335/flash_crc.h) in the table flash_crc_table,
    * which main.c checks at start-up; the table itself in .TI.crctab.
    * .cinit and .pinit (built by the linker) are not covered. */
   .text         : > FLASHHC,   PAGE = 0, crc_table(_flash_crc_table, algorithm = CRC32_PRIME)
   .cinit        : > FLASHA,    PAGE = 0
   .pinit        : > FLASHA,    PAGE = 0
   .econst       : > FLASHHC,   PAGE = 0, crc_table(_flash_crc_table, algorithm = CRC32_PRIME)
   .switch       : > FLASHA,    PAGE = 0, crc_table(_flash_crc_table, algorithm = CRC32_PRIME)
   .TI.crctab    : > FLASHA,    PAGE = 0

   /* Code that runs from RAM: the control ISR path (RAMFUNC functions and
    * control/, --ramfunc=on: .TI.ramfunc; FPUfastRTS members) and the flash
    * wait-state set-up; last, the parameter store's writer (nvfuncs:
    * hal_f28335_nv.c's hal_nv_write and its callback). Stored in flash,
    * copied to L0-L5 by hal_init() (hal_f28335_sysctrl.c). The members are
    * named in the COFF library that holds the objects (firmware/f28335/
    * target.mk links the same library).
    * TI's flash API (Flash28_API: the Flash2833x API library's code and
    * constants) must run from RAM too, but only while the writer runs, with
    * every interrupt held off: it runs over the start of ramfuncs (a UNION:
    * the same run address), copied there by hal_nv_write and ramfuncs' start
    * copied back after it. Its 1.5K words end far before nvfuncs, which the
    * API must not overwrite (tools/check/ram_budget.py checks it), and lie
    * in L0, inside the code security module's secure zone, where the API
    * runs on a secured device. */
   UNION run = RAML0L5, PAGE = 0
   {
      ramfuncs    : {
                       *(ramfuncs)
                       *(.TI.ramfunc)
                       rts2800_fpu32_fast_supplement_coff.lib<sincos_f32.obj>(.text)
                       rts2800_fpu32_fast_supplement_coff.lib<atan2_f32.obj>(.text)
                       rts2800_fpu32_fast_supplement_coff.lib<sqrt_f32.obj>(.text)
                       rts2800_fpu32_fast_supplement_coff.lib<div_f32.obj>(.text)
                       *(nvfuncs)
                    }
                    LOAD = FLASHHC, PAGE = 0,
                    LOAD_START(_RamfuncsLoadStart),
                    LOAD_SIZE(_RamfuncsLoadSize),
                    RUN_START(_RamfuncsRunStart),
                    crc_table(_flash_crc_table, algorithm = CRC32_PRIME)
      Flash28_API : {
                       Flash28335_API_V210.lib(.econst)
                       Flash28335_API_V210.lib(.text)
                    }
                    LOAD = FLASHHC, PAGE = 0,
                    LOAD_START(_Flash28_API_LoadStart),
                    LOAD_END(_Flash28_API_LoadEnd),
                    RUN_START(_Flash28_API_RunStart),
                    crc_table(_flash_crc_table, algorithm = CRC32_PRIME)
   }

   csmpasswds    : > CSM_PWL,   PAGE = 0
   csm_rsvd      : > CSM_RSVD,  PAGE = 0

   /* Data. */
   .stack        : > RAMM1,     PAGE = 1
   /* .ebss: zeroed by f28335_codestart.asm before _c_int00 (COFF zeroes nothing). */
   .ebss         : > RAML5L7,   PAGE = 1,
                   RUN_START(_EbssRunStart),
                   RUN_SIZE(_EbssRunSize)
   .esysmem      : > RAMM0,     PAGE = 1
   /* Objects placed here (DATA_SECTION): main.c's commissioning state and
    * command blocks, the flash API's two globals (hal_f28335_nv.c), in M0,
    * which .esysmem leaves free; each is set whole before it is read (not
    * zeroed: only .ebss is). */
   m0data        : > RAMM0,     PAGE = 1

   /* Tables already in boot ROM: referenced, never loaded. */
   FPUmathTables : > FPUTABLES, PAGE = 0, TYPE = NOLOAD

   /* ADC_cal is factory code in OTP: referenced (hal_f28335_adc.c calls it
    * as TI's InitAdc does), never loaded. */
   .adc_cal      : load = ADC_CAL, PAGE = 0, TYPE = NOLOAD

   /* The reset vector lives in boot ROM; keep the RTS one out of the image. */
   .reset        : > RESET,     PAGE = 0, TYPE = DSECT
}
