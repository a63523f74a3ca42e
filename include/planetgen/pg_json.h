/* pg_json.h - a tiny JSON document builder for planetgen's reports (--json).
 *
 * Reports are small trees of objects, numbers and strings; this builds them in
 * memory and serialises them with correct string escaping and no NaN/Inf (they
 * become null, as JSON has no such numbers). glTF JSON is NOT written with this:
 * tinygltf owns that format. */
#ifndef PLANETGEN_PG_JSON_H
#define PLANETGEN_PG_JSON_H

#include <stdbool.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pg_json pg_json;

pg_json *pg_json_object(void);
pg_json *pg_json_array(void);
void pg_json_free(pg_json *j);

/* Object members; each returns the value it set (for nesting), or NULL on OOM.
 * Setting an existing key replaces its value. */
pg_json *pg_json_set_object(pg_json *obj, const char *key);
pg_json *pg_json_set_array(pg_json *obj, const char *key);
void pg_json_set_number(pg_json *obj, const char *key, double v);
void pg_json_set_string(pg_json *obj, const char *key, const char *v);
void pg_json_set_bool(pg_json *obj, const char *key, bool v);

/* Array elements. */
pg_json *pg_json_push_object(pg_json *arr);
void pg_json_push_number(pg_json *arr, double v);
void pg_json_push_string(pg_json *arr, const char *v);

/* Serialise with two-space indentation. Returns 0 on success, -1 on write error. */
int pg_json_write(const pg_json *j, FILE *f);

#ifdef __cplusplus
}
#endif

#endif
