/// @file machine.h
/// The machine and build a benchmark ran on, for the first line of its output or the
/// header of its report: CPU model, cores online, OpenMP threads, elastopt version,
/// build type, compiler (eo_build_config.h) and git revision (eo_revision.h, written by
/// meson's vcs_tag at every build; "-dirty" when the tree had uncommitted changes).
///
/// ```c
/// char line[512];
/// eo_machine_describe(line, sizeof line);
/// printf("bench_x: %s\n", line);
/// // "machine AMD EPYC 7B13, 2 cores, 2 OpenMP threads; build debugoptimized, gcc 12.2.0, revision 0ac21de"
///
/// eo_machine m;                       // or the fields one by one, for a table
/// eo_machine_get(&m);
/// printf("| CPU | %s |\n", m.cpu);
/// ```
/// Ownership: the strings of eo_machine are either inside it (cpu) or static; nothing
/// is allocated. Reads /proc/cpuinfo where it exists ("unknown" elsewhere).
#ifndef ELASTOPT_MACHINE_H
#define ELASTOPT_MACHINE_H

#include "export.h"
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct eo_machine {
    char cpu[128];          ///< CPU model name ("model name" of /proc/cpuinfo), or "unknown"
    long cores;             ///< processors online, -1 if unknown
    int omp_threads;        ///< omp_get_max_threads(), 1 in a build without OpenMP
    double mem_bytes;       ///< physical memory in bytes, 0 if unknown
    const char *version;    ///< elastopt version (static)
    const char *build_type; ///< meson build type (static)
    const char *compiler;   ///< compiler id and version (static)
    const char *revision;   ///< `git describe --always --dirty` at build time, or "unknown" (static)
} eo_machine;

/// Fill *m. Never fails.
EO_API void eo_machine_get(eo_machine *m);

/// One line (no newline) describing machine and build into buf (n bytes, truncated,
/// always terminated when n > 0). Returns the length snprintf would have written.
EO_API int eo_machine_describe(char *buf, size_t n);

#ifdef __cplusplus
}
#endif
#endif
