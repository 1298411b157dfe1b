/* The output folder of `elastopt run`: lock, earlier runs, per-step logs, restart file
 * (see run_output.h). */
#define _POSIX_C_SOURCE 200809L
#include "run_output.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "elastopt/io.h"

#ifndef NAME_MAX
#define NAME_MAX 255
#endif

static const char *kind_name(mode_t m)
{
    if (S_ISREG(m)) return "a file";
    if (S_ISFIFO(m)) return "a FIFO (named pipe)";
    if (S_ISCHR(m)) return "a character device";
    if (S_ISBLK(m)) return "a block device";
    if (S_ISSOCK(m)) return "a socket";
    return "not a folder";
}

/* ---------------------------------------------------------------- folder and lock */

static int try_lock(const char *lock)
{
    int fd = open(lock, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0) return -errno;
    char buf[32];
    int n = snprintf(buf, sizeof buf, "%ld\n", (long)getpid());
    int ok = write(fd, buf, (size_t)n) == n;
    close(fd);
    if (!ok) {
        unlink(lock);
        return -EIO;
    }
    return 0;
}

static long lock_owner(const char *lock)
{
    int fd = open(lock, O_RDONLY | O_NONBLOCK);
    if (fd < 0) return -1;
    char buf[32] = {0};
    ssize_t n = read(fd, buf, sizeof buf - 1);
    close(fd);
    if (n <= 0) return -1;
    char *e;
    long pid = strtol(buf, &e, 10);
    return e != buf && pid > 0 ? pid : -1;
}

int eo_run_dir_open(eo_ctx *ctx, const char *path, eo_run_dir *d)
{
    memset(d, 0, sizeof d[0]);
    size_t n = strlen(path);
    if (n == 0) return eo_error(ctx, EO_ERR_IO, "empty output folder name; expected a path");
    if (n >= sizeof d->path - 16)
        return eo_error(ctx, EO_ERR_IO, "%.200s...: output folder name of %zu characters is too long (max %zu)", path,
                        n, sizeof d->path - 17);
    for (const char *c = path; *c;) {
        const char *e = strchr(c, '/');
        size_t k = e ? (size_t)(e - c) : strlen(c);
        if (k > NAME_MAX)
            return eo_error(ctx, EO_ERR_IO, "%.200s...: a component of %zu characters is longer than the system allows (%d)",
                            path, k, NAME_MAX);
        c += k;
        while (*c == '/') c++;
    }
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISDIR(st.st_mode))
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot write into it: it is %s; expected a folder",
                           kind_name(st.st_mode));
    int rc = eo_mkdir_p(ctx, path);
    if (rc < 0) return rc;
    snprintf(d->path, sizeof d->path, "%s", path);
    snprintf(d->lock, sizeof d->lock, "%s/run.lock", path);
    for (int attempt = 0; attempt < 2; attempt++) {
        int e = try_lock(d->lock);
        if (e == 0) {
            d->locked = 1;
            return EO_OK;
        }
        if (e != -EEXIST)
            return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(d->lock, -1), "cannot create the lock file: %s",
                               strerror(-e));
        long pid = lock_owner(d->lock);
        if (pid > 0 && (kill((pid_t)pid, 0) == 0 || errno == EPERM))
            return eo_error(ctx, EO_ERR_IO,
                            "%s is in use by another elastopt run (pid %ld, lock file %s); wait for it to end or "
                            "choose another folder with --out",
                            path, pid, d->lock);
        if (pid < 0 && attempt == 0) { /* being written right now? look once more */
            struct timespec ts = {0, 100000000};
            nanosleep(&ts, NULL);
            pid = lock_owner(d->lock);
            if (pid > 0 && (kill((pid_t)pid, 0) == 0 || errno == EPERM))
                return eo_error(ctx, EO_ERR_IO, "%s is in use by another elastopt run (pid %ld, lock file %s)", path,
                                pid, d->lock);
        }
        unlink(d->lock); /* stale: its process is gone */
    }
    return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(d->lock, -1), "cannot take the lock");
}

void eo_run_dir_close(eo_run_dir *d)
{
    if (d->locked) unlink(d->lock);
    d->locked = 0;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcmp(s + n - k, suffix) == 0;
}

/* frame_NNNNNN.vtu, a distributed run's frame_NNNNNN.pvtu and its pieces
 * frame_NNNNNN_rR.vtu: its step, else -1 */
static long frame_step(const char *name)
{
    if (strncmp(name, "frame_", 6) != 0) return -1;
    char *e;
    long k = strtol(name + 6, &e, 10);
    if (e == name + 6 || k < 0) return -1;
    if (strcmp(e, ".vtu") == 0 || strcmp(e, ".pvtu") == 0) return k;
    if (strncmp(e, "_r", 2) != 0) return -1;
    char *e2;
    long r = strtol(e + 2, &e2, 10);
    return e2 != e + 2 && r >= 0 && strcmp(e2, ".vtu") == 0 ? k : -1;
}

/* restart.dat.R-of-P (a distributed run's per-rank restart file): 1 and R, P; else 0 */
static int rank_restart(const char *name, int *r, int *p)
{
    if (strncmp(name, "restart.dat.", 12) != 0) return 0;
    const char *s = name + 12;
    char *e;
    long rr = strtol(s, &e, 10);
    if (e == s || *s == '-' || *s == '+' || strncmp(e, "-of-", 4) != 0) return 0;
    s = e + 4;
    long pp = strtol(s, &e, 10);
    if (e == s || *s == '-' || *s == '+' || *e || rr < 0 || pp < 2 || rr >= pp || pp > 1 << 24) return 0;
    if (r) *r = (int)rr;
    if (p) *p = (int)pp;
    return 1;
}

void eo_run_restart_rank_name(int rank, int size, char *buf, size_t n)
{
    snprintf(buf, n, "restart.dat.%d-of-%d", rank, size);
}

int eo_run_restart_ranks(const char *dir, int *nranks, int *nfiles)
{
    *nranks = 0;
    *nfiles = 0;
    DIR *d = opendir(dir);
    if (!d) return 0;
    int kinds = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        int r, p;
        if (!rank_restart(e->d_name, &r, &p)) continue;
        if (p != *nranks) {
            kinds++;
            if (p > *nranks) {
                *nranks = p;
                *nfiles = 0;
            } else continue;
        }
        (*nfiles)++;
    }
    closedir(d);
    return kinds;
}

static int is_run_file(const char *name)
{
    static const char *const fixed[] = {"run.json", "summary.json", "iterations.csv", "steps.csv", "restart.dat",
                                        NULL};
    char base[NAME_MAX + 1];
    snprintf(base, sizeof base, "%s", name);
    char *tmp = strstr(base, ".tmp.");
    if (tmp) *tmp = 0; /* a temporary of one of ours */
    for (const char *const *f = fixed; *f; f++)
        if (strcmp(base, *f) == 0) return 1;
    return ends_with(base, ".pvd") || frame_step(base) >= 0 || rank_restart(base, NULL, NULL);
}

int eo_run_dir_count_earlier(const eo_run_dir *d, char *names, size_t n)
{
    DIR *dir = opendir(d->path);
    if (!dir) return 0;
    int count = 0;
    size_t used = 0;
    if (names && n) names[0] = 0;
    struct dirent *e;
    int shown = 0;
    for (int pass = 0; pass < 2; pass++) { /* name the logs and the summary before frames */
        rewinddir(dir);
        while ((e = readdir(dir))) {
            if (!is_run_file(e->d_name) || (frame_step(e->d_name) >= 0) != pass) continue;
            if (names && shown < 4 && used + strlen(e->d_name) + 3 < n) {
                used += (size_t)snprintf(names + used, n - used, "%s%s", shown ? ", " : "", e->d_name);
                shown++;
            }
            count++;
        }
    }
    closedir(dir);
    return count;
}

int eo_run_dir_remove_earlier(eo_ctx *ctx, const eo_run_dir *d)
{
    DIR *dir = opendir(d->path);
    if (!dir) return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(d->path, -1), "cannot list: %s", strerror(errno));
    int rc = EO_OK;
    struct dirent *e;
    char p[1400];
    while ((e = readdir(dir))) {
        if (!is_run_file(e->d_name)) continue;
        snprintf(p, sizeof p, "%s/%s", d->path, e->d_name);
        if (unlink(p) != 0 && rc >= 0)
            rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(p, -1), "cannot remove the earlier run's file: %s",
                             strerror(errno));
    }
    closedir(dir);
    return rc;
}

void eo_run_dir_remove_frames_after(const eo_run_dir *d, int step)
{
    DIR *dir = opendir(d->path);
    if (!dir) return;
    struct dirent *e;
    char p[1400];
    while ((e = readdir(dir))) {
        long k = frame_step(e->d_name);
        if (k > step) {
            snprintf(p, sizeof p, "%s/%s", d->path, e->d_name);
            unlink(p);
        }
    }
    closedir(dir);
}

void eo_run_frame_name(int step, char *buf, size_t n) { snprintf(buf, n, "frame_%06d.vtu", step); }

/* ---------------------------------------------------------------- steps.csv */

const char *eo_run_num(char buf[32], double v, int digits)
{
    if (!isfinite(v)) buf[0] = 0;
    else if (digits == 17) eo_fmt_double(buf, v); /* shortest form that reads back exactly */
    else snprintf(buf, 32, "%.6e", v);
    return buf;
}

/* a number field as written by eo_run_num: empty = NAN */
static double num_field(const char *s) { return *s ? strtod(s, NULL) : NAN; }

void eo_run_record_write(FILE *f, const eo_run_record *r)
{
    const eo_step_stats *s = &r->stats;
    char b[17][32];
    fprintf(f, "%d,%s,%d,%s,%d,%s,%s,%s,%s,%ld,%ld,%ld,%ld,%s,%s,%s,%s,%s,%d,%s,%s,%s,%d,%s,%s,%s,%s", r->step,
            eo_run_num(b[0], r->t, 17), r->iterations, eo_reason_name(r->reason),
            eo_reason_is_converged(r->reason) && !eo_reason_is_explicit(r->reason),
            eo_run_num(b[1], r->time, 17), eo_run_num(b[2], r->wall, 17), eo_run_num(b[3], r->g, 17),
            eo_run_num(b[4], r->grad_norm, 17), r->n_value, r->n_gradient, r->n_hessian, r->n_factor,
            eo_run_num(b[5], s->com[0], 17), eo_run_num(b[6], s->com[1], 17), eo_run_num(b[7], s->com[2], 17),
            eo_run_num(b[8], s->max_disp, 17), eo_run_num(b[9], s->min_J, 17), s->inverted,
            eo_run_num(b[10], s->kinetic, 17), eo_run_num(b[11], s->elastic, 17), eo_run_num(b[12], s->gravity, 17), r->entry,
            eo_run_num(b[13], s->contact, 17), eo_run_num(b[14], s->potential, 17),
            eo_run_num(b[15], s->work_prescribed, 17), eo_run_num(b[16], s->total_energy, 17));
    /* appended: adaptive stepping */
    fprintf(f, ",%d,%d,%s", r->rejected, r->substeps, eo_run_num(b[13], r->min_substep, 17));
    /* appended: factorizations that found the matrix not positive definite */
    fprintf(f, ",%ld", r->n_not_pd);
    /* appended: CPU seconds of the solving thread (solve_time is wall time) */
    fprintf(f, ",%s\n", eo_run_num(b[14], r->cpu, 17));
}

static int reason_from_name(const char *s, int *reason)
{
    if (strcmp(s, "converged_explicit") == 0) { /* the explicit steps' former reason name */
        *reason = EO_REASON_EXPLICIT;
        return 0;
    }
    for (int r = -64; r <= 64; r++) {
        const char *n = eo_reason_name(r);
        if (n && strcmp(n, s) == 0) {
            *reason = r;
            return 0;
        }
    }
    return -1;
}

/* parse one row (NUL-terminated, no newline) */
static int parse_record(char *line, eo_run_record *r)
{
    enum { NF = 32, NF_P = 31, NF_A = 30, NF_E = 27, NF_OLD = 23 }; /* NF_OLD: before the energy columns, NF_E:
                                                           before the adaptive ones, NF_A: before n_not_pd, NF_P:
                                                           before solve_cpu_time */
    char *f[NF];
    int n = 0;
    for (char *p = line; n < NF; n++) {
        f[n] = p;
        char *c = strchr(p, ',');
        if (!c) {
            n++;
            break;
        }
        *c = 0;
        p = c + 1;
    }
    if (n != NF && n != NF_P && n != NF_A && n != NF_E && n != NF_OLD) return -1;
    memset(r, 0, sizeof *r);
    r->step = atoi(f[0]);
    r->t = num_field(f[1]);
    r->iterations = atoi(f[2]);
    if (reason_from_name(f[3], &r->reason) < 0) return -1;
    r->time = num_field(f[5]);
    r->wall = num_field(f[6]);
    r->g = num_field(f[7]);
    r->grad_norm = num_field(f[8]);
    r->n_value = strtol(f[9], NULL, 10);
    r->n_gradient = strtol(f[10], NULL, 10);
    r->n_hessian = strtol(f[11], NULL, 10);
    r->n_factor = strtol(f[12], NULL, 10);
    for (int k = 0; k < 3; k++) r->stats.com[k] = num_field(f[13 + k]);
    r->stats.max_disp = num_field(f[16]);
    r->stats.min_J = num_field(f[17]);
    r->stats.inverted = atoi(f[18]);
    r->stats.kinetic = num_field(f[19]);
    r->stats.elastic = num_field(f[20]);
    r->stats.gravity = num_field(f[21]);
    r->entry = atoi(f[22]);
    r->stats.contact = n >= NF_E ? num_field(f[23]) : NAN;
    r->stats.potential = n >= NF_E ? num_field(f[24]) : NAN;
    r->stats.work_prescribed = n >= NF_E ? num_field(f[25]) : NAN;
    r->stats.total_energy = n >= NF_E ? num_field(f[26]) : NAN;
    r->substeps = 1;
    r->min_substep = NAN;
    if (n >= NF_A) {
        r->rejected = atoi(f[27]);
        r->substeps = atoi(f[28]);
        r->min_substep = num_field(f[29]);
    }
    r->n_not_pd = n >= NF_P ? strtol(f[30], NULL, 10) : 0;
    r->cpu = n == NF ? num_field(f[31]) : NAN;
    return 0;
}

/* Keep the header and the complete rows whose step is <= steps (rows are in step order);
 * cut the file after them. With rec: every kept row is parsed into rec and must be
 * step 1, 2, ... in order. Returns the number of kept rows or a negative status. */
static int resume_csv(eo_ctx *ctx, const char *path, int steps, eo_run_record *rec)
{
    char *text = NULL;
    size_t len = 0;
    int rc = eo_read_file(ctx, path, &text, &len);
    if (rc < 0) return rc;
    char *nl = strchr(text, '\n');
    if (!nl || strncmp(text, "step,", 5) != 0) {
        eo_free(ctx, text);
        return eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(path, 1), "no header line; expected a run's log");
    }
    size_t keep = (size_t)(nl + 1 - text);
    int rows = 0, line = 1;
    for (char *p = nl + 1; *p; line++) {
        char *e = strchr(p, '\n');
        if (!e) break; /* incomplete last line: dropped */
        long step = strtol(p, NULL, 10);
        if (step > steps) break;
        if (rec) {
            *e = 0;
            if (step != rows + 1 || parse_record(p, rec + rows) < 0) {
                eo_free(ctx, text);
                return eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(path, line + 1),
                                   "malformed row (expected step %d with %s)", rows + 1, EO_RUN_STEPS_CSV_HEADER);
            }
            rows++;
        }
        p = e + 1;
        keep = (size_t)(p - text);
    }
    eo_free(ctx, text);
    if (keep < len && truncate(path, (off_t)keep) != 0)
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot cut after step %d: %s", steps,
                           strerror(errno));
    return rows;
}

int eo_run_logs_resume(eo_ctx *ctx, const eo_run_dir *d, int steps, eo_run_record *rec)
{
    char p[1400];
    snprintf(p, sizeof p, "%s/steps.csv", d->path);
    int rows = resume_csv(ctx, p, steps, rec);
    if (rows < 0) return rows;
    if (rows != steps)
        return eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(p, -1),
                           "holds %d complete steps but restart.dat is at step %d; cannot continue this run", rows,
                           steps);
    snprintf(p, sizeof p, "%s/iterations.csv", d->path);
    int r = resume_csv(ctx, p, steps, NULL);
    return r < 0 ? r : EO_OK;
}

/* ---------------------------------------------------------------- restart file */

static const char *endian_name(void)
{
    const uint16_t one = 1;
    return *(const unsigned char *)&one ? "little" : "big";
}

int eo_run_restart_write(eo_ctx *ctx, const char *path, int step, double t, int nv, const eo_run_array *a, int na)
{
    eo_afile *af = NULL;
    int rc = eo_afile_open(ctx, path, &af);
    if (rc < 0) return rc;
    FILE *f = eo_afile_fp(af);
    fprintf(f, "elastopt-restart 1\nstep %d\nt %a\nnv %d\nendian %s\n", step, t, nv, endian_name());
    for (int i = 0; i < na; i++) {
        if (!a[i].data) continue;
        fprintf(f, "array %s %zu\n", a[i].name, a[i].count);
        fwrite(a[i].data, sizeof(double), a[i].count, f);
        fputc('\n', f);
    }
    fputs("end\n", f);
    return eo_afile_commit(ctx, &af);
}

/* next header line into line[], advancing *p; -1 at the end of the text */
static int next_line(const char **p, const char *end, char *line, size_t n)
{
    const char *e = memchr(*p, '\n', (size_t)(end - *p));
    if (!e || (size_t)(e - *p) >= n) return -1;
    memcpy(line, *p, (size_t)(e - *p));
    line[e - *p] = 0;
    *p = e + 1;
    return 0;
}

int eo_run_restart_read(eo_ctx *ctx, const char *path, int *step, double *t, int nv, eo_run_array *a, int na)
{
    char *text = NULL;
    size_t len = 0;
    /* the largest file this scene can have: its arrays plus the text lines (each < 256
     * bytes); checked from the file's size before anything is allocated */
    size_t max_bytes = 8 * 256;
    for (int i = 0; i < na; i++) max_bytes += a[i].count * sizeof(double) + 256;
    int rc = eo_read_file_max(ctx, path, max_bytes, "the restart file of this scene (its arrays and header)", &text,
                              &len);
    if (rc < 0) return rc;
    const char *p = text, *end = text + len;
    char line[256], name[128], endian[16];
    int version = 0, file_nv = -1, ln = 0;
    *step = -1;
    *t = NAN;
    for (int i = 0; i < na; i++) a[i].present = 0;
#define BAD(...)                                                                              \
    do {                                                                                      \
        rc = eo_error_at(ctx, EO_ERR_PARSE, EO_ERRLOC_FILE(path, ln), __VA_ARGS__);           \
        goto done;                                                                            \
    } while (0)
    ln++;
    if (next_line(&p, end, line, sizeof line) < 0 || sscanf(line, "elastopt-restart %d", &version) != 1 ||
        version != 1)
        BAD("not an elastopt restart file (version 1)");
    for (;;) {
        ln++;
        if (next_line(&p, end, line, sizeof line) < 0) BAD("truncated (no 'end' line)");
        if (strcmp(line, "end") == 0) break;
        size_t count;
        if (sscanf(line, "step %d", step) == 1 || sscanf(line, "nv %d", &file_nv) == 1) continue;
        if (strncmp(line, "t ", 2) == 0) {
            char *e;
            *t = strtod(line + 2, &e);
            if (e == line + 2 || !isfinite(*t)) BAD("bad time '%s'", line + 2);
            continue;
        }
        if (sscanf(line, "endian %15s", endian) == 1) {
            if (strcmp(endian, endian_name()) != 0) BAD("written on a %s-endian machine; this one is %s-endian", endian, endian_name());
            continue;
        }
        if (sscanf(line, "array %127s %zu", name, &count) == 2) {
            size_t bytes = count * sizeof(double);
            if (count > (size_t)(end - p) / sizeof(double) || (size_t)(end - p) < bytes + 1 || p[bytes] != '\n')
                BAD("array %s: truncated", name);
            for (int i = 0; i < na; i++) {
                if (strcmp(a[i].name, name) != 0) continue;
                if (count != a[i].count) BAD("array %s has %zu values; this scene needs %zu", name, count, a[i].count);
                memcpy(a[i].data, p, bytes);
                for (size_t j = 0; j < count; j++) /* a state that would fail steps later */
                    if (!isfinite(a[i].data[j])) {
                        if (strcmp(name, "x") == 0 || strcmp(name, "v") == 0)
                            BAD("array %s: value %zu (vertex %zu, %c) is %g; a restart state must be finite", name, j,
                                j / 3, "xyz"[j % 3], a[i].data[j]);
                        BAD("array %s: value %zu is %g; a restart state must be finite", name, j, a[i].data[j]);
                    }
                a[i].present = 1;
            }
            p += bytes + 1;
            continue;
        }
        BAD("unexpected line '%.60s'", line);
    }
    ln = -1;
    if (*step < 0 || !isfinite(*t)) BAD("no step or no time");
    if (file_nv != nv) BAD("state of %d vertices; the scene's mesh has %d", file_nv, nv);
    for (int i = 0; i < na; i++)
        if (a[i].required && !a[i].present) BAD("no array '%s'", a[i].name);
    rc = EO_OK;
#undef BAD
done:
    eo_free(ctx, text);
    return rc;
}
