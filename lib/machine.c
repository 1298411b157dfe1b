/* Machine and build description shared by the benchmarks (machine.h). */
#include "elastopt/machine.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>
#if defined(_OPENMP)
#include <omp.h>
#endif

#include "eo_build_config.h"
#include "eo_revision.h"

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
