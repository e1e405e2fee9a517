/*
 * Loader of the .bpt patch format: a patch count N, then per patch the
 * degrees "3 3" and 16 control points "x y z", whitespace separated.
 * Every error names the file and the line of the offending token.
 */
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>
#include <stdlib.h>
#include <string.h>

#include "reyes.h"

#define TOKEN_MAX 64

typedef struct tokenizer {
    const char *at;
    const char *name;
    unsigned line;       /* line of the read position */
    unsigned token_line; /* line of the last token read (errors point here) */
    char token[TOKEN_MAX + 1];
    int truncated; /* the token was longer than TOKEN_MAX */
} tokenizer;

/* Read the next token; 0 at the end of the text. */
static int next_token(tokenizer *t)
{
    while (*t->at && isspace((unsigned char)*t->at)) {
        if (*t->at == '\n')
            ++t->line;
        ++t->at;
    }
    if (!*t->at)
        return 0;
    t->token_line = t->line;
    size_t n = 0;
    t->truncated = 0;
    while (*t->at && !isspace((unsigned char)*t->at)) {
        if (n < TOKEN_MAX)
            t->token[n++] = *t->at;
        else
            t->truncated = 1;
        ++t->at;
    }
    t->token[n] = '\0';
    return 1;
}

/* The last token as a message shows it: bytes outside printable ASCII
 * (a stray BOM, a control character) as \xHH, so none is invisible. */
static const char *shown(const tokenizer *t, char *out, size_t size)
{
    size_t n = 0;
    for (const unsigned char *c = (const unsigned char *)t->token; *c && n + 5 < size; ++c) {
        if (*c >= 0x20 && *c < 0x7f)
            out[n++] = (char)*c;
        else
            n += (size_t)snprintf(out + n, size - n, "\\x%02X", *c);
    }
    out[n] = '\0';
    return out;
}

static reyes_status syntax_error(const tokenizer *t, reyes_error *error, const char *what)
{
    return reyes_fail(error, REYES_ERR_FORMAT, "%s:%u: %s", t->name, t->token_line, what);
}

/* A decimal count without sign. */
static int parse_count(const tokenizer *t, unsigned long *out)
{
    if (t->truncated || !isdigit((unsigned char)t->token[0]))
        return 0;
    char *end;
    errno = 0;
    unsigned long value = strtoul(t->token, &end, 10);
    if (errno || *end)
        return 0;
    *out = value;
    return 1;
}

static reyes_status read_coordinate(tokenizer *t, size_t patch, int point, float *out,
                                    reyes_error *error)
{
    char what[160];
    if (!next_token(t)) {
        snprintf(what, sizeof what, "file ends inside patch %zu (control point %d of 16)",
                 patch + 1, point + 1);
        return syntax_error(t, error, what);
    }
    char *end;
    errno = 0;
    float value = t->truncated ? NAN : strtof(t->token, &end);
    /* Overflow gives an infinity (refused); underflow to a tiny or zero
     * value sets ERANGE too but is a fine coordinate. */
    if (t->truncated || *end || !isfinite(value)) {
        char token[4 * TOKEN_MAX + 1];
        snprintf(what, sizeof what, "patch %zu, control point %d: '%s' is not a finite number",
                 patch + 1, point + 1, shown(t, token, sizeof token));
        return syntax_error(t, error, what);
    }
    if (fabsf(value) > REYES_MAX_COORDINATE) {
        snprintf(what, sizeof what, "patch %zu, control point %d: %s is beyond +-%g, where the renderer's "
                 "single-precision arithmetic overflows", patch + 1, point + 1, t->token,
                 (double)REYES_MAX_COORDINATE);
        return syntax_error(t, error, what);
    }
    *out = value;
    return REYES_OK;
}

static reyes_status read_degrees(tokenizer *t, size_t patch, reyes_error *error)
{
    char what[160];
    for (int k = 0; k < 2; ++k) {
        if (!next_token(t)) {
            snprintf(what, sizeof what, "file ends before patch %zu", patch + 1);
            return syntax_error(t, error, what);
        }
        if (strcmp(t->token, "3") != 0) {
            char token[4 * TOKEN_MAX + 1];
            snprintf(what, sizeof what, "patch %zu: degree '%s', only bicubic '3 3' is supported",
                     patch + 1, shown(t, token, sizeof token));
            return syntax_error(t, error, what);
        }
    }
    return REYES_OK;
}

reyes_status reyes_scene_parse_bpt(reyes_scene *scene, const char *text, const char *name,
                                   uint32_t rgba, reyes_error *error)
{
    /* A UTF-8 byte order mark (some editors write one) is not part of the model. */
    static const char bom[] = "\xEF\xBB\xBF";
    if (strncmp(text, bom, sizeof bom - 1) == 0)
        text += sizeof bom - 1;
    tokenizer t = { .at = text, .name = name, .line = 1, .token_line = 1 };
    char what[160], token[4 * TOKEN_MAX + 1];
    unsigned long count;
    if (!next_token(&t))
        return syntax_error(&t, error, "empty file, expected a patch count");
    if (!parse_count(&t, &count) || count == 0) {
        snprintf(what, sizeof what, "patch count '%s' is not a positive integer", shown(&t, token, sizeof token));
        return syntax_error(&t, error, what);
    }
    if (count > REYES_MAX_PATCHES) {
        snprintf(what, sizeof what, "patch count %lu exceeds the limit of %u", count,
                 REYES_MAX_PATCHES);
        return syntax_error(&t, error, what);
    }
    size_t first = scene->patch_count;
    for (size_t patch = 0; patch < count; ++patch) {
        float cp[4][4][3];
        reyes_status status = read_degrees(&t, patch, error);
        for (int point = 0; point < 16 && status == REYES_OK; ++point)
            for (int k = 0; k < 3 && status == REYES_OK; ++k)
                status = read_coordinate(&t, patch, point, &cp[point / 4][point % 4][k], error);
        if (status == REYES_OK)
            status = reyes_scene_add_patch(scene, cp, rgba, error);
        if (status != REYES_OK) {
            scene->patch_count = first; /* leave the scene as it was */
            return status;
        }
    }
    if (next_token(&t)) {
        scene->patch_count = first;
        snprintf(what, sizeof what, "unexpected '%s' after the %lu patches", shown(&t, token, sizeof token), count);
        return syntax_error(&t, error, what);
    }
    return REYES_OK;
}

/* Larger model files are refused before reading: REYES_MAX_PATCHES
 * patches of text fit well below this, and reading more could exhaust
 * memory. */
#define REYES_MAX_FILE_BYTES ((size_t)4 << 30)

static const char *file_kind(mode_t mode)
{
    return S_ISDIR(mode) ? "directory" : S_ISCHR(mode) ? "character device" : S_ISBLK(mode) ? "block device"
         : S_ISSOCK(mode) ? "socket" : "special file";
}

/* Open a model: a regular file no larger than the limit, or a named pipe
 * (read up to the limit).  Anything else (a directory, /dev/zero, a
 * terminal) is refused by kind before a byte is read. */
static reyes_status open_model(const char *path, FILE **out, reyes_error *error)
{
    /* Not blocking: opening a pipe or a device must not wait before we know what it is. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0) {
        reyes_status status = reyes_fail(error, REYES_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
        if (fd >= 0)
            close(fd);
        return status;
    }
    if (!S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode)) {
        close(fd);
        return reyes_fail(error, REYES_ERR_IO, "%s: a %s is not a model file (a model is a regular file or "
                          "a named pipe)", path, file_kind(st.st_mode));
    }
    if (S_ISREG(st.st_mode) && (uintmax_t)st.st_size > REYES_MAX_FILE_BYTES) {
        close(fd);
        return reyes_fail(error, REYES_ERR_FORMAT, "%s: file of %lld bytes is larger than the %zu bytes a "
                          "model may have", path, (long long)st.st_size, REYES_MAX_FILE_BYTES);
    }
    if (S_ISFIFO(st.st_mode)) {
        /* Wait for a writer, as cat would: until one opens the pipe, a
         * read would see an empty file. */
        struct pollfd wait = { .fd = fd, .events = POLLIN };
        while (poll(&wait, 1, -1) < 0 && errno == EINTR)
            continue;
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    *out = fdopen(fd, "rb");
    if (!*out) {
        close(fd);
        return reyes_fail(error, REYES_ERR_NO_MEMORY, "%s: out of memory opening the file", path);
    }
    return REYES_OK;
}

/* Read a whole model into a NUL-terminated buffer, never more than the
 * limit (a pipe or a file that grew is refused there). */
static reyes_status read_file(const char *path, char **out, reyes_error *error)
{
    FILE *f;
    reyes_status status = open_model(path, &f, error);
    if (status != REYES_OK)
        return status;
    size_t size = 0, capacity = 1 << 16;
    char *text = malloc(capacity);
    status = text ? REYES_OK : REYES_ERR_NO_MEMORY;
    while (status == REYES_OK) {
        if (capacity - size < 2) {
            /* Room for one byte past the limit, which tells that it is passed. */
            size_t grown = capacity * 2 < REYES_MAX_FILE_BYTES + 2 ? capacity * 2 : REYES_MAX_FILE_BYTES + 2;
            char *bigger = realloc(text, grown);
            if (!bigger) {
                status = REYES_ERR_NO_MEMORY;
                break;
            }
            text = bigger;
            capacity = grown;
        }
        size_t got = fread(text + size, 1, capacity - size - 1, f);
        size += got;
        if (size > REYES_MAX_FILE_BYTES)
            status = reyes_fail(error, REYES_ERR_FORMAT, "%s: larger than the %zu bytes a model may have",
                                path, REYES_MAX_FILE_BYTES);
        if (got == 0)
            break;
    }
    if (status == REYES_OK && ferror(f))
        status = reyes_fail(error, REYES_ERR_IO, "%s: read error: %s", path, strerror(errno));
    else if (status == REYES_ERR_NO_MEMORY)
        reyes_fail(error, status, "%s: out of memory reading the file (%zu bytes so far)", path, size);
    fclose(f);
    if (status != REYES_OK) {
        free(text);
        return status;
    }
    if (memchr(text, '\0', size)) {
        free(text);
        return reyes_fail(error, REYES_ERR_FORMAT, "%s: binary data (NUL byte), not a .bpt file",
                          path);
    }
    text[size] = '\0';
    *out = text;
    return REYES_OK;
}

reyes_status reyes_scene_load_bpt(reyes_scene *scene, const char *path, uint32_t rgba,
                                  reyes_error *error)
{
    char *text = NULL;
    reyes_status status = read_file(path, &text, error);
    if (status != REYES_OK)
        return status;
    status = reyes_scene_parse_bpt(scene, text, path, rgba, error);
    free(text);
    return status;
}
