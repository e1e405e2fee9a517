/*
 * A disk cache of compiled programs, for OpenCL implementations that do not
 * keep one, and for a farm whose nodes should not each compile the same
 * program: Intel's CPU runtime compiles the Reyes megakernel for 16 s (over
 * a minute on a loaded machine) at every perma_build, and loads the same
 * program from its binary in a quarter of a second.  Programs whose build
 * and warm-up launch took at least PERMA_CACHE_MIN_SECONDS (default 1) of
 * CPU time are stored: CPU time, not wall time, so that the same build is
 * stored or not whatever the machine's load.  The entry is written after
 * the warm-up launch, whose compile an implementation's binary may then
 * hold.
 *
 * PoCL keeps compiled kernels in a cache of its own (POCL_CACHE_DIR), and
 * asking it for a program's binary makes it compile every kernel of the
 * program once more, for any local size: 1.7 s of CPU for a small
 * megakernel, three times its first-launch compile, and minutes of wall
 * time on a loaded machine.  (Before this rule a PoCL build that took over
 * 1 s of wall time, i.e. any build at load 8, was stored, and that compile
 * ran inside perma_build where no watchdog sees it: a benchmark that
 * builds 18 programs ran past its test's timeout with no message.)  So
 * PoCL's programs are stored only when PERMA_CACHE_MIN_SECONDS is 0,
 * which stores every program.
 *
 * Directory: PERMA_CACHE_DIR, else $XDG_CACHE_HOME/perma, else
 * $HOME/.cache/perma; PERMA_CACHE_DIR=off turns the cache off.  An entry is
 * named by a 64-bit hash and holds its whole key (perma's version, the
 * platform, device and driver versions, the build options and the
 * generated source), compared in full before its binary is used.
 *
 * Faults an entry survives (docs/reliability.md):
 *   - a damaged entry (cut short, a flipped bit, empty, not an entry):
 *     the header gives the key's and the binary's lengths and a checksum
 *     of both, checked before the implementation sees a byte (PoCL
 *     crashes on a truncated binary); a bad entry is removed with a
 *     one-line notice and the program built from source;
 *   - a binary the implementation refuses: removed likewise;
 *   - two processes (or threads) storing at once: each writes a
 *     temporary file of its own (mkstemp), flushed to disk, and renames it
 *     over the entry, so a reader sees a whole old entry or a whole new
 *     one, never half of one;
 *   - N processes building the same program at once (the ranks of a farm
 *     sharing a cache directory): the first to miss holds the entry's
 *     build lock (flock on NAME.lock) while it builds and stores; the
 *     others wait for it, then load its entry instead of compiling N
 *     times (PoCL's programs, which PoCL caches itself: a lock per host,
 *     see lock_path).  The wait is bounded (LOCK_WAIT_SECONDS), a dead builder's
 *     lock is released by the kernel, and a holder removes the lock file
 *     before it lets go (a waiter that then holds a removed file tries
 *     again), so no lock files are left behind.
 * At most CACHE_ENTRIES entries are kept, the least recently used go
 * first; temporary files older than an hour (a writer that died) go too.
 */
#define _DEFAULT_SOURCE /* flock */
#include "build_log.h"
#include "clock.h"
#include "internal.h"
#include "program_cache.h"
#include "strbuf.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include <utime.h>

#define CACHE_MAGIC "perma program cache 2\n"
/* After the magic: the key's length, the binary's length, the checksum of
 * the key and the binary, each 64 bits in the host's byte order (an
 * entry of another byte order fails the checks and is rebuilt). */
#define HEADER_WORDS 3
#define HEADER_BYTES (sizeof CACHE_MAGIC - 1 + HEADER_WORDS * sizeof(uint64_t))
#define CACHE_ENTRIES 256
/* Longest wait for another process building the same program: longer than
 * any build seen (Intel's runtime, Reyes, loaded machine: about 70 s). */
#define LOCK_WAIT_SECONDS 300.0
#define STALE_TEMPORARY_SECONDS 3600

/* The cache directory (created if needed), or false when there is none. */
static bool cache_dir(const perma_settings *settings, char *out, size_t size)
{
    const char *dir = settings->cache_dir_set ? settings->cache_dir : NULL;
    if (dir && (strcmp(dir, "off") == 0 || strcmp(dir, "0") == 0))
        return false;
    int n;
    if (dir && *dir) {
        n = snprintf(out, size, "%s", dir);
    } else {
        const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
        if (xdg && *xdg)
            n = snprintf(out, size, "%s/perma", xdg);
        else if (home && *home)
            n = snprintf(out, size, "%s/.cache/perma", home);
        else
            return false;
        if (!(xdg && *xdg) && n > 0 && (size_t)n < size) {
            char parent[1024];
            snprintf(parent, sizeof parent, "%s/.cache", home);
            if (mkdir(parent, 0700) != 0 && errno != EEXIST)
                return false;
        }
    }
    if (n <= 0 || (size_t)n >= size)
        return false;
    return mkdir(out, 0700) == 0 || errno == EEXIST;
}

static void append_info(perma_strbuf *key, const char *label, const char *value)
{
    perma_strbuf_printf(key, "%s: %s\n", label, value);
}

/* The full key of a program: everything its binary depends on. */
static bool cache_key(perma_runtime *rt, const char *source, const char *options, perma_strbuf *key)
{
    char text[512];
    append_info(key, "perma", PERMA_VERSION_STRING);
    static const cl_platform_info platform_info[] = { CL_PLATFORM_NAME, CL_PLATFORM_VERSION };
    for (size_t i = 0; i < sizeof platform_info / sizeof platform_info[0]; ++i) {
        text[0] = '\0';
        clGetPlatformInfo(rt->platform, platform_info[i], sizeof text - 1, text, NULL);
        append_info(key, "platform", text);
    }
    static const cl_device_info device_info[] = { CL_DEVICE_NAME, CL_DEVICE_VERSION, CL_DRIVER_VERSION };
    for (size_t i = 0; i < sizeof device_info / sizeof device_info[0]; ++i) {
        text[0] = '\0';
        clGetDeviceInfo(rt->device, device_info[i], sizeof text - 1, text, NULL);
        append_info(key, "device", text);
    }
    append_info(key, "options", options);
    perma_strbuf_append(key, "source:\n");
    perma_strbuf_append(key, source);
    return !key->failed;
}

/* FNV-1a over 64-bit words (the tail byte by byte), continuing from `h`:
 * names entries and checks them.  A change confined to one word always
 * changes the result (each step is a bijection of h), and it runs at a
 * multiply per 8 bytes, a few milliseconds for a large binary. */
static uint64_t checksum(uint64_t h, const void *data, size_t length)
{
    const unsigned char *bytes = data;
    size_t i = 0;
    for (; i + 8 <= length; i += 8) {
        uint64_t word;
        memcpy(&word, bytes + i, 8);
        h = (h ^ word) * 1099511628211ull;
    }
    for (; i < length; ++i)
        h = (h ^ bytes[i]) * 1099511628211ull;
    return h;
}

#define CHECKSUM_SEED 1469598103934665603ull

/* The checksum an entry's header keeps. */
static uint64_t entry_checksum(const void *key, size_t key_length, const void *binary, size_t binary_length)
{
    return checksum(checksum(CHECKSUM_SEED, key, key_length), binary, binary_length);
}

/* What a file that is not a regular one is, for a message. */
static const char *file_kind(mode_t mode)
{
    return S_ISDIR(mode) ? "a directory" : S_ISFIFO(mode) ? "a named pipe" : S_ISCHR(mode) ? "a character device"
           : S_ISBLK(mode) ? "a block device" : S_ISSOCK(mode) ? "a socket" : "not a regular file";
}

/* Read a whole regular file into *data (NULL for an empty one); false with
 * errno when it cannot be read, or with *kind naming what it is when it
 * is not a regular file.  Opened without blocking: opening a named pipe
 * for reading waits for a writer (it hung perma_build). */
static bool read_file(const char *path, unsigned char **data, size_t *size, const char **kind)
{
    *data = NULL;
    *size = 0;
    *kind = NULL;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return false;
    struct stat st;
    bool stated = fstat(fd, &st) == 0;
    if (!stated || !S_ISREG(st.st_mode) || st.st_size < 0) {
        *kind = stated ? file_kind(st.st_mode) : NULL;
        close(fd);
        return false;
    }
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        close(fd);
        return false;
    }
    bool ok = false;
    size_t length = (size_t)st.st_size;
    unsigned char *bytes = length ? malloc(length) : NULL;
    if (length == 0 || (bytes && fread(bytes, 1, length, f) == length)) {
        *data = bytes;
        *size = length;
        ok = true;
    } else {
        free(bytes);
        if (!errno)
            errno = EIO;
    }
    fclose(f);
    return ok;
}

void perma_cache_entry_open(perma_runtime *rt, const char *source, const char *options, perma_cache_entry *entry)
{
    entry->usable = false;
    entry->lock_fd = -1;
    entry->waited = 0.0;
    perma_strbuf_init(&entry->key);
    if (!cache_dir(&rt->settings, entry->dir, sizeof entry->dir) || !cache_key(rt, source, options, &entry->key))
        return;
    const perma_strbuf *key = &entry->key;
    int n = snprintf(entry->path, sizeof entry->path, "%s/%016llx.bin", entry->dir,
                     (unsigned long long)checksum(CHECKSUM_SEED, key->data, key->length));
    entry->usable = n > 0 && (size_t)n < sizeof entry->path;
    entry->stores = !rt->caps.caches_programs || rt->settings.cache_min_seconds <= 0.0;
}

/* The lock file's name: the entry's with .lock for .bin.  A program that
 * will not be stored here (PoCL's, in its own cache) is locked per host,
 * NAME.HOST.lock: the ranks on one node share PoCL's cache and compile
 * once, while nodes whose PoCL caches are their own (the usual case) must
 * not wait for each other's compiles, from which they gain nothing. */
static void lock_path(const perma_cache_entry *entry, char *out, size_t size)
{
    size_t n = strlen(entry->path) - strlen(".bin");
    char host[256] = "";
    if (!entry->stores && gethostname(host, sizeof host - 1) != 0)
        host[0] = '\0';
    for (char *c = host; *c; ++c)
        if (*c == '/')
            *c = '_';
    snprintf(out, size, "%.*s%s%s.lock", (int)n, entry->path, host[0] ? "." : "", host);
}

static void cache_unlock(perma_cache_entry *entry)
{
    if (entry->lock_fd < 0)
        return;
    char path[sizeof entry->path + 300];
    lock_path(entry, path, sizeof path);
    unlink(path); /* before letting go: a waiter then sees it gone and tries again */
    close(entry->lock_fd);
    entry->lock_fd = -1;
}

void perma_cache_entry_close(perma_cache_entry *entry)
{
    cache_unlock(entry);
    perma_strbuf_free(&entry->key);
    entry->usable = false;
}

bool perma_cache_lock(perma_cache_entry *entry)
{
    if (!entry->usable || entry->lock_fd >= 0)
        return entry->lock_fd >= 0;
    char path[sizeof entry->path + 300];
    lock_path(entry, path, sizeof path);
    double start = perma_now();
    while (perma_now() - start < LOCK_WAIT_SECONDS) {
        int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0600);
        if (fd < 0)
            break; /* a read-only cache: build without the lock */
        int locked;
        while ((locked = flock(fd, LOCK_EX | LOCK_NB)) != 0 && errno == EWOULDBLOCK
               && perma_now() - start < LOCK_WAIT_SECONDS) {
            const struct timespec pause = { 0, 20000000 }; /* 20 ms */
            nanosleep(&pause, NULL);
        }
        struct stat held, named;
        if (locked == 0 && fstat(fd, &held) == 0 && stat(path, &named) == 0 && held.st_dev == named.st_dev
            && held.st_ino == named.st_ino) {
            entry->lock_fd = fd;
            break;
        }
        close(fd); /* not locked in time, or the file we locked was removed by its last holder */
        if (locked != 0)
            break;
    }
    entry->waited = perma_now() - start;
    return entry->lock_fd >= 0;
}

/* Remove a bad entry; the one-line notice saying why in notice[]. */
static void discard(const char *path, const char *why, char *notice, size_t size)
{
    if (unlink(path) != 0 && errno == EISDIR)
        rmdir(path); /* an empty directory where the entry should be */
    snprintf(notice, size, "perma: discarded the damaged program-cache entry %s (%s); building the program from "
             "source", path, why);
}

/* Why `data` (the file's `size` bytes) is not a sound entry, or NULL if it
 * is one; its key and binary then in *key_at, *binary_at. */
static const char *check_entry(const unsigned char *data, size_t size, char *why, size_t why_size,
                               const unsigned char **key_at, uint64_t *key_length, const unsigned char **binary_at,
                               uint64_t *binary_length)
{
    size_t magic = sizeof CACHE_MAGIC - 1;
    if (size == 0)
        return "an empty file";
    if (size < magic || memcmp(data, CACHE_MAGIC, magic) != 0)
        return "not a program-cache entry of this perma version";
    if (size < HEADER_BYTES) {
        snprintf(why, why_size, "cut short: %zu bytes, less than its header", size);
        return why;
    }
    uint64_t header[HEADER_WORDS];
    memcpy(header, data + magic, sizeof header);
    *key_length = header[0];
    *binary_length = header[1];
    uint64_t body = size - HEADER_BYTES;
    if (*key_length > body || *binary_length > body - *key_length) {
        snprintf(why, why_size, "cut short: %zu bytes of %llu", size,
                 (unsigned long long)(HEADER_BYTES + *key_length + *binary_length));
        return why;
    }
    if (*key_length + *binary_length != body) {
        snprintf(why, why_size, "%llu bytes after its end",
                 (unsigned long long)(body - *key_length - *binary_length));
        return why;
    }
    *key_at = data + HEADER_BYTES;
    *binary_at = *key_at + *key_length;
    if (entry_checksum(*key_at, (size_t)*key_length, *binary_at, (size_t)*binary_length) != header[2])
        return "its checksum does not match its contents";
    return NULL;
}

/* The program in an entry's `size` bytes of `data`, if it is sound and
 * built for this key; a bad entry is removed, saying why in notice[]. */
static cl_program load_entry(perma_runtime *rt, const perma_cache_entry *entry, const char *options,
                             const unsigned char *data, size_t size, char *notice, size_t notice_size)
{
    const char *path = entry->path;
    char why[128];
    const unsigned char *key_at = NULL, *binary = NULL;
    uint64_t key_length = 0, binary_length = 0;
    const char *bad = check_entry(data, size, why, sizeof why, &key_at, &key_length, &binary, &binary_length);
    const perma_strbuf *key = &entry->key;
    if (bad) {
        discard(path, bad, notice, notice_size);
        return NULL;
    }
    if (key_length != key->length || memcmp(key_at, key->data, key->length) != 0)
        return NULL; /* another program with the same hash: a miss, overwritten by the store */
    cl_int status = CL_SUCCESS, err;
    size_t binary_size = (size_t)binary_length;
    cl_program program = clCreateProgramWithBinary(rt->context, 1, &rt->device, &binary_size, &binary, &status, &err);
    cl_int built = program && err == CL_SUCCESS && status == CL_SUCCESS
                       ? clBuildProgram(program, 1, &rt->device, options, NULL, NULL)
                       : (err != CL_SUCCESS ? err : status);
    if (built != CL_SUCCESS) {
        if (program)
            clReleaseProgram(program);
        snprintf(why, sizeof why, "the OpenCL implementation refused its binary: %s", perma_cl_error_name(built));
        discard(path, why, notice, notice_size);
        return NULL;
    }
    utime(path, NULL); /* recently used */
    return program;
}

cl_program perma_cache_load(perma_runtime *rt, const perma_cache_entry *entry, const char *options)
{
    if (!entry->usable)
        return NULL;
    char notice[2 * PERMA_MESSAGE_MAX] = ""; /* at most one, shown at the end (perma_notice cuts it) */
    unsigned char *data = NULL;
    size_t size = 0;
    cl_program program = NULL;
    const char *kind;
    if (read_file(entry->path, &data, &size, &kind))
        program = load_entry(rt, entry, options, data, size, notice, sizeof notice);
    else if (kind) {
        char why[64];
        snprintf(why, sizeof why, "%s, not a file", kind);
        discard(entry->path, why, notice, sizeof notice);
    }
    else if (errno != ENOENT)
        snprintf(notice, sizeof notice, "perma: cannot read the program-cache entry %s (%s); building the program "
                 "from source", entry->path, strerror(errno));
    free(data);
    if (notice[0])
        perma_notice(rt, "%s", notice);
    return program;
}

/* Remove the least recently used entries beyond CACHE_ENTRIES, and
 * temporary files a writer that died left. */
static void evict(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct entry { char name[64]; time_t used; } *entries = NULL;
    size_t count = 0, alloc = 0;
    time_t now = time(NULL);
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        bool temporary = strstr(e->d_name, ".tmp.") != NULL;
        if (n >= sizeof entries->name || (!temporary && (n < 5 || strcmp(e->d_name + n - 4, ".bin") != 0)))
            continue;
        char path[1200];
        struct stat st;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (stat(path, &st) != 0)
            continue;
        if (temporary) {
            if (now - st.st_mtime > STALE_TEMPORARY_SECONDS)
                unlink(path);
            continue;
        }
        if (count == alloc) {
            size_t grown = alloc ? 2 * alloc : 64;
            struct entry *more = realloc(entries, grown * sizeof *entries);
            if (!more)
                break;
            entries = more;
            alloc = grown;
        }
        snprintf(entries[count].name, sizeof entries[count].name, "%s", e->d_name);
        entries[count++].used = st.st_mtime;
    }
    closedir(d);
    while (count > CACHE_ENTRIES) {
        size_t oldest = 0;
        for (size_t i = 1; i < count; ++i)
            if (entries[i].used < entries[oldest].used)
                oldest = i;
        char path[1200];
        snprintf(path, sizeof path, "%s/%s", dir, entries[oldest].name);
        unlink(path);
        entries[oldest] = entries[--count];
    }
    free(entries);
}

/* Write the entry to a temporary file of its own in the directory, flushed
 * to disk, and rename it into place. */
static bool write_entry(const perma_cache_entry *entry, const unsigned char *binary, size_t binary_size)
{
    const perma_strbuf *key = &entry->key;
    char temporary[sizeof entry->path + 16];
    snprintf(temporary, sizeof temporary, "%.*s.tmp.XXXXXX", (int)(strlen(entry->path) - strlen(".bin")),
             entry->path);
    int fd = mkstemp(temporary);
    if (fd < 0)
        return false;
    FILE *f = fdopen(fd, "wb");
    if (!f) {
        close(fd);
        unlink(temporary);
        return false;
    }
    uint64_t header[HEADER_WORDS] = { key->length, binary_size,
                                      entry_checksum(key->data, key->length, binary, binary_size) };
    size_t magic = sizeof CACHE_MAGIC - 1;
    bool written = fwrite(CACHE_MAGIC, 1, magic, f) == magic && fwrite(header, sizeof header, 1, f) == 1
                   && fwrite(key->data, 1, key->length, f) == key->length
                   && fwrite(binary, 1, binary_size, f) == binary_size && fflush(f) == 0 && fsync(fd) == 0;
    if (fclose(f) != 0)
        written = false;
    if (written && rename(temporary, entry->path) == 0)
        return true;
    unlink(temporary);
    return false;
}

bool perma_cache_store(perma_runtime *rt, const perma_cache_entry *entry, double cpu_seconds)
{
    double least = rt->settings.cache_min_seconds;
    if (!entry->usable || !entry->stores || cpu_seconds < least)
        return false;
    size_t binary_size = 0;
    cl_program program = rt->build.program;
    if (clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof binary_size, &binary_size, NULL) != CL_SUCCESS
        || binary_size == 0)
        return false;
    unsigned char *binary = malloc(binary_size);
    bool stored = binary
                  && clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof binary, &binary, NULL) == CL_SUCCESS
                  && write_entry(entry, binary, binary_size);
    if (stored)
        evict(entry->dir);
    free(binary);
    return stored;
}
