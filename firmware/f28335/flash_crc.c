/* flash_crc.c - CRC32_PRIME over the program image, in watchdog-sized
 * chunks; see flash_crc.h. Start-up code: runs from flash. */
#include "flash_crc.h"

#define OCTET_MASK 0x00FFu
#define OCTET_BITS 8u
#define CRC_TOP_SHIFT 24u
#define CRC_MSB 0x80000000UL

uint32_t flash_crc32_prime_octet(uint32_t crc, uint16_t octet)
{
    uint16_t bit;

    crc ^= (uint32_t)(octet & OCTET_MASK) << CRC_TOP_SHIFT;
    for (bit = 0u; bit < OCTET_BITS; bit++) {
        crc = ((crc & CRC_MSB) != 0UL) ? ((crc << 1) ^ FLASH_CRC32_PRIME_POLY) : (crc << 1);
    }
    return crc;
}

uint32_t flash_crc32_prime_words(uint32_t crc, const volatile uint16_t *words, uint32_t n_words)
{
    uint32_t k;

    for (k = 0UL; k < n_words; k++) {
        const uint16_t w = words[k];
        crc = flash_crc32_prime_octet(crc, (uint16_t)(w & OCTET_MASK));
        crc = flash_crc32_prime_octet(crc, (uint16_t)(w >> OCTET_BITS));
    }
    return crc;
}

bool flash_crc_record_ok(uint16_t alg_id, const volatile uint16_t *addr, uint32_t n_words,
                         uint32_t crc_expected, void (*service)(void))
{
    uint32_t crc = 0UL;
    uint32_t done = 0UL;

    if (alg_id != FLASH_CRC32_PRIME_ID) {
        return false;
    }
    while (done < n_words) {
        const uint32_t left = n_words - done;
        const uint32_t n = (left < FLASH_CRC_CHUNK_WORDS) ? left : FLASH_CRC_CHUNK_WORDS;
        service();
        crc = flash_crc32_prime_words(crc, &addr[done], n);
        done += n;
    }
    service();
    return crc == crc_expected;
}
