/*
 * flash_crc.h - the start-up check of the program image in flash against
 * the CRCs cl2000's linker records (crc_table() in f28335_flash.cmd).
 *
 * Algorithm CRC32_PRIME (firmware/params/crc32.h: the linker's ID 0 in
 * TI's crc_tbl.h, its definition and check value).
 *
 * The check runs before interrupts, in chunks of FLASH_CRC_CHUNK_WORDS
 * with the watchdog serviced between them, so that it holds at the
 * watchdog's shortest timeout (the reset prescaler: 512 x 256 OSCCLK
 * cycles at 30 MHz = 4.37 ms) whether or not start-up has the watchdog
 * running.
 */
#ifndef FLASH_CRC_H
#define FLASH_CRC_H

#include <stdbool.h>
#include <stdint.h>

#include "crc32.h"

#define FLASH_CRC32_PRIME_ID 0u          /* crc_tbl.h CRC32_PRIME */

/* Words between watchdog services: the bitwise CRC takes an estimated
 * 200 cycles a word at most (16 shift/XOR steps of about 10 cycles, the
 * flash read's wait states), so a chunk is about 12800 cycles: 1.7 ms even at the 7.5 MHz SYSCLKOUT before
 * the PLL is set (OSCCLK / 4), under half the 4.37 ms timeout. */
#define FLASH_CRC_CHUNK_WORDS 64u

/* Start-up, before interrupts: true when the n_words words at addr give
 * crc_expected by algorithm alg_id (a crc_tbl.h ID; only CRC32_PRIME is
 * known: any other gives false, an image the check cannot vouch for).
 * service() (the watchdog kick) is called before each chunk of
 * FLASH_CRC_CHUNK_WORDS words and once at the end. */
bool flash_crc_record_ok(uint16_t alg_id, const volatile uint16_t *addr, uint32_t n_words,
                         uint32_t crc_expected, void (*service)(void));

#endif /* FLASH_CRC_H */
