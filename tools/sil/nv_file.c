/* nv_file.c - drive_sil --nv FILE; see nv_file.h. */
#include "nv_file.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "hal.h"
#include "hal_sim.h"
#include "link_nv.h"

#define NV_FILE_BYTES (2u * HAL_SIM_NV_WORDS)
#define OCTET 8u
#define OCTET_MASK 0xFFu
#define PATH_LEN 4096

static const char *g_path;
static int g_failed;

/* The sector into path (a temporary renamed over it); 0, or -1 with err. */
static int write_image(const char *path, char *err, size_t errlen)
{
    static unsigned char bytes[NV_FILE_BYTES];
    char tmp[PATH_LEN];
    const uint16_t *img = hal_sim_nv_image();
    for (uint32_t k = 0; k < HAL_SIM_NV_WORDS; k++) {
        bytes[2u * k] = (unsigned char)(img[k] & OCTET_MASK);
        bytes[2u * k + 1u] = (unsigned char)(img[k] >> OCTET);
    }
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (f == NULL || fwrite(bytes, 1, sizeof bytes, f) != sizeof bytes || fclose(f) != 0 || rename(tmp, path) != 0) {
        snprintf(err, errlen, "--nv %s: cannot write: %s", path, strerror(errno));
        (void)remove(tmp);
        return -1;
    }
    return 0;
}

static void on_write(void *user)
{
    char err[PATH_LEN];
    (void)user;
    if (write_image(g_path, err, sizeof err) != 0) {
        fprintf(stderr, "drive_sil: %s\n", err);
        g_failed = 1;
    }
}

int nv_file_open(const char *path, char *err, size_t errlen)
{
    static unsigned char bytes[NV_FILE_BYTES + 1u];
    uint16_t *img = hal_sim_nv_image();
    FILE *f = fopen(path, "rb");
    g_path = path;
    if (f == NULL) {
        if (errno != ENOENT) {
            snprintf(err, errlen, "--nv %s: cannot read: %s", path, strerror(errno));
            return -1;
        }
        hal_sim_nv_erase();   /* no file: a sector nothing was saved in */
        if (write_image(path, err, errlen) != 0) {
            return -1;
        }
    } else {
        const size_t n = fread(bytes, 1, sizeof bytes, f);
        fclose(f);
        if (n != NV_FILE_BYTES) {
            snprintf(err, errlen, "--nv %s: not a parameter sector's image: %zu bytes, a sector is %u (%u words)",
                     path, n, (unsigned)NV_FILE_BYTES, (unsigned)HAL_SIM_NV_WORDS);
            return -1;
        }
        for (uint32_t k = 0; k < HAL_SIM_NV_WORDS; k++) {
            img[k] = (uint16_t)(bytes[2u * k] | ((unsigned)bytes[2u * k + 1u] << OCTET));
        }
    }
    hal_sim_nv_on_write(on_write, NULL);
    return 0;
}

nv_status_t nv_file_apply(scenario_t *sc, const char *path, char *msg, size_t len)
{
    static scenario_t copy;
    static const nv_dev_t DEV = { HAL_SIM_NV_WORDS, hal_nv_read, hal_nv_write };
    static uint16_t buf[NV_BLOCK_WORDS_MAX];
    uint16_t n = 0;
    char where[SCENARIO_ORIGIN_LEN];
    char err[SCENARIO_ERR_LEN];
    const nv_status_t st = nv_load(&DEV, nv_params_table_id(&LINK_NV_PARAMS), buf, &n);
    if (st == NV_EMPTY) {
        snprintf(msg, len, "--nv %s: NV_EMPTY: nothing saved; the scenario's values", path);
        return st;
    }
    if (st != NV_OK) {
        snprintf(msg, len, "--nv %s: NV_INVALID: the sector holds no valid block of this drive's parameter table "
                 "(a header, its CRC, the table it was saved with, or the words after it: "
                 "firmware/params/nv_store.h); the scenario's values", path);
        return NV_INVALID;
    }
    const uint16_t bad = nv_params_refused(&LINK_NV_PARAMS, buf, n);
    if (bad < n) {   /* as nv_params_read refuses it, named */
        const nv_pair_t pair = nv_block_get(buf, bad);
        const uint16_t k = nv_params_of(&LINK_NV_PARAMS, buf, bad);
        if (k == NV_PARAMS_NOT_LISTED) {
            snprintf(msg, len, "--nv %s: NV_INVALID: the saved block names parameter 0x%04X, which is no parameter "
                     "of the link's table; the scenario's values", path, (unsigned)pair.id);
        } else {
            snprintf(msg, len, "--nv %s: NV_INVALID: the saved %s = %.9g is outside its bounds; the scenario's "
                     "values", path, LINK_NV_PARAMS.key(k), (double)pair.value);
        }
        return NV_INVALID;
    }
    copy = *sc;
    snprintf(where, sizeof where, "--nv %s", path);
    int used = snprintf(msg, len, "--nv %s: loaded %u parameters:", path, (unsigned)n);
    for (uint16_t j = 0; j < n; j++) {
        const char *key = LINK_NV_PARAMS.key(nv_params_of(&LINK_NV_PARAMS, buf, j));
        const float v = nv_block_get(buf, j).value;
        char set[SCENARIO_ORIGIN_LEN];
        snprintf(set, sizeof set, "controller.%s=%.9g", key, (double)v);
        if (scenario_set_from(&copy, set, where, err, sizeof err) != 0) {
            snprintf(msg, len, "NV_INVALID: %s; the scenario's values", err);
            return NV_INVALID;
        }
        if (used > 0 && (size_t)used < len) {
            used += snprintf(msg + used, len - (size_t)used, " %s=%.9g", key, (double)v);
        }
    }
    *sc = copy;
    return NV_OK;
}

int nv_file_failed(void)
{
    return g_failed;
}
