#ifndef PERMA_CODEGEN_H
#define PERMA_CODEGEN_H

#include "perma.h"
#include "strbuf.h"

/* codegen.c: the program's text, with the reductions' parts
 * (perma_reductions_generate). */
perma_status perma_generate_program(perma_runtime *rt, const perma_strbuf *reduce_constants,
                                    const perma_strbuf *reduce_helpers, perma_strbuf *out);

#endif
