/* ini_edit.c - an INI file copied with keys set, removed or noted; see ini_edit.h. */
#include "ini_edit.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

#define INI_LINE_MAX 4096
#define INI_NAME_MAX 128
#define INI_EDITS_MAX 256

/* s[0..n) without surrounding blanks into out (at most len - 1 characters). */
static void trimmed(const char *s, size_t n, char *out, size_t len)
{
    while (n > 0u && isspace((unsigned char)s[0])) {
        s++;
        n--;
    }
    while (n > 0u && isspace((unsigned char)s[n - 1u])) {
        n--;
    }
    if (n >= len) {
        n = len - 1u;
    }
    memcpy(out, s, n);
    out[n] = '\0';
}

/* The last edit of section.key, or -1. */
static int edit_of(const ini_edit_t *e, size_t n, const char *section, const char *key)
{
    int found = -1;
    for (size_t i = 0; i < n; i++) {
        if (strcmp(e[i].section, section) == 0 && strcmp(e[i].key, key) == 0) {
            found = (int)i;
        }
    }
    return found;
}

/* The edits of section not yet written (the last of each key), at its end. */
static void flush_section(FILE *out, const ini_edit_t *e, size_t n, const char *section, unsigned char *done)
{
    for (size_t i = 0; i < n; i++) {
        if (done[i] || strcmp(e[i].section, section) != 0 || edit_of(e, n, section, e[i].key) != (int)i) {
            continue;
        }
        done[i] = 1u;
        if (e[i].kind == INI_REMOVE) {
            continue;
        }
        if (e[i].why != NULL) {
            fprintf(out, "; %s\n", e[i].why);
        }
        fprintf(out, "%s%s = %s\n", (e[i].kind == INI_NOTE) ? "; " : "", e[i].key, e[i].value);
    }
}

/* A "key = value" line (p: past its indent, eq: at its = or :) of section:
 * as it is, or as the key's edit says (set; removed, with why). */
static void key_line(FILE *out, const char *line, const char *p, const char *eq, const ini_edit_t *e, size_t n,
                     const char *section, unsigned char *done)
{
    char key[INI_NAME_MAX];
    trimmed(p, (size_t)(eq - p), key, sizeof key);
    const int i = edit_of(e, n, section, key);
    if (i < 0 || done[i]) {
        fputs(line, out);
        return;
    }
    done[i] = 1u;
    if (e[i].kind == INI_SET) {
        fprintf(out, "%s = %s\n", key, e[i].value);
        return;
    }
    if (e[i].why != NULL) {
        fprintf(out, "; %s\n", e[i].why);
    }
    fprintf(out, "; removed: %s", p);
    if (line[strlen(line) - 1u] != '\n') {
        fputc('\n', out);
    }
}

/* The edits of sections the file does not have, each section at the end under its header. */
static void new_sections(FILE *out, const ini_edit_t *e, size_t n, unsigned char *done)
{
    for (size_t i = 0; i < n; i++) {
        if (!done[i] && e[i].kind != INI_REMOVE && edit_of(e, n, e[i].section, e[i].key) == (int)i) {
            fprintf(out, "\n[%s]\n", e[i].section);
            flush_section(out, e, n, e[i].section, done);
        }
    }
}

int ini_edit_copy(FILE *in, FILE *out, const ini_edit_t *e, size_t n)
{
    static char line[INI_LINE_MAX];
    char section[INI_NAME_MAX] = "";
    unsigned char done[INI_EDITS_MAX];
    if (n > INI_EDITS_MAX) {
        n = INI_EDITS_MAX;
    }
    memset(done, 0, sizeof done);
    unsigned blanks = 0u;   /* blank lines held back: a section's additions go before them */
    while (fgets(line, sizeof line, in) != NULL) {
        const char *p = line;
        while (*p == ' ' || *p == '\t') {
            p++;
        }
        if (*p == '\n' || *p == '\r' || *p == '\0') {
            blanks++;
            continue;
        }
        if (*p == '[') {
            const char *end = strchr(p, ']');
            if (end != NULL) {
                flush_section(out, e, n, section, done);
                trimmed(p + 1, (size_t)(end - p - 1), section, sizeof section);
            }
        }
        for (; blanks > 0u; blanks--) {
            fputc('\n', out);
        }
        const char *eq = strpbrk(p, "=:");
        if (*p == '[' || *p == ';' || *p == '#' || eq == NULL) {
            fputs(line, out);
        } else {
            key_line(out, line, p, eq, e, n, section, done);
        }
    }
    if (ferror(in)) {
        return -1;
    }
    flush_section(out, e, n, section, done);
    for (; blanks > 0u; blanks--) {
        fputc('\n', out);
    }
    new_sections(out, e, n, done);
    return 0;
}
