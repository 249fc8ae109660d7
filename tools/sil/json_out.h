/*
 * json_out.h - the JSON drive_sil writes (.resolved.json, --summary,
 * --batch lines, --check): strings escaped, numbers to the digits they
 * hold, null for a value that is not finite. Each writer puts `sep` (", "
 * or the object's close) after the pair.
 */
#ifndef JSON_OUT_H
#define JSON_OUT_H

#include <stdio.h>

/* text as a JSON string (quoted; quotes, backslashes and control characters escaped). */
void json_string(FILE *f, const char *text);

/* "key": v to 10 significant digits (a double of the plant or a figure), then sep. */
void json_num(FILE *f, const char *key, double v, const char *sep);

/* "key": v to the digits a float holds (a controller value: 0.0165f reads 0.0165), then sep. */
void json_flt(FILE *f, const char *key, float v, const char *sep);

#endif /* JSON_OUT_H */
