/*
 * crc32.h - CRC32_PRIME, the one CRC of the image's stored data: the
 * linker's records of the program sections (firmware/f28335/flash_crc.h)
 * and the parameter store's blocks (nv_store.h).
 *
 * Algorithm CRC32_PRIME (ID 0 in TI's crc_tbl.h; SPRU513 "Linker-Generated
 * CRC Tables"): polynomial 0x04C11DB7, initial value 0, no reflection, no
 * final XOR, octets in address order and, in each 16-bit C28x word, the
 * low octet first (TI's VCU CRC routines called on a CRC_RECORD with
 * "even" parity and 2 x size octets). Check value: "123456789" gives
 * 0x89A1897F, the complement of CRC-32/POSIX's 0x765E7680 (the same
 * algorithm with a final XOR of 0xFFFFFFFF). Bitwise: no table in flash
 * or RAM; start-up and background code only.
 */
#ifndef CRC32_H
#define CRC32_H

#include <stdint.h>

#define CRC32_PRIME_POLY 0x04C11DB7UL

/* One octet (the low 8 bits of octet) into a CRC32_PRIME. Any context. */
uint32_t crc32_prime_octet(uint32_t crc, uint16_t octet);

/* n_words 16-bit words, each low octet first, into a CRC32_PRIME. Any context. */
uint32_t crc32_prime_words(uint32_t crc, const volatile uint16_t *words, uint32_t n_words);

#endif /* CRC32_H */
