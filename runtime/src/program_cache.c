/*
 * A disk cache of compiled programs, for OpenCL implementations that do not
 * keep one: Intel's CPU runtime compiles the Reyes megakernel for 16 s (over
 * a minute on a loaded machine) at every perma_build, and loads the same
 * program from its binary in a quarter of a second.  PoCL builds in a tenth
 * of a second (it compiles at the first launch, from its own kernel
 * cache), so only builds slower than PERMA_CACHE_MIN_SECONDS (default 1)
 * are stored: the rule needs no knowledge of the implementation.
 *
 * Directory: PERMA_CACHE_DIR, else $XDG_CACHE_HOME/perma, else
 * $HOME/.cache/perma; PERMA_CACHE_DIR=off turns the cache off.  An entry is
 * named by a 64-bit hash and holds its whole key (perma's version, the
 * platform, device and driver versions, the build options and the
 * generated source), compared in full before its binary is used.  Entries
 * are written to a temporary file and renamed, so a concurrent reader never
 * sees half of one; a binary the implementation refuses is deleted and the
 * program built from source.  At most CACHE_ENTRIES entries are kept, the
 * least recently used go first.
 */
#include "internal.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <utime.h>

#define CACHE_MAGIC "perma program cache 1\n"
#define CACHE_ENTRIES 256

/* The cache directory (created if needed), or false when there is none. */
static bool cache_dir(char *out, size_t size)
{
    const char *dir = getenv("PERMA_CACHE_DIR");
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

/* FNV-1a, 64 bits. */
static uint64_t hash_text(const char *text, size_t length)
{
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < length; ++i) {
        h ^= (unsigned char)text[i];
        h *= 1099511628211ull;
    }
    return h;
}

static double min_seconds(void)
{
    const char *value = getenv("PERMA_CACHE_MIN_SECONDS");
    char *end = NULL;
    double seconds = value && *value ? strtod(value, &end) : 1.0;
    return end && *end ? 1.0 : seconds;
}

/* Read a whole file; NULL if it cannot be read. */
static unsigned char *read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char *data = NULL;
    long length = -1;
    if (fseek(f, 0, SEEK_END) == 0 && (length = ftell(f)) > 0 && fseek(f, 0, SEEK_SET) == 0) {
        data = malloc((size_t)length);
        if (data && fread(data, 1, (size_t)length, f) != (size_t)length) {
            free(data);
            data = NULL;
        }
    }
    fclose(f);
    *size = data ? (size_t)length : 0;
    return data;
}

void perma_cache_entry_open(perma_runtime *rt, const char *source, const char *options, perma_cache_entry *entry)
{
    entry->usable = false;
    perma_strbuf_init(&entry->key);
    if (!cache_dir(entry->dir, sizeof entry->dir) || !cache_key(rt, source, options, &entry->key))
        return;
    const perma_strbuf *key = &entry->key;
    int n = snprintf(entry->path, sizeof entry->path, "%s/%016llx.bin", entry->dir,
                     (unsigned long long)hash_text(key->data, key->length));
    entry->usable = n > 0 && (size_t)n < sizeof entry->path;
}

void perma_cache_entry_close(perma_cache_entry *entry)
{
    perma_strbuf_free(&entry->key);
    entry->usable = false;
}

cl_program perma_cache_load(perma_runtime *rt, const perma_cache_entry *entry, const char *options)
{
    const perma_strbuf *key = &entry->key;
    const char *path = entry->path;
    cl_program program = NULL;
    size_t size = 0, magic = strlen(CACHE_MAGIC);
    unsigned char *data = entry->usable ? read_file(path, &size) : NULL;
    /* magic, key length (8 bytes), key, binary */
    if (data && size > magic + 8 && memcmp(data, CACHE_MAGIC, magic) == 0) {
        uint64_t key_length;
        memcpy(&key_length, data + magic, 8);
        const unsigned char *binary = data + magic + 8 + key_length;
        size_t binary_size = size - magic - 8 - (size_t)key_length;
        if (key_length == key->length && key_length < size - magic - 8
            && memcmp(data + magic + 8, key->data, key->length) == 0) {
            cl_int status = CL_SUCCESS, err;
            program = clCreateProgramWithBinary(rt->context, 1, &rt->device, &binary_size, &binary, &status, &err);
            if (program && (err != CL_SUCCESS || status != CL_SUCCESS
                            || clBuildProgram(program, 1, &rt->device, options, NULL, NULL) != CL_SUCCESS)) {
                clReleaseProgram(program);
                program = NULL;
            }
            if (program)
                utime(path, NULL); /* recently used */
            else
                unlink(path);      /* refused: rebuilt from source and stored again */
        }
    }
    free(data);
    return program;
}

/* Remove the least recently used entries beyond CACHE_ENTRIES. */
static void evict(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct entry { char name[64]; time_t used; } *entries = NULL;
    size_t count = 0, alloc = 0;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        size_t n = strlen(e->d_name);
        if (n < 5 || n >= sizeof entries->name || strcmp(e->d_name + n - 4, ".bin") != 0)
            continue;
        char path[1200];
        struct stat st;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (stat(path, &st) != 0)
            continue;
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

void perma_cache_store(cl_program program, const perma_cache_entry *entry, double build_seconds)
{
    if (!entry->usable || build_seconds < min_seconds())
        return;
    size_t binary_size = 0;
    if (clGetProgramInfo(program, CL_PROGRAM_BINARY_SIZES, sizeof binary_size, &binary_size, NULL) != CL_SUCCESS
        || binary_size == 0)
        return;
    unsigned char *binary = malloc(binary_size);
    const perma_strbuf *key = &entry->key;
    char temporary[1200];
    if (binary && clGetProgramInfo(program, CL_PROGRAM_BINARIES, sizeof binary, &binary, NULL) == CL_SUCCESS) {
        snprintf(temporary, sizeof temporary, "%s.%ld.tmp", entry->path, (long)getpid());
        FILE *f = fopen(temporary, "wb");
        uint64_t key_length = key->length;
        bool written = f && fwrite(CACHE_MAGIC, 1, strlen(CACHE_MAGIC), f) == strlen(CACHE_MAGIC)
                       && fwrite(&key_length, 8, 1, f) == 1 && fwrite(key->data, 1, key->length, f) == key->length
                       && fwrite(binary, 1, binary_size, f) == binary_size;
        if (f && fclose(f) != 0)
            written = false;
        if (written && rename(temporary, entry->path) == 0)
            evict(entry->dir);
        else if (f)
            unlink(temporary);
    }
    free(binary);
}
