/* Reading source files and checking names and built-in types. */
#include "files.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

perma_status perma_read_text_file(perma_runtime *rt, const char *path, char **out)
{
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return perma_set_error(rt, PERMA_ERR_IO, "cannot open '%s': %s", path, strerror(errno));
    perma_strbuf sb;
    perma_strbuf_init(&sb);
    char chunk[4096];
    size_t n;
    while ((n = fread(chunk, 1, sizeof chunk - 1, f)) > 0) {
        chunk[n] = '\0';
        if (memchr(chunk, '\0', n)) {
            fclose(f);
            perma_strbuf_free(&sb);
            return perma_set_error(rt, PERMA_ERR_IO, "'%s' is not a text file (contains NUL bytes)", path);
        }
        perma_strbuf_append(&sb, chunk);
    }
    bool read_error = ferror(f);
    fclose(f);
    if (read_error) {
        perma_strbuf_free(&sb);
        return perma_set_error(rt, PERMA_ERR_IO, "error reading '%s'", path);
    }
    if (sb.failed) {
        perma_strbuf_free(&sb);
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory reading '%s'", path);
    }
    if (!sb.data) {
        sb.data = calloc(1, 1);
        if (!sb.data)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory reading '%s'", path);
    }
    *out = sb.data;
    return PERMA_OK;
}

bool perma_is_identifier(const char *s)
{
    if (!s || !(isalpha((unsigned char)s[0]) || s[0] == '_'))
        return false;
    for (const char *p = s; *p; ++p)
        if (!(isalnum((unsigned char)*p) || *p == '_'))
            return false;
    return strlen(s) <= PERMA_NAME_MAX;
}

/* OpenCL C's keywords (C99's and its own), and names its headers define. */
static const char *const keywords[] = {
    "auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else", "enum", "extern",
    "float", "for", "goto", "if", "inline", "int", "long", "register", "restrict", "return", "short", "signed",
    "sizeof", "static", "struct", "switch", "typedef", "union", "unsigned", "void", "volatile", "while",
    "global", "local", "constant", "private", "generic", "kernel", "read_only", "write_only", "read_write",
    "uniform", "pipe", "typeof", "true", "false", "NULL", NULL,
};

/* Type names other than the scalars and vectors of scalar_sizes. */
static const char *const other_types[] = {
    "bool", "size_t", "ptrdiff_t", "intptr_t", "uintptr_t", "image1d_t", "image1d_array_t", "image1d_buffer_t",
    "image2d_t", "image2d_array_t", "image2d_depth_t", "image2d_array_depth_t", "image3d_t", "sampler_t",
    "event_t", "queue_t", "ndrange_t", "clk_event_t", "reserve_id_t", "cl_mem_fence_flags", "quad", "complex",
    "imaginary", NULL,
};

/* The scalar types whose vectors (TYPE2, 3, 4, 8, 16) are types too. */
static const struct { const char *name; size_t size; } scalar_sizes[] = {
    { "char", 1 }, { "uchar", 1 }, { "short", 2 }, { "ushort", 2 }, { "int", 4 }, { "uint", 4 },
    { "long", 8 }, { "ulong", 8 }, { "float", 4 }, { "double", 8 }, { "half", 2 },
};

static bool listed(const char *const *list, const char *name)
{
    for (; *list; ++list)
        if (strcmp(*list, name) == 0)
            return true;
    return false;
}

size_t perma_cl_type_size(const char *name)
{
    for (size_t i = 0; name && i < sizeof scalar_sizes / sizeof scalar_sizes[0]; ++i) {
        size_t n = strlen(scalar_sizes[i].name);
        if (strncmp(name, scalar_sizes[i].name, n) != 0)
            continue;
        const char *lanes = name + n;
        size_t size = scalar_sizes[i].size;
        if (!*lanes)
            return size;
        if (strcmp(lanes, "2") == 0 || strcmp(lanes, "4") == 0 || strcmp(lanes, "8") == 0 || strcmp(lanes, "16") == 0)
            return size * (size_t)atoi(lanes);
        if (strcmp(lanes, "3") == 0)
            return size * 4; /* a 3-vector takes the room of a 4-vector */
    }
    return 0;
}

size_t perma_cl_pointee_size(const char *pointer_type, char *pointee, size_t size)
{
    static const char *const qualifiers[] = {
        "__global", "global", "__constant", "constant", "const", "volatile", "restrict", "__restrict", NULL,
    };
    char words[2][PERMA_NAME_MAX + 1];
    unsigned count = 0;
    const char *at = pointer_type, *star = pointer_type ? strchr(pointer_type, '*') : NULL;
    if (pointee && size)
        pointee[0] = '\0';
    if (!star || strchr(star + 1, '*'))
        return 0;
    while (at < star) {
        while (at < star && isspace((unsigned char)*at))
            ++at;
        size_t n = 0;
        while (at + n < star && !isspace((unsigned char)at[n]))
            ++n;
        if (!n)
            break;
        char word[PERMA_NAME_MAX + 1];
        if (n >= sizeof word)
            return 0;
        memcpy(word, at, n);
        word[n] = '\0';
        at += n;
        if (listed(qualifiers, word))
            continue;
        if (count == 2)
            return 0;
        memcpy(words[count++], word, n + 1);
    }
    const char *name = count == 1 ? words[0] : NULL;
    char spelled[PERMA_NAME_MAX + 2];
    if (count == 2 && (strcmp(words[0], "unsigned") == 0 || strcmp(words[0], "signed") == 0)) {
        /* "unsigned int" is uint, "signed char" char */
        snprintf(spelled, sizeof spelled, "%s%s", words[0][0] == 'u' ? "u" : "", words[1]);
        name = spelled;
    }
    if (!name)
        return 0;
    if (pointee && size)
        snprintf(pointee, size, "%s", name);
    return perma_cl_type_size(name);
}

const char *perma_reserved_name(const char *name)
{
    if (!name)
        return NULL;
    if (listed(keywords, name))
        return "an OpenCL C keyword";
    if (perma_cl_type_size(name) || listed(other_types, name))
        return "an OpenCL C type";
    if (strncmp(name, "perma_", 6) == 0 || strncmp(name, "PERMA_", 6) == 0)
        return "reserved for perma's own names (perma_ and PERMA_)";
    if (name[0] == '_' && (name[1] == '_' || isupper((unsigned char)name[1])))
        return "reserved for the compiler (two underscores, or one and a capital letter, begin its names)";
    return NULL;
}
