/*
 * ini_edit.h - an INI file copied with some keys set, removed or noted:
 * drive_sil --commission writes the input scenario with the measured
 * values (OUT.ini). Every other line, comments and blank lines included,
 * is copied as it is.
 */
#ifndef INI_EDIT_H
#define INI_EDIT_H

#include <stddef.h>
#include <stdio.h>

typedef enum {
    INI_SET = 0,               /* key = value: replaces the key's line, or is added at its section's end */
    INI_REMOVE = 1,            /* the key's line is kept as a comment after "; removed: " */
    INI_NOTE = 2               /* "; key = value" added at the section's end (a value with no key to take it) */
} ini_edit_kind_t;

typedef struct {
    const char *section;
    const char *key;
    const char *value;         /* INI_SET, INI_NOTE */
    ini_edit_kind_t kind;
    const char *why;           /* INI_REMOVE, INI_NOTE: a comment line before it, or NULL */
} ini_edit_t;

/* Copy the INI text of in to out with the edits (of the same section and
 * key, the last one counts); a section with a set or note but no header in
 * in is appended. Returns 0, or -1 on a read error of in. */
int ini_edit_copy(FILE *in, FILE *out, const ini_edit_t *edits, size_t n);

#endif /* INI_EDIT_H */
