/* flash_crc.c - the program image against its CRC records, in
 * watchdog-sized chunks; see flash_crc.h. Start-up code: runs from flash. */
#include "flash_crc.h"

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
        crc = crc32_prime_words(crc, &addr[done], n);
        done += n;
    }
    service();
    return crc == crc_expected;
}
