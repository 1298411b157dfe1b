/* Files: atomic writing (temporary name + rename), folders, whole-file reads. */
#define _POSIX_C_SOURCE 200809L
#include "elastopt/io.h"

#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const char *eo_fmt_double(char buf[32], double v)
{
    if (!isfinite(v)) {
        snprintf(buf, 32, "%g", v);
        return buf;
    }
    for (int digits = 15; digits < 17; digits++) {
        snprintf(buf, 32, "%.*g", digits, v);
        if (strtod(buf, NULL) == v) return buf;
    }
    snprintf(buf, 32, "%.17g", v); /* always round-trips (IEEE double) */
    return buf;
}

struct eo_afile {
    FILE *fp;
    char *path;
    char *tmp;
};

int eo_afile_open(eo_ctx *ctx, const char *path, eo_afile **out)
{
    *out = NULL;
    /* a folder, FIFO, device or socket at the path (rename would replace a FIFO or a
     * device node by a file) or a parent that is missing, not a folder or unwritable */
    int rc = eo_path_check(ctx, path, EO_PATH_WRITE);
    if (rc < 0) return rc;
    eo_afile *f = eo_calloc(ctx, 1, sizeof *f);
    if (!f) return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    size_t n = strlen(path);
    f->path = eo_strdup(ctx, path);
    f->tmp = eo_calloc(ctx, 1, n + 32);
    if (!f->path || !f->tmp) {
        eo_afile_abort(ctx, &f);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory");
    }
    snprintf(f->tmp, n + 32, "%s.tmp.%ld", path, (long)getpid());
    f->fp = fopen(f->tmp, "wb");
    if (!f->fp) {
        int e = errno;
        eo_afile_abort(ctx, &f);
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot write: %s", strerror(e));
    }
    *out = f;
    return EO_OK;
}

FILE *eo_afile_fp(eo_afile *f) { return f->fp; }

int eo_afile_commit(eo_ctx *ctx, eo_afile **pf)
{
    eo_afile *f = *pf;
    int bad = ferror(f->fp);
    int e = errno;
    if (fclose(f->fp) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    f->fp = NULL;
    if (bad) {
        int rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(f->path, -1), "write failed: %s", strerror(e));
        eo_afile_abort(ctx, pf);
        return rc;
    }
    if (rename(f->tmp, f->path) != 0) {
        e = errno;
        int rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(f->path, -1), "cannot rename into place: %s",
                             strerror(e));
        eo_afile_abort(ctx, pf);
        return rc;
    }
    eo_free(ctx, f->tmp);
    f->tmp = NULL;
    eo_afile_abort(ctx, pf);
    return EO_OK;
}

void eo_afile_abort(eo_ctx *ctx, eo_afile **pf)
{
    if (!pf || !*pf) return;
    eo_afile *f = *pf;
    if (f->fp) fclose(f->fp);
    if (f->tmp && f->tmp[0]) remove(f->tmp);
    eo_free(ctx, f->tmp);
    eo_free(ctx, f->path);
    eo_free(ctx, f);
    *pf = NULL;
}

int eo_mkdir_p(eo_ctx *ctx, const char *path)
{
    char buf[4096];
    if (strlen(path) >= sizeof buf)
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "path too long");
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/') continue;
        *p = 0;
        struct stat cs;
        if (stat(buf, &cs) == 0 && !S_ISDIR(cs.st_mode))
            return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot create folder: '%s' is %s, not a folder",
                               buf, S_ISREG(cs.st_mode) ? "a file" : "a FIFO, device or socket");
        if (mkdir(buf, 0777) != 0 && errno != EEXIST)
            return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(buf, -1), "cannot create folder: %s",
                               strerror(errno));
        *p = '/';
    }
    if (mkdir(buf, 0777) != 0 && errno != EEXIST)
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot create folder: %s",
                           strerror(errno));
    struct stat st;
    if (stat(buf, &st) != 0 || !S_ISDIR(st.st_mode))
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "is %s; expected a folder",
                           S_ISREG(st.st_mode) ? "a file" : "a FIFO, device or socket");
    if (access(buf, W_OK) != 0)
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "folder not writable");
    return EO_OK;
}

int eo_read_file(eo_ctx *ctx, const char *path, char **text, size_t *len)
{
    return eo_read_file_max(ctx, path, SIZE_MAX, NULL, text, len);
}

int eo_read_file_max(eo_ctx *ctx, const char *path, size_t max_bytes, const char *what, char **text, size_t *len)
{
    *text = NULL;
    *len = 0;
    /* O_NONBLOCK: opening a FIFO must not wait for a writer; anything but a regular file
     * (a FIFO, a device such as /dev/zero that never ends, a folder) is refused */
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd < 0) return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const char *what = S_ISDIR(st.st_mode)    ? "a folder"
                           : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                           : S_ISCHR(st.st_mode)  ? "a character device"
                           : S_ISBLK(st.st_mode)  ? "a block device"
                           : S_ISSOCK(st.st_mode) ? "a socket"
                                                  : "not a regular file";
        close(fd);
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot read: it is %s; expected a regular file",
                           what);
    }
    if ((unsigned long long)st.st_size > (unsigned long long)max_bytes) {
        close(fd);
        return eo_error_at(ctx, EO_ERR_RANGE, EO_ERRLOC_FILE(path, -1),
                           "%lld bytes (%.3g MB); the limit for %s is %zu bytes (%.3g MB)", (long long)st.st_size,
                           (double)st.st_size / 1e6, what ? what : "this file", max_bytes, (double)max_bytes / 1e6);
    }
    int fl = fcntl(fd, F_GETFL);
    if (fl >= 0) fcntl(fd, F_SETFL, fl & ~O_NONBLOCK);
    FILE *fp = fdopen(fd, "rb");
    if (!fp) {
        int e = errno;
        close(fd);
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot open: %s", strerror(e));
    }
    size_t cap = st.st_size > 0 ? (size_t)st.st_size + 1 : 4096, n = 0;
    char *buf = eo_malloc(ctx, cap);
    if (!buf) {
        fclose(fp);
        return eo_error(ctx, EO_ERR_NOMEM, "out of memory reading %s", path);
    }
    for (;;) {
        if (n + 1 >= cap) {
            char *nb = eo_realloc(ctx, buf, cap * 2);
            if (!nb) {
                eo_free(ctx, buf);
                fclose(fp);
                return eo_error(ctx, EO_ERR_NOMEM, "out of memory reading %s", path);
            }
            buf = nb;
            cap *= 2;
        }
        size_t r = fread(buf + n, 1, cap - 1 - n, fp);
        n += r;
        if (r == 0) break;
        if (n > max_bytes) { /* grew while being read */
            eo_free(ctx, buf);
            fclose(fp);
            return eo_error_at(ctx, EO_ERR_RANGE, EO_ERRLOC_FILE(path, -1),
                               "more than %zu bytes (it grew while being read); the limit for %s", max_bytes,
                               what ? what : "this file");
        }
    }
    int bad = ferror(fp);
    fclose(fp);
    if (bad) {
        eo_free(ctx, buf);
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "read error");
    }
    buf[n] = 0;
    *text = buf;
    *len = n;
    return EO_OK;
}
