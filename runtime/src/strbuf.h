/* A growable string for generating program text. */
#ifndef PERMA_STRBUF_H
#define PERMA_STRBUF_H

#include <stdbool.h>
#include <stddef.h>

typedef struct perma_strbuf {
    char *data;
    size_t length;
    size_t capacity;
    size_t lines;   /* newlines appended so far */
    bool failed;    /* an allocation failed; data is incomplete */
} perma_strbuf;

void perma_strbuf_init(perma_strbuf *sb);
void perma_strbuf_free(perma_strbuf *sb);
void perma_strbuf_append(perma_strbuf *sb, const char *text);
void perma_strbuf_printf(perma_strbuf *sb, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
