/// @file suggest.h
/// "Did you mean" suggestions for unknown names: config keys, method names, CLI commands
/// and options, file extensions. Every "unknown ... ; valid: a, b, c" message of the library
/// and the CLI asks eo_suggest for the closest valid name first. Compiles alone.
///
/// ```c
/// char hint[64], msg[96];
/// if (eo_suggest("hessianfix", "optimizer, hessian_fix, linesearch", hint, sizeof hint))
///     ...  // hint = "hessian_fix"
/// eo_suggest_hint("hessianfix", list, "solver.", msg, sizeof msg);
///     // msg = " (did you mean 'solver.hessian_fix'?)"
/// int d = eo_edit_distance("newtn", "newton");  // 2: one ordinary edit
/// ```
/// The distance is the optimal-string-alignment (restricted Damerau–Levenshtein)
/// distance in half-edits: an insertion, deletion, substitution or swap of two adjacent
/// characters costs 2; the slips that rarely change meaning cost 1: a difference of case
/// only, '_' and '-' swapped for each other, and a missing or extra '_', '-' or '.'.
/// A candidate is suggested when its distance is at most 2 * max(1, strlen(name) / 4)
/// (one ordinary edit per 4 typed characters, at least one), the closest one first in
/// the list on ties. Nothing is allocated; names longer than 63 characters get no
/// suggestion.
#ifndef ELASTOPT_SUGGEST_H
#define ELASTOPT_SUGGEST_H

#include <stddef.h>

#include "export.h"

#ifdef __cplusplus
extern "C" {
#endif

/// Weighted edit distance between a and b in half-edits (see the file comment); -1 if
/// either is NULL or longer than 63 characters.
EO_API int eo_edit_distance(const char *a, const char *b);

/// The candidate closest to `name` in `list` (names separated by commas and/or blanks,
/// the form of every "valid: ..." list), if close enough: copied into out (n bytes,
/// truncated) and 1 returned; else out = "" and 0. A candidate equal to name is skipped.
EO_API int eo_suggest(const char *name, const char *list, char *out, size_t n);

/// The message fragment " (did you mean '<prefix><candidate>'?)" for eo_suggest's pick, or
/// "" when nothing is close; written into buf (n bytes) and returned. prefix may be NULL
/// (the key path of a config level: "solver." gives "solver.hessian_fix").
EO_API const char *eo_suggest_hint(const char *name, const char *list, const char *prefix, char *buf,
                                   size_t n);

#ifdef __cplusplus
}
#endif
#endif
