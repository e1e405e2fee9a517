#ifndef PERMA_BUILD_LOG_H
#define PERMA_BUILD_LOG_H

#include "perma.h"

#include <stdbool.h>
#include <stddef.h>

/* build_log.c: whether line[0..length) is a compiler diagnostic of `kind`
 * ("error", "warning"); if so its location ("FILE:LINE:COL") in where[]
 * and *text at its message, whichever form the compiler wrote it in. */
bool perma_build_log_diagnostic(const char *line, size_t length, const char *kind, char *where, size_t where_size,
                                const char **text);
/* After a build: its warnings if it succeeded, or the whole log with
 * PERMA_BUILD_LOG, to config.build_log or stderr.  Returns the number of
 * warnings (0 for a failed build). */
unsigned perma_build_log_show(perma_runtime *rt, const char *log, bool failed);
/* A one-line notice about the build (e.g. a damaged cache entry), to
 * config.build_log or stderr; the newline is added. */
void perma_notice(perma_runtime *rt, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif
