/* Output files written whole or not at all (perma.h, *Output files*): a
 * temporary file beside the target, renamed over it only when complete.
 *
 * The stream is a fopencookie stream (glibc, musl) over the file
 * descriptor so that the first failing write's errno is kept: stdio
 * reports only that some write failed, and a later call may have changed
 * errno by the time the writer checks. */
#define _GNU_SOURCE
#include "perma.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

struct perma_output {
    FILE *stream;
    int fd;
    char *path;      /* where the file goes (a symbolic link's target) */
    char *temporary; /* NULL: written in place (a device or a named pipe) */
    int write_errno; /* the first failed write's errno, 0 if none */
    bool replaces;   /* a file was there when the output was opened */
    bool finished;   /* flushed, synced and closed */
};

static perma_status fail(perma_error *error, perma_status status, const char *fmt, ...)
{
    if (error) {
        va_list args;
        va_start(args, fmt);
        vsnprintf(error->message, sizeof error->message, fmt, args);
        va_end(args);
        error->status = status;
    }
    return status;
}

static ssize_t cookie_write(void *cookie, const char *data, size_t size)
{
    perma_output *out = cookie;
    size_t done = 0;
    while (done < size) {
        ssize_t n = write(out->fd, data + done, size - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            if (!out->write_errno)
                out->write_errno = n < 0 ? errno : EIO;
            return done ? (ssize_t)done : -1;
        }
        done += (size_t)n;
    }
    return (ssize_t)done;
}

static int count_temporaries(void)
{
    static int next;
    return __atomic_fetch_add(&next, 1, __ATOMIC_RELAXED);
}

/* Where the file really goes: `path`, or the regular file a symbolic
 * link at `path` points to (the link stays).  *existing is what is there
 * now, if anything (*exists).  NULL with errno on failure. */
static char *resolve(const char *path, struct stat *existing, bool *exists)
{
    *exists = stat(path, existing) == 0;
    struct stat link;
    if (*exists && S_ISREG(existing->st_mode) && lstat(path, &link) == 0 && S_ISLNK(link.st_mode))
        return realpath(path, NULL);
    char *copy = strdup(path);
    if (!copy)
        errno = ENOMEM;
    return copy;
}

static char *temporary_name(const char *path)
{
    size_t size = strlen(path) + 64;
    char *name = malloc(size);
    if (name)
        snprintf(name, size, "%s.%ld-%d.tmp", path, (long)getpid(), count_temporaries());
    return name;
}

/* Create a new temporary file beside `path`: its descriptor, or -1 with errno. */
static int create_temporary(const char *path, char **name)
{
    for (int attempt = 0; attempt < 100; ++attempt) {
        *name = temporary_name(path);
        if (!*name) {
            errno = ENOMEM;
            return -1;
        }
        int fd = open(*name, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST)
            return fd;
        free(*name);
        *name = NULL;
    }
    errno = EEXIST;
    return -1;
}

/* Refuse what a new file at `path` cannot replace. */
static perma_status check_target(const char *path, const struct stat *existing, bool exists, perma_error *error)
{
    if (exists && S_ISDIR(existing->st_mode))
        return fail(error, PERMA_ERR_IO, "cannot write '%s': it is a directory", path);
    /* Renaming would replace a read-only file that writing could not. */
    if (exists && S_ISREG(existing->st_mode) && access(path, W_OK) != 0)
        return fail(error, PERMA_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    return PERMA_OK;
}

void perma_output_discard(perma_output *out)
{
    if (!out)
        return;
    if (out->stream)
        fclose(out->stream);
    if (out->fd >= 0)
        close(out->fd);
    if (out->temporary)
        unlink(out->temporary);
    free(out->temporary);
    free(out->path);
    free(out);
}

/* The file descriptor the output writes to: a new temporary file beside
 * the target, or the target itself if it is there and not a regular file. */
static perma_status open_file(perma_output *out, const char *path, perma_error *error)
{
    struct stat existing;
    bool exists;
    out->path = resolve(path, &existing, &exists);
    if (!out->path)
        return fail(error, PERMA_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    perma_status st = check_target(path, &existing, exists, error);
    if (st != PERMA_OK)
        return st;
    out->replaces = exists;
    if (exists && !S_ISREG(existing.st_mode)) {
        out->fd = open(out->path, O_WRONLY | O_CLOEXEC); /* /dev/null, /dev/stdout, a pipe */
    } else {
        out->fd = create_temporary(out->path, &out->temporary);
        if (out->fd >= 0 && exists)
            fchmod(out->fd, existing.st_mode & 07777); /* keep the file's permissions */
    }
    if (out->fd < 0)
        return fail(error, PERMA_ERR_IO, "cannot create '%s': %s", path, strerror(errno));
    return PERMA_OK;
}

perma_status perma_output_open(const char *path, perma_output **result, perma_error *error)
{
    *result = NULL;
    if (!path || !*path)
        return fail(error, PERMA_ERR_ARGUMENT, "an output file name is empty");
    perma_output *out = calloc(1, sizeof *out);
    if (!out)
        return fail(error, PERMA_ERR_NO_MEMORY, "out of memory opening '%s'", path);
    out->fd = -1;
    perma_status st = open_file(out, path, error);
    if (st == PERMA_OK) {
        cookie_io_functions_t io = { .read = NULL, .write = cookie_write, .seek = NULL, .close = NULL };
        out->stream = fopencookie(out, "w", io);
        if (!out->stream)
            st = fail(error, PERMA_ERR_NO_MEMORY, "out of memory opening '%s'", path);
    }
    if (st != PERMA_OK) {
        perma_output_discard(out);
        return st;
    }
    *result = out;
    return PERMA_OK;
}

perma_status perma_output_check(const char *path, perma_error *error)
{
    /* A device or a pipe that is there is written in place: opening a
     * pipe now would wait for its reader. */
    struct stat existing;
    if (path && stat(path, &existing) == 0 && !S_ISREG(existing.st_mode) && !S_ISDIR(existing.st_mode))
        return PERMA_OK;
    perma_output *out;
    perma_status st = perma_output_open(path, &out, error);
    perma_output_discard(out);
    return st;
}

FILE *perma_output_stream(perma_output *out)
{
    return out ? out->stream : NULL;
}

perma_status perma_output_finish(perma_output *out, perma_error *error)
{
    if (!out)
        return fail(error, PERMA_ERR_ARGUMENT, "perma_output_finish: no output");
    if (out->finished)
        return PERMA_OK;
    int flushed = fflush(out->stream);
    int stream_error = ferror(out->stream);
    fclose(out->stream);
    out->stream = NULL;
    int err = out->write_errno;
    if (!err && (flushed != 0 || stream_error))
        err = EIO;
    /* A full disk may show only now (delayed allocation, network file systems). */
    if (!err && out->temporary && fsync(out->fd) != 0)
        err = errno;
    if (close(out->fd) != 0 && !err)
        err = errno;
    out->fd = -1;
    if (err) {
        const char *outcome = !out->temporary ? ""
                              : out->replaces ? " (the file there before is unchanged)"
                                              : " (no file was written)";
        perma_status st = fail(error, PERMA_ERR_IO, "writing '%s' failed: %s%s", out->path, strerror(err), outcome);
        perma_output_discard(out);
        return st;
    }
    out->finished = true;
    return PERMA_OK;
}

perma_status perma_output_commit(perma_output *out, perma_error *error)
{
    perma_status st = perma_output_finish(out, error);
    if (st != PERMA_OK)
        return st; /* out is gone */
    if (out->temporary && rename(out->temporary, out->path) != 0) {
        st = fail(error, PERMA_ERR_IO, "writing '%s' failed: cannot rename '%s' to it: %s", out->path,
                  out->temporary, strerror(errno));
        perma_output_discard(out);
        return st;
    }
    free(out->temporary);
    out->temporary = NULL;
    perma_output_discard(out);
    return PERMA_OK;
}

/* ---- Outputs that would overwrite each other or an input ---- */

/* What a path is, for comparing: the device and inode of the file there,
 * or (nothing there) the absolute path it would be created at. */
typedef struct file_identity {
    int kind;           /* IDENTITY_* */
    dev_t dev;
    ino_t ino;
    char *path;         /* IDENTITY_PATH: normalised, absolute */
    size_t index;       /* into the caller's files; `count` for the trace */
} file_identity;

enum { IDENTITY_NONE = 0, IDENTITY_INODE, IDENTITY_PATH };

/* Remove "." and "x/.." components and repeated slashes from an absolute
 * path, in place. */
static void collapse(char *path)
{
    char *out = path;
    const char *in = path;
    while (*in) {
        while (*in == '/')
            ++in;
        const char *end = in + strcspn(in, "/");
        size_t n = (size_t)(end - in);
        if (n == 1 && in[0] == '.') {
            /* nothing */
        } else if (n == 2 && in[0] == '.' && in[1] == '.') {
            while (out > path && *--out != '/')
                ;
        } else if (n) {
            *out++ = '/';
            memmove(out, in, n);
            out += n;
        }
        in = end;
    }
    if (out == path)
        *out++ = '/';
    *out = '\0';
}

/* The directory part of the last path normalised, and what it resolved to:
 * the frames of an animation share one. */
typedef struct directory_cache {
    char *name, *resolved;
} directory_cache;

/* The absolute path a file that is not there would be created at: its
 * directory resolved (symbolic links, "..") where it exists, the rest
 * collapsed.  NULL when out of memory. */
static char *creation_path(const char *path, directory_cache *cache)
{
    const char *slash = strrchr(path, '/');
    char *directory = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
    const char *base = slash ? slash + 1 : path;
    if (!directory)
        return NULL;
    if (!cache->name || strcmp(cache->name, directory) != 0) {
        free(cache->name);
        free(cache->resolved);
        cache->name = directory;
        cache->resolved = realpath(directory, NULL);
        if (!cache->resolved) {
            /* Not there (creating the file fails anyway): the text itself,
             * made absolute. */
            char cwd[PATH_MAX] = "";
            if (directory[0] != '/' && !getcwd(cwd, sizeof cwd))
                snprintf(cwd, sizeof cwd, ".");
            size_t size = strlen(cwd) + strlen(directory) + 2;
            cache->resolved = malloc(size);
            if (cache->resolved)
                snprintf(cache->resolved, size, "%s/%s", cwd, directory);
        }
    } else {
        free(directory);
    }
    if (!cache->resolved)
        return NULL;
    size_t size = strlen(cache->resolved) + strlen(base) + 2;
    char *full = malloc(size);
    if (full) {
        snprintf(full, size, "%s/%s", cache->resolved, base);
        collapse(full);
    }
    return full;
}

static int compare_identities(const void *pa, const void *pb)
{
    const file_identity *a = pa, *b = pb;
    if (a->kind != b->kind)
        return a->kind < b->kind ? -1 : 1;
    int c = 0;
    if (a->kind == IDENTITY_INODE)
        c = a->dev != b->dev ? (a->dev < b->dev ? -1 : 1) : a->ino != b->ino ? (a->ino < b->ino ? -1 : 1) : 0;
    else if (a->kind == IDENTITY_PATH)
        c = strcmp(a->path, b->path);
    return c ? c : a->index < b->index ? -1 : a->index > b->index;
}

static int same_identity(const file_identity *a, const file_identity *b)
{
    return a->kind == b->kind && (a->kind == IDENTITY_INODE ? a->dev == b->dev && a->ino == b->ino
                                                            : strcmp(a->path, b->path) == 0);
}

/* Where `path` is (IDENTITY_NONE: a device or pipe, written in place, or
 * out of memory with *failed set). */
static void identify(const char *path, size_t index, directory_cache *cache, file_identity *out, bool *failed)
{
    struct stat st;
    memset(out, 0, sizeof *out);
    out->index = index;
    if (stat(path, &st) == 0) {
        if (S_ISREG(st.st_mode) || S_ISDIR(st.st_mode)) {
            out->kind = IDENTITY_INODE;
            out->dev = st.st_dev;
            out->ino = st.st_ino;
        }
        return;
    }
    out->path = creation_path(path, cache);
    if (out->path)
        out->kind = IDENTITY_PATH;
    else
        *failed = true;
}

/* The first clash of sorted identities: two entries of one group of which
 * one is written, as the lower and higher index; 0 if none. */
static int find_clash(const file_identity *ids, size_t n, const perma_file_role *files, size_t count,
                      size_t *first, size_t *second)
{
    int found = 0;
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && same_identity(&ids[i], &ids[j]))
            ++j;
        /* The group ids[i..j) is sorted by index: its first output, paired
         * with the group's first other member. */
        for (size_t k = i; k < j && j - i > 1; ++k) {
            size_t at = ids[k].index;
            if (at != count && !files[at].written)
                continue;
            size_t other = ids[k == i ? i + 1 : i].index;
            size_t a = other < at ? other : at, b = other < at ? at : other;
            if (!found || a < *first || (a == *first && b < *second))
                *first = a, *second = b;
            found = 1;
            break;
        }
        i = j;
    }
    return found;
}

perma_status perma_check_distinct_files(const perma_file_role *files, size_t count, perma_error *error)
{
    const char *trace = getenv("PERMA_TRACE");
    file_identity *ids = calloc(count + 1, sizeof *ids);
    if (!ids)
        return fail(error, PERMA_ERR_NO_MEMORY, "out of memory comparing %zu file names", count);
    directory_cache cache = { NULL, NULL };
    bool failed = false;
    size_t n = 0;
    for (size_t k = 0; k <= count; ++k) {
        const char *path = k < count ? files[k].path : trace;
        if (path && *path) {
            identify(path, k, &cache, &ids[n], &failed);
            n += ids[n].kind != IDENTITY_NONE;
        }
    }
    free(cache.name);
    free(cache.resolved);
    perma_status st = PERMA_OK;
    size_t a = 0, b = 0;
    qsort(ids, n, sizeof *ids, compare_identities);
    if (failed) {
        st = fail(error, PERMA_ERR_NO_MEMORY, "out of memory comparing %zu file names", count);
    } else if (find_clash(ids, n, files, count, &a, &b)) {
        /* a < b, so only b can be the trace, which is written. */
        const char *names[2] = { files[a].name, b == count ? "PERMA_TRACE" : files[b].name };
        const char *paths[2] = { files[a].path, b == count ? trace : files[b].path };
        bool b_written = b == count || files[b].written;
        if (files[a].written && b_written)
            st = fail(error, PERMA_ERR_ARGUMENT, "%s '%s' and %s '%s' are the same file: one would overwrite the other",
                      names[0], paths[0], names[1], paths[1]);
        else {
            int out = files[a].written ? 0 : 1;
            st = fail(error, PERMA_ERR_ARGUMENT, "%s '%s' is the same file as %s '%s', which it would overwrite",
                      names[out], paths[out], names[1 - out], paths[1 - out]);
        }
    }
    for (size_t k = 0; k < n; ++k)
        free(ids[k].path);
    free(ids);
    return st;
}
