/*
 * flash_crc.h - the start-up check of the program image in flash against
 * the CRCs cl2000's linker records (crc_table() in f28335_flash.cmd).
 *
 * Algorithm CRC32_PRIME (ID 0 in TI's crc_tbl.h; SPRU513 "Linker-Generated
 * CRC Tables"): polynomial 0x04C11DB7, initial value 0, no reflection, no
 * final XOR, octets in address order and, in each 16-bit C28x word, the
 * low octet first (TI's VCU CRC routines called on a CRC_RECORD with
 * "even" parity and 2 x size octets). Check value: "123456789" gives
 * 0x89A1897F, the complement of CRC-32/POSIX's 0x765E7680 (the same
 * algorithm with a final XOR of 0xFFFFFFFF).
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

#define FLASH_CRC32_PRIME_ID 0u          /* crc_tbl.h CRC32_PRIME */
#define FLASH_CRC32_PRIME_POLY 0x04C11DB7UL

/* Words between watchdog services: the bitwise CRC takes an estimated
 * 200 cycles a word at most (16 shift/XOR steps of about 10 cycles, the
 * flash read's wait states), so a chunk is about 12800 cycles: 1.7 ms even at the 7.5 MHz SYSCLKOUT before
 * the PLL is set (OSCCLK / 4), under half the 4.37 ms timeout. */
#define FLASH_CRC_CHUNK_WORDS 64u

/* One octet (the low 8 bits of octet) into a CRC32_PRIME. Any context. */
uint32_t flash_crc32_prime_octet(uint32_t crc, uint16_t octet);

/* n_words 16-bit words, each low octet first, into a CRC32_PRIME. Any context. */
uint32_t flash_crc32_prime_words(uint32_t crc, const volatile uint16_t *words, uint32_t n_words);

/* Start-up, before interrupts: true when the n_words words at addr give
 * crc_expected by algorithm alg_id (a crc_tbl.h ID; only CRC32_PRIME is
 * known: any other gives false, an image the check cannot vouch for).
 * service() (the watchdog kick) is called before each chunk of
 * FLASH_CRC_CHUNK_WORDS words and once at the end. */
bool flash_crc_record_ok(uint16_t alg_id, const volatile uint16_t *addr, uint32_t n_words,
                         uint32_t crc_expected, void (*service)(void));

#endif /* FLASH_CRC_H */
