/*
 * drive_sil.c - the SIL runner program:
 *   drive_sil --scenario FILE [--set section.key=value ...] --out FILE.csv
 * Runs the firmware application on the simulated board (sil.h) and writes
 * one CSV row per logged period. Bad input (scenario, override, flag,
 * output path) prints a message naming file, line and key, exits 2 and
 * leaves no CSV: rows go to FILE.csv.tmp.PID, renamed at the end.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scenario.h"
#include "sil.h"

#define EXIT_BAD_INPUT 2
#define MAX_SETS 64
#define TMP_SUFFIX_LEN 32

static void usage(FILE *f)
{
    fprintf(f,
            "usage: drive_sil --scenario FILE [--set section.key=value ...] --out FILE.csv\n"
            "       drive_sil --help\n"
            "Runs the drive firmware on the simulated board for one scenario (INI)\n"
            "and writes the CSV trace. Every key is optional (defaults: paper Table I).\n"
            "Profiles: \"t:value, t:value\" steps; \"t:value~\" ramps to value at t.\n"
            "Keys (section, name, default, meaning):\n");
    scenario_print_keys(f);
    fprintf(f, "See hal/sim/README.md for the CSV columns.\n");
}

static int write_row(const sil_row_t *row, void *user)
{
    FILE *f = user;
    sil_csv_row(f, row);
    return ferror(f) ? 1 : 0;
}

int main(int argc, char **argv)
{
    const char *scenario_path = NULL;
    const char *out_path = NULL;
    const char *sets[MAX_SETS];
    int n_sets = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            return EXIT_SUCCESS;
        }
        if ((strcmp(a, "--scenario") == 0 || strcmp(a, "--out") == 0 || strcmp(a, "--set") == 0) &&
            i + 1 >= argc) {
            fprintf(stderr, "drive_sil: %s needs a value\n", a);
            return EXIT_BAD_INPUT;
        }
        if (strcmp(a, "--scenario") == 0) {
            scenario_path = argv[++i];
        } else if (strcmp(a, "--out") == 0) {
            out_path = argv[++i];
        } else if (strcmp(a, "--set") == 0) {
            if (n_sets >= MAX_SETS) {
                fprintf(stderr, "drive_sil: more than %d --set\n", MAX_SETS);
                return EXIT_BAD_INPUT;
            }
            sets[n_sets++] = argv[++i];
        } else {
            fprintf(stderr, "drive_sil: unknown argument \"%s\" (see --help)\n", a);
            return EXIT_BAD_INPUT;
        }
    }
    if (scenario_path == NULL || out_path == NULL) {
        fprintf(stderr, "drive_sil: --scenario and --out are required (see --help)\n");
        return EXIT_BAD_INPUT;
    }

    static scenario_t sc;
    char err[SCENARIO_ERR_LEN];
    scenario_defaults(&sc);
    if (scenario_load(&sc, scenario_path, err, sizeof err) != 0) {
        fprintf(stderr, "drive_sil: %s\n", err);
        return EXIT_BAD_INPUT;
    }
    for (int i = 0; i < n_sets; i++) {
        if (scenario_set(&sc, sets[i], err, sizeof err) != 0) {
            fprintf(stderr, "drive_sil: %s\n", err);
            return EXIT_BAD_INPUT;
        }
    }
    if (scenario_finish(&sc, err, sizeof err) != 0) {
        fprintf(stderr, "drive_sil: %s\n", err);
        return EXIT_BAD_INPUT;
    }

    size_t tmp_len = strlen(out_path) + TMP_SUFFIX_LEN;
    char *tmp_path = malloc(tmp_len);
    if (tmp_path == NULL) {
        fprintf(stderr, "drive_sil: out of memory\n");
        return EXIT_FAILURE;
    }
    snprintf(tmp_path, tmp_len, "%s.tmp.%ld", out_path, (long)getpid());
    FILE *f = fopen(tmp_path, "w");
    if (f == NULL) {
        fprintf(stderr, "drive_sil: --out %s: cannot write: ", out_path);
        perror(NULL);
        free(tmp_path);
        return EXIT_BAD_INPUT;
    }
    sil_csv_header(f);
    sil_result_t res;
    int rc = sil_run(&sc, write_row, f, &res);
    if (fclose(f) != 0 || rc != 0) {
        fprintf(stderr, "drive_sil: --out %s: write error\n", out_path);
        remove(tmp_path);
        free(tmp_path);
        return EXIT_FAILURE;
    }
    if (rename(tmp_path, out_path) != 0) {
        fprintf(stderr, "drive_sil: --out %s: cannot rename the finished file: ", out_path);
        perror(NULL);
        remove(tmp_path);
        free(tmp_path);
        return EXIT_BAD_INPUT;
    }
    free(tmp_path);
    printf("drive_sil: %s: %u periods, %u rows, final state %d, fault %d, max |i| %.2f A -> %s\n",
           scenario_path, res.periods, res.rows, res.final_state, res.final_fault, res.max_abs_i_A, out_path);
    return EXIT_SUCCESS;
}
