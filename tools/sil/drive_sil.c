/*
 * drive_sil.c - the SIL runner program:
 *   drive_sil --scenario FILE [--set section.key=value ...]
 *             [--out FILE.csv] [--summary FILE.json|-] [--window T0:T1] [--check | --batch]
 *             [--max-csv-mb N]
 *   drive_sil --scenario FILE [--set ...] --commission OUT.ini [--out FILE.csv]
 *   drive_sil --scenario FILE [--set ...] --board-config DIR
 *   drive_sil --help | --version
 * Runs the firmware application on the simulated board (sil.h) and writes
 * one CSV row per logged period (--out; beside it OUT.resolved.json, the run's
 * resolved plant and controller values) and/or the steady window's figures
 * as JSON (--summary, summary.h; "-" is stdout), or with --check only
 * validates the scenario and overrides. --batch is the sweep's worker
 * (tools/drivekit/drivekit/sweep.py): one run per stdin line "ID<TAB>section.key=value<TAB>..."
 * (overrides on top of the scenario's), one summary line per run on stdout,
 * {"id": ID, "error": "..."} for refused overrides. Bad input (scenario, override,
 * flag, output path) prints a message naming file, line and key, exits 2
 * and leaves no output: each file is written as FILE.tmp.PID, renamed at
 * the end (an existing non-regular file such as /dev/null is written in
 * place). A write error (disk full) names the file, exits 1 and leaves no
 * output. The CSV is formatted and written by a second thread
 * (csv_writer.h) while the run goes on; --batch runs have no CSV and no
 * thread. Exit status (usage() prints it): 0 a run that ends outside
 * FAULT, 1 a write error, 2 bad input, 3 a run that ends in FAULT (every
 * output written in full), 128 + N a run ended early by signal N
 * (SIGINT, SIGTERM, SIGHUP: the handler only sets a flag; the run stops
 * after the period it is in, the CSV keeps the rows so far under its own
 * name).
 * --commission OUT.ini measures the motor instead (firmware/commission/commission.h:
 * the scenario's plant and board, a free shaft, [reference] and [load]
 * ignored, [faults] applied) and writes OUT.ini: the scenario file with
 * the --set overrides and the measured values in [controller], its
 * R_factor, L_factor, psif_factor kept as comments. A refusal writes no
 * OUT.ini, names the fault, the stage, the value and its limit, exits 3.
 * --board-config DIR resolves the scenario as a run would, with the
 * bench's defaults for the keys a simulation defaults otherwise, and
 * writes the F28335 image's configuration (DIR/drive_config.h,
 * DIR/drive_config.json; board_config.h), running nothing: `make board`.
 */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "app_step.h"
#include "board_config.h"
#include "csv_writer.h"
#include "ini_edit.h"
#include "json_out.h"
#include "link_sil.h"
#include "nv_file.h"
#include "scenario.h"
#include "sil.h"
#include "sil_version.h"
#include "summary.h"

#define EXIT_BAD_INPUT 2
#define EXIT_FAULT 3                  /* the run ended in FAULT: a result, outputs complete */
#define EXIT_SIGNAL_BASE 128          /* + the signal that ended the run early */
#define DEFAULT_MAX_CSV_MB 1024.0     /* --max-csv-mb */
#define BYTES_PER_MB 1048576.0
#define PROGRESS_AFTER_S 3.0          /* wall time before the first progress line */
#define PROGRESS_EVERY_S 1.0          /* wall time between progress lines */
#define PROGRESS_TICK_PERIODS 1000u   /* periods between looks at the clock */
#define MAX_SETS 64
#define TMP_SUFFIX_LEN 32
#define NAME_LEN 64
#define RESOLVED_SUFFIX ".resolved.json"   /* beside the CSV: the run's resolved values */
#define BATCH_LINE_LEN 8192
#define BATCH_FIELD_SEP "\t"

typedef struct {
    const char *scenario_path;
    const char *out_path;        /* CSV, or NULL */
    const char *summary_path;    /* JSON, "-" for stdout, or NULL */
    const char *window;          /* "T0:T1", or NULL for the default */
    const char *commission_path; /* --commission OUT.ini, or NULL */
    const char *board_dir;       /* --board-config DIR, or NULL */
    const char *nv_path;         /* --nv FILE: the parameter store's sector, or NULL */
    int check;                   /* validate only */
    int batch;                   /* one run per stdin line */
    double max_csv_mb;           /* the CSV stops growing here */
    const char *sets[MAX_SETS];
    int n_sets;
    link_sil_opts_t link;        /* --link, --baud, --realtime (link_sil.h) */
} args_t;

/* An output written to a temporary name and renamed when complete, or
 * (stdout, a device, a pipe) written in place. */
typedef struct {
    const char *path;
    char *tmp_path;              /* NULL: written in place */
    FILE *f;
} out_file_t;

typedef struct {
    csv_writer_t *csv;           /* or NULL */
    summary_t *summary;          /* or NULL */
    const args_t *args;
    int cap_told;                /* the size limit's warning was printed */
} sink_t;

/* The progress line on stderr (a terminal only). */
typedef struct {
    struct timespec t0;          /* wall clock at the start */
    double next_s;               /* wall time of the next line */
    double duration_s;           /* simulated time of the whole run */
    int shown;                   /* a line was printed (end it with a newline) */
} progress_t;

/* The signal that asked the run to stop (0: none); the handler only sets it. */
static volatile sig_atomic_t g_signal;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: drive_sil --scenario FILE [--set section.key=value ...]\n"
            "                 [--out FILE.csv] [--summary FILE.json|-] [--window T0:T1] [--check | --batch]\n"
            "                 [--max-csv-mb N] [--link tcp:PORT | --link pty [--baud B] [--realtime F]]\n"
            "       drive_sil --scenario FILE [--set ...] --commission OUT.ini [--out FILE.csv]\n"
            "       drive_sil --scenario FILE [--set ...] --board-config DIR\n"
            "       (a run, --link or --commission: [--nv FILE])\n"
            "       drive_sil --help | --version | --list-keys [--markdown]\n"
            "Runs the drive firmware on the simulated board for one scenario (INI)\n"
            "and writes the CSV trace (--out) and/or the steady window's figures as\n"
            "JSON (--summary; - for stdout; tools/sil/summary.h names them). The\n"
            "window defaults to 0.8:0.95 s for a run of 1.05 s or more, else the\n"
            "last quarter. --check validates the scenario and overrides, runs nothing.\n"
            "--batch runs one point per stdin line \"ID<TAB>section.key=value<TAB>...\"\n"
            "(overrides on top of the scenario's) and prints one summary line per point.\n"
            "--link serves the drive's link (firmware/link/link_protocol.md) on 127.0.0.1:PORT\n"
            "or a pty for drivetool, paced at --baud (115200) in simulated time;\n"
            "--realtime F paces the run to wall time (0: unpaced); with --link,\n"
            "run.duration_s = 0 runs until drivetool quit (tools/sil/link_sil.h).\n"
            "--max-csv-mb N (default %g): the CSV stops at the last whole row below N MB\n"
            "(2^20 bytes) with a warning; the run and --summary go on. --version prints\n"
            "the source revision drive_sil was built from. --list-keys prints the\n"
            "scenario keys below; --markdown as tools/sil/SCENARIO_KEYS.md.\n"
            "--commission OUT.ini measures the motor (firmware/commission/commission.h) on the\n"
            "scenario's plant and board with a free shaft ([reference], [load] ignored,\n"
            "[faults] applied; the current bound is [motor] i_rated_A, the speed\n"
            "bound n_rated_rpm) and writes OUT.ini: the scenario with the overrides\n"
            "and the measured R_ohm, L_H, psif_Wb, pole_pairs, J_kgm2, B_Nms,\n"
            "encoder_offset_el_rad and speed gains in [controller] (a value with no key\n"
            "in this drive_sil as a comment), R_factor, L_factor, psif_factor commented\n"
            "out. A refusal (exit 3) writes none and names fault, stage, value, limit.\n"
            "--board-config DIR resolves the scenario as a run does and writes the F28335\n"
            "image's configuration, DIR/drive_config.h and DIR/drive_config.json (make board\n"
            "MOTOR=FILE.ini; tools/sil/board_config.h); keys a simulation defaults otherwise\n"
            "take the board's values unless set: [plant] deadtime_s, adc_full_scale_A,\n"
            "trip_A, [run] level (1), calibrate, align. Runs nothing.\n"
            "--nv FILE keeps the drive's parameter sector (firmware/params/nv_store.h) in FILE,\n"
            "as the board's flash keeps it: its newest block's values replace the [controller]\n"
            "keys they name before the run (stderr says NV_EMPTY, NV_INVALID or what was\n"
            "loaded), and every save during the run (--link: drivetool save) writes FILE again.\n"
            "On a terminal, a run longer than %g s of wall time shows its progress on stderr.\n"
            "Exit status:\n"
            "  0    the run ended outside FAULT (--check: the input is good; --batch: every\n"
            "       line answered, a faulted or refused point is a result)\n"
            "  1    a write error (disk full): no output left\n"
            "  2    bad input (scenario, override, flag, output path): no output left\n"
            "  3    the run ended in FAULT; CSV, .resolved.json and --summary written in full\n"
            "  130  stopped by SIGINT (143 SIGTERM, 129 SIGHUP): the CSV kept under its name\n"
            "       to the last whole period, with its .resolved.json; no --summary\n"
            "Every key is optional (defaults: paper Table I).\n"
            "Profiles: \"t:value, t:value\" steps; \"t:value~\" ramps to value at t.\n"
            "Keys (section, name, default, meaning):\n", DEFAULT_MAX_CSV_MB, PROGRESS_AFTER_S);
    scenario_print_keys(f);
    scenario_print_bounds(f);
    fprintf(f, "The CSV columns: tools/sil/CSV_COLUMNS.md.\n");
}

/* --help, --list-keys [--markdown] and --version answer and exit; any other
 * argument returns. */
static void answer_info(int argc, char **argv, int i)
{
    const char *s = argv[i];
    if (strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0) {
        usage(stdout);
        exit(EXIT_SUCCESS);
    }
    if (strcmp(s, "--list-keys") == 0) {
        /* the key table alone: as text, or (--markdown next) the documented list */
        if (i + 1 < argc && strcmp(argv[i + 1], "--markdown") == 0) {
            scenario_print_keys_markdown(stdout);
        } else if (i + 1 < argc) {
            fprintf(stderr, "drive_sil: --list-keys takes only --markdown (see --help)\n");
            exit(EXIT_BAD_INPUT);
        } else {
            scenario_print_keys(stdout);
        }
        exit(EXIT_SUCCESS);
    }
    if (strcmp(s, "--version") == 0) {
        printf("drive_sil %s\n", sil_revision);
        exit(EXIT_SUCCESS);
    }
}

/* Where the value of option s goes, or NULL (named on stderr) for an
 * unknown option or one --set too many. */
static const char **value_slot(args_t *a, const char *s, const char **max_csv_mb)
{
    if (strcmp(s, "--scenario") == 0) {
        return &a->scenario_path;
    }
    if (strcmp(s, "--out") == 0) {
        return &a->out_path;
    }
    if (strcmp(s, "--summary") == 0) {
        return &a->summary_path;
    }
    if (strcmp(s, "--commission") == 0) {
        return &a->commission_path;
    }
    if (strcmp(s, "--board-config") == 0) {
        return &a->board_dir;
    }
    if (strcmp(s, "--nv") == 0) {
        return &a->nv_path;
    }
    if (strcmp(s, "--window") == 0) {
        return &a->window;
    }
    if (strcmp(s, "--max-csv-mb") == 0) {
        return max_csv_mb;
    }
    if (strcmp(s, "--set") == 0) {
        if (a->n_sets >= MAX_SETS) {
            fprintf(stderr, "drive_sil: more than %d --set\n", MAX_SETS);
            return NULL;
        }
        return &a->sets[a->n_sets++];
    }
    fprintf(stderr, "drive_sil: unknown argument \"%s\" (see --help)\n", s);
    return NULL;
}

/* The options together: --max-csv-mb a size, and the combinations that
 * make sense. 0, or -1 with the problem named. */
static int args_valid(args_t *a, const char *max_csv_mb)
{
    if (max_csv_mb != NULL) {
        char *end;
        errno = 0;
        a->max_csv_mb = strtod(max_csv_mb, &end);
        if (end == max_csv_mb || *end != '\0' || errno != 0 || !(a->max_csv_mb > 0.0) || !isfinite(a->max_csv_mb)) {
            fprintf(stderr, "drive_sil: --max-csv-mb %s: expected a size in MB > 0\n", max_csv_mb);
            return -1;
        }
    }
    const char *why = NULL;
    if (a->batch && (a->check || a->out_path != NULL || a->summary_path != NULL)) {
        why = "--batch writes its summaries to stdout (no --out, --summary, --check)";
    } else if (a->commission_path != NULL &&
               (a->batch || a->check || a->summary_path != NULL || a->window != NULL || a->link.on)) {
        why = "--commission writes OUT.ini (and --out's trace): no --batch, --check, --summary, --window, --link";
    } else if (a->board_dir != NULL && (a->batch || a->check || a->out_path != NULL || a->summary_path != NULL ||
                                        a->commission_path != NULL || a->window != NULL || a->link.on)) {
        why = "--board-config writes the image's configuration only: no --out, --summary, --commission, --batch, "
              "--check, --window, --link";
    } else if (a->nv_path != NULL && (a->batch || a->check || a->board_dir != NULL)) {
        why = "--nv keeps one run's parameter sector: not with --batch, --check, --board-config";
    } else if (a->scenario_path == NULL || (!a->check && !a->batch && a->out_path == NULL &&
                                            a->summary_path == NULL && a->commission_path == NULL &&
                                            a->board_dir == NULL)) {
        why = "--scenario and --out or --summary are required (see --help)";
    } else if ((a->link.baud != 0 || a->link.realtime > 0.0) && !a->link.on) {
        why = "--baud and --realtime pace the link: they need --link";
    } else if (a->link.on && a->batch) {
        why = "--link serves one run: not with --batch";
    } else if (a->out_path != NULL && strcmp(a->out_path, "-") == 0) {
        why = "--out -: the CSV goes to a file (--summary - is stdout)";
    }
    if (why != NULL) {
        fprintf(stderr, "drive_sil: %s\n", why);
        return -1;
    }
    return 0;
}

static int parse_args(int argc, char **argv, args_t *a)
{
    memset(a, 0, sizeof *a);
    a->max_csv_mb = DEFAULT_MAX_CSV_MB;
    const char *max_csv_mb = NULL;
    for (int i = 1; i < argc; i++) {
        const char *s = argv[i];
        const int link_arg = link_sil_arg(&a->link, argc, argv, &i);
        if (link_arg != 0) {
            if (link_arg < 0) {
                return -1;
            }
            continue;
        }
        answer_info(argc, argv, i);
        if (strcmp(s, "--check") == 0 || strcmp(s, "--batch") == 0) {
            *((s[2] == 'c') ? &a->check : &a->batch) = 1;
            continue;
        }
        const char **slot = value_slot(a, s, &max_csv_mb);
        if (slot == NULL) {
            return -1;
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "drive_sil: %s needs a value\n", s);
            return -1;
        }
        *slot = argv[++i];
    }
    return args_valid(a, max_csv_mb);
}

static int summary_on_stdout(const args_t *a)
{
    return a->summary_path != NULL && strcmp(a->summary_path, "-") == 0;
}

/* The scenario file and the --set overrides, not yet finished (resolved). */
static int load_base(const args_t *a, scenario_t *sc)
{
    char err[SCENARIO_ERR_LEN];
    scenario_defaults(sc);
    sc->run.endless_ok = (a->link.on != 0);   /* duration_s = 0: until the host quits */
    if (scenario_load(sc, a->scenario_path, err, sizeof err) != 0) {
        fprintf(stderr, "drive_sil: %s\n", err);
        return -1;
    }
    for (int i = 0; i < a->n_sets; i++) {
        if (scenario_set(sc, a->sets[i], err, sizeof err) != 0) {
            fprintf(stderr, "drive_sil: %s\n", err);
            return -1;
        }
    }
    return 0;
}

/* --nv FILE: the sector from FILE, its newest block over the scenario as
 * the board takes it at start-up (nv_file.h), what was taken on stderr;
 * values that do not fit the scenario as a whole (scenario_finish) are
 * NV_INVALID too: the scenario's own. 0, or -1 (FILE unusable). */
static int nv_start(args_t *a, scenario_t *sc)
{
    static scenario_t before;
    static scenario_t probe;
    char err[SCENARIO_ERR_LEN];
    char msg[SCENARIO_ERR_LEN * 2];
    if (nv_file_open(a->nv_path, err, sizeof err) != 0) {
        fprintf(stderr, "drive_sil: %s\n", err);
        return -1;
    }
    before = *sc;
    a->link.nv = 1;
    a->link.nv_loaded = (int)nv_file_apply(sc, a->nv_path, msg, sizeof msg);
    if (a->link.nv_loaded == (int)NV_OK) {
        probe = *sc;
        if (scenario_finish(&probe, err, sizeof err) != 0) {
            *sc = before;
            a->link.nv_loaded = (int)NV_INVALID;
            snprintf(msg, sizeof msg, "--nv %s: NV_INVALID: the saved values do not fit this scenario (%s); the "
                     "scenario's values", a->nv_path, err);
        }
    }
    fprintf(stderr, "drive_sil: %s\n", msg);
    return 0;
}

static int load_scenario(args_t *a, scenario_t *sc)
{
    char err[SCENARIO_ERR_LEN];
    if (load_base(a, sc) != 0) {
        return -1;
    }
    /* A commissioning neither uses the method nor the told R, L, psi_f: the
     * proposed method's refusals of them (no observer gain, no step 1) do
     * not stop it. OUT.ini keeps the file's method (it is written from the
     * file's text). */
    if (a->commission_path != NULL && scenario_set(sc, "controller.method=conventional", err, sizeof err) != 0) {
        fprintf(stderr, "drive_sil: %s\n", err);
        return -1;
    }
    if (a->nv_path != NULL && nv_start(a, sc) != 0) {
        return -1;
    }
    if (scenario_finish(sc, err, sizeof err) != 0) {
        fprintf(stderr, "drive_sil: %s\n", err);
        return -1;
    }
    scenario_warnings(sc, err, sizeof err);
    if (err[0] != '\0') {
        fprintf(stderr, "drive_sil: warning: %s\n", err);
    }
    return 0;
}

/* --window T0:T1 (or the default for the run), T0 < T1, both finite. */
static int window_of(const args_t *a, const scenario_t *sc, double *t0, double *t1)
{
    if (a->window == NULL) {
        summary_default_window(sc->run.duration_s, t0, t1);
        return 0;
    }
    char *end;
    *t0 = strtod(a->window, &end);
    if (end != a->window && *end == ':') {
        const char *p = end + 1;
        *t1 = strtod(p, &end);
        if (end != p && *end == '\0' && *t0 < *t1) {
            return 0;
        }
    }
    fprintf(stderr, "drive_sil: --window %s: expected T0:T1 in seconds with T0 < T1\n", a->window);
    return -1;
}

static int out_open(out_file_t *o, const char *path, const char *flag)
{
    o->path = path;
    o->tmp_path = NULL;
    o->f = NULL;
    if (path == NULL) {
        return 0;
    }
    if (strcmp(path, "-") == 0) {
        o->f = stdout;
        return 0;
    }
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {   /* a device or pipe: no rename over it */
        o->f = fopen(path, "w");
        if (o->f == NULL) {
            fprintf(stderr, "drive_sil: %s %s: cannot write: ", flag, path);
            perror(NULL);
            return -1;
        }
        return 0;
    }
    size_t len = strlen(path) + TMP_SUFFIX_LEN;
    o->tmp_path = malloc(len);
    if (o->tmp_path == NULL) {
        fprintf(stderr, "drive_sil: out of memory\n");
        return -1;
    }
    snprintf(o->tmp_path, len, "%s.tmp.%ld", path, (long)getpid());
    o->f = fopen(o->tmp_path, "w");
    if (o->f == NULL) {
        fprintf(stderr, "drive_sil: %s %s: cannot write: ", flag, path);
        perror(NULL);
        free(o->tmp_path);
        o->tmp_path = NULL;
        return -1;
    }
    return 0;
}

/* Drop an unfinished output (one written in place is closed as it is). */
static void out_abandon(out_file_t *o)
{
    if (o->f != NULL && o->f != stdout) {
        fclose(o->f);
    }
    if (o->tmp_path != NULL) {
        remove(o->tmp_path);
        free(o->tmp_path);
        o->tmp_path = NULL;
    }
    o->f = NULL;
}

/* Close and rename into place; 0, or -1 with the temporary removed. */
static int out_commit(out_file_t *o, const char *flag)
{
    if (o->f == NULL) {
        return 0;
    }
    int bad = ferror(o->f);
    FILE *f = o->f;
    o->f = NULL;
    errno = 0;
    if (((f == stdout) ? fflush(f) : fclose(f)) != 0 || bad) {
        fprintf(stderr, "drive_sil: %s %s: write error: %s\n", flag, o->path,
                (errno != 0) ? strerror(errno) : "stream error");
        out_abandon(o);
        return -1;
    }
    if (o->tmp_path == NULL) {
        return 0;
    }
    /* The old file goes first: ext4 writes a file renamed over another out
     * at once (auto_da_alloc), 0.7 ms of a whole run's CSV; the old one is
     * never needed, and a reader sees the complete file or none. */
    (void)remove(o->path);
    if (rename(o->tmp_path, o->path) != 0) {
        fprintf(stderr, "drive_sil: %s %s: cannot rename the finished file: ", flag, o->path);
        perror(NULL);
        out_abandon(o);
        return -1;
    }
    free(o->tmp_path);
    o->tmp_path = NULL;
    return 0;
}

/* DIR/name into path[len]; 0, or -1 (named) when it does not fit. */
static int dir_file(char *path, size_t len, const char *dir, const char *name)
{
    const int n = snprintf(path, len, "%s/%s", dir, name);
    if (n < 0 || (size_t)n >= len) {
        fprintf(stderr, "drive_sil: --board-config %s: the path is too long\n", dir);
        return -1;
    }
    return 0;
}

#define BOARD_PATH_LEN 4096

/* --board-config DIR: the scenario resolved with the bench's defaults,
 * the image's header and JSON written (each complete or none). */
static int board_config(const args_t *a)
{
    static scenario_t sc;
    static char h_path[BOARD_PATH_LEN];
    static char js_path[BOARD_PATH_LEN];
    char err[SCENARIO_ERR_LEN];
    if (load_base(a, &sc) != 0) {
        return EXIT_BAD_INPUT;
    }
    if (board_config_bench(&sc, err, sizeof err) != 0 || scenario_finish(&sc, err, sizeof err) != 0) {
        fprintf(stderr, "drive_sil: %s\n", err);
        return EXIT_BAD_INPUT;
    }
    scenario_warnings(&sc, err, sizeof err);
    if (err[0] != '\0') {
        fprintf(stderr, "drive_sil: warning: %s\n", err);
    }
    out_file_t h;
    out_file_t js;
    if (dir_file(h_path, sizeof h_path, a->board_dir, "drive_config.h") != 0 ||
        dir_file(js_path, sizeof js_path, a->board_dir, "drive_config.json") != 0 ||
        out_open(&h, h_path, "--board-config") != 0) {
        return EXIT_BAD_INPUT;
    }
    if (out_open(&js, js_path, "--board-config") != 0) {
        out_abandon(&h);
        return EXIT_BAD_INPUT;
    }
    if (board_config_write(h.f, js.f, &sc, a->scenario_path, a->sets, a->n_sets, err, sizeof err) != 0) {
        fprintf(stderr, "drive_sil: %s: %s\n", a->scenario_path, err);
        out_abandon(&h);
        out_abandon(&js);
        return EXIT_BAD_INPUT;
    }
    if (out_commit(&h, "--board-config") != 0 || out_commit(&js, "--board-config") != 0) {
        out_abandon(&js);
        return EXIT_FAILURE;
    }
    printf("drive_sil: %s: the board image's configuration -> %s, %s (build level %lu at power-on)\n",
           a->scenario_path, h_path, js_path, (unsigned long)sc.run.level);
    return EXIT_SUCCESS;
}

/* OUT.resolved.json beside the CSV (--out OUT.csv, or OUT + that suffix
 * for another name; not OUT.json, a --summary's usual name): the resolved
 * truth and controller values of the run (sil_write_resolved), for the
 * report instead of the INI. None beside a CSV written in place (/dev/null). */
static int resolved_write(const args_t *a, const scenario_t *sc, const sil_result_t *res, int csv_in_place)
{
    if (a->out_path == NULL || csv_in_place) {
        return 0;
    }
    const size_t n = strlen(a->out_path);
    const size_t stem = (n > 4u && strcmp(a->out_path + n - 4u, ".csv") == 0) ? n - 4u : n;
    char *path = malloc(stem + sizeof RESOLVED_SUFFIX);
    if (path == NULL) {
        fprintf(stderr, "drive_sil: out of memory\n");
        return -1;
    }
    memcpy(path, a->out_path, stem);
    memcpy(path + stem, RESOLVED_SUFFIX, sizeof RESOLVED_SUFFIX);
    out_file_t o;
    int rc = out_open(&o, path, "--out");
    if (rc == 0) {
        const sil_origin_t origin = { a->scenario_path, a->sets, a->n_sets, a->commission_path != NULL };
        char wbuf[SUMMARY_WARNING_LEN];
        sil_write_resolved(o.f, sc, &origin, summary_warning_text(res, wbuf, sizeof wbuf));
        rc = out_commit(&o, "--out");
    }
    free(path);
    return rc;
}

static int on_row(const sil_row_t *row, void *user)
{
    sink_t *k = user;
    if (k->summary != NULL) {
        summary_add(k->summary, row);
    }
    if (k->csv != NULL) {
        if (csv_writer_put(k->csv, row) != 0) {
            return 1;
        }
        if (k->csv->seen_capped && !k->cap_told) {
            /* t_capped_s was set with capped, under the lock of the hand-over that saw it */
            fprintf(stderr, "drive_sil: warning: --out %s: the CSV reached --max-csv-mb %g at t = %.6g s: "
                    "no more rows are written, the run goes on\n", k->args->out_path, k->args->max_csv_mb,
                    k->csv->t_capped_s);
            k->cap_told = 1;
        }
    }
    return 0;
}

static void on_signal(int sig)
{
    g_signal = sig;
}

/* SIGINT, SIGTERM and SIGHUP (the terminal closed) set g_signal (the run stops after its period), unless
 * the caller had the signal ignored (a background job's SIGINT); 0 or -1. */
static int catch_signals(void)
{
    static const int SIGNALS[] = { SIGINT, SIGTERM, SIGHUP };
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sa.sa_flags = SA_RESTART;
    sigemptyset(&sa.sa_mask);
    for (size_t i = 0; i < sizeof SIGNALS / sizeof SIGNALS[0]; i++) {
        struct sigaction old;
        if (sigaction(SIGNALS[i], NULL, &old) != 0 ||
            (old.sa_handler != SIG_IGN && sigaction(SIGNALS[i], &sa, NULL) != 0)) {
            perror("drive_sil: sigaction");
            return -1;
        }
    }
    return 0;
}

static double wall_s_since(const struct timespec *t0)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)(t.tv_sec - t0->tv_sec) + 1e-9 * (double)(t.tv_nsec - t0->tv_nsec);
}

/* sil_tick_fn: after PROGRESS_AFTER_S of wall time, a line per PROGRESS_EVERY_S. */
static void on_tick(double t_s, void *user)
{
    progress_t *p = user;
    const double wall_s = wall_s_since(&p->t0);
    if (wall_s < p->next_s) {
        return;
    }
    p->next_s = wall_s + PROGRESS_EVERY_S;
    const double done = (p->duration_s > 0.0) ? t_s / p->duration_s : 1.0;
    const double left_s = (done > 0.0) ? wall_s * (1.0 - done) / done : 0.0;
    fprintf(stderr, "\rdrive_sil: t = %.1f of %.1f s (%.0f %%), %.0f s elapsed, about %.0f s left ", t_s,
            p->duration_s, 100.0 * done, wall_s, left_s);
    p->shown = 1;
}

static int add_to_summary(const sil_row_t *row, void *user)
{
    summary_add(user, row);
    return 0;
}

/* One batch line "ID<TAB>set<TAB>set..." (newline removed) on top of *base: its summary line. */
static void batch_point(const args_t *a, const scenario_t *base, char *line)
{
    static scenario_t sc;
    static summary_t sum;
    char err[SCENARIO_ERR_LEN];
    char *save = NULL;
    const char *id = strtok_r(line, BATCH_FIELD_SEP, &save);
    if (id == NULL) {
        id = "";
    }
    sc = *base;
    int bad = 0;
    for (char *set = strtok_r(NULL, BATCH_FIELD_SEP, &save); set != NULL && !bad;
         set = strtok_r(NULL, BATCH_FIELD_SEP, &save)) {
        bad = scenario_set(&sc, set, err, sizeof err);
    }
    if (!bad) {
        bad = scenario_finish(&sc, err, sizeof err);
    }
    if (bad) {
        fputs("{\"id\": ", stdout);
        json_string(stdout, id);
        fputs(", \"error\": ", stdout);
        json_string(stdout, err);
        fputs("}\n", stdout);
        return;
    }
    double t0 = 0.0;
    double t1 = 0.0;
    if (window_of(a, &sc, &t0, &t1) != 0) {
        exit(EXIT_BAD_INPUT);
    }
    summary_init(&sum, &sc, t0, t1);
    sil_result_t res;
    (void)sil_run(&sc, add_to_summary, &sum, &res);
    summary_write_json(stdout, &sum, &sc, &res, a->scenario_path, id);
}

/* --batch: every stdin line a point; 0 at end of input, -1 on a line too long. */
static int run_batch(const args_t *a)
{
    static scenario_t base;
    static char line[BATCH_LINE_LEN];
    if (load_base(a, &base) != 0) {
        return EXIT_BAD_INPUT;
    }
    while (fgets(line, sizeof line, stdin) != NULL) {
        size_t n = strlen(line);
        if (n > 0u && line[n - 1u] == '\n') {
            line[--n] = '\0';
        } else if (!feof(stdin)) {
            fprintf(stderr, "drive_sil: --batch: a line longer than %d characters\n", BATCH_LINE_LEN - 2);
            return EXIT_BAD_INPUT;
        }
        batch_point(a, &base, line);
        if (fflush(stdout) != 0) {
            return EXIT_FAILURE;
        }
    }
    return EXIT_SUCCESS;
}

#define COMM_VALUE_LEN 32
#define COMM_EDITS_MAX (MAX_SETS + 16)

/* One measured value into [controller]: the key if this drive_sil has it, else a note. */
static void comm_edit(ini_edit_t *e, size_t *n, char (*val)[COMM_VALUE_LEN], const char *key, double v)
{
    snprintf(val[*n], COMM_VALUE_LEN, "%.9g", v);
    const int known = scenario_key_known("controller", key);
    e[*n] = (ini_edit_t){ "controller", key, val[*n], known ? INI_SET : INI_NOTE,
                          known ? NULL : "measured by --commission; this drive_sil has no key for it" };
    (*n)++;
}

/* The measured values as OUT.ini's keys: [controller] the motor, the speed
 * PI, the inverter's error (the told dead time kept, the rest a device
 * drop, what the measurement leaves uncertain); [identify] mode = trusted:
 * R is measured, no step 1 (tracked in service by track_R). */
static void comm_edits(ini_edit_t *e, size_t *n, char (*val)[COMM_VALUE_LEN], const sil_result_t *res)
{
    comm_edit(e, n, val, "R_ohm", res->comm_R_ohm);
    comm_edit(e, n, val, "L_H", res->comm_L_H);
    comm_edit(e, n, val, "psif_Wb", res->comm_psif_Wb);
    comm_edit(e, n, val, "pole_pairs", (double)res->comm_pole_pairs);
    comm_edit(e, n, val, "J_kgm2", res->comm_J_kgm2);
    comm_edit(e, n, val, "B_Nms", res->comm_B_Nms);
    comm_edit(e, n, val, "encoder_offset_el_rad", res->comm_enc_offset_el_rad);
    comm_edit(e, n, val, "speed_kp_Nms_rad", res->comm_speed_kp_Nms_rad);
    comm_edit(e, n, val, "speed_ki_Nm_rad", res->comm_speed_ki_Nm_rad);
    comm_edit(e, n, val, "deadtime_s", res->comm_deadtime_s);
    comm_edit(e, n, val, "device_drop_V", res->comm_device_drop_V);
    comm_edit(e, n, val, "untold_deadtime_s", res->comm_untold_deadtime_s);
    e[(*n)++] = (ini_edit_t){ "identify", "mode", "trusted", INI_SET, NULL };
}

/* OUT.ini of a completed commissioning: the scenario file, the --set
 * overrides, the measured values; 0, or -1 (message printed, no file). */
static int commission_write(const args_t *a, const sil_result_t *res, out_file_t *o)
{
    static ini_edit_t e[COMM_EDITS_MAX];
    static char val[COMM_EDITS_MAX][COMM_VALUE_LEN];
    static char sets[MAX_SETS][BATCH_LINE_LEN / 8];
    size_t n = 0;
    for (int i = 0; i < a->n_sets; i++) {   /* checked by scenario_set: "section.key=value" */
        snprintf(sets[i], sizeof sets[i], "%s", a->sets[i]);
        char *dot = strchr(sets[i], '.');
        char *eq = (dot != NULL) ? strchr(dot, '=') : NULL;
        if (eq == NULL) {
            continue;
        }
        *dot = '\0';
        *eq = '\0';
        e[n++] = (ini_edit_t){ sets[i], dot + 1, eq + 1, INI_SET, NULL };
    }
    static const char *const FACTORS[] = { "R_factor", "L_factor", "psif_factor" };
    for (size_t i = 0; i < sizeof FACTORS / sizeof FACTORS[0]; i++) {
        e[n++] = (ini_edit_t){ "controller", FACTORS[i], NULL, INI_REMOVE, "the commissioning measured the value" };
    }
    comm_edits(e, &n, val, res);

    FILE *in = fopen(a->scenario_path, "r");
    if (in == NULL) {
        fprintf(stderr, "drive_sil: --scenario %s: cannot read it again: ", a->scenario_path);
        perror(NULL);
        out_abandon(o);
        return -1;
    }
    fprintf(o->f, "; commissioned by drive_sil %s from %s\n", sil_revision, a->scenario_path);
    const int rc = ini_edit_copy(in, o->f, e, n);
    fclose(in);
    if (rc != 0) {
        fprintf(stderr, "drive_sil: --scenario %s: read error\n", a->scenario_path);
        out_abandon(o);
        return -1;
    }
    return out_commit(o, "--commission");
}

static const char *comm_stage_name(int stage)
{
    static const char *const NAMES[] = { "NONE", "R", "L", "ENCODER", "SPIN", "DONE", "WIRING" };
    return (stage >= 0 && (size_t)stage < sizeof NAMES / sizeof NAMES[0]) ? NAMES[stage] : "?";
}

/* The commissioning's outcome: OUT.ini and the values on stdout, or the refusal. */
static int commission_finish(const args_t *a, const sil_result_t *res, out_file_t *o)
{
    char fbuf[NAME_LEN];
    if (!res->comm_valid) {
        fprintf(stderr, "drive_sil: --commission: refused: %s in stage %s (state %d): value %.6g, limit %.6g; "
                "gates on in fault: %u periods; no %s written\n",
                summary_fault_name(res->final_fault, fbuf, sizeof fbuf), comm_stage_name(res->comm_stage),
                res->fault_state, res->fault_value, res->fault_limit, res->gates_on_in_fault, a->commission_path);
        out_abandon(o);
        return EXIT_FAULT;
    }
    if (commission_write(a, res, o) != 0) {
        return EXIT_FAILURE;
    }
    printf("drive_sil: commissioned: R_ohm=%.6g L_H=%.6g psif_Wb=%.6g pole_pairs=%u J_kgm2=%.6g B_Nms=%.6g "
           "encoder_offset_el_rad=%.6g speed_kp_Nms_rad=%.6g speed_ki_Nm_rad=%.6g deadtime_s=%.6g "
           "device_drop_V=%.6g untold_deadtime_s=%.6g u_err_V=%.4g inv_dv_V=%.4g max_abs_i_A=%.4g "
           "max_abs_speed_rpm=%.5g periods=%u -> %s\n",
           res->comm_R_ohm, res->comm_L_H, res->comm_psif_Wb, res->comm_pole_pairs, res->comm_J_kgm2,
           res->comm_B_Nms, res->comm_enc_offset_el_rad, res->comm_speed_kp_Nms_rad, res->comm_speed_ki_Nm_rad,
           res->comm_deadtime_s, res->comm_device_drop_V, res->comm_untold_deadtime_s, res->comm_u_err_V,
           res->comm_inv_dv_V, res->max_abs_i_A, res->max_abs_speed_rpm, res->periods, a->commission_path);
    return EXIT_SUCCESS;
}

/* The run's output files: the CSV (--out), the summary (--summary) and
 * OUT.ini (--commission); each one's f NULL when not asked for. */
typedef struct {
    out_file_t csv;
    out_file_t js;
    out_file_t comm_ini;
} outputs_t;

/* Every output dropped: no temporary left, nothing under its name (one
 * committed already or never opened is left as it is). */
static void outputs_abandon(outputs_t *o)
{
    out_abandon(&o->csv);
    out_abandon(&o->js);
    out_abandon(&o->comm_ini);
}

/* All opened before the run, so that a bad path is bad input (OUT.ini's
 * too): 0, or -1 with none left open. */
static int outputs_open(const args_t *a, outputs_t *o)
{
    memset(o, 0, sizeof *o);
    if (out_open(&o->csv, a->out_path, "--out") != 0 || out_open(&o->js, a->summary_path, "--summary") != 0 ||
        out_open(&o->comm_ini, a->commission_path, "--commission") != 0) {
        outputs_abandon(o);
        return -1;
    }
    return 0;
}

/* The CSV's header, then its writer thread: 0, or -1 with the error named. */
static int csv_start(const args_t *a, FILE *f, csv_writer_t *writer)
{
    sil_csv_header(f);
    const long header_bytes = ftell(f);   /* a pipe: -1, counted as 0 */
    const int err = csv_writer_start(writer, f, (header_bytes > 0) ? (uint64_t)header_bytes : 0u,
                                     (uint64_t)(a->max_csv_mb * BYTES_PER_MB));
    if (err != 0) {
        fprintf(stderr, "drive_sil: --out %s: cannot start the CSV writer thread: %s\n", a->out_path, strerror(err));
        return -1;
    }
    return 0;
}

/* The run itself, with the link when asked (a port taken is a bad --link:
 * EXIT_BAD_INPUT) and the progress line on a terminal (none for a run with
 * no end: --link, duration 0); *stopped when a signal, a failed write (seen
 * by the caller) or the link's quit ended it early. 0, or an exit status. */
static int run(const args_t *a, const scenario_t *sc, sink_t *sink, sil_result_t *res, int *stopped)
{
    progress_t prog;
    clock_gettime(CLOCK_MONOTONIC, &prog.t0);
    prog.next_s = PROGRESS_AFTER_S;
    prog.duration_s = sc->run.duration_s;
    prog.shown = 0;
    sil_hooks_t hooks;
    if (a->link.on && link_sil_open(&a->link, sc, &hooks) != 0) {
        return EXIT_BAD_INPUT;
    }
    const int show = isatty(STDERR_FILENO) && sc->run.duration_s > 0.0;
    const sil_ctl_t ctl = { &g_signal, show ? on_tick : NULL, &prog, PROGRESS_TICK_PERIODS, a->link.on ? &hooks : NULL,
                            a->commission_path != NULL };
    *stopped = (sil_run_ctl(sc, on_row, sink, &ctl, res) == SIL_STOPPED);
    if (a->link.on) {
        link_sil_close();
    }
    if (prog.shown) {
        fputc('\n', stderr);
    }
    return 0;
}

/* After the run: the CSV's writer joined, the summary written (none for a
 * run cut short: the window's figures would mislead), the CSV, its
 * resolved values and the summary in place. 0, or EXIT_FAILURE with every
 * output dropped. */
static int outputs_finish(const args_t *a, const scenario_t *sc, outputs_t *o, const sink_t *sink,
                          const sil_result_t *res, int stopped)
{
    const int err = (sink->csv != NULL) ? csv_writer_finish(sink->csv) : 0;
    if (err != 0) {
        fprintf(stderr, "drive_sil: --out %s: write error: %s\n", a->out_path, strerror(err));
        outputs_abandon(o);
        return EXIT_FAILURE;
    }
    if (stopped) {
        out_abandon(&o->js);
    } else if (o->js.f != NULL) {
        summary_write_json(o->js.f, sink->summary, sc, res, a->scenario_path, NULL);
    }
    const int csv_in_place = (o->csv.f != NULL && o->csv.tmp_path == NULL);
    if (out_commit(&o->csv, "--out") != 0 || resolved_write(a, sc, res, csv_in_place) != 0 ||
        out_commit(&o->js, "--summary") != 0) {
        outputs_abandon(o);
        return EXIT_FAILURE;
    }
    if (sink->csv != NULL && sink->csv->capped) {
        fprintf(stderr, "drive_sil: warning: --out %s: holds the rows to t < %.6g s only (--max-csv-mb %g)\n",
                a->out_path, sink->csv->t_capped_s, a->max_csv_mb);
    }
    return 0;
}

/* The run's line on stdout (with --out, unless the summary is there) and,
 * stopped by a signal, its line on stderr; the exit status. */
static int run_status(const args_t *a, const sil_result_t *res, int stopped)
{
    if (a->out_path != NULL && !summary_on_stdout(a)) {
        char sbuf[NAME_LEN];
        char fbuf[NAME_LEN];
        char wbuf[SUMMARY_WARNING_LEN];
        const char *warn = summary_warning_text(res, wbuf, sizeof wbuf);
        printf("drive_sil: %s: %u periods, %u rows, final state %d (%s), fault %d (%s), max |i| %.2f A%s%s -> %s\n",
               a->scenario_path, res->periods, res->rows, res->final_state,
               summary_state_name(res->final_state, sbuf, sizeof sbuf), res->final_fault,
               summary_fault_name(res->final_fault, fbuf, sizeof fbuf), res->max_abs_i_A,
               (warn[0] != '\0') ? ", warning " : "", warn, a->out_path);
    }
    if (stopped) {
        fprintf(stderr, "drive_sil: stopped by signal %d after %u periods, %u rows%s%s%s\n", (int)g_signal,
                res->periods, res->rows, (a->out_path != NULL) ? ", kept in " : "",
                (a->out_path != NULL) ? a->out_path : "", (a->summary_path != NULL) ? "; no --summary" : "");
        return EXIT_SIGNAL_BASE + (int)g_signal;
    }
    return (res->final_state == (int)APP_STATE_FAULT) ? EXIT_FAULT : EXIT_SUCCESS;
}

int main(int argc, char **argv)
{
    args_t a;
    static scenario_t sc;
    static outputs_t out;
    static summary_t sum;
    static csv_writer_t writer;
    double t0 = 0.0;
    double t1 = 0.0;
    if (parse_args(argc, argv, &a) != 0) {
        return EXIT_BAD_INPUT;
    }
    if (a.batch) {
        return run_batch(&a);
    }
    if (a.board_dir != NULL) {
        return board_config(&a);
    }
    if (load_scenario(&a, &sc) != 0 || window_of(&a, &sc, &t0, &t1) != 0) {
        return EXIT_BAD_INPUT;
    }
    if (a.check) {
        printf("drive_sil: %s: ok\n", a.scenario_path);
        return EXIT_SUCCESS;
    }
    if (catch_signals() != 0) {
        return EXIT_FAILURE;
    }
    if (outputs_open(&a, &out) != 0) {
        return EXIT_BAD_INPUT;
    }
    summary_init(&sum, &sc, t0, t1);
    sink_t sink = { (out.csv.f != NULL) ? &writer : NULL, (out.js.f != NULL) ? &sum : NULL, &a, 0 };
    if (out.csv.f != NULL && csv_start(&a, out.csv.f, &writer) != 0) {
        outputs_abandon(&out);
        return EXIT_FAILURE;
    }
    sil_result_t res;
    int stopped = 0;
    int rc = run(&a, &sc, &sink, &res, &stopped);
    if (rc != 0) {
        if (sink.csv != NULL) {
            (void)csv_writer_finish(sink.csv);
        }
        outputs_abandon(&out);
        return rc;
    }
    rc = outputs_finish(&a, &sc, &out, &sink, &res, stopped);
    if (rc != 0) {
        return rc;
    }
    if (a.commission_path != NULL && !stopped) {
        return commission_finish(&a, &res, &out.comm_ini);
    }
    out_abandon(&out.comm_ini);   /* stopped by a signal: no OUT.ini */
    rc = run_status(&a, &res, stopped);
    return (a.nv_path != NULL && nv_file_failed()) ? EXIT_FAILURE : rc;
}
