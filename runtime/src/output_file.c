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
