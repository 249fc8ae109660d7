/* crc32.c - CRC32_PRIME, bitwise; see crc32.h. Start-up and background
 * code: runs from flash. */
#include "crc32.h"

#define OCTET_MASK 0x00FFu
#define OCTET_BITS 8u
#define CRC_TOP_SHIFT 24u
#define CRC_MSB 0x80000000UL

uint32_t crc32_prime_octet(uint32_t crc, uint16_t octet)
{
    uint16_t bit;

    crc ^= (uint32_t)(octet & OCTET_MASK) << CRC_TOP_SHIFT;
    for (bit = 0u; bit < OCTET_BITS; bit++) {
        crc = ((crc & CRC_MSB) != 0UL) ? ((crc << 1) ^ CRC32_PRIME_POLY) : (crc << 1);
    }
    return crc;
}

uint32_t crc32_prime_words(uint32_t crc, const volatile uint16_t *words, uint32_t n_words)
{
    uint32_t k;

    for (k = 0UL; k < n_words; k++) {
        const uint16_t w = words[k];
        crc = crc32_prime_octet(crc, (uint16_t)(w & OCTET_MASK));
        crc = crc32_prime_octet(crc, (uint16_t)(w >> OCTET_BITS));
    }
    return crc;
}
