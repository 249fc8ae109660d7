/* Unit tests for tools/sil/ini_edit: drive_sil --commission's OUT.ini is
 * the input with keys replaced in place, missing ones added at their
 * section's end (before its trailing blank lines; a missing section appended), removed keys kept as
 * comments, notes as comments; every other line as it was. Expected texts
 * written out by hand. */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>

#include "ini_edit.h"

#define OUT_LEN 4096

/* The edits applied to in_text, the result as a string. */
static const char *edit(const char *in_text, const ini_edit_t *e, size_t n)
{
    static char out[OUT_LEN];
    FILE *in = tmpfile();
    FILE *o = tmpfile();
    assert_non_null(in);
    assert_non_null(o);
    fputs(in_text, in);
    rewind(in);
    assert_int_equal(ini_edit_copy(in, o, e, n), 0);
    rewind(o);
    const size_t len = fread(out, 1, sizeof out - 1u, o);
    out[len] = '\0';
    fclose(in);
    fclose(o);
    return out;
}

static void keys_set_removed_noted_and_added(void **state)
{
    (void)state;
    const char *in = "; a scenario\n"
                     "[plant]\n"
                     "R_ohm = 0.5\n"
                     "\n"
                     "[controller]\n"
                     "R_factor = 1.5\n"
                     "  R_ohm: 9\n"
                     "method = conventional\n"
                     "[reference]\n"
                     "speed_rpm = 0:0, 0.1:450~\n";
    const ini_edit_t e[] = {
        { "controller", "R_ohm", "1", INI_SET, NULL },
        { "controller", "R_factor", NULL, INI_REMOVE, "measured" },
        { "controller", "L_H", "0.005", INI_SET, NULL },
        { "controller", "J_kgm2", "0.01", INI_NOTE, "no key" },
        { "controller", "R_ohm", "0.501", INI_SET, NULL },   /* the last of a key counts */
        { "run", "duration_s", "3", INI_SET, NULL },
        { "plant", "L_H", "0.011", INI_SET, NULL },         /* added before the blank line ending [plant] */
    };
    const char *want = "; a scenario\n"
                       "[plant]\n"
                       "R_ohm = 0.5\n"
                       "L_H = 0.011\n"
                       "\n"
                       "[controller]\n"
                       "; measured\n"
                       "; removed: R_factor = 1.5\n"
                       "R_ohm = 0.501\n"
                       "method = conventional\n"
                       "L_H = 0.005\n"
                       "; no key\n"
                       "; J_kgm2 = 0.01\n"
                       "[reference]\n"
                       "speed_rpm = 0:0, 0.1:450~\n"
                       "\n"
                       "[run]\n"
                       "duration_s = 3\n";
    assert_string_equal(edit(in, e, sizeof e / sizeof e[0]), want);
}

/* No [controller] in the input: appended with its sets; a removal of a
 * key that is not there leaves nothing. */
static void missing_section_is_appended(void **state)
{
    (void)state;
    const char *in = "[plant]\nvdc_V = 24";     /* no newline at the end */
    const ini_edit_t e[] = {
        { "controller", "L_factor", NULL, INI_REMOVE, "measured" },
        { "controller", "L_H", "0.0002", INI_SET, NULL },
    };
    assert_string_equal(edit(in, e, sizeof e / sizeof e[0]),
                        "[plant]\nvdc_V = 24\n[controller]\nL_H = 0.0002\n");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(keys_set_removed_noted_and_added),
        cmocka_unit_test(missing_section_is_appended),
    };
    return cmocka_run_group_tests_name("ini_edit", tests, NULL, NULL);
}
