/* Reading source files and checking names. */
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
