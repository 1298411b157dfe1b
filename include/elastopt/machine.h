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
///
/// The BLAS (eo_blas_get, eo_blas_describe): which BLAS the process runs (OpenBLAS,
/// BLIS, MKL or the reference BLAS), found at run time through the library that provides
/// `dgemm_` (dlsym + dladdr; libelastopt calls no implementation-specific symbol), its
/// kernel set ("core"), its thread count, and whether that core is a generic fallback
/// on a CPU that supports better kernels. Debian 12's OpenBLAS 0.3.21 does not know
/// some newer CPUs (e.g. Intel family 6 model 207) and runs its Prescott (SSE3) kernels
/// on them: a CHOLMOD factorization of 108k tets was 2.1x slower than with SkylakeX.
/// OpenBLAS reads OPENBLAS_CORETYPE once, when it is loaded, so the library can only
/// report this; the elastopt CLI re-executes itself with OPENBLAS_CORETYPE set (see
/// elastopt(1), "BLAS kernels").
///
/// ```c
/// char line[512];
/// eo_blas_describe(line, sizeof line);
/// // "BLAS OpenBLAS 0.3.21, core SkylakeX (fixed from Prescott), 2 threads (DYNAMIC_ARCH ...)"
/// eo_blas_info b;
/// eo_blas_get(&b);
/// if (b.fallback) printf("set OPENBLAS_CORETYPE=%s\n", b.recommended);
/// ```
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

/// The CPU features that decide which BLAS kernels can run: cpuid on x86 (a vector
/// extension counts only when the OS also saves its registers, XGETBV); all 0 elsewhere.
typedef struct eo_cpu_features {
    char vendor[16];  ///< "GenuineIntel", "AuthenticAMD", ...; "" when unknown
    int family;       ///< display family (cpuid leaf 1, extended family added), -1 when unknown
    int model;        ///< display model (extended model added), -1 when unknown
    int avx, fma, avx2;                     ///< 1 when usable
    int avx512f, avx512dq, avx512bw, avx512vl; ///< 1 when usable (SkylakeX kernels need all four)
} eo_cpu_features;

/// Fill *f with this CPU's features. Never fails.
EO_API void eo_cpu_features_get(eo_cpu_features *f);

/// Which BLAS implementation eo_blas_get found.
typedef enum eo_blas_kind {
    EO_BLAS_UNKNOWN = 0,   ///< no `dgemm_` found, or a BLAS none of the others
    EO_BLAS_OPENBLAS,
    EO_BLAS_BLIS,
    EO_BLAS_MKL,
    EO_BLAS_REFERENCE,     ///< netlib's libblas (single-threaded, unoptimized)
} eo_blas_kind;

/// The BLAS of this process (eo_blas_get). Strings are inside the struct or static.
typedef struct eo_blas_info {
    eo_blas_kind kind;
    const char *name;         ///< "OpenBLAS", "BLIS", "MKL", "reference", "unknown" (static)
    char version[32];         ///< "0.3.21"; "" when unknown
    char config[192];         ///< OpenBLAS: openblas_get_config() ("OpenBLAS 0.3.21 NO_LAPACKE DYNAMIC_ARCH ..."); MKL: its version string; "" otherwise
    char core[64];            ///< kernel set: OpenBLAS openblas_get_corename() ("SkylakeX"), BLIS its arch ("skx"); "" when unknown
    int threads;              ///< threads the BLAS uses now; 1 for the reference BLAS; -1 when unknown
    char library[256];        ///< the file that provides `dgemm_`; "" when not found
    int fallback;             ///< 1: OpenBLAS runs a generic core on a CPU with better kernels (eo_blas_is_fallback)
    const char *recommended;  ///< when fallback: the OPENBLAS_CORETYPE to set ("SkylakeX"), else NULL (static)
    char fixed_from[64];      ///< the core before the CLI re-executed itself with OPENBLAS_CORETYPE (environment
                              ///< ELASTOPT_BLAS_FIXED_FROM, set by the CLI); "" when it did not
} eo_blas_info;

/// Fill *b: the BLAS providing `dgemm_` in this process, its core, threads, and whether
/// the core is a fallback for this CPU (eo_cpu_features_get + eo_blas_is_fallback).
/// Never fails: an unidentified BLAS is EO_BLAS_UNKNOWN.
EO_API void eo_blas_get(eo_blas_info *b);

/// Whether OpenBLAS core `core` (openblas_get_corename(), case-insensitive) is a generic
/// fallback on a CPU with features *cpu — a pure function, no I/O. A fallback is a core
/// without AVX2 kernels (Prescott, Core2, Nehalem, Katmai, Atom, Opteron, Barcelona,
/// generic, ...) on an AVX2+FMA or AVX-512 CPU, or an SSE-only core on an AVX CPU.
/// AVX2 cores (Haswell, Zen, Excavator) on an AVX-512 CPU are not: measured on an AMD
/// EPYC (Zen 4, AVX-512), 1-thread DGEMM n = 1200 ran at 46-48 GFLOP/s with Haswell, Zen,
/// SkylakeX and Cooperlake alike, 30 with Sandybridge, 12.5 with Prescott.
/// Unknown core names are never a fallback. When it returns 1, *recommended (if not
/// NULL) is the OPENBLAS_CORETYPE to set, a name OpenBLAS 0.3.21 accepts: "SkylakeX"
/// (avx512f+dq+bw+vl; 0.3.21 ignores OPENBLAS_CORETYPE=Cooperlake, and Cooperlake's
/// DGEMM kernels are SkylakeX's), "Zen" (AMD) or "Haswell" (others) for AVX2+FMA,
/// "Sandybridge" for AVX; otherwise *recommended is NULL. Returns 1 or 0.
EO_API int eo_blas_is_fallback(const eo_cpu_features *cpu, const char *core, const char **recommended);

/// One line (no newline) describing the BLAS into buf (n bytes, truncated, always
/// terminated when n > 0): name, version, core, "(fixed from X)" after the CLI's
/// re-execution, or the OPENBLAS_CORETYPE advice when the core is a fallback, threads,
/// and the OpenBLAS build configuration. Returns the length snprintf would have written.
EO_API int eo_blas_describe(char *buf, size_t n);

/// Set the number of threads of the BLAS (openblas_set_num_threads,
/// bli_thread_set_num_threads, mkl_set_num_threads). Returns EO_OK, EO_ERR_RANGE for
/// nthreads < 1, EO_ERR_UNSUPPORTED when the BLAS has no such call (reference BLAS:
/// always 1 thread). Process-wide: call it between computations, not during one.
EO_API int eo_blas_set_threads(int nthreads);

#ifdef __cplusplus
}
#endif
#endif
