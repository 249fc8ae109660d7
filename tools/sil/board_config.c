/* board_config.c - the F28335 image's configuration from a motor file; see
 * board_config.h. */
#include "board_config.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "app.h"
#include "board_cfg.h"
#include "drive_params.h"
#include "hal_f28335_cfg.h"
#include "json_out.h"
#include "sil.h"
#include "sil_version.h"

#define NS_PER_S 1e9
#define TEXT_LEN 64

/* ---- the bench's defaults -------------------------------------------------- */

static int bench_key(scenario_t *sc, const char *section, const char *name, const char *value, char *err,
                     size_t errlen)
{
    char set[TEXT_LEN * 2];
    if (scenario_key_set(sc, section, name)) {
        return 0;   /* the motor file's */
    }
    snprintf(set, sizeof set, "%s.%s=%s", section, name, value);
    return scenario_set(sc, set, err, errlen);
}

int board_config_bench(scenario_t *sc, char *err, size_t errlen)
{
    static app_cfg_t ac; /* large: not on the stack */
    char v[TEXT_LEN];
    app_cfg_default(&ac);
    const bool offset_told = scenario_key_set(sc, "controller", "encoder_offset_el_rad") != 0;

    snprintf(v, sizeof v, "%.9g", (double)BOARD_DEADTIME_NS / NS_PER_S);
    if (bench_key(sc, "plant", "deadtime_s", v, err, errlen) != 0) {
        return -1;
    }
    snprintf(v, sizeof v, "%.9g", (double)BOARD_I_FULL_SCALE_A);
    if (bench_key(sc, "plant", "adc_full_scale_A", v, err, errlen) != 0) {
        return -1;
    }
    snprintf(v, sizeof v, "%.9g", (double)BOARD_HW_TRIP_A);
    if (bench_key(sc, "plant", "trip_A", v, err, errlen) != 0) {
        return -1;
    }
    snprintf(v, sizeof v, "%u", (unsigned)ac.lvl.level);
    if (bench_key(sc, "run", "level", v, err, errlen) != 0 ||
        bench_key(sc, "run", "calibrate", ac.calibrate ? "on" : "off", err, errlen) != 0) {
        return -1;
    }
    /* a told (measured) encoder offset is used as it is; else the board aligns at power-up */
    return bench_key(sc, "run", "align", (ac.align && !offset_told) ? "on" : "off", err, errlen);
}

/* ---- the header ---------------------------------------------------------------- */

/* v as a C float literal that reads back to the same float: digits, a
 * point or an exponent, the f suffix. */
static void c_float(char *buf, size_t len, float v)
{
    snprintf(buf, len, "%.9g", (double)v);
    if (strpbrk(buf, ".e") == NULL) {
        strncat(buf, ".0", len - strlen(buf) - 1u);
    }
    strncat(buf, "f", len - strlen(buf) - 1u);
}

/* The parameter set's fields (drive_params.h's lists): path, type, offset. */
typedef enum { F_FLOAT, F_U16, F_U32 } field_type_t;
typedef struct {
    const char *path;
    field_type_t type;
    size_t offset;
} param_field_t;

#define F_TYPE_float F_FLOAT
#define F_TYPE_uint16_t F_U16
#define F_TYPE_uint32_t F_U32
#define PARAM_FIELD(group, field, type, dflt, to) { #group "." #field, F_TYPE_##type, offsetof(drive_params_t, group.field) },
static const param_field_t PARAM_FIELDS[] = { DRIVE_PARAMS(PARAM_FIELD) };
#define N_PARAM_FIELDS (sizeof PARAM_FIELDS / sizeof PARAM_FIELDS[0])

/* The enums among the app's fields a key sets (sc_conv_t ENUM): their C types. */
typedef struct {
    const char *path;
    const char *c_type;
} enum_field_t;
static const enum_field_t ENUM_FIELDS[] = {
    { "rsid.mode", "app_rsid_mode_t" },
    { "rsid.on_refusal", "app_rsid_refusal_t" },
};

static const char *enum_type(const char *path)
{
    for (size_t i = 0; i < sizeof ENUM_FIELDS / sizeof ENUM_FIELDS[0]; i++) {
        if (strcmp(ENUM_FIELDS[i].path, path) == 0) {
            return ENUM_FIELDS[i].c_type;
        }
    }
    return NULL;
}

/* DRIVE_CONFIG_PARAMS: every field of *p. */
static int params_macro(FILE *h, const drive_params_t *p, char *err, size_t errlen)
{
    char num[TEXT_LEN];
    fputs("/* The parameter set, every field (drive_params.h), at the end of drive_params_board(). */\n"
          "#define DRIVE_CONFIG_PARAMS(p) do { \\\n", h);
    for (size_t i = 0; i < N_PARAM_FIELDS; i++) {
        const param_field_t *f = &PARAM_FIELDS[i];
        const char *at = (const char *)p + f->offset;
        if (f->type == F_U16) {
            fprintf(h, "    (p)->%s = (uint16_t)%uU; \\\n", f->path, (unsigned)*(const uint16_t *)(const void *)at);
        } else if (f->type == F_U32) {
            fprintf(h, "    (p)->%s = %luUL; \\\n", f->path, (unsigned long)*(const uint32_t *)(const void *)at);
        } else {
            const float v = *(const float *)(const void *)at;
            if (!isfinite(v)) {
                snprintf(err, errlen, "the parameter set's %s is not finite (%g)", f->path, (double)v);
                return -1;
            }
            c_float(num, sizeof num, v);
            fprintf(h, "    (p)->%s = %s; \\\n", f->path, num);
        }
    }
    /* what the derivation derived (a derived torque limit follows the learned psi_f on the board too) */
    fprintf(h, "    (p)->derived = (uint16_t)%uU; \\\n", (unsigned)p->derived);
    fputs("} while (0)\n\n", h);
    return 0;
}

/* DRIVE_CONFIG_APP: every field of the app's configuration a key sets (SC_TO_APP). */
static int app_macro(FILE *h, const app_cfg_t *ac, double Ts_s, char *err, size_t errlen)
{
    char num[TEXT_LEN];
    fputs("/* The app's settings the scenario keys name ([run], [identify], ...), at the end of\n"
          " * app_cfg_default(). */\n"
          "#define DRIVE_CONFIG_APP(c) do { \\\n", h);
    for (int i = 0; i < scenario_key_count(); i++) {
        scenario_key_info_t k;
        scenario_key_info(i, &k);
        if (k.to.target != SC_TO_APP) {
            continue;
        }
        const double v = scenario_loc_read(&k.to, ac, Ts_s);
        const char *ty = enum_type(k.to.path);
        switch (k.to.conv) {
        case SC_CONV_F32:
            c_float(num, sizeof num, (float)v);
            fprintf(h, "    (c)->%s = %s; \\\n", k.to.path, num);
            break;
        case SC_CONV_U16:
            fprintf(h, "    (c)->%s = (uint16_t)%.0fU; \\\n", k.to.path, v);
            break;
        case SC_CONV_U32:
        case SC_CONV_PERIODS:   /* the periods the app holds, read back in s: whole periods again */
            fprintf(h, "    (c)->%s = %.0fUL; \\\n", k.to.path, (k.to.conv == SC_CONV_PERIODS) ? round(v / Ts_s) : v);
            break;
        case SC_CONV_BOOL:
            fprintf(h, "    (c)->%s = %s; \\\n", k.to.path, (v != 0.0) ? "true" : "false");
            break;
        case SC_CONV_ENUM:
            if (ty == NULL) {
                snprintf(err, errlen, "[%s] %s: the app's field %s is an enum board_config.c has no C type for",
                         k.section, k.name, k.to.path);
                return -1;
            }
            fprintf(h, "    (c)->%s = (%s)%.0f; \\\n", k.to.path, ty, v);
            break;
        default:
            snprintf(err, errlen, "[%s] %s: no C form for its conversion into the app's %s", k.section, k.name,
                     k.to.path);
            return -1;
        }
    }
    fputs("} while (0)\n\n", h);
    return 0;
}

/* The board facts the HAL builds from (board_hw.h), in its units; -1 for
 * a dead time the dead band cannot hold. */
static int facts_macros(FILE *h, const scenario_t *sc, char *err, size_t errlen)
{
    char num[TEXT_LEN];
    const double db_max_s = (double)F28335_DB_MAX_COUNTS / (double)F28335_TBCLK_HZ;
    if (sc->plant.deadtime_s > db_max_s) {
        snprintf(err, errlen, "[plant] deadtime_s: %g s is beyond the ePWM dead band's %u TBCLK (%.4g s)",
                 sc->plant.deadtime_s, (unsigned)F28335_DB_MAX_COUNTS, db_max_s);
        return -1;
    }
    fputs("/* The board facts (hal/f28335/board_hw.h), from [plant]. */\n", h);
    fprintf(h, "#define BOARD_DEADTIME_NS %.0fUL /* [plant] deadtime_s = %.9g s */\n",
            round(sc->plant.deadtime_s * NS_PER_S), sc->plant.deadtime_s);
    fprintf(h, "#define BOARD_ENC_LINES %luUL /* [plant] encoder_lines */\n", (unsigned long)sc->plant.encoder_lines);
    c_float(num, sizeof num, (float)sc->plant.adc_full_scale_A);
    fprintf(h, "#define BOARD_I_FULL_SCALE_A %s /* [plant] adc_full_scale_A [A] */\n", num);
    c_float(num, sizeof num, (float)sc->plant.trip_A);
    fprintf(h, "#define BOARD_HW_TRIP_A %s /* [plant] trip_A [A] */\n\n", num);
    return 0;
}

/* ---- the JSON --------------------------------------------------------------- */

/* A group's keys: its section's, but for those the image has no value of
 * (the controller's factors, folded into its values; the operator's
 * method and mode, cmd_t's at run time). */
typedef struct {
    const char *group;          /* the JSON's group */
    const char *section;        /* the scenario's section */
    const char *const *only;    /* these keys only (NULL: all but skip) */
    const char *const *skip;
} json_group_t;

static const char *const CONTROLLER_SKIP[] = { "R_factor", "L_factor", "psif_factor", "method", "mode", NULL };
static const char *const RUN_KEYS[] = { "level", "level4_i_limit_A", "level12_vdc_max_V", "calibrate", "align", NULL };
static const char *const BOARD_KEYS[] = { "vdc_V", "adc_full_scale_A", "trip_A", "encoder_lines", "deadtime_s", NULL };
static const json_group_t GROUPS[] = {
    { "controller", "controller", NULL, CONTROLLER_SKIP },
    { "motor", "motor", NULL, NULL },
    { "identify", "identify", NULL, NULL },
    { "run", "run", RUN_KEYS, NULL },
    { "board", "plant", BOARD_KEYS, NULL },
};

static bool listed(const char *const *names, const char *name)
{
    for (size_t i = 0; names != NULL && names[i] != NULL; i++) {
        if (strcmp(names[i], name) == 0) {
            return true;
        }
    }
    return false;
}

/* A key's value in the image where the scenario left it to the drive
 * (NaN: derived at the start, the ratings' defaults): the parameter set's
 * or the app's; the R^ band the controller's. */
static double image_value(const scenario_key_info_t *k, const drive_params_t *p, const app_cfg_t *ac, double Ts_s)
{
    if (strcmp(k->section, "controller") == 0 && strcmp(k->name, "R_min_ohm") == 0) {
        return (double)ac->ctrl.est_cfg.R_min_Ohm;
    }
    if (strcmp(k->section, "controller") == 0 && strcmp(k->name, "R_max_ohm") == 0) {
        return (double)ac->ctrl.est_cfg.R_max_Ohm;
    }
    if (strcmp(k->section, "controller") == 0 && strcmp(k->name, "encoder_offset_el_rad") == 0) {
        return (double)p->board.enc_offset_el_rad; /* the told one; 0 until the alignment's with align on */
    }
    if (k->to.target == SC_TO_PARAMS) {
        return scenario_loc_read(&k->to, p, Ts_s);
    }
    return (k->to.target == SC_TO_APP) ? scenario_loc_read(&k->to, ac, Ts_s) : NAN;
}

static void json_group(FILE *js, const json_group_t *g, const scenario_t *sc, const drive_params_t *p,
                       const app_cfg_t *ac, double Ts_s)
{
    const char *sep = "";
    fprintf(js, " \"%s\": {", g->group);
    for (int i = 0; i < scenario_key_count(); i++) {
        scenario_key_info_t k;
        scenario_key_info(i, &k);
        if (strcmp(k.section, g->section) != 0 || (g->only != NULL && !listed(g->only, k.name)) ||
            listed(g->skip, k.name)) {
            continue;
        }
        fprintf(js, "%s\n  ", sep);
        sep = ",";
        if (k.type == SC_KEY_REAL && isnan(scenario_key_value(sc, i))) {
            json_num(js, k.name, image_value(&k, p, ac, Ts_s), ""); /* left to the drive: the image's */
        } else {
            /* the resolved value as .resolved.json's "keys" spell it */
            fprintf(js, "\"%s\": ", k.name);
            scenario_key_json(js, sc, i);
        }
    }
    fputs("\n }", js);
}

int board_config_write(FILE *h, FILE *js, const scenario_t *sc, const char *scenario_path,
                       const char *const *overrides, int n_sets, char *err, size_t errlen)
{
    static drive_params_t p;
    static app_cfg_t ac;
    sil_drive_config(sc, &p, &ac);
    const double Ts_s = (double)p.board.Ts_s;

    fputs("/* drive_config.h - the F28335 image's configuration, generated by drive_sil --board-config\n", h);
    fprintf(h, " * (drive_sil %s) from ", sil_revision);
    fputs(scenario_path, h);
    for (int i = 0; i < n_sets; i++) {
        fprintf(h, " --set %s", overrides[i]);
    }
    fputs(".\n * Do not edit: edit the motor file and run make board again (tools/sil/board_config.h).\n"
          " * Read through hal/f28335/board_hw.h when DRIVE_CONFIG is defined. */\n"
          "#ifndef DRIVE_CONFIG_H\n#define DRIVE_CONFIG_H\n\n", h);
    if (facts_macros(h, sc, err, errlen) != 0 || params_macro(h, &p, err, errlen) != 0 ||
        app_macro(h, &ac, Ts_s, err, errlen) != 0) {
        return -1;
    }
    fputs("#endif /* DRIVE_CONFIG_H */\n", h);

    fputs("{\"scenario\": ", js);
    json_string(js, scenario_path);
    fputs(", \"overrides\": [", js);
    for (int i = 0; i < n_sets; i++) {
        json_string(js, overrides[i]);
        fputs((i + 1 < n_sets) ? ", " : "", js);
    }
    fputs("], \"drive_sil\": ", js);
    json_string(js, sil_revision);
    fputs(",\n", js);
    for (size_t g = 0; g < sizeof GROUPS / sizeof GROUPS[0]; g++) {
        json_group(js, &GROUPS[g], sc, &p, &ac, Ts_s);
        fputs((g + 1 < sizeof GROUPS / sizeof GROUPS[0]) ? ",\n" : "\n}\n", js);
    }
    return 0;
}
