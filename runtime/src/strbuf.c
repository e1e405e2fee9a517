#include "strbuf.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void perma_strbuf_init(perma_strbuf *sb)
{
    memset(sb, 0, sizeof *sb);
}

void perma_strbuf_free(perma_strbuf *sb)
{
    free(sb->data);
    perma_strbuf_init(sb);
}

static bool strbuf_reserve(perma_strbuf *sb, size_t extra)
{
    if (sb->failed)
        return false;
    if (sb->length + extra + 1 <= sb->capacity)
        return true;
    size_t capacity = sb->capacity ? sb->capacity : 4096;
    while (capacity < sb->length + extra + 1)
        capacity *= 2;
    char *data = realloc(sb->data, capacity);
    if (!data) {
        sb->failed = true;
        return false;
    }
    sb->data = data;
    sb->capacity = capacity;
    return true;
}

static void strbuf_count_lines(perma_strbuf *sb, const char *text, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        sb->lines += text[i] == '\n';
}

void perma_strbuf_append(perma_strbuf *sb, const char *text)
{
    size_t n = strlen(text);
    if (!strbuf_reserve(sb, n))
        return;
    memcpy(sb->data + sb->length, text, n + 1);
    strbuf_count_lines(sb, text, n);
    sb->length += n;
}

void perma_strbuf_printf(perma_strbuf *sb, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0 || !strbuf_reserve(sb, (size_t)n)) {
        sb->failed = true;
        return;
    }
    va_start(ap, fmt);
    vsnprintf(sb->data + sb->length, (size_t)n + 1, fmt, ap);
    va_end(ap);
    strbuf_count_lines(sb, sb->data + sb->length, (size_t)n);
    sb->length += (size_t)n;
}
