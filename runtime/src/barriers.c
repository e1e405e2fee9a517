/* Barriers only in cooperative procedures.  A procedure that is not
 * .cooperative runs only on the work-items that have an item (its call is
 * guarded by ctx->active), so a barrier in it is divergent: wrong results
 * on PoCL, a hang on a GPU.  The generated program therefore defines
 * barrier() and the work_group_* functions away around the source of such
 * a procedure, as calls of an undeclared function whose name says why: the
 * compiler reports them at the user's file and line, and the host turns
 * that error into a sentence naming the procedure. */
#include "barriers.h"
#include "build_log.h"
#include "internal.h"
#include "strbuf.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

#define GUARD_PREFIX "perma_barrier_in_noncooperative_procedure_"

/* Calls a non-cooperative procedure must not make (OpenCL C 1.2 and 2.0). */
static const char *const group_functions[] = {
    "barrier", "work_group_barrier", "work_group_broadcast", "work_group_all", "work_group_any",
    "work_group_reduce_add", "work_group_reduce_min", "work_group_reduce_max",
    "work_group_scan_inclusive_add", "work_group_scan_inclusive_min", "work_group_scan_inclusive_max",
    "work_group_scan_exclusive_add", "work_group_scan_exclusive_min", "work_group_scan_exclusive_max",
};
#define GROUP_FUNCTION_COUNT (sizeof group_functions / sizeof group_functions[0])

/* Some headers define a few of these as macros (work_group_barrier):
 * they are saved and given back after the source. */
void perma_barriers_forbid(const perma_runtime *rt, unsigned proc, perma_strbuf *sb)
{
    for (size_t i = 0; i < GROUP_FUNCTION_COUNT; ++i)
        perma_strbuf_printf(sb, "#pragma push_macro(\"%s\")\n#undef %s\n#define %s(...) " GUARD_PREFIX "%s()\n",
                            group_functions[i], group_functions[i], group_functions[i], rt->procs[proc].name);
}

bool perma_same_source(const perma_source_text *a, const perma_source_text *b)
{
    return strcmp(a->name, b->name) == 0 && strcmp(a->text, b->text) == 0;
}

void perma_barriers_allow(perma_strbuf *sb)
{
    for (size_t i = 0; i < GROUP_FUNCTION_COUNT; ++i)
        perma_strbuf_printf(sb, "#undef %s\n#pragma pop_macro(\"%s\")\n", group_functions[i], group_functions[i]);
}

/* The procedures sharing p's source (same name and text), as "'a', 'b'". */
static void procedures_with_source(const perma_runtime *rt, const perma_proc_info *p, char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (unsigned i = 0; i < rt->proc_count && used < size; ++i) {
        const perma_proc_info *q = &rt->procs[i];
        if (perma_same_source(&q->source, &p->source))
            used += (size_t)snprintf(out + used, size - used, "%s'%s'", used ? ", " : "", q->name);
    }
}

bool perma_barriers_explain_log(const perma_runtime *rt, const char *log, char *out, size_t size)
{
    for (const char *line = log, *newline; *line; line = newline ? newline + 1 : line + strlen(line)) {
        newline = strchr(line, '\n');
        size_t length = newline ? (size_t)(newline - line) : strlen(line);
        const char *guard = strstr(line, GUARD_PREFIX), *text;
        char where[256];
        if (!guard || guard >= line + length ||
            !perma_build_log_diagnostic(line, length, "error", where, sizeof where, &text))
            continue;
        /* "FILE:LINE:COL: error: ... 'perma_barrier_..._NAME'": the name
         * ends at the first character that is not part of an identifier. */
        const char *name = guard + strlen(GUARD_PREFIX);
        size_t name_length = 0;
        while (isalnum((unsigned char)name[name_length]) || name[name_length] == '_')
            ++name_length;
        const perma_proc_info *p = NULL;
        for (unsigned i = 0; i < rt->proc_count && !p; ++i)
            if (strlen(rt->procs[i].name) == name_length && strncmp(rt->procs[i].name, name, name_length) == 0)
                p = &rt->procs[i];
        if (!p)
            continue;
        char users[512];
        procedures_with_source(rt, p, users, sizeof users);
        bool shared = strchr(users, ',') != NULL;
        snprintf(out, size,
                 "%s: barrier() (or a work_group_*() function) in %s %s, which %s not declared .cooperative: only "
                 "a cooperative procedure is called by every work-item of the group, as a barrier needs; set "
                 ".cooperative = 1 (and test ctx->active) or remove the barrier", where,
                 shared ? "the source of procedures" : "procedure", users, shared ? "are" : "is");
        return true;
    }
    return false;
}
