#ifndef PERMA_BARRIERS_H
#define PERMA_BARRIERS_H

#include "perma.h"
#include "strbuf.h"

#include <stdbool.h>
#include <stddef.h>

/* Defined in internal.h (a registered source). */
typedef struct perma_source_text perma_source_text;

/* barriers.c: around the source of a procedure that is not .cooperative,
 * turn barrier() and work_group_*() into a compile error at the caller's
 * line; the sentence for a build log that has one (false when none). */
void perma_barriers_forbid(const perma_runtime *rt, unsigned proc, perma_strbuf *sb);
void perma_barriers_allow(perma_strbuf *sb);
/* The same source: the same name and the same text (procedures registered
 * from one source share it, the program includes it once, and its
 * barriers are forbidden unless one of them is cooperative). */
bool perma_same_source(const perma_source_text *a, const perma_source_text *b);
bool perma_barriers_explain_log(const perma_runtime *rt, const char *log, char *out, size_t size);

#endif
