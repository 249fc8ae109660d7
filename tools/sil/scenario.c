/* scenario.c - the scenario keys (the table of scenario_keys.h), INI loading
 * (libinih), overrides and the mapping into the configuration; see scenario.h. */
#include "scenario.h"
#include "sim_units.h"

#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "drive_params.h"
#include "hal_sim.h"
#include "link_params.h"

/* K_RPROFILE: a positive profile starting at t = 0 (a bare number is a
 * constant); its value at t = 0 also goes to the double at offset_t0. */
typedef enum { K_REAL, K_UINT, K_ENUM, K_PROFILE, K_RPROFILE } key_kind_t;

typedef struct {
    const char *section;
    const char *name;
    key_kind_t kind;
    size_t offset;             /* of the field in scenario_t */
    size_t offset_t0;          /* K_RPROFILE: the double that takes the value at t = 0 */
    double lo, hi;             /* K_REAL, K_UINT: allowed range */
    bool lo_open;              /* K_REAL: lo itself excluded */
    const char *const *names;  /* K_ENUM: value k is names[k] */
    const char *def;           /* default as text; NULL: unset (NaN, resolved in scenario_finish) */
    const char *from_keys;     /* def DERIVED: the keys it is derived from */
    sc_loc_t from;             /* def PARAMS: where the default is read */
    sc_loc_t to;               /* where the value goes */
    const char *help;
} sc_key_t;

static const char *const SC_MODEL_NAMES[] = { "averaged", "switching", NULL };
static const char *const SC_METHOD_NAMES[] = { "conventional", "proposed", NULL };
static const char *const SC_MODE_NAMES[] = { "speed", "torque", "open_loop", NULL };
static const char *const SC_ONOFF_NAMES[] = { "off", "on", NULL };
static const char *const SC_RSID_NAMES[] = { "off", "windows", "speeds", "trusted", NULL };
static const char *const SC_PHASE_NAMES[] = { "a", "b", "c", NULL };
static const char *const SC_PAIR_NAMES[] = { "ab", "bc", "ca", NULL };
static const char *const SC_CHANNEL_NAMES[] = { "a", "b", NULL };
static const char *const SC_REFUSAL_NAMES[] = { "fault", "conventional", "told", NULL };
static const char *const SC_TRACK_NAMES[] = { "off", "on", "auto", NULL };
static const char *const SC_DIRECTION_NAMES[] = { "1", "-1", NULL };   /* sc_direction_t */
static const char *const SC_ORDER_NAMES[] = { "abc", "acb", NULL };   /* sc_phase_order_t */

/* Keys whose default is not text of this table but a configuration's
 * value: the drive's parameter set (firmware/params/drive_params.h, the board's
 * values), the app's configuration of the board (app_cfg_default), or,
 * for the simulated board's own settings (ideal inverter and ADC), its
 * defaults (hal_sim_default_cfg). See params_default(). */
static const char PARAMS[] = "(drive_params)";
/* Keys derived in scenario_finish from the motor's data (drive_params_derive;
 * firmware/params/params_design.md) unless set: NaN until then. */
static const char DERIVED[] = "(derived)";

#define SC_UINT32_MAX_D 4294967295.0
#define SC_UINT16_MAX_D 65535.0        /* drive_params_t's pole_pairs is 16 bits */

/* scenario_keys.h's columns, expanded into sc_key_t */
#define SC_KIND_REAL K_REAL
#define SC_KIND_UINT K_UINT
#define SC_KIND_ENUM K_ENUM
#define SC_KIND_PROF K_PROFILE
#define SC_KIND_RPROF K_RPROFILE
#define SC_OFFSET_REAL(sec, key) offsetof(scenario_t, sec.key), 0
#define SC_OFFSET_UINT(sec, key) offsetof(scenario_t, sec.key), 0
#define SC_OFFSET_ENUM(sec, key) offsetof(scenario_t, sec.key), 0
#define SC_OFFSET_PROF(sec, key) offsetof(scenario_t, sec.key), 0
#define SC_OFFSET_RPROF(sec, key) offsetof(scenario_t, sec.key##_profile), offsetof(scenario_t, sec.key)
#define SC_GT0 0.0, HUGE_VAL, true, NULL
#define SC_GE0 0.0, HUGE_VAL, false, NULL
#define SC_ANY -HUGE_VAL, HUGE_VAL, false, NULL
#define SC_IN(lo, hi) lo, hi, false, NULL
#define SC_NAMES(n) 0.0, 0.0, false, n
#define SC_NONE 0.0, 0.0, false, NULL
#define SC_TEXT(t) t, NULL
#define SC_PARAMS PARAMS, NULL
#define SC_DERIVED(from) DERIVED, from
#define SC_UNSET NULL, NULL
#define SC_LOC(tgt, type, f, conv, scale) { tgt, offsetof(type, f), SC_CONV_##conv, scale, #f }
#define SC_P(f, conv, scale) SC_LOC(SC_TO_PARAMS, drive_params_t, f, conv, scale)
#define SC_A(f, conv, scale) SC_LOC(SC_TO_APP, app_cfg_t, f, conv, scale)
#define SC_S(f, conv, scale) SC_LOC(SC_TO_SIM, hal_sim_cfg_t, f, conv, scale)
#define SC_F(f, conv, scale) SC_LOC(SC_TO_FAULTS, hal_sim_faults_t, f, conv, scale)
#define SC_L(f, conv, scale) SC_LOC(SC_TO_LINK, link_cfg_t, f, conv, scale)
#define SC_NO { SC_TO_NONE, 0, SC_CONV_NONE, 1.0, NULL }
#define SC_SAME { SC_TO_SAME, 0, SC_CONV_NONE, 1.0, NULL }
#define SC_KEY(sec, key, KIND, range, def, from, to, help) \
    { #sec, #key, SC_KIND_##KIND, SC_OFFSET_##KIND(sec, key), range, def, from, to, help },

static const sc_key_t KEYS[] = { SC_KEYS(SC_KEY) };

#define N_KEYS ((int)(sizeof KEYS / sizeof KEYS[0]))

typedef char sc_key_table_fits[(N_KEYS <= SCENARIO_MAX_KEYS) ? 1 : -1];

static void *field(scenario_t *sc, const sc_key_t *k)
{
    return (char *)sc + k->offset;
}

/* The double at offset in a scenario read only. */
static double real_value(const scenario_t *sc, size_t offset)
{
    return *(const double *)(const void *)((const char *)sc + offset);
}

static int find_key(const char *section, const char *name, int *section_known)
{
    *section_known = 0;
    for (int i = 0; i < N_KEYS; i++) {
        if (strcmp(KEYS[i].section, section) == 0) {
            *section_known = 1;
            if (strcmp(KEYS[i].name, name) == 0) {
                return i;
            }
        }
    }
    return -1;
}

int scenario_key_known(const char *section, const char *name)
{
    int known;
    return find_key(section, name, &known) >= 0;
}

/* ---- plausibility ----------------------------------------------------------
 * Bounds that refuse the absurd (a unit slip: mH written as H, a typo), not
 * the merely beyond-limit: a value past the drive's ratings or trips runs and
 * may fault (a speed reference above overspeed_rpm trips OVERSPEED). Each
 * bound holds for the plant's value on every point of a profile;
 * scenario_finish() checks them, drive_sil --help prints them
 * (scenario_print_bounds). The controller's values that are the drive's
 * parameters on the link are checked against the link's table
 * (firmware/link/link_params.h: one range for the key and the link's WRITE),
 * after the factors and the derived keys are resolved (check_params). */
#define R_PLAUSIBLE_OHM (double)LINK_PARAM_R_OHM_LO, (double)LINK_PARAM_R_OHM_HI     /* the link's (link_params.h) */
#define L_PLAUSIBLE_H (double)LINK_PARAM_L_H_LO, (double)LINK_PARAM_L_H_HI
#define PSIF_PLAUSIBLE_WB (double)LINK_PARAM_PSIF_WB_LO, (double)LINK_PARAM_PSIF_WB_HI
#define J_PLAUSIBLE_KGM2 (double)LINK_PARAM_J_KGM2_LO, (double)LINK_PARAM_J_KGM2_HI
#define SPEED_PLAUSIBLE_RPM -1e5, 1e5

#define F(field) offsetof(scenario_t, field)
typedef enum { B_REAL, B_UINT, B_PROFILE } bound_kind_t;

typedef struct {
    const char *section, *name;   /* the key */
    bound_kind_t kind;
    size_t offset;                /* of its double, uint32_t or profile_t in scenario_t */
    double lo, hi;                /* plausible: lo <= value <= hi */
    const char *unit;
    const char *factor;           /* [controller] key whose factor x the plant's value it may be, or NULL */
} sc_bound_t;

static const sc_bound_t BOUNDS[] = {
    { "plant", "R_ohm", B_PROFILE, F(plant.R_ohm_profile), R_PLAUSIBLE_OHM, "ohm", NULL },
    { "plant", "L_H", B_REAL, F(plant.L_H), L_PLAUSIBLE_H, "H", NULL },
    { "plant", "psif_Wb", B_REAL, F(plant.psif_Wb), PSIF_PLAUSIBLE_WB, "Wb", NULL },
    { "plant", "pole_pairs", B_UINT, F(plant.pole_pairs), 1.0, 64.0, "", NULL },
    { "plant", "J_kgm2", B_REAL, F(plant.J_kgm2), J_PLAUSIBLE_KGM2, "kg m^2", NULL },
    { "plant", "vdc_V", B_REAL, F(plant.vdc_V), 5.0, 1500.0, "V", NULL },
    { "plant", "speed0_rpm", B_REAL, F(plant.speed0_rpm), SPEED_PLAUSIBLE_RPM, "r/min", NULL },
    { "identify", "speed_1_rpm", B_REAL, F(identify.speed_1_rpm), SPEED_PLAUSIBLE_RPM, "r/min", NULL },
    { "identify", "speed_2_rpm", B_REAL, F(identify.speed_2_rpm), SPEED_PLAUSIBLE_RPM, "r/min", NULL },
    { "reference", "speed_rpm", B_PROFILE, F(reference.speed_rpm), SPEED_PLAUSIBLE_RPM, "r/min", NULL },
};
#define N_BOUNDS ((int)(sizeof BOUNDS / sizeof BOUNDS[0]))

static int parse_real(const sc_key_t *k, const char *v, double *out, char *err, size_t errlen)
{
    char *end;
    errno = 0;
    double x = strtod(v, &end);
    while (*end == ' ' || *end == '\t') {
        end++;
    }
    if (end == v || *end != '\0' || errno == ERANGE || !isfinite(x)) {
        snprintf(err, errlen, "\"%s\" is not a number", v);
        return -1;
    }
    if (x < k->lo || (k->lo_open && x <= k->lo)) {
        snprintf(err, errlen, "%g is out of range (must be %s %g)", x, k->lo_open ? ">" : ">=", k->lo);
        return -1;
    }
    if (x > k->hi) {
        snprintf(err, errlen, "%g is out of range (must be <= %g)", x, k->hi);
        return -1;
    }
    *out = x;
    return 0;
}

static int parse_uint(const sc_key_t *k, const char *v, uint32_t *out, char *err, size_t errlen)
{
    const char *p = v;
    while (*p >= '0' && *p <= '9') {
        p++;
    }
    if (p == v || *p != '\0') {
        snprintf(err, errlen, "\"%s\" is not a whole number", v);
        return -1;
    }
    errno = 0;
    double x = strtod(v, NULL);
    if (x < k->lo || x > k->hi) {
        snprintf(err, errlen, "%s is out of range (%g .. %g)", v, k->lo, k->hi);
        return -1;
    }
    *out = (uint32_t)x;
    return 0;
}

static int parse_enum(const sc_key_t *k, const char *v, uint32_t *out, char *err, size_t errlen)
{
    for (uint32_t i = 0; k->names[i] != NULL; i++) {
        if (strcmp(k->names[i], v) == 0) {
            *out = i;
            return 0;
        }
    }
    int n = snprintf(err, errlen, "unknown value \"%s\" (one of:", v);
    for (uint32_t i = 0; k->names[i] != NULL && n > 0 && (size_t)n < errlen; i++) {
        n += snprintf(err + n, errlen - (size_t)n, " %s", k->names[i]);
    }
    if (n > 0 && (size_t)n < errlen) {
        snprintf(err + n, errlen - (size_t)n, ")");
    }
    return -1;
}

/* K_RPROFILE: text into the profile (appended or replacing), which must
 * start at t = 0 with every value > 0; *t0 = its value at t = 0. */
static int parse_rprofile(const sc_key_t *k, profile_t *p, double *t0, const char *v, bool append,
                          char *err, size_t errlen)
{
    profile_t q = *p;
    if (!append) {
        q.n = 0u;
    }
    if (profile_parse_append(&q, v, err, errlen) != 0) {
        return -1;
    }
    if (q.n == 0u || q.pt[0].t_s > 0.0) {
        snprintf(err, errlen, "\"%s\": the profile must start at t = 0", v);
        return -1;
    }
    for (uint32_t j = 0; j < q.n; j++) {
        if (!(q.pt[j].value > k->lo)) {
            snprintf(err, errlen, "%g is out of range (must be > %g)", q.pt[j].value, k->lo);
            return -1;
        }
    }
    *p = q;
    *t0 = q.pt[0].value;
    return 0;
}

/* Set key i from text v; append: extend a profile instead of replacing it. */
/* True when v spells the number zero ("0", "0.0", "0e3"). */
static bool zero_text(const char *v)
{
    char *end;
    const double x = strtod(v, &end);
    while (*end == ' ' || *end == '\t') {
        end++;
    }
    return end != v && *end == '\0' && !(x < 0.0) && !(x > 0.0);
}

static int set_value(scenario_t *sc, int i, const char *v, bool append, char *err, size_t errlen)
{
    const sc_key_t *k = &KEYS[i];
    switch (k->kind) {
    case K_REAL:
        if (sc->run.endless_ok && (double *)field(sc, k) == &sc->run.duration_s && zero_text(v)) {
            sc->run.duration_s = 0.0;   /* run until the link's host ends it (drive_sil --link) */
            return 0;
        }
        return parse_real(k, v, (double *)field(sc, k), err, errlen);
    case K_UINT:
        return parse_uint(k, v, (uint32_t *)field(sc, k), err, errlen);
    case K_ENUM:
        return parse_enum(k, v, (uint32_t *)field(sc, k), err, errlen);
    case K_PROFILE: {
        profile_t *p = (profile_t *)field(sc, k);
        if (!append) {
            p->n = 0u;
        }
        return profile_parse_append(p, v, err, errlen);
    }
    case K_RPROFILE:
        return parse_rprofile(k, (profile_t *)field(sc, k), (double *)((char *)sc + k->offset_t0), v, append,
                              err, errlen);
    }
    return -1;
}

/* The value at loc in *base, in the key's unit (Ts_s: a period for SC_CONV_PERIODS). */
static double loc_read(const sc_loc_t *loc, const void *base, double Ts_s)
{
    const char *at = (const char *)base + loc->offset;
    switch (loc->conv) {
    case SC_CONV_U16:
        return (double)*(const uint16_t *)(const void *)at;
    case SC_CONV_U32:
        return (double)*(const uint32_t *)(const void *)at;
    case SC_CONV_U64:
        return (double)*(const uint64_t *)(const void *)at;
    case SC_CONV_I32:
        return (double)*(const int32_t *)(const void *)at;
    case SC_CONV_ENUM:
        return (double)*(const unsigned int *)(const void *)at;
    case SC_CONV_PERIODS:
        return (double)*(const uint32_t *)(const void *)at * Ts_s;
    case SC_CONV_F64:
        return *(const double *)(const void *)at * loc->scale;
    case SC_CONV_BOOL:
        return *(const bool *)(const void *)at ? 1.0 : 0.0;
    case SC_CONV_F32:
        return (double)*(const float *)(const void *)at * loc->scale;
    case SC_CONV_NONE:
        break;
    }
    return NAN;
}

/* Value v (the key's unit) into loc in *base; NaN leaves it. */
static void loc_write(const sc_loc_t *loc, void *base, double v, double Ts_s)
{
    char *at = (char *)base + loc->offset;
    if (isnan(v)) {
        return;
    }
    switch (loc->conv) {
    case SC_CONV_U16:
        *(uint16_t *)(void *)at = (uint16_t)v;
        break;
    case SC_CONV_U32:
        *(uint32_t *)(void *)at = (uint32_t)v;
        break;
    case SC_CONV_U64:
        *(uint64_t *)(void *)at = (uint64_t)v;
        break;
    case SC_CONV_I32:
        *(int32_t *)(void *)at = (int32_t)llround(v);
        break;
    case SC_CONV_ENUM:
        *(unsigned int *)(void *)at = (unsigned int)v;
        break;
    case SC_CONV_PERIODS:
        *(uint32_t *)(void *)at = (uint32_t)llround(v / Ts_s);
        break;
    case SC_CONV_F64:
        *(double *)(void *)at = v / loc->scale;
        break;
    case SC_CONV_BOOL:
        *(bool *)(void *)at = (v != 0.0);
        break;
    case SC_CONV_F32:
        *(float *)(void *)at = (float)(v / loc->scale);
        break;
    case SC_CONV_NONE:
        break;
    }
}

double scenario_loc_read(const sc_loc_t *loc, const void *cfg, double Ts_s)
{
    return loc_read(loc, cfg, Ts_s);
}

/* Where key k's value goes: SC_TO_SAME resolved to where its default is read. */
static const sc_loc_t *key_to(const sc_key_t *k)
{
    return (k->to.target == SC_TO_SAME) ? &k->from : &k->to;
}

/* The default of a PARAMS key as text: the board's value in the key's
 * unit, to 6 significant digits (the decimal board_cfg.h spells: 0.011f
 * reads 0.011, not 0.0109999999); an enum key's value (or an on/off
 * key's 0/1) by its name. "" for a value with no name. */
static const char *params_default(const sc_key_t *k, char *buf, size_t len)
{
    static drive_params_t p;
    static app_cfg_t ac; /* large: not on the stack */
    static hal_sim_cfg_t hs;
    static link_cfg_t lc;
    drive_params_board(&p);
    app_cfg_default(&ac);
    hal_sim_default_cfg(&hs);
    link_cfg_default(&lc);
    buf[0] = '\0';
    const sc_loc_t *q = &k->from;
    const void *src = (q->target == SC_TO_PARAMS) ? (const void *)&p
                      : (q->target == SC_TO_APP)  ? (const void *)&ac
                      : (q->target == SC_TO_LINK) ? (const void *)&lc
                                                  : (const void *)&hs;
    const double v = loc_read(q, src, (double)ac.ctrl.Ts_s);
    if (k->kind != K_ENUM) {
        snprintf(buf, len, "%.6g", v);
        /* a float read back from 6 digits that is not the same float
         * (a derived constant): every digit of it */
        if (q->conv == SC_CONV_F32 &&
            (float)(strtod(buf, NULL) / q->scale) != *(const float *)(const void *)((const char *)src + q->offset)) {
            snprintf(buf, len, "%.9g", v);
        }
        return buf;
    }
    for (size_t n = 0; k->names[n] != NULL; n++) {
        if ((double)n == v) {
            snprintf(buf, len, "%s", k->names[n]);
        }
    }
    return buf;
}

/* A key's default as text: the table's, or the parameter set's; NULL: unset. */
static const char *default_text(const sc_key_t *k, char *buf, size_t len)
{
    if (k->def == DERIVED) {
        return NULL;
    }
    return (k->def == PARAMS) ? params_default(k, buf, len) : k->def;
}

void scenario_defaults(scenario_t *sc)
{
    memset(sc, 0, sizeof *sc);
    char err[SCENARIO_ERR_LEN];
    char buf[32];
    for (int i = 0; i < N_KEYS; i++) {
        const char *def = default_text(&KEYS[i], buf, sizeof buf);
        if (def == NULL) {
            *(double *)field(sc, &KEYS[i]) = NAN;
        } else if (set_value(sc, i, def, false, err, sizeof err) != 0) {
            /* a PARAMS value with no name: a bug of the table, not of
             * the user's input */
            fprintf(stderr, "scenario.c: the default of [%s] %s does not parse: %s\n", KEYS[i].section,
                    KEYS[i].name, err);
            abort();
        }
    }
}

/* After n = snprintf(err, errlen, ...): a message cut to errlen ends in
 * "..." so that it does not read as complete. */
static void err_mark_cut(int n, char *err, size_t errlen)
{
    static const char CUT[] = "...";
    if (n >= 0 && (size_t)n >= errlen && errlen >= sizeof CUT) {
        memcpy(err + errlen - sizeof CUT, CUT, sizeof CUT);
    }
}

/* Apply one key; on failure write "WHERE: [section] key: problem" to err. */
static int apply(scenario_t *sc, const char *where, const char *section, const char *name,
                 const char *value, bool append, char *err, size_t errlen)
{
    int known = 0;
    int i = find_key(section, name, &known);
    char why[SCENARIO_ERR_LEN];
    if (section[0] == '\0') {
        snprintf(err, errlen, "%s: %s: a key before any [section] line", where, name);
        return -1;
    }
    if (i < 0) {
        snprintf(err, errlen, "%s: [%s] %s: %s", where, section, name,
                 known ? "unknown key" : "unknown section");
        return -1;
    }
    if (value[0] == '\0') {
        snprintf(err, errlen, "%s: [%s] %s: no value (give one, or leave the key out for its default)", where,
                 section, name);
        return -1;
    }
    if (set_value(sc, i, value, append, why, sizeof why) != 0) {
        /* where and why may each fill their buffers: err takes what fits */
        err_mark_cut(snprintf(err, errlen, "%s: [%s] %s: %s", where, section, name, why), err, errlen);
        return -1;
    }
    snprintf(sc->origin[i], SCENARIO_ORIGIN_LEN, "%s", where);
    return 0;
}

/* ---- INI files ------------------------------------------------------------- */

typedef struct {
    scenario_t *sc;
    const char *path;
    FILE *f;
    int lineno;                      /* of the line inih is handling */
    bool indented;                   /* that line starts with a blank: a continuation */
    bool seen[SCENARIO_MAX_KEYS];    /* set earlier in this file */
    int first_line[SCENARIO_MAX_KEYS];   /* where, when seen */
    char err[SCENARIO_ERR_LEN];      /* first error, "" if none */
} load_ctx_t;

/* A line "[name" without its "]": inih would name no error before the next
 * key, as one in section "" - this names the line. */
static void header_check(load_ctx_t *ctx, const char *line)
{
    const char *p = line + strspn(line, " \t");
    if (*p != '[' || strchr(p, ']') != NULL || ctx->err[0] != '\0') {
        return;
    }
    const int len = (int)strcspn(p, "\r\n");
    snprintf(ctx->err, sizeof ctx->err, "%s:%d: section line \"%.*s\" has no closing ']'", ctx->path, ctx->lineno,
             len, p);
}

/* inih's line reader, counting lines so every message can name one, and
 * refusing lines longer than inih's buffer instead of splitting them. */
static char *read_line(char *buf, int num, void *stream)
{
    load_ctx_t *ctx = stream;
    int n = 0;
    int ch = EOF;
    bool too_long = false;
    while ((ch = fgetc(ctx->f)) != EOF) {
        if (n < num - 1) {
            buf[n++] = (char)ch;
        } else {
            too_long = true;
        }
        if (ch == '\n') {
            break;
        }
    }
    if (n == 0 && ch == EOF) {
        return NULL;
    }
    buf[n] = '\0';
    ctx->lineno++;
    ctx->indented = (buf[0] == ' ' || buf[0] == '\t');
    header_check(ctx, buf);
    if (too_long && ctx->err[0] == '\0') {
        snprintf(ctx->err, sizeof ctx->err, "%s:%d: line longer than %d characters (continue a profile on an indented line)",
                 ctx->path, ctx->lineno, num - 2);
        buf[0] = '\0';
    }
    return buf;
}

static int on_key(void *user, const char *section, const char *name, const char *value)
{
    load_ctx_t *ctx = user;
    if (strcmp(section, SCENARIO_IGNORED_SECTION) == 0) {
        return 1;
    }
    char where[SCENARIO_ORIGIN_LEN];
    snprintf(where, sizeof where, "%s:%d", ctx->path, ctx->lineno);
    int known = 0;
    int i = find_key(section, name, &known);
    bool append = false;
    if (i >= 0 && ctx->seen[i]) {
        if (KEYS[i].kind != K_PROFILE && KEYS[i].kind != K_RPROFILE) {
            if (ctx->err[0] == '\0') {
                snprintf(ctx->err, sizeof ctx->err, "%s: [%s] %s: given twice (first at %s:%d)",
                         where, section, name, ctx->path, ctx->first_line[i]);
            }
            return 0;
        }
        append = true;   /* continuation line, or the key again: extends the profile */
    }
    char err[SCENARIO_ERR_LEN];
    if (apply(ctx->sc, where, section, name, value, append, err, sizeof err) != 0) {
        if (ctx->err[0] != '\0') {
            return 0;
        }
        if (append && !ctx->indented) {
            /* the key again: say so before what its value lacks as more of the profile */
            char prefix[SCENARIO_ERR_LEN];
            const int n = snprintf(prefix, sizeof prefix, "%s: [%s] %s: ", where, section, name);
            const char *why = (n > 0 && strncmp(err, prefix, (size_t)n) == 0) ? err + n : err;
            err_mark_cut(snprintf(ctx->err, sizeof ctx->err,
                                  "%s: [%s] %s: given twice (first at %s:%d; a repeated profile key adds t:value "
                                  "points to it): %s",
                                  where, section, name, ctx->path, ctx->first_line[i], why),
                         ctx->err, sizeof ctx->err);
        } else {
            snprintf(ctx->err, sizeof ctx->err, "%s", err);
        }
        return 0;
    }
    if (append) {
        snprintf(ctx->sc->origin[i], SCENARIO_ORIGIN_LEN, "%s", ctx->path);
    } else {
        ctx->first_line[i] = ctx->lineno;
    }
    ctx->seen[i] = true;
    return 1;
}

int scenario_load(scenario_t *sc, const char *path, char *err, size_t errlen)
{
    load_ctx_t ctx;
    memset(&ctx, 0, sizeof ctx);
    ctx.sc = sc;
    ctx.path = path;
    ctx.f = fopen(path, "r");
    if (ctx.f == NULL) {
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(errno));
        return -1;
    }
    int rc = ini_parse_stream(read_line, &ctx, on_key, &ctx);
    fclose(ctx.f);
    if (ctx.err[0] != '\0') {
        snprintf(err, errlen, "%s", ctx.err);
        return -1;
    }
    if (rc != 0) {
        snprintf(err, errlen, "%s:%d: syntax error (expected [section] or key = value)", path, rc);
        return -1;
    }
    return 0;
}

int scenario_set(scenario_t *sc, const char *assignment, char *err, size_t errlen)
{
    char where[SCENARIO_ORIGIN_LEN];
    snprintf(where, sizeof where, "--set %s", assignment);
    return scenario_set_from(sc, assignment, where, err, errlen);
}

int scenario_set_from(scenario_t *sc, const char *assignment, const char *where, char *err, size_t errlen)
{
    char buf[SCENARIO_ERR_LEN];
    if (strlen(assignment) >= sizeof buf) {
        snprintf(err, errlen, "%s: too long", where);
        return -1;
    }
    strcpy(buf, assignment);
    char *eq = strchr(buf, '=');
    char *dot = strchr(buf, '.');
    if (eq == NULL || dot == NULL || dot > eq) {
        snprintf(err, errlen, "%s: expected section.key=value", where);
        return -1;
    }
    *eq = '\0';
    *dot = '\0';
    return apply(sc, where, buf, dot + 1, eq + 1, false, err, errlen);
}

/* ---- cross-key checks ------------------------------------------------------ */

/* Controller value from absolute key abs_i or factor key fac_i (not both) times the plant value. */
static int resolve(scenario_t *sc, const char *abs_name, const char *fac_name, double plant_value,
                   double *abs_v, double fac_v, char *err, size_t errlen)
{
    int known = 0;
    int ia = find_key("controller", abs_name, &known);
    int iff = find_key("controller", fac_name, &known);
    if (!isnan(*abs_v) && !isnan(fac_v)) {
        snprintf(err, errlen, "%s: [controller] %s: conflicts with %s set at %s (give one of them)",
                 sc->origin[ia], abs_name, fac_name, sc->origin[iff]);
        return -1;
    }
    if (isnan(*abs_v)) {
        *abs_v = (isnan(fac_v) ? 1.0 : fac_v) * plant_value;
    }
    return 0;
}

/* method = proposed with step 1 off would run the conventional method
 * unannounced (ctrl.h): refused, naming the fix. */
static int check_identify(const scenario_t *sc, char *err, size_t errlen)
{
    int known = 0;
    const int i_mode = find_key("identify", "mode", &known);
    const int i_method = find_key("controller", "method", &known);
    if (sc->controller.method != SC_METHOD_PROPOSED || sc->identify.mode != SC_RSID_OFF) {
        return 0;
    }
    /* where mode was set to off, else where the method was asked for */
    const char *where = (sc->origin[i_mode][0] != '\0') ? sc->origin[i_mode] : sc->origin[i_method];
    snprintf(err, errlen,
             "%s: [identify] mode: off with [controller] method = proposed: the proposed method needs step 1; "
             "set [identify] mode = windows | speeds (identify R), or trusted (the controller's R_ohm is right), "
             "or method = conventional",
             where);
    return -1;
}

/* [faults] encoder_jump_counts: a count is whole, and within a 32-bit jump. */
static int check_faults(const scenario_t *sc, char *err, size_t errlen)
{
    int known = 0;
    const int i = find_key("faults", "encoder_jump_counts", &known);
    const double n = sc->faults.encoder_jump_counts;
    if (n == floor(n) && fabs(n) <= 2147483647.0) {
        return 0;
    }
    snprintf(err, errlen, "%s: [faults] encoder_jump_counts: %g is not a whole number of counts (|n| < 2^31)",
             sc->origin[i], n);
    return -1;
}

/* [controller] i_limit_A: never above the peak rating, and below the
 * overcurrent trip by drive_trip_margin_A() (the ADC's noise), or the drive
 * would trip where it should limit. Set by the user: named; derived: the rating and the ADC
 * range named, with the numbers. */
static int check_limits(const scenario_t *sc, char *err, size_t errlen)
{
    int known = 0;
    const int i = find_key("controller", "i_limit_A", &known);
    const int i_pk = find_key("motor", "i_peak_A", &known);
    const int i_ir = find_key("motor", "i_rated_A", &known);
    const int i_fs = find_key("plant", "adc_full_scale_A", &known);
    drive_params_t p;
    scenario_params(sc, &p);
    if ((sc->derive_status & DRIVE_DERIVE_I_LIMIT) != 0u) {
        snprintf(err, errlen, "%s: [controller] i_limit_A: %g A is above the motor's peak current [motor] i_peak_A = %g A",
                 sc->origin[i], sc->controller.i_limit_A, (double)p.rating.i_peak_A);
        return -1;
    }
    const double margin = (double)drive_trip_margin_A(&p);
    if (sc->controller.i_limit_A + margin <= sc->controller.i_max_A) {
        return 0;
    }
    if (sc->origin[i][0] != '\0') {
        snprintf(err, errlen,
                 "%s: [controller] i_limit_A: %g A is not below the overcurrent trip i_max_A (%g A) by the %.3g A "
                 "a sample at the limit may read above it (6 sigma of the ADC's noise)",
                 sc->origin[i], sc->controller.i_limit_A, sc->controller.i_max_A, margin);
        return -1;
    }
    const char *where = (sc->origin[i_pk][0] != '\0') ? sc->origin[i_pk]
                        : (sc->origin[i_fs][0] != '\0') ? sc->origin[i_fs] : sc->origin[i_ir];
    snprintf(err, errlen,
             "%s: [motor] i_peak_A = %g A: the current limit (i_limit_A = i_peak_A) plus the %.3g A a sample at "
             "it may read above it (6 sigma of the ADC's noise) reaches the overcurrent trip (i_max_A %g A: 1.26 x i_peak_A, at most "
             "%.4g A, the largest current the ADC reads: [plant] adc_full_scale_A = %g A less the accepted offset); "
             "a wider ADC range (above %.4g A) or a lower i_peak_A",
             (where[0] != '\0') ? where : "[motor]", (double)p.rating.i_peak_A, margin, sc->controller.i_max_A,
             (double)drive_i_readable_A(&p), sc->plant.adc_full_scale_A,
             sc->controller.i_limit_A * sc->plant.adc_full_scale_A / ((double)drive_i_readable_A(&p) - margin));
    return -1;
}

void scenario_map(const scenario_t *sc, sc_target_t target, void *cfg, double Ts_s)
{
    for (int i = 0; i < N_KEYS; i++) {
        const sc_key_t *k = &KEYS[i];
        const sc_loc_t *to = key_to(k);
        /* a derived key nobody set stays to derive (DRIVE_PARAM_DERIVED): the parameter set
         * then knows it derived it (a derived torque limit follows the learned psi_f) */
        if (to->target == target && !(k->def == DERIVED && sc->origin[i][0] == '\0')) {
            const double v = (k->kind == K_REAL || k->kind == K_RPROFILE)
                                 ? real_value(sc, (k->kind == K_RPROFILE) ? k->offset_t0 : k->offset)
                                 : (double)*(const uint32_t *)(const void *)((const char *)sc + k->offset);
            loc_write(to, cfg, v, Ts_s);
        }
    }
}

void scenario_params(const scenario_t *sc, drive_params_t *p)
{
    hal_sim_cfg_t hs;
    hal_sim_default_cfg(&hs);
    drive_params_board(p);
    /* the board's bus limits relative to its nominal bus, at the scenario's bus */
    const float bus_scale = (float)sc->plant.vdc_V / p->board.vdc_nominal_V;
    p->limits.vdc_max_V = p->limits.vdc_max_V * bus_scale;
    p->limits.vdc_min_V = p->limits.vdc_min_V * bus_scale;
    /* the keys whose target is the parameter set: the controller's values
     * (what it is told), the ratings, the tuning; a derived key left to
     * derive (NaN) keeps the board's DRIVE_PARAM_DERIVED */
    scenario_map(sc, SC_TO_PARAMS, p, hs.inv.Ts_s);
    /* what the controller is told of the board: the plant's, as if measured */
    p->board.vdc_nominal_V = (float)sc->plant.vdc_V;
    p->board.i_full_scale_A = (float)sc->plant.adc_full_scale_A;
    p->board.enc_lines = sc->plant.encoder_lines;
    p->board.Ts_s = (float)hs.inv.Ts_s;
    /* the dead time as if measured, unless the scenario gives the controller another */
    if (isnan(sc->controller.deadtime_s)) {
        p->board.deadtime_s = (float)sc->plant.deadtime_s;
    }
    /* align off: told [controller] encoder_offset_el_rad, else the plant's as if measured;
     * on: the alignment's measurement replaces it */
    const double enc_told = isnan(sc->controller.encoder_offset_el_rad) ? sc->plant.encoder_offset_el_rad
                                                                        : sc->controller.encoder_offset_el_rad;
    p->board.enc_offset_el_rad = (sc->run.align == SC_ON) ? 0.0f : (float)enc_told;
    /* the ratings left out: i_peak 2 x i_rated, n_max n_rated */
    if (isnan(sc->motor.i_peak_A)) {
        p->rating.i_peak_A = (float)(2.0 * sc->motor.i_rated_A);
    }
    if (isnan(sc->motor.n_max_rpm)) {
        p->rating.n_max_rad_s = (float)(sc->motor.n_rated_rpm / SIM_RPM_PER_RAD_S);
    }
}

int scenario_key_set(const scenario_t *sc, const char *section, const char *name)
{
    int known = 0;
    const int i = find_key(section, name, &known);
    return (i >= 0 && sc->origin[i][0] != '\0') ? 1 : 0;
}

void scenario_warnings(const scenario_t *sc, char *buf, size_t len)
{
    buf[0] = '\0';
    if ((sc->derive_status & DRIVE_DERIVE_WARN_BEMF) != 0u) {
        const double n_max = isnan(sc->motor.n_max_rpm) ? sc->motor.n_rated_rpm : sc->motor.n_max_rpm;
        const double e_V = n_max / SIM_RPM_PER_RAD_S * (double)sc->controller.pole_pairs * sc->controller.psif_Wb;
        snprintf(buf, len,
                 "BEMF_ABOVE_BUS: the back-EMF at [motor] n_max_rpm = %g r/min is %.4g V, beyond the bus's "
                 "phase-voltage limit [plant] vdc_V / sqrt(3) = %.4g V (a trip there generates into the bus)",
                 n_max, e_V, sc->plant.vdc_V / sqrt(3.0));
    }
}

/* The derived keys left unset: derived from the motor's data (drive_params_derive);
 * a motor the drive cannot run refused, naming the keys. */
static int derive_keys(scenario_t *sc, char *err, size_t errlen)
{
    drive_params_t p;
    int known = 0;
    const int i_ir = find_key("motor", "i_rated_A", &known);
    scenario_params(sc, &p);
    const drive_derive_t st = drive_params_derive(&p);
    sc->derive_status = st;
    if ((st & DRIVE_DERIVE_RATINGS) != 0u) {
        snprintf(err, errlen,
                 "%s: [motor]: ratings do not fit: i_rated_A %g A, i_peak_A %g A (>= i_rated_A), t_peak_s %g s, "
                 "n_rated_rpm %g, n_max_rpm %g (>= n_rated_rpm)",
                 (sc->origin[i_ir][0] != '\0') ? sc->origin[i_ir] : "[motor]", (double)p.rating.i_rated_A,
                 (double)p.rating.i_peak_A, (double)p.rating.t_peak_s, (double)p.rating.n_rated_rad_s * SIM_RPM_PER_RAD_S,
                 (double)p.rating.n_max_rad_s * SIM_RPM_PER_RAD_S);
        return -1;
    }
    if ((st & DRIVE_DERIVE_OBSERVER) != 0u && sc->controller.method == SC_METHOD_PROPOSED) {
        snprintf(err, errlen,
                 "[controller] L_H, R_ohm: no observer gain for this motor: its L/R = %g s is %.3g PWM periods "
                 "(Ts = %g s), below the %g periods the observer needs (its own decay e^(-Ts R/L) must stay "
                 "above its designed pole; a shorter PWM period or method = conventional)",
                 sc->controller.L_H / sc->controller.R_ohm,
                 sc->controller.L_H / (sc->controller.R_ohm * (double)p.board.Ts_s), (double)p.board.Ts_s,
                 (double)SMO_LR_MIN_PERIODS);
        return -1;
    }
    for (int i = 0; i < N_KEYS; i++) {
        const sc_key_t *k = &KEYS[i];
        double *v = (double *)field(sc, k);
        if (k->def == DERIVED && isnan(*v)) {
            *v = loc_read(&k->to, &p, 0.0);
        }
    }
    return 0;
}

/* Level 4's current limit: below the limit of the full drive. */
static int check_level(const scenario_t *sc, char *err, size_t errlen)
{
    int known = 0;
    const int i = find_key("run", "level4_i_limit_A", &known);
    if (sc->run.level4_i_limit_A <= sc->controller.i_limit_A) {
        return 0;
    }
    snprintf(err, errlen, "%s: [run] level4_i_limit_A: %g A is above [controller] i_limit_A (%g A)",
             sc->origin[i], sc->run.level4_i_limit_A, sc->controller.i_limit_A);
    return -1;
}

/* Where bound b's value came from, for its message: the key's line, else
 * (a controller value from its factor) the factor's, else the plant's. */
static const char *bound_origin(const scenario_t *sc, const sc_bound_t *b, char *how, size_t howlen)
{
    int known = 0;
    const int i = find_key(b->section, b->name, &known);
    how[0] = '\0';
    if (sc->origin[i][0] != '\0' || b->factor == NULL) {
        return (sc->origin[i][0] != '\0') ? sc->origin[i] : "the defaults";
    }
    const int f = find_key("controller", b->factor, &known);
    const int p = find_key("plant", b->name, &known);
    const double fac = *(const double *)(const void *)((const char *)sc + KEYS[f].offset);
    snprintf(how, howlen, " (%s %g x [plant] %s)", b->factor, isnan(fac) ? 1.0 : fac, b->name);
    if (sc->origin[f][0] != '\0') {
        return sc->origin[f];
    }
    return (sc->origin[p][0] != '\0') ? sc->origin[p] : "the defaults";
}

/* The first value of bound b outside it (*v; for a profile of several
 * points, its time *t_s, else NaN); false if none. */
static bool bound_broken(const scenario_t *sc, const sc_bound_t *b, double *v, double *t_s)
{
    const char *at = (const char *)sc + b->offset;
    *t_s = NAN;
    if (b->kind == B_PROFILE) {
        const profile_t *pr = (const profile_t *)(const void *)at;
        for (uint32_t n = 0; n < pr->n; n++) {
            *v = pr->pt[n].value;
            if (!(*v >= b->lo && *v <= b->hi)) {
                *t_s = (pr->n > 1u) ? pr->pt[n].t_s : NAN;
                return true;
            }
        }
        return false;
    }
    *v = (b->kind == B_UINT) ? (double)*(const uint32_t *)(const void *)at : *(const double *)(const void *)at;
    /* NaN: a derived key not yet derived (derive_keys runs after) */
    return !isnan(*v) && !(*v >= b->lo && *v <= b->hi);
}

/* The [controller] factor key of a told value, or NULL. */
static const char *factor_of(const char *key)
{
    static const char *const ABS[] = { "R_ohm", "L_H", "psif_Wb" };
    static const char *const FAC[] = { "R_factor", "L_factor", "psif_factor" };
    for (size_t i = 0; i < sizeof ABS / sizeof ABS[0]; i++) {
        if (strcmp(ABS[i], key) == 0) {
            return FAC[i];
        }
    }
    return NULL;
}

/* The controller's values that are the drive's parameters (firmware/link/link_params.h) within the
 * link's ranges, after the factors and the derived keys; else err names key, value and range.
 * A value left to the plant's (NaN: encoder offset, dead time) is the plant's own key's. */
static int check_params(const scenario_t *sc, char *err, size_t errlen)
{
    for (uint16_t k = 0u; k < (uint16_t)LINK_PARAM_COUNT; k++) {
        const link_param_t *d = link_param(k);
        int known = 0;
        const int i = find_key("controller", d->key, &known);
        const double v = (KEYS[i].kind == K_UINT) ? (double)*(const uint32_t *)(const void *)((const char *)sc + KEYS[i].offset)
                                                  : real_value(sc, KEYS[i].offset);
        if (isnan(v) || link_param_ok(k, (float)v)) {
            continue;
        }
        char how[SCENARIO_ORIGIN_LEN] = "";
        const char *where = (sc->origin[i][0] != '\0') ? sc->origin[i] : "the defaults";
        const char *fac = factor_of(d->key);
        const int f = (fac != NULL) ? find_key("controller", fac, &known) : -1;
        if (sc->origin[i][0] == '\0' && f >= 0) {
            const double x = real_value(sc, KEYS[f].offset);
            snprintf(how, sizeof how, " (%s %g x [plant] %s)", fac, isnan(x) ? 1.0 : x, d->key);
            where = (sc->origin[f][0] != '\0') ? sc->origin[f] : where;
        }
        const char *sp = (d->unit[0] != '\0') ? " " : "";
        err_mark_cut(snprintf(err, errlen, "%s: [controller] %s: %g%s%s%s is not plausible: the bound is %s%g .. %g%s%s",
                              where, d->key, v, sp, d->unit, how, d->lo_open ? "> " : "", (double)d->lo,
                              (double)d->hi, sp, d->unit),
                     err, errlen);
        return -1;
    }
    return 0;
}

/* Every BOUNDS value within its bound; else err names key, value and bound. */
static int check_bounds(const scenario_t *sc, char *err, size_t errlen)
{
    for (int j = 0; j < N_BOUNDS; j++) {
        const sc_bound_t *b = &BOUNDS[j];
        double v = 0.0;
        double t_s = NAN;
        if (!bound_broken(sc, b, &v, &t_s)) {
            continue;
        }
        char how[SCENARIO_ORIGIN_LEN];
        const char *where = bound_origin(sc, b, how, sizeof how);
        if (!isnan(t_s)) {
            snprintf(how, sizeof how, " (at t = %g s)", t_s);
        }
        const char *sp = (b->unit[0] != '\0') ? " " : "";
        err_mark_cut(snprintf(err, errlen, "%s: [%s] %s: %g%s%s%s is not plausible: the bound is %g .. %g%s%s", where,
                              b->section, b->name, v, sp, b->unit, how, b->lo, b->hi, sp, b->unit),
                     err, errlen);
        return -1;
    }
    return 0;
}

int scenario_finish(scenario_t *sc, char *err, size_t errlen)
{
    if (sc->controller.pole_pairs == 0u) {
        sc->controller.pole_pairs = sc->plant.pole_pairs;
    }
    if (resolve(sc, "R_ohm", "R_factor", sc->plant.R_ohm, &sc->controller.R_ohm,
                sc->controller.R_factor, err, errlen) != 0 ||
        resolve(sc, "L_H", "L_factor", sc->plant.L_H, &sc->controller.L_H,
                sc->controller.L_factor, err, errlen) != 0 ||
        resolve(sc, "psif_Wb", "psif_factor", sc->plant.psif_Wb, &sc->controller.psif_Wb,
                sc->controller.psif_factor, err, errlen) != 0) {
        return -1;
    }
    if (isnan(sc->controller.J_kgm2)) {
        sc->controller.J_kgm2 = sc->plant.J_kgm2;
    }
    if (isnan(sc->controller.B_Nms)) {
        sc->controller.B_Nms = sc->plant.B_Nms;
    }
    if (check_bounds(sc, err, errlen) != 0 || derive_keys(sc, err, errlen) != 0 ||
        check_params(sc, err, errlen) != 0) {
        return -1;
    }
    /* level 4's limit from the current limit, derived or set */
    if (isnan(sc->run.level4_i_limit_A)) {
        sc->run.level4_i_limit_A = SC_LEVEL4_I_LIMIT_PER_LIMIT * sc->controller.i_limit_A;
    }
    if (check_level(sc, err, errlen) != 0 || check_faults(sc, err, errlen) != 0 ||
        check_limits(sc, err, errlen) != 0) {
        return -1;
    }
    return check_identify(sc, err, errlen);
}

void scenario_print_keys(FILE *f)
{
    const char *section = "";
    for (int i = 0; i < N_KEYS; i++) {
        const sc_key_t *k = &KEYS[i];
        if (strcmp(k->section, section) != 0) {
            section = k->section;
            fprintf(f, "  [%s]\n", section);
        }
        char buf[32];
        const char *text = default_text(k, buf, sizeof buf);
        const char *def = (k->def == DERIVED) ? "derived" : ((text == NULL) ? "-" : ((k->kind == K_PROFILE) ? "0" : text));
        fprintf(f, "    %-22s %-13s %s\n", k->name, def, k->help);
    }
    fprintf(f, "  [%s]  skipped: drive-campaign's tolerance distributions (tools/drivekit/CAMPAIGN_KEYS.md)\n",
            SCENARIO_IGNORED_SECTION);
}

void scenario_print_bounds(FILE *f)
{
    fprintf(f, "Plausibility bounds (a value outside is refused, exit 2; the controller's after its factor):\n");
    for (int j = 0; j < N_BOUNDS; j++) {
        const sc_bound_t *b = &BOUNDS[j];
        char key[SCENARIO_ORIGIN_LEN];
        snprintf(key, sizeof key, "[%s] %s", b->section, b->name);
        fprintf(f, "    %-26s %g .. %g%s%s\n", key, b->lo, b->hi, (b->unit[0] != '\0') ? " " : "", b->unit);
    }
    for (uint16_t k = 0u; k < (uint16_t)LINK_PARAM_COUNT; k++) {   /* the link's parameters' ranges */
        const link_param_t *d = link_param(k);
        char key[SCENARIO_ORIGIN_LEN];
        snprintf(key, sizeof key, "[controller] %s", d->key);
        fprintf(f, "    %-26s %s%g .. %g%s%s\n", key, d->lo_open ? "> " : "", (double)d->lo, (double)d->hi,
                (d->unit[0] != '\0') ? " " : "", d->unit);
    }
}

void scenario_print_keys_markdown(FILE *f)
{
    fputs("# Scenario keys\n\n"
          "Generated from `tools/sil/scenario_keys.h` by `drive_sil --list-keys --markdown`\n"
          "(`make scenario-keys` rewrites it; `make test` checks it). The format, the\n"
          "defaults' sources and notes on the keys: `tools/sil/README.md`; the values\n"
          "derived from the motor's data: `firmware/params/params_design.md`.\n\n"
          "Default: a value; `derived` (from the keys named, unless set); `-` (unset:\n"
          "see the meaning). Range: what the parser accepts (the plausibility bounds\n"
          "of `drive_sil --help` come on top). A `[" SCENARIO_IGNORED_SECTION "]` section is skipped: it\n"
          "holds `drive-campaign`'s tolerance distributions\n"
          "(`tools/drivekit/CAMPAIGN_KEYS.md`), so one file serves both.\n\n"
          "| section | key | default | range | meaning |\n"
          "| --- | --- | --- | --- | --- |\n", f);
    for (int i = 0; i < N_KEYS; i++) {
        const sc_key_t *k = &KEYS[i];
        char buf[32];
        char range[96];
        const char *text = default_text(k, buf, sizeof buf);
        const char *def = (k->def == DERIVED) ? "derived" : ((text == NULL) ? "-" : ((k->kind == K_PROFILE) ? "0" : text));
        switch (k->kind) {
        case K_REAL:
            if (k->lo == -HUGE_VAL) {
                snprintf(range, sizeof range, "number");
            } else if (k->hi < HUGE_VAL) {
                snprintf(range, sizeof range, "%g .. %g", k->lo, k->hi);
            } else {
                snprintf(range, sizeof range, "%s %g", k->lo_open ? ">" : ">=", k->lo);
            }
            break;
        case K_UINT:
            snprintf(range, sizeof range, "%g .. %g", k->lo, k->hi);
            break;
        case K_ENUM: {
            int n = 0;
            range[0] = '\0';
            for (size_t j = 0; k->names[j] != NULL && n >= 0 && (size_t)n < sizeof range; j++) {
                n += snprintf(range + n, sizeof range - (size_t)n, "%s%s", (j > 0u) ? " \\| " : "", k->names[j]);
            }
            break;
        }
        case K_PROFILE:
            snprintf(range, sizeof range, "profile");
            break;
        case K_RPROFILE:
            snprintf(range, sizeof range, "profile from t = 0, > 0");
            break;
        }
        fprintf(f, "| %s | %s | %s%s%s | %s | ", k->section, k->name, def, (k->from_keys != NULL) ? ": " : "",
                (k->from_keys != NULL) ? k->from_keys : "", range);
        for (const char *c = k->help; *c != '\0'; c++) {
            if (*c == '|') {
                fputc('\\', f);
            }
            fputc(*c, f);
        }
        fputs(" |\n", f);
    }
}

int scenario_key_count(void)
{
    return N_KEYS;
}

void scenario_key_info(int i, scenario_key_info_t *out)
{
    const sc_key_t *k = &KEYS[i];
    out->section = k->section;
    out->name = k->name;
    out->help = k->help;
    out->from_keys = k->from_keys;
    out->to = *key_to(k);
    out->lo = k->lo;
    out->hi = k->hi;
    out->names = k->names;
    out->type = (k->kind == K_REAL)   ? SC_KEY_REAL
                : (k->kind == K_UINT) ? SC_KEY_UINT
                : (k->kind == K_ENUM) ? SC_KEY_ENUM
                                      : SC_KEY_PROFILE;
}

double scenario_key_value(const scenario_t *sc, int i)
{
    const sc_key_t *k = &KEYS[i];
    if (k->kind == K_REAL) {
        return real_value(sc, k->offset);
    }
    if (k->kind == K_UINT || k->kind == K_ENUM) {
        return (double)*(const uint32_t *)(const void *)((const char *)sc + k->offset);
    }
    return NAN;
}

void scenario_key_json(FILE *f, const scenario_t *sc, int i)
{
    const sc_key_t *k = &KEYS[i];
    const char *at = (const char *)sc + k->offset;
    switch (k->kind) {
    case K_REAL: {
        const double v = real_value(sc, k->offset);
        if (isfinite(v)) {
            fprintf(f, "%.10g", v);
        } else {
            fputs("null", f);
        }
        return;
    }
    case K_UINT:
        fprintf(f, "%lu", (unsigned long)*(const uint32_t *)(const void *)at);
        return;
    case K_ENUM:
        fprintf(f, "\"%s\"", k->names[*(const uint32_t *)(const void *)at]);
        return;
    case K_PROFILE:
    case K_RPROFILE:
        break;
    }
    const profile_t *pr = (const profile_t *)(const void *)at;
    fputc('[', f);
    for (uint32_t n = 0; n < pr->n; n++) {
        fprintf(f, "%s[%.10g, %.10g, %s]", (n > 0u) ? ", " : "", pr->pt[n].t_s, pr->pt[n].value,
                pr->pt[n].ramp ? "true" : "false");
    }
    fputc(']', f);
}
