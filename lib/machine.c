/* Machine and build description shared by the benchmarks (machine.h), and the BLAS of
 * the process: which one, its kernel set ("core"), its threads, and whether the core is
 * a generic fallback on this CPU.
 *
 * The BLAS is found at run time, never linked by name: dlsym(RTLD_DEFAULT, "dgemm_") is
 * the dgemm every caller in the process (CHOLMOD included) resolves to; dladdr names its
 * file, dlopen(RTLD_NOLOAD) of that file gives a handle in which the implementation's own
 * queries are looked up (openblas_get_corename, bli_info_get_version_str,
 * mkl_get_version_string). When libelastopt was loaded RTLD_LOCAL (Python's cffi), the
 * BLAS is not in the global scope; then the usual sonames are tried with RTLD_NOLOAD. */
#define _GNU_SOURCE /* RTLD_DEFAULT, RTLD_NOLOAD, dladdr */
#include "elastopt/machine.h"

#include <ctype.h>
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#define EO_HAVE_CPUID 1
#endif
#if defined(_OPENMP)
#include <omp.h>
#endif

#include "eo_build_config.h"
#include "eo_revision.h"
#include "elastopt/status.h"

/* "model name : X" of /proc/cpuinfo into buf, else "unknown". */
static void cpu_model(char *buf, size_t n)
{
    snprintf(buf, n, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (!f) return;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        if (strncmp(line, "model name", 10) != 0) continue;
        char *c = strchr(line, ':');
        if (!c) continue;
        c++;
        while (*c == ' ' || *c == '\t') c++;
        c[strcspn(c, "\n")] = 0;
        snprintf(buf, n, "%s", c);
        break;
    }
    fclose(f);
}

void eo_machine_get(eo_machine *m)
{
    cpu_model(m->cpu, sizeof m->cpu);
#if defined(_SC_NPROCESSORS_ONLN)
    m->cores = sysconf(_SC_NPROCESSORS_ONLN);
#else
    m->cores = -1;
#endif
    m->mem_bytes = 0;
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGESIZE)
    long pages = sysconf(_SC_PHYS_PAGES), psize = sysconf(_SC_PAGESIZE);
    if (pages > 0 && psize > 0) m->mem_bytes = (double)pages * (double)psize;
#endif
#if defined(_OPENMP)
    m->omp_threads = omp_get_max_threads();
#else
    m->omp_threads = 1;
#endif
    m->version = EO_VERSION;
    m->build_type = EO_BUILDTYPE;
    m->compiler = EO_COMPILER;
    m->revision = EO_GIT_REVISION;
}

int eo_machine_describe(char *buf, size_t n)
{
    eo_machine m;
    eo_machine_get(&m);
    return snprintf(buf, n, "machine %s, %ld cores, %d OpenMP threads; elastopt %s, build %s, %s, revision %s",
                    m.cpu, m.cores, m.omp_threads, m.version, m.build_type, m.compiler, m.revision);
}

/* ------------------------------------------------------------------ CPU features */

#if defined(EO_HAVE_CPUID)
static unsigned long long xgetbv0(void)
{
    unsigned int lo, hi;
    __asm__ volatile(".byte 0x0f, 0x01, 0xd0" : "=a"(lo), "=d"(hi) : "c"(0)); /* xgetbv, XCR0 */
    return ((unsigned long long)hi << 32) | lo;
}
#endif

void eo_cpu_features_get(eo_cpu_features *f)
{
    memset(f, 0, sizeof *f);
    f->family = f->model = -1;
#if defined(EO_HAVE_CPUID)
    unsigned int a, b, c, d;
    if (!__get_cpuid(0, &a, &b, &c, &d)) return;
    unsigned int maxleaf = a;
    memcpy(f->vendor, &b, 4);
    memcpy(f->vendor + 4, &d, 4);
    memcpy(f->vendor + 8, &c, 4);
    f->vendor[12] = 0;
    if (maxleaf < 1) return;
    __cpuid(1, a, b, c, d);
    int fam = (int)((a >> 8) & 0xf), mod = (int)((a >> 4) & 0xf);
    if (fam == 0xf) fam += (int)((a >> 20) & 0xff);
    if (fam == 6 || fam >= 0xf) mod += (int)(((a >> 16) & 0xf) << 4);
    f->family = fam;
    f->model = mod;
    int osxsave = (c >> 27) & 1;
    unsigned long long xcr0 = osxsave ? xgetbv0() : 0;
    int os_avx = (xcr0 & 0x6) == 0x6;            /* XMM and YMM state */
    int os_avx512 = os_avx && (xcr0 & 0xe0) == 0xe0; /* opmask, ZMM0-15 upper, ZMM16-31 */
    f->avx = os_avx && ((c >> 28) & 1);
    f->fma = f->avx && ((c >> 12) & 1);
    if (maxleaf >= 7) {
        __cpuid_count(7, 0, a, b, c, d);
        f->avx2 = f->avx && ((b >> 5) & 1);
        f->avx512f = os_avx512 && ((b >> 16) & 1);
        f->avx512dq = os_avx512 && ((b >> 17) & 1);
        f->avx512bw = os_avx512 && ((b >> 30) & 1);
        f->avx512vl = os_avx512 && ((b >> 31) & 1);
    }
#endif
}

/* ------------------------------------------------------------------ core advice */

/* Vector level of an OpenBLAS core's kernels (x86 DYNAMIC_ARCH names of 0.3.21 and
 * later): 4 AVX-512, 3 AVX2 (+FMA), 2 AVX, 1 SSE or older, -1 unknown (never flagged). */
static int core_level(const char *core)
{
    static const char *const l4[] = {"SkylakeX", "Cooperlake", "SapphireRapids", NULL};
    static const char *const l3[] = {"Haswell", "Zen", "Excavator", NULL};
    static const char *const l2[] = {"Sandybridge", "Bulldozer", "Piledriver", "Steamroller", NULL};
    static const char *const l1[] = {"Katmai", "Coppermine", "Northwood", "Prescott", "Banias", "Atom",
                                     "Core2", "Penryn", "Dunnington", "Nehalem", "Athlon", "Opteron",
                                     "Opteron_SSE3", "Barcelona", "Nano", "Bobcat", "Generic", "Unknown", NULL};
    static const char *const *const levels[] = {l1, l2, l3, l4};
    if (!core) return -1;
    for (int l = 0; l < 4; l++)
        for (const char *const *n = levels[l]; *n; n++)
            if (strcasecmp(core, *n) == 0) return l + 1;
    return -1;
}

static int cpu_level(const eo_cpu_features *cpu)
{
    if (cpu->avx512f && cpu->avx512dq && cpu->avx512bw && cpu->avx512vl) return 4;
    if (cpu->avx2 && cpu->fma) return 3;
    if (cpu->avx) return 2;
    return 1;
}

int eo_blas_is_fallback(const eo_cpu_features *cpu, const char *core, const char **recommended)
{
    if (recommended) *recommended = NULL;
    int have = core_level(core), can = cpu_level(cpu);
    /* AVX2 kernels on an AVX-512 CPU are tuned kernels, not a fallback (machine.h). */
    if (have < 1 || have >= 3 || can <= have) return 0;
    if (recommended) {
        if (can == 4) *recommended = "SkylakeX";
        else if (can == 3) *recommended = strcmp(cpu->vendor, "AuthenticAMD") == 0 ? "Zen" : "Haswell";
        else *recommended = "Sandybridge";
    }
    return 1;
}

/* ------------------------------------------------------------------ the BLAS */

static void copy(char *dst, size_t n, const char *src)
{
    snprintf(dst, n, "%s", src ? src : "");
}

/* A handle on the library providing dgemm_ (its file into path), or NULL. */
static void *blas_handle(char *path, size_t n)
{
    Dl_info di;
    void *sym = dlsym(RTLD_DEFAULT, "dgemm_");
    if (sym && dladdr(sym, &di) && di.dli_fname) {
        copy(path, n, di.dli_fname);
        void *h = dlopen(di.dli_fname, RTLD_LAZY | RTLD_NOLOAD);
        if (h) return h;
    }
    static const char *const sonames[] = {"libopenblas.so.0", "libblis.so.4", "libblis.so.3", "libmkl_rt.so.2",
                                          "libmkl_rt.so", "libblas.so.3", NULL};
    for (const char *const *s = sonames; *s; s++) {
        void *h = dlopen(*s, RTLD_LAZY | RTLD_NOLOAD);
        if (!h) continue;
        sym = dlsym(h, "dgemm_");
        if (sym && dladdr(sym, &di) && di.dli_fname) copy(path, n, di.dli_fname);
        else copy(path, n, *s);
        return h;
    }
    return NULL;
}

static void blas_query(void *h, eo_blas_info *b)
{
    char *(*ob_core)(void) = NULL, *(*ob_config)(void) = NULL;
    int (*ob_threads)(void) = NULL;
    *(void **)(&ob_core) = dlsym(h, "openblas_get_corename");
    *(void **)(&ob_config) = dlsym(h, "openblas_get_config");
    *(void **)(&ob_threads) = dlsym(h, "openblas_get_num_threads");
    if (ob_core || ob_config) {
        b->kind = EO_BLAS_OPENBLAS;
        b->name = "OpenBLAS";
        if (ob_core) copy(b->core, sizeof b->core, ob_core());
        if (ob_config) {
            const char *cfg = ob_config();
            copy(b->config, sizeof b->config, cfg);
            if (cfg && strncmp(cfg, "OpenBLAS ", 9) == 0) { /* "OpenBLAS 0.3.21 NO_LAPACKE ..." */
                size_t k = strcspn(cfg + 9, " ");
                snprintf(b->version, sizeof b->version, "%.*s", (int)(k < sizeof b->version ? k : sizeof b->version - 1),
                         cfg + 9);
            }
        }
        if (ob_threads) b->threads = ob_threads();
        return;
    }
    const char *(*bli_version)(void) = NULL, *(*bli_arch_string)(int) = NULL;
    int (*bli_arch)(void) = NULL;
    long (*bli_threads)(void) = NULL;
    *(void **)(&bli_version) = dlsym(h, "bli_info_get_version_str");
    if (bli_version) {
        b->kind = EO_BLAS_BLIS;
        b->name = "BLIS";
        copy(b->version, sizeof b->version, bli_version());
        *(void **)(&bli_arch) = dlsym(h, "bli_arch_query_id");
        *(void **)(&bli_arch_string) = dlsym(h, "bli_arch_string");
        if (bli_arch && bli_arch_string) copy(b->core, sizeof b->core, bli_arch_string(bli_arch()));
        *(void **)(&bli_threads) = dlsym(h, "bli_thread_get_num_threads");
        if (bli_threads) b->threads = (int)bli_threads();
        return;
    }
    void (*mkl_version)(char *, int) = NULL;
    int (*mkl_threads)(void) = NULL;
    *(void **)(&mkl_version) = dlsym(h, "mkl_get_version_string");
    if (mkl_version) {
        b->kind = EO_BLAS_MKL;
        b->name = "MKL";
        mkl_version(b->config, (int)sizeof b->config);
        *(void **)(&mkl_threads) = dlsym(h, "mkl_get_max_threads");
        if (mkl_threads) b->threads = mkl_threads();
        return;
    }
    /* netlib's libblas: only the standard symbols; its file is libblas.so.* */
    const char *base = strrchr(b->library, '/');
    base = base ? base + 1 : b->library;
    if (strncmp(base, "libblas.so", 10) == 0) {
        b->kind = EO_BLAS_REFERENCE;
        b->name = "reference";
        b->threads = 1;
    }
}

void eo_blas_get(eo_blas_info *b)
{
    memset(b, 0, sizeof *b);
    b->kind = EO_BLAS_UNKNOWN;
    b->name = "unknown";
    b->threads = -1;
    void *h = blas_handle(b->library, sizeof b->library);
    if (h) {
        blas_query(h, b);
        dlclose(h);
    }
    if (b->kind == EO_BLAS_OPENBLAS) {
        eo_cpu_features cpu;
        eo_cpu_features_get(&cpu);
        b->fallback = eo_blas_is_fallback(&cpu, b->core, &b->recommended);
    }
    copy(b->fixed_from, sizeof b->fixed_from, getenv("ELASTOPT_BLAS_FIXED_FROM"));
}

int eo_blas_describe(char *buf, size_t n)
{
    eo_blas_info b;
    eo_blas_get(&b);
    char core[320] = "";
    if (b.core[0] && b.fixed_from[0] && b.fallback)
        snprintf(core, sizeof core, ", core %s (a generic fallback on this CPU; re-executed from %s with "
                 "OPENBLAS_CORETYPE=%s, which this OpenBLAS did not take)", b.core, b.fixed_from,
                 getenv("OPENBLAS_CORETYPE") ? getenv("OPENBLAS_CORETYPE") : "(unset)");
    else if (b.core[0] && b.fixed_from[0] && strcasecmp(b.fixed_from, b.core) != 0)
        snprintf(core, sizeof core, ", core %s (fixed from %s)", b.core, b.fixed_from);
    else if (b.core[0] && b.fallback)
        snprintf(core, sizeof core, ", core %s (a generic fallback on this CPU: OPENBLAS_CORETYPE=%s runs its kernels)",
                 b.core, b.recommended);
    else if (b.core[0])
        snprintf(core, sizeof core, ", core %s", b.core);
    char thr[32] = "";
    if (b.threads > 0) snprintf(thr, sizeof thr, ", %d thread%s", b.threads, b.threads == 1 ? "" : "s");
    char cfg[272] = "";
    const char *c = b.config;
    size_t pre = strlen(b.name); /* "OpenBLAS 0.3.21 DYNAMIC_ARCH ...": name and version are printed already */
    if (b.version[0] && strncmp(c, b.name, pre) == 0 && c[pre] == ' ' && strncmp(c + pre + 1, b.version, strlen(b.version)) == 0)
        c += pre + 1 + strlen(b.version) + (c[pre + 1 + strlen(b.version)] == ' ');
    if (*c) snprintf(cfg, sizeof cfg, " (%s)", c);
    else if (b.kind == EO_BLAS_UNKNOWN && b.library[0]) snprintf(cfg, sizeof cfg, " (%s)", b.library);
    return snprintf(buf, n, "BLAS %s%s%s%s%s%s", b.name, b.version[0] ? " " : "", b.version, core, thr, cfg);
}

int eo_blas_set_threads(int nthreads)
{
    if (nthreads < 1) return EO_ERR_RANGE;
    char path[8];
    void *h = blas_handle(path, sizeof path);
    if (!h) return EO_ERR_UNSUPPORTED;
    void (*ob_set)(int) = NULL, (*mkl_set)(int) = NULL, (*bli_set)(long) = NULL;
    *(void **)(&ob_set) = dlsym(h, "openblas_set_num_threads");
    *(void **)(&bli_set) = dlsym(h, "bli_thread_set_num_threads");
    *(void **)(&mkl_set) = dlsym(h, "mkl_set_num_threads");
    int rc = EO_OK;
    if (ob_set) ob_set(nthreads);
    else if (bli_set) bli_set(nthreads);
    else if (mkl_set) mkl_set(nthreads);
    else rc = EO_ERR_UNSUPPORTED;
    dlclose(h);
    return rc;
}
