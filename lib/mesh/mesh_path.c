/* Paths of mesh files: checks before use, and all-or-nothing renames of file groups.
 *
 * eo_path_check stats the path (never opens it: opening a FIFO for reading blocks
 * until a writer appears, and a device such as /dev/zero never ends), so every path
 * that cannot be used fails at once with a message saying why. eo_rename_all moves a
 * group of finished temporaries (a TetGen .node/.ele pair) over their targets so that
 * a failure leaves every pre-existing target as it was. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "elastopt/io.h"
#include "mesh_io.h"

#ifndef PATH_MAX
#define PATH_MAX 4096
#endif
#ifndef NAME_MAX
#define NAME_MAX 255
#endif

static const char *kind_name(mode_t m)
{
    if (S_ISREG(m)) return "a file";
    if (S_ISDIR(m)) return "a folder";
    if (S_ISFIFO(m)) return "a FIFO (named pipe)";
    if (S_ISCHR(m)) return "a character device";
    if (S_ISBLK(m)) return "a block device";
    if (S_ISSOCK(m)) return "a socket";
    return "not a regular file";
}

/* print at most 200 characters of a path in messages */
#define SHORT(p) (strlen(p) > 200 ? 200 : (int)strlen(p)), (p)

int eo_path_check(eo_ctx *ctx, const char *path, eo_path_mode mode)
{
    size_t n = strlen(path);
    if (n == 0) return eo_error(ctx, EO_ERR_IO, "empty file name; expected a path");
    if (n >= PATH_MAX)
        return eo_error(ctx, EO_ERR_IO, "%.*s...: file name of %zu characters is longer than the system allows (%d)",
                        SHORT(path), n, PATH_MAX - 1);
    for (const char *c = path; *c;) {
        const char *e = strchr(c, '/');
        size_t k = e ? (size_t)(e - c) : strlen(c);
        if (k > NAME_MAX)
            return eo_error(ctx, EO_ERR_IO, "%.*s...: a component of %zu characters is longer than the system allows (%d)",
                            SHORT(path), k, NAME_MAX);
        c += k;
        while (*c == '/') c++;
    }
    struct stat st;
    if (mode == EO_PATH_READ) {
        if (stat(path, &st) != 0)
            return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot open: %s", strerror(errno));
        if (!S_ISREG(st.st_mode))
            return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "is %s; expected a mesh file",
                               kind_name(st.st_mode));
        if (access(path, R_OK) != 0)
            return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot open: %s", strerror(errno));
        if (st.st_size == 0)
            return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "the file is empty (0 bytes); expected a mesh");
        return EO_OK;
    }
    if (path[n - 1] == '/')
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "names a folder; expected a file name");
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot write: it is %s; expected a file name",
                           kind_name(st.st_mode));
    char dir[PATH_MAX];
    const char *slash = strrchr(path, '/');
    if (slash == path) snprintf(dir, sizeof dir, "/");
    else if (slash) snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    else snprintf(dir, sizeof dir, ".");
    if (stat(dir, &st) != 0)
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot write: folder '%s': %s", dir,
                           strerror(errno));
    if (!S_ISDIR(st.st_mode))
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot write: '%s' is %s, not a folder", dir,
                           kind_name(st.st_mode));
    if (access(dir, W_OK | X_OK) != 0)
        return eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(path, -1), "cannot write: folder '%s': %s", dir,
                           strerror(errno));
    return EO_OK;
}

int eo_rename_all(eo_ctx *ctx, int n, const char *const *tmp, const char *const *dst)
{
    enum { MAXN = 4 };
    char bak[MAXN][PATH_MAX + 32];
    int have_bak[MAXN] = {0}, done = 0, rc = EO_OK;
    if (n > MAXN) return eo_error(ctx, EO_ERR_INVALID, "eo_rename_all: at most %d files", MAXN);
    for (int i = 0; i < n; i++) {
        snprintf(bak[i], sizeof bak[i], "%s.bak.%ld", dst[i], (long)getpid());
        if (link(dst[i], bak[i]) == 0) have_bak[i] = 1;
        else if (errno != ENOENT) {
            rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(dst[i], -1), "cannot keep a backup before replacing it: %s",
                             strerror(errno));
            goto undo;
        }
    }
    for (; done < n; done++)
        if (rename(tmp[done], dst[done]) != 0) {
            rc = eo_error_at(ctx, EO_ERR_IO, EO_ERRLOC_FILE(dst[done], -1), "cannot rename into place: %s",
                             strerror(errno));
            goto undo;
        }
    for (int i = 0; i < n; i++)
        if (have_bak[i]) unlink(bak[i]);
    return EO_OK;
undo:
    for (int i = 0; i < done; i++) {
        if (have_bak[i]) rename(bak[i], dst[i]);
        else unlink(dst[i]);
        have_bak[i] = 0;
    }
    for (int i = 0; i < n; i++) {
        if (have_bak[i]) unlink(bak[i]);
        if (i >= done) unlink(tmp[i]);
    }
    return rc;
}
