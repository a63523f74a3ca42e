/* pg_json.c - the report-JSON builder; see pg_json.h.
 *
 * A node is an object, array, number, string or bool; containers keep their
 * children in insertion order in a growable array, which keeps reports readable
 * and diffs of reports stable. */
#include "planetgen/pg_json.h"

#include "pg_array.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef enum { J_OBJECT, J_ARRAY, J_NUMBER, J_STRING, J_BOOL } j_type;

struct pg_json {
    j_type type;
    char *key; /* member name when inside an object */
    double num;
    char *str;
    bool b;
    pg_json **items;
    size_t n, cap;
};

static pg_json *node_new(j_type t) {
    pg_json *j = calloc(1, sizeof *j);
    if (j) j->type = t;
    return j;
}

pg_json *pg_json_object(void) {
    return node_new(J_OBJECT);
}

pg_json *pg_json_array(void) {
    return node_new(J_ARRAY);
}

void pg_json_free(pg_json *j) {
    if (!j) return;
    for (size_t i = 0; i < j->n; i++)
        pg_json_free(j->items[i]);
    free(j->items);
    free(j->key);
    free(j->str);
    free(j);
}

static char *dup_str(const char *s) {
    size_t n = strlen(s ? s : "") + 1;
    char *d = malloc(n);
    if (d) memcpy(d, s ? s : "", n);
    return d;
}

static int append(pg_json *c, pg_json *child) {
    if (PG_ARRAY_RESERVE(c->items, &c->cap, c->n + 1, NULL)) return -1;
    c->items[c->n++] = child;
    return 0;
}

/* Attach child under key, replacing an existing member of that name. */
static pg_json *set_member(pg_json *obj, const char *key, pg_json *child) {
    if (!obj || !child || obj->type != J_OBJECT) {
        pg_json_free(child);
        return NULL;
    }
    child->key = dup_str(key);
    for (size_t i = 0; i < obj->n; i++) {
        if (strcmp(obj->items[i]->key, key) == 0) {
            pg_json_free(obj->items[i]);
            obj->items[i] = child;
            return child;
        }
    }
    if (append(obj, child) != 0) {
        pg_json_free(child);
        return NULL;
    }
    return child;
}

static pg_json *push(pg_json *arr, pg_json *child) {
    if (!arr || !child || arr->type != J_ARRAY || append(arr, child) != 0) {
        pg_json_free(child);
        return NULL;
    }
    return child;
}

pg_json *pg_json_set_object(pg_json *obj, const char *key) {
    return set_member(obj, key, node_new(J_OBJECT));
}

pg_json *pg_json_set_array(pg_json *obj, const char *key) {
    return set_member(obj, key, node_new(J_ARRAY));
}

static pg_json *num_node(double v) {
    pg_json *j = node_new(J_NUMBER);
    if (j) j->num = v;
    return j;
}

static pg_json *str_node(const char *v) {
    pg_json *j = node_new(J_STRING);
    if (j) j->str = dup_str(v);
    return j;
}

void pg_json_set_number(pg_json *obj, const char *key, double v) {
    set_member(obj, key, num_node(v));
}

void pg_json_set_string(pg_json *obj, const char *key, const char *v) {
    set_member(obj, key, str_node(v));
}

void pg_json_set_bool(pg_json *obj, const char *key, bool v) {
    pg_json *j = node_new(J_BOOL);
    if (j) j->b = v;
    set_member(obj, key, j);
}

pg_json *pg_json_push_object(pg_json *arr) {
    return push(arr, node_new(J_OBJECT));
}

void pg_json_push_number(pg_json *arr, double v) {
    push(arr, num_node(v));
}

void pg_json_push_string(pg_json *arr, const char *v) {
    push(arr, str_node(v));
}

static void write_string(const char *s, FILE *f) {
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        switch (*p) {
        case '"':
            fputs("\\\"", f);
            break;
        case '\\':
            fputs("\\\\", f);
            break;
        case '\n':
            fputs("\\n", f);
            break;
        case '\r':
            fputs("\\r", f);
            break;
        case '\t':
            fputs("\\t", f);
            break;
        default:
            if (*p < 0x20)
                fprintf(f, "\\u%04x", *p);
            else
                fputc(*p, f);
        }
    }
    fputc('"', f);
}

static void write_node(const pg_json *j, FILE *f, int depth) {
    switch (j->type) {
    case J_NUMBER:
        if (!isfinite(j->num))
            fputs("null", f);
        else if (j->num == floor(j->num) && fabs(j->num) < 1e15)
            fprintf(f, "%.0f", j->num);
        else
            fprintf(f, "%.10g", j->num);
        return;
    case J_STRING:
        write_string(j->str, f);
        return;
    case J_BOOL:
        fputs(j->b ? "true" : "false", f);
        return;
    default:
        break;
    }
    bool obj = j->type == J_OBJECT;
    if (j->n == 0) {
        fputs(obj ? "{}" : "[]", f);
        return;
    }
    fputs(obj ? "{\n" : "[\n", f);
    for (size_t i = 0; i < j->n; i++) {
        fprintf(f, "%*s", 2 * (depth + 1), "");
        if (obj) {
            write_string(j->items[i]->key, f);
            fputs(": ", f);
        }
        write_node(j->items[i], f, depth + 1);
        fputs(i + 1 < j->n ? ",\n" : "\n", f);
    }
    fprintf(f, "%*s%c", 2 * depth, "", obj ? '}' : ']');
}

int pg_json_write(const pg_json *j, FILE *f) {
    write_node(j, f, 0);
    fputc('\n', f);
    return ferror(f) ? -1 : 0;
}
