/*
 * sil_scenario.h - test helper of the SIL tests: tools/scenarios/<name>.ini
 * loaded over the defaults, overrides applied, finished. Any parser error
 * fails the test with the parser's own message (FILE:LINE: [section] key).
 * Include after <cmocka.h>.
 */
#ifndef SIL_SCENARIO_H
#define SIL_SCENARIO_H

#include <stdio.h>

#include "scenario.h"

/* Defaults, then tools/scenarios/<name>.ini. */
static inline void sil_scenario_open(scenario_t *sc, const char *name)
{
    char path[128];
    char err[SCENARIO_ERR_LEN];

    scenario_defaults(sc);
    snprintf(path, sizeof path, "tools/scenarios/%s.ini", name);
    if (scenario_load(sc, path, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
}

/* Overrides "section.key=value", NULL-terminated; sets may be NULL. */
static inline void sil_scenario_set(scenario_t *sc, const char *const *sets)
{
    char err[SCENARIO_ERR_LEN];

    for (const char *const *s = sets; s != NULL && *s != NULL; s++) {
        if (scenario_set(sc, *s, err, sizeof err) != 0) {
            fail_msg("%s", err);
        }
    }
}

/* Resolves and checks the scenario (scenario_finish). */
static inline void sil_scenario_finish(scenario_t *sc)
{
    char err[SCENARIO_ERR_LEN];

    if (scenario_finish(sc, err, sizeof err) != 0) {
        fail_msg("%s", err);
    }
}

#endif /* SIL_SCENARIO_H */
