/* Machine and BLAS report (machine.h): the OpenBLAS core advice on a table of CPUs and
 * cores (a generic core on a CPU with AVX2 / AVX-512 kernels is a fallback, and the
 * recommended OPENBLAS_CORETYPE is one OpenBLAS 0.3.21 accepts), and the live report of
 * this process's BLAS: found, consistent, its thread count settable. */
#define _GNU_SOURCE /* setenv */
#include <lapacke.h>
#include <stdlib.h>
#include <string.h>

#include "elastopt/machine.h"
#include "elastopt/status.h"
#include "testutil.h"

enum { SSE = 0, AVX = 1, AVX2 = 2, AVX512 = 3, KNL = 4 };

static eo_cpu_features cpu(const char *vendor, int family, int model, int isa)
{
    eo_cpu_features f;
    memset(&f, 0, sizeof f);
    snprintf(f.vendor, sizeof f.vendor, "%s", vendor);
    f.family = family;
    f.model = model;
    f.avx = isa >= AVX;
    f.fma = f.avx2 = isa >= AVX2;
    f.avx512f = isa >= AVX512;
    f.avx512dq = f.avx512bw = f.avx512vl = isa == AVX512; /* KNL: avx512f without dq/bw/vl */
    return f;
}

static void test_advice_table(void)
{
    static const char *const INTEL = "GenuineIntel", *const AMD = "AuthenticAMD";
    const struct {
        const char *what, *vendor;
        int family, model, isa;
        const char *core;
        int fallback;
        const char *recommended;
    } t[] = {
        {"Intel AVX-512 (6/207) left on Prescott", INTEL, 6, 207, AVX512, "Prescott", 1, "SkylakeX"},
        {"Intel AVX-512, Nehalem", INTEL, 6, 207, AVX512, "Nehalem", 1, "SkylakeX"},
        {"Intel AVX-512, core2 (any case)", INTEL, 6, 207, AVX512, "core2", 1, "SkylakeX"},
        {"Intel AVX-512, Sandybridge", INTEL, 6, 143, AVX512, "Sandybridge", 1, "SkylakeX"},
        {"Intel AVX-512, SkylakeX", INTEL, 6, 85, AVX512, "SkylakeX", 0, NULL},
        {"Intel AVX-512, Cooperlake", INTEL, 6, 85, AVX512, "Cooperlake", 0, NULL},
        {"Intel AVX-512, Haswell (AVX2 kernels: tuned)", INTEL, 6, 85, AVX512, "Haswell", 0, NULL},
        {"AMD Zen 2, Zen", AMD, 23, 49, AVX2, "Zen", 0, NULL},
        {"AMD Zen 4 (AVX-512), Zen", AMD, 25, 17, AVX512, "Zen", 0, NULL},
        {"AMD Zen 4, Cooperlake", AMD, 25, 17, AVX512, "Cooperlake", 0, NULL},
        {"AMD Zen 4, Prescott", AMD, 25, 17, AVX512, "Prescott", 1, "SkylakeX"},
        {"Intel AVX2 (6/60), Prescott", INTEL, 6, 60, AVX2, "Prescott", 1, "Haswell"},
        {"AMD AVX2, Prescott", AMD, 23, 1, AVX2, "Prescott", 1, "Zen"},
        {"AMD AVX2, Opteron", AMD, 23, 1, AVX2, "Opteron", 1, "Zen"},
        {"Intel AVX2, Sandybridge", INTEL, 6, 60, AVX2, "Sandybridge", 1, "Haswell"},
        {"AMD Excavator (AVX2), Excavator", AMD, 21, 96, AVX2, "Excavator", 0, NULL},
        {"Intel AVX (Sandy Bridge), Prescott", INTEL, 6, 42, AVX, "Prescott", 1, "Sandybridge"},
        {"Intel AVX, Sandybridge", INTEL, 6, 42, AVX, "Sandybridge", 0, NULL},
        {"no AVX (Nehalem CPU), Nehalem", INTEL, 6, 26, SSE, "Nehalem", 0, NULL},
        {"no AVX, Prescott", INTEL, 6, 26, SSE, "Prescott", 0, NULL},
        {"Knights Landing (avx512f only), Prescott", INTEL, 6, 87, KNL, "Prescott", 1, "Haswell"},
        {"unknown core name", INTEL, 6, 207, AVX512, "NEOVERSEN1", 0, NULL},
        {"no core name", INTEL, 6, 207, AVX512, "", 0, NULL},
    };
    for (size_t k = 0; k < sizeof t / sizeof t[0]; k++) {
        eo_cpu_features f = cpu(t[k].vendor, t[k].family, t[k].model, t[k].isa);
        const char *rec = "unset";
        int fb = eo_blas_is_fallback(&f, t[k].core, &rec);
        CHECK(fb == t[k].fallback, "%s: fallback %d, expected %d", t[k].what, fb, t[k].fallback);
        CHECK(t[k].recommended ? rec && strcmp(rec, t[k].recommended) == 0 : rec == NULL, "%s: recommended %s, expected %s",
              t[k].what, rec ? rec : "NULL", t[k].recommended ? t[k].recommended : "NULL");
        CHECK(eo_blas_is_fallback(&f, t[k].core, NULL) == fb, "%s: a NULL recommended pointer is allowed", t[k].what);
    }
    eo_cpu_features f = cpu(INTEL, 6, 207, AVX512);
    CHECK(eo_blas_is_fallback(&f, NULL, NULL) == 0, "NULL core");
}

static void test_cpu_features(void)
{
    eo_cpu_features f;
    eo_cpu_features_get(&f);
    /* each level implies the one below: the OS check applies to all of them */
    CHECK(!f.avx2 || f.avx, "avx2 without avx");
    CHECK(!f.fma || f.avx, "fma without avx");
    CHECK(!f.avx512f || f.avx2, "avx512f without avx2");
    CHECK(!(f.avx512dq || f.avx512bw || f.avx512vl) || f.avx512f, "avx512 subsets without avx512f");
#if defined(__x86_64__)
    CHECK(f.vendor[0] != 0 && f.family > 0 && f.model >= 0, "x86-64: vendor '%s', family %d, model %d", f.vendor,
          f.family, f.model);
#endif
}

static void test_blas_live(void)
{
    /* A LAPACK call, as the library's solvers make: it loads the BLAS into this
     * statically linked test (the linker keeps only the libraries a program uses). */
    double A[4] = {4, 2, 2, 3}; /* [4 2; 2 3] = L L', L = [2 0; 1 sqrt(2)] */
    CHECK(LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', 2, A, 2) == 0, "dpotrf");
    CHECK_CLOSE(A[0], 2.0, 1e-15);
    CHECK_CLOSE(A[1], 1.0, 1e-15);
    CHECK_CLOSE(A[3], sqrt(2.0), 1e-15);

    eo_blas_info b;
    eo_blas_get(&b);
    /* the test links the BLAS that meson found (OpenBLAS on Debian): it must be found */
    CHECK(b.kind != EO_BLAS_UNKNOWN, "BLAS not identified (dgemm_ from '%s')", b.library);
    CHECK(b.library[0] != 0, "the file providing dgemm_");
    CHECK(b.threads >= 1, "threads %d", b.threads);
    if (b.kind == EO_BLAS_OPENBLAS) {
        CHECK(b.core[0] != 0 && b.version[0] != 0, "OpenBLAS core '%s' version '%s'", b.core, b.version);
        CHECK(strstr(b.config, b.core) != NULL, "the config string names the core: %s", b.config);
        eo_cpu_features f;
        eo_cpu_features_get(&f);
        const char *rec;
        CHECK(b.fallback == eo_blas_is_fallback(&f, b.core, &rec) && b.recommended == rec, "advice of the live core");
    }
    int t0 = b.threads;
    if (b.kind != EO_BLAS_REFERENCE) {
        CHECK(eo_blas_set_threads(1) == EO_OK, "set 1 thread");
        eo_blas_get(&b);
        CHECK(b.threads == 1, "threads after set(1): %d", b.threads);
        CHECK(eo_blas_set_threads(t0) == EO_OK, "restore");
        eo_blas_get(&b);
        CHECK(b.threads == t0, "threads after restore: %d, expected %d", b.threads, t0);
    }
    CHECK(eo_blas_set_threads(0) == EO_ERR_RANGE, "0 threads");

    char line[512];
    unsetenv("ELASTOPT_BLAS_FIXED_FROM");
    int len = eo_blas_describe(line, sizeof line);
    CHECK(len > 0 && (size_t)len < sizeof line && strncmp(line, "BLAS ", 5) == 0, "%s", line);
    CHECK(strstr(line, "fixed from") == NULL, "no re-execution: %s", line);
    if (b.kind == EO_BLAS_OPENBLAS) {
        CHECK(strstr(line, b.core) != NULL, "names the core: %s", line);
        /* the CLI's marker after a re-execution: the core it left */
        setenv("ELASTOPT_BLAS_FIXED_FROM", strcmp(b.core, "Prescott") ? "Prescott" : "Katmai", 1);
        eo_blas_describe(line, sizeof line);
        CHECK(b.fallback ? strstr(line, "did not take") != NULL : strstr(line, "(fixed from ") != NULL, "%s", line);
        unsetenv("ELASTOPT_BLAS_FIXED_FROM");
    }
    char small[8];
    eo_blas_describe(small, sizeof small);
    CHECK(strlen(small) == sizeof small - 1, "truncated and terminated");
}

int main(void)
{
    test_advice_table();
    test_cpu_features();
    test_blas_live();
    return eo_test_finish("test_machine");
}
