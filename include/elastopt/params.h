/// @file params.h
/// Typed parameter structs described by descriptor tables.
///
/// Each configurable thing (a method, a config section) has a plain C struct and one
/// `eo_param_desc` table. The table alone drives: defaults, loading from a JSON object,
/// `-o key=value` overrides, range checks, `--help` text and echoing the effective
/// values back as JSON. Keys equal the field names.
///
/// ```c
/// typedef struct { int max_iters; double c1; } my_params;
/// static const eo_param_desc my_desc[] = {
///     { .key = "max_iters", .kind = EO_PARAM_INT, .offset = offsetof(my_params, max_iters),
///       .def.i = 50, .min = 1, .range = EO_RANGE_MIN, .help = "iteration cap" },
///     { .key = "c1", .kind = EO_PARAM_DOUBLE, .offset = offsetof(my_params, c1),
///       .def.d = 1e-4, .min = 0, .max = 1, .range = EO_RANGE_OPEN, .help = "Armijo constant" },
///     { 0 } };
/// my_params p; eo_params_default(my_desc, &p);
/// rc = eo_params_load(ctx, my_desc, &p, json_section, &where);
/// ```
/// Ownership: descriptor tables are static const; values are copied into the struct
/// (strings into fixed char arrays of `.size` bytes), nothing is borrowed.
#ifndef ELASTOPT_PARAMS_H
#define ELASTOPT_PARAMS_H

#include "export.h"
#include <stddef.h>
#include <stdio.h>
#include "ctx.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct json_t json_t; /* jansson */

typedef enum eo_param_kind {
    EO_PARAM_END = 0,  ///< terminates a table
    EO_PARAM_INT,      ///< int
    EO_PARAM_DOUBLE,   ///< double
    EO_PARAM_BOOL,     ///< int 0/1
    EO_PARAM_STRING,   ///< char[.size]
    EO_PARAM_CHOICE,   ///< char[.size], one of .choices
    EO_PARAM_METHOD,   ///< char[.size], a name registered in .registry
    EO_PARAM_VEC3      ///< double[3]
} eo_param_kind;

enum {
    EO_RANGE_MIN = 1,       ///< value >= min
    EO_RANGE_MAX = 2,       ///< value <= max
    EO_RANGE_MIN_OPEN = 4,  ///< value > min
    EO_RANGE_MAX_OPEN = 8,  ///< value < max
    EO_RANGE_CLOSED = EO_RANGE_MIN | EO_RANGE_MAX,
    EO_RANGE_OPEN = EO_RANGE_MIN_OPEN | EO_RANGE_MAX_OPEN,
    EO_RANGE_POSITIVE = EO_RANGE_MIN_OPEN  ///< with min = 0
};

typedef struct eo_param_desc {
    const char *key;           ///< config key, equal to the field name
    eo_param_kind kind;
    size_t offset;             ///< offsetof(struct, field)
    size_t size;               ///< bytes of a string field (STRING/CHOICE/METHOD)
    union {
        long i;                ///< INT, BOOL
        double d;              ///< DOUBLE
        const char *s;         ///< STRING, CHOICE, METHOD
        double v[3];           ///< VEC3
    } def;                     ///< documented default
    double min, max;           ///< range, used as told by .range
    unsigned range;            ///< EO_RANGE_* bits; 0 = unbounded
    const char *const *choices;///< CHOICE: NULL-terminated list; METHOD: extra values
                               ///< accepted besides the registered names (e.g. "auto"),
                               ///< given a meaning by the table's owner (NULL: none)
    const struct eo_registry *registry; ///< METHOD: the registry of the kind (registry.h)
    const char *help;          ///< one line: meaning and unit
} eo_param_desc;

/// Where values come from, for error messages: config file path and its text (to
/// find the line of a key), or the command-line override text.
typedef struct eo_param_src {
    const char *file;   ///< config file path, or "-o" for command-line overrides
    const char *text;   ///< the file's text (may be NULL)
    const char *path;   ///< dotted key path of the section being loaded ("solver.newton")
    const char *overridden; ///< "\npath\npath\n": full key paths set by -o (may be NULL);
                            ///< errors on those keys name the override, not the file
} eo_param_src;

/// Number of entries of a table (up to the END entry).
EO_API size_t eo_params_count(const eo_param_desc *d);
/// Find a key in a table; NULL if absent.
EO_API const eo_param_desc *eo_params_find(const eo_param_desc *d, const char *key);
/// Set every field of `obj` to its default.
EO_API void eo_params_default(const eo_param_desc *d, void *obj);
/// Check every field against its range/choices. EO_ERR_RANGE with the key named.
EO_API int eo_params_check(eo_ctx *ctx, const eo_param_desc *d, const void *obj, const eo_param_src *src);
/// Load the members of a JSON object into `obj`. Keys not in the table are an error
/// (EO_ERR_UNKNOWN_KEY listing the valid keys) unless listed in `extra_keys`
/// (NULL-terminated; sub-sections the caller handles). Type mismatch: EO_ERR_TYPE;
/// out of range: EO_ERR_RANGE; unknown choice/method: EO_ERR_UNKNOWN_NAME.
EO_API int eo_params_load(eo_ctx *ctx, const eo_param_desc *d, void *obj, const json_t *section,
                   const char *const *extra_keys, const eo_param_src *src);
/// Set one field from a JSON value (already parsed), with the same checks.
EO_API int eo_params_set_json(eo_ctx *ctx, const eo_param_desc *p, void *obj, const json_t *value,
                       const eo_param_src *src);
/// Echo the effective values as a new JSON object (caller owns the reference).
EO_API json_t *eo_params_to_json(const eo_param_desc *d, const void *obj);
/// JSON Schema (draft 2020-12) of a params table: an object with one property per key
/// (type, enum of choices or registered names, range, default, description) and
/// additionalProperties false. New reference.
EO_API json_t *eo_params_schema(const eo_param_desc *d, const char *description);
/// Print `--help` lines: "  prefix.key  type  default  range — help".
EO_API void eo_params_help(FILE *f, const eo_param_desc *d, const char *prefix);
/// Format the valid keys of a table, comma-separated, into buf.
EO_API void eo_params_keys(const eo_param_desc *d, const char *const *extra, char *buf, size_t n);

/// Parse the value text of `-o key=value`: JSON if it parses as JSON (numbers, true,
/// false, arrays, quoted strings, objects), else a plain string. New reference.
EO_API json_t *eo_json_from_override(const char *text);
/// Byte offset of the first byte of `s` (NUL-terminated) that is not valid UTF-8
/// (overlong forms, surrogates and code points beyond U+10FFFF are invalid), or -1.
EO_API long eo_utf8_invalid_at(const char *s);
/// Find the 1-based line and column of a dotted key path ("solver.newton.c1",
/// list items as "boundary.2") in JSON text. Returns 0 if found, -1 if not.
EO_API int eo_json_locate(const char *text, const char *path, long *line, long *col);
/// Name of a JSON value's type ("number", "string", ...).
EO_API const char *eo_json_type_name(const json_t *v);
/// json_dumps(j, flags) with every real written in its shortest round-trip form
/// (eo_fmt_double of io.h: 0.4 as 0.4, not 0.40000000000000002), still marked as a real
/// ("1.0"); any JSON_REAL_PRECISION in flags is replaced. Returns a malloc'ed string
/// (free() it), NULL when out of memory.
EO_API char *eo_json_dumps(const json_t *j, size_t flags);
/// A JSON value for messages, with its article and, for arrays, its length: "an array
/// of 2", "an empty array", "a string", "an integer", "a number", "a boolean", "null",
/// "an object", "nothing" (v NULL). Written into buf (n bytes, 32 is enough) and returned.
/// Every "expected an array of N ..." message uses it: "got an array of 2".
EO_API const char *eo_json_describe(const json_t *v, char *buf, size_t n);

#ifdef __cplusplus
}
#endif
#endif
