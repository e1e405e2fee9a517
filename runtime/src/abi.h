#ifndef PERMA_ABI_CHECKS_H
#define PERMA_ABI_CHECKS_H

#include "perma.h"
#include "strbuf.h"

#include <stdbool.h>
#include <stddef.h>

/* abi.c: the generated program's layout checks, and the sentence for a
 * build log in which one failed (false when none did). */
void perma_abi_append_struct_checks(perma_strbuf *sb);
void perma_abi_append_item_checks(const perma_runtime *rt, perma_strbuf *sb);
void perma_abi_append_element_checks(const perma_runtime *rt, perma_strbuf *sb);
bool perma_abi_explain_log(const perma_runtime *rt, const char *log, char *out, size_t size);

#endif
