/* Edge lists: growth and the plain-text reader. */
#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "bfs.h"

int bfs_edges_add(bfs_edges *e, uint32_t u, uint32_t v)
{
    if (e->count == e->capacity) {
        size_t capacity = e->capacity ? 2 * e->capacity : 1024;
        void *pairs = realloc(e->pairs, capacity * sizeof *e->pairs);
        if (!pairs)
            return -1;
        e->pairs = pairs;
        e->capacity = capacity;
    }
    e->pairs[e->count][0] = u;
    e->pairs[e->count][1] = v;
    e->count++;
    uint32_t top = (u > v ? u : v) + 1;
    if (top > e->vertices)
        e->vertices = top;
    return 0;
}

void bfs_edges_free(bfs_edges *e)
{
    free(e->pairs);
    *e = (bfs_edges){ 0 };
}

/* One vertex id at *at; advances past it.  0 if there is no valid id. */
static int parse_id(const char **at, uint32_t *out)
{
    const char *s = *at;
    if (!isdigit((unsigned char)*s))
        return 0;
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno || v >= BFS_MAX_VERTICES)
        return 0;
    *out = (uint32_t)v;
    *at = end;
    return 1;
}

static const char *skip_blanks(const char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\r')
        ++s;
    return s;
}

/* 1: an edge, 0: nothing on the line, -1: malformed. */
static int parse_line(const char *line, uint32_t *u, uint32_t *v)
{
    const char *at = skip_blanks(line);
    if (*at == '\0' || *at == '\n' || *at == '#')
        return 0;
    if (!parse_id(&at, u))
        return -1;
    const char *gap = at;
    at = skip_blanks(at);
    if (at == gap || !parse_id(&at, v))
        return -1;
    at = skip_blanks(at);
    return *at == '\0' || *at == '\n' || *at == '#' ? 1 : -1;
}

bfs_status bfs_read_edges(const char *path, bfs_edges *out, char *message, size_t size)
{
    *out = (bfs_edges){ 0 };
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(message, size, "%s: cannot open: %s", path, strerror(errno));
        return BFS_ERR_RUNTIME;
    }
    char *line = NULL;
    size_t line_size = 0;
    unsigned long number = 0;
    bfs_status st = BFS_OK;
    while (getline(&line, &line_size, f) != -1) {
        ++number;
        uint32_t u, v;
        int kind = parse_line(line, &u, &v);
        if (kind < 0) {
            line[strcspn(line, "\r\n")] = '\0';
            snprintf(message, size, "%s:%lu: expected 'u v' (two vertex ids below %u), got '%.60s'",
                     path, number, BFS_MAX_VERTICES, line);
            st = BFS_ERR_RUNTIME;
            break;
        }
        if (kind > 0 && bfs_edges_add(out, u, v) != 0) {
            snprintf(message, size, "%s:%lu: out of memory for %zu edges", path, number, out->count);
            st = BFS_ERR_RUNTIME;
            break;
        }
    }
    if (st == BFS_OK && ferror(f)) {
        snprintf(message, size, "%s:%lu: read error: %s", path, number + 1, strerror(errno));
        st = BFS_ERR_RUNTIME;
    }
    if (st == BFS_OK && out->count == 0) {
        snprintf(message, size, "%s: no edges in %lu lines", path, number);
        st = BFS_ERR_RUNTIME;
    }
    free(line);
    fclose(f);
    if (st != BFS_OK)
        bfs_edges_free(out);
    return st;
}
