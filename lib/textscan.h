/* Private: a tokenizer over a whole file held in memory, shared by every text mesh
 * reader so they all report errors the same way:
 *
 *     <file>:<line>: [<kind> <index>: ]expected <what>, got '<token>'
 *     <file>:<line>: [<kind> <index>: ]expected <what>, got end of file
 *
 * The text must be NUL-terminated (eo_read_file guarantees it). Numbers are parsed
 * in place with strtol/strtod: no allocation per token. A token ends at whitespace,
 * NUL or the comment character; "1.5abc" is one token and not a number.
 *
 * Also here: eo_tagmap, a map from arbitrary input ids (Gmsh node tags) to 0-based
 * indices, dense when the ids are compact, sorted + binary search otherwise. */
#ifndef EO_TEXTSCAN_H
#define EO_TEXTSCAN_H

#include <stddef.h>

#include "elastopt/ctx.h"

typedef struct eo_scan {
    eo_ctx *ctx;
    const char *file;  /* for messages (borrowed) */
    const char *p;     /* next unread character */
    const char *end;   /* one past the last character (*end == 0) */
    long line;         /* 1-based line of p */
    char comment;      /* comment character to end of line, 0 for none */
    const char *kind;  /* item being read, for messages ("tet", "vertex"); NULL = none */
    long index;        /* its index as the input numbers it, -1 = none */
    int in_record;     /* 1: tokens do not cross the end of the line (see eo_scan_record) */
    char sep;          /* 0, or one more separator read as a blank (',': "1, 0.5, 0, 0") */
} eo_scan;

void eo_scan_init(eo_scan *s, eo_ctx *ctx, const char *file, const char *text, size_t len, char comment);
/* Name the item being read (kind NULL to clear). */
static inline void eo_scan_item(eo_scan *s, const char *kind, long index)
{
    s->kind = kind;
    s->index = index;
}
/* Skip whitespace, newlines and comments. Returns 1 if a token follows, 0 at the end. */
int eo_scan_skip(eo_scan *s);
/* Start a one-line record: skip to its first token (crossing blank lines and comments)
 * and keep the following reads on that line, so a missing field reads "got end of
 * line" instead of taking the next line's first number. eo_scan_eol ends the record.
 * Returns the record's line. */
long eo_scan_record(eo_scan *s);
/* Next token (not NUL-terminated) without consuming it; 0 at the end. */
int eo_scan_peek(eo_scan *s, const char **tok, size_t *n);
/* 1 if the next token equals word (and consumes it), else 0. */
int eo_scan_accept(eo_scan *s, const char *word);
/* Consume the next token; EO_ERR_PARSE "expected <what>" at the end of the text. */
int eo_scan_word(eo_scan *s, const char *what, const char **tok, size_t *n);
/* Consume word exactly or fail with "expected 'word', got ...". */
int eo_scan_expect(eo_scan *s, const char *word);
/* Integers: any long; an int in [lo, hi]; a count in [0, max(remaining bytes/2, 0)]
 * (a count the rest of the file cannot hold is rejected before anything is allocated). */
int eo_scan_long(eo_scan *s, const char *what, long *v);
int eo_scan_int(eo_scan *s, const char *what, long lo, long hi, int *v);
int eo_scan_count(eo_scan *s, const char *what, int *v);
/* A double (strtod syntax, including nan/inf: callers check finiteness). */
int eo_scan_double(eo_scan *s, const char *what, double *v);
/* Only blanks or a comment may follow on this line: "expected end of line after
 * <what>, got 'tok'" otherwise. Ends a record. */
int eo_scan_eol(eo_scan *s, const char *what);
/* Skip the rest of the current line. */
void eo_scan_skip_line(eo_scan *s);
/* Skip the rest of the current line, then n non-blank lines; "expected <n> <what>"
 * when the text ends first. */
int eo_scan_skip_lines(eo_scan *s, long n, const char *what);
/* "expected <what>, got '<next token>'" (or end of file) at the current position. */
int eo_scan_fail(eo_scan *s, const char *what);
/* Any error at the current line and item, with the given status. */
int eo_scan_error(eo_scan *s, int status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Gmsh (.msh, both readers): the "$MeshFormat … $EndMeshFormat" header, ASCII 2.2 or
 * 4.1 only (*v41 set for 4.1); and a section whose "$Name" token (name, len) was
 * consumed, skipped up to the line starting "$EndName". */
int eo_scan_gmsh_format(eo_scan *s, int *v41);
int eo_scan_gmsh_skip_section(eo_scan *s, const char *name, size_t len);

typedef struct eo_tagmap {
    long min, span;  /* dense: index = dense[tag - min] */
    int *dense;
    long *keys;      /* sparse: sorted tags and their indices */
    int *vals;
    int n;
} eo_tagmap;

/* Build a map tag[i] -> i. On a repeated tag returns EO_ERR_PARSE with *dup set to the
 * index of the second occurrence (message left to the caller); NOMEM on failure. */
int eo_tagmap_build(eo_ctx *ctx, const long *tags, int n, eo_tagmap *map, int *dup);
/* Index of tag, or -1. */
int eo_tagmap_find(const eo_tagmap *map, long tag);
void eo_tagmap_deinit(eo_ctx *ctx, eo_tagmap *map);

#endif
