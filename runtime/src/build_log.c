/* Reading the compiler's build log: where a diagnostic points, and showing
 * the warnings of a build that succeeded (config.build_log, or stderr).
 * The generated program's #line directives make the compiler name the
 * user's files and lines; this only brings the lines into one form,
 * "FILE:LINE:COL: warning: TEXT", whichever way the compiler wrote them
 * (PoCL: "warning: FILE:LINE:COL: TEXT", clang and Intel's compiler:
 * "FILE:LINE:COL: warning: TEXT"). */
#include "build_log.h"
#include "internal.h"
#include "strbuf.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* `kind` ("error", "warning") followed by ": " at text[0..length). */
static bool kind_at(const char *text, size_t length, const char *kind)
{
    size_t n = strlen(kind);
    return length >= n + 2 && strncmp(text, kind, n) == 0 && text[n] == ':' && text[n + 1] == ' ';
}

bool perma_build_log_diagnostic(const char *line, size_t length, const char *kind, char *where, size_t where_size,
                                const char **text)
{
    const char *location = NULL, *location_end = NULL;
    size_t kind_length = strlen(kind);
    if (kind_at(line, length, kind)) {
        /* PoCL: "warning: FILE:LINE:COL[ <Spelling=...>]: TEXT" */
        location = line + kind_length + 2;
        const char *end = line + length;
        const char *spelling = strstr(location, " <Spelling=");
        const char *colon = NULL;
        for (const char *c = location; c + 1 < end; ++c)
            if (c[0] == ':' && c[1] == ' ') {
                colon = c;
                break;
            }
        if (!colon)
            return false;
        location_end = spelling && spelling < colon ? spelling : colon;
        *text = colon + 2;
    } else {
        /* clang: "FILE:LINE:COL: warning: TEXT" */
        for (const char *c = line; c + 2 + kind_length + 2 <= line + length; ++c)
            if (c[0] == ':' && c[1] == ' ' && kind_at(c + 2, (size_t)(line + length - c - 2), kind)) {
                location = line;
                location_end = c;
                *text = c + 2 + kind_length + 2;
                break;
            }
        if (!location)
            return false;
    }
    size_t n = (size_t)(location_end - location);
    if (n >= where_size)
        n = where_size - 1;
    memcpy(where, location, n);
    where[n] = '\0';
    return true;
}

static void emit(perma_runtime *rt, const char *text)
{
    if (rt->config.build_log)
        rt->config.build_log(rt->config.build_log_user, text);
    else
        fputs(text, stderr);
}

/* The warnings of `log`, one per line in the compiler's usual form, each
 * once (PoCL repeats some). */
static void collect_warnings(const char *log, perma_strbuf *out, unsigned *count)
{
    *count = 0;
    for (const char *line = log, *newline; *line; line = newline ? newline + 1 : line + strlen(line)) {
        newline = strchr(line, '\n');
        size_t length = newline ? (size_t)(newline - line) : strlen(line);
        char where[512];
        const char *text;
        if (!perma_build_log_diagnostic(line, length, "warning", where, sizeof where, &text))
            continue;
        perma_strbuf one;
        perma_strbuf_init(&one);
        perma_strbuf_printf(&one, "%s: warning: %.*s\n", where, (int)(line + length - text), text);
        if (!one.failed && (!out->data || !strstr(out->data, one.data))) {
            perma_strbuf_append(out, one.data);
            ++*count;
        }
        perma_strbuf_free(&one);
    }
}

unsigned perma_build_log_show(perma_runtime *rt, const char *log, bool failed)
{
    perma_strbuf sb, warnings;
    perma_strbuf_init(&sb);
    perma_strbuf_init(&warnings);
    /* The warnings are counted for the caller even when the whole log is
     * shown instead of them. */
    unsigned count = 0;
    if (!failed)
        collect_warnings(log, &warnings, &count);
    if (rt->settings.build_log) {
        perma_strbuf_printf(&sb, "perma: build log%s:\n%s%s", failed ? " (the build failed)" : "", log,
                            log[0] && log[strlen(log) - 1] != '\n' ? "\n" : "");
    } else if (count) {
        perma_strbuf_printf(&sb, "perma: the program built with %u compiler warning%s:\n%s", count,
                            count == 1 ? "" : "s", warnings.data);
    }
    if (!sb.failed && sb.data && sb.data[0])
        emit(rt, sb.data);
    perma_strbuf_free(&warnings);
    perma_strbuf_free(&sb);
    return count;
}

void perma_notice(perma_runtime *rt, const char *fmt, ...)
{
    char text[PERMA_MESSAGE_MAX];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(text, sizeof text - 1, fmt, ap);
    va_end(ap);
    if (n < 0)
        return;
    size_t used = (size_t)n < sizeof text - 1 ? (size_t)n : sizeof text - 2;
    text[used] = '\n';
    text[used + 1] = '\0';
    emit(rt, text);
}
