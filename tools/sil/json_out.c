/* json_out.c - JSON of drive_sil's outputs; see json_out.h. */
#include "json_out.h"

#include <math.h>

void json_string(FILE *f, const char *text)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)text; *p != '\0'; p++) {
        if (*p == '"' || *p == '\\') {
            fprintf(f, "\\%c", *p);
        } else if (*p < 0x20u) {
            fprintf(f, "\\u%04x", *p);
        } else {
            fputc(*p, f);
        }
    }
    fputc('"', f);
}

void json_num(FILE *f, const char *key, double v, const char *sep)
{
    if (isfinite(v)) {
        fprintf(f, "\"%s\": %.10g%s", key, v, sep);
    } else {
        fprintf(f, "\"%s\": null%s", key, sep);
    }
}

void json_flt(FILE *f, const char *key, float v, const char *sep)
{
    if (isfinite(v)) {
        fprintf(f, "\"%s\": %.7g%s", key, (double)v, sep);
    } else {
        fprintf(f, "\"%s\": null%s", key, sep);
    }
}
