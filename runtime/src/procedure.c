/* Registering procedures and shared sources, seeding their queues. */
#include "files.h"
#include "internal.h"
#include "layout.h"
#include "program.h"

#include <stdlib.h>
#include <string.h>

static char *copy_string(const char *s)
{
    return s ? strdup(s) : NULL;
}

/* Load text from `source` or, if NULL, from the file `file`. */
static perma_status load_source(perma_runtime *rt, const char *source, const char *file,
                                const char *fallback_name, perma_source_text *out)
{
    out->text = NULL;
    out->name = NULL;
    if (source) {
        out->text = strdup(source);
    } else {
        perma_status st = perma_read_text_file(rt, file, &out->text);
        if (st != PERMA_OK)
            return st;
    }
    out->name = strdup(file ? file : fallback_name);
    if (!out->text || !out->name) {
        free(out->text);
        free(out->name);
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory copying a source");
    }
    return PERMA_OK;
}

static void invalidate_build(perma_runtime *rt)
{
    perma_release_program(rt);
    rt->built = false;
}

static perma_status add_source_call(perma_runtime *rt, const char *source, const char *file)
{
    perma_status begun = perma_call_begin(rt, "perma_add_source", true);
    if (begun != PERMA_OK)
        return begun;
    if (!source && !file)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_add_source: both source and file are NULL");
    if (rt->source_count == PERMA_MAX_PROCEDURES)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_add_source: more than %d sources",
                               PERMA_MAX_PROCEDURES);
    char fallback[32];
    snprintf(fallback, sizeof fallback, "<source %u>", rt->source_count + 1);
    perma_status st = load_source(rt, source, file, fallback, &rt->sources[rt->source_count]);
    if (st != PERMA_OK)
        return st;
    rt->source_count++;
    invalidate_build(rt);
    return PERMA_OK;
}

perma_status perma_add_source(perma_runtime *rt, const char *source, const char *file)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_add_source", add_source_call(rt, source, file));
}

/* Check every field of a description; the message names the field. */
static perma_status validate(perma_runtime *rt, const perma_procedure *d)
{
    const char *n = d->name ? d->name : "(null)";
    if (!perma_is_identifier(d->name))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "procedure name '%s' is not a C identifier of at most %d characters",
                               n, PERMA_NAME_MAX);
    const char *reserved = perma_reserved_name(d->name);
    if (reserved)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "procedure name '%s' is %s; choose another name", n, reserved);
    for (unsigned i = 0; i < rt->proc_count; ++i)
        if (strcmp(rt->procs[i].name, d->name) == 0)
            return perma_set_error(rt, PERMA_ERR_ARGUMENT, "procedure '%s' is already registered", n);
    if (!d->item_type || !*d->item_type)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "procedure '%s': item_type is empty", n);
    if (strpbrk(d->item_type, ";{}\n"))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "procedure '%s': item_type '%s' is not a type name", n, d->item_type);
    if (d->item_size < 4 || d->item_size > PERMA_MAX_ITEM_SIZE || d->item_size % 4 != 0)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "procedure '%s': item_size %zu must be a multiple of 4 in 4..%d",
                               n, d->item_size, PERMA_MAX_ITEM_SIZE);
    unsigned tpi = d->threads_per_item ? d->threads_per_item : 1;
    if (tpi > rt->group_size)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "procedure '%s': threads_per_item %u exceeds the group size %u",
                               n, tpi, rt->group_size);
    if (d->local_bytes_per_item > perma_local_memory(rt))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "procedure '%s': local_bytes_per_item %zu exceeds the %zu bytes of __local memory a "
                               "group may use (%s)", n, d->local_bytes_per_item, perma_local_memory(rt),
                               perma_local_memory(rt) < rt->caps.local_mem_size ? "config.local_memory_limit"
                                                                           : "the device's local memory");
    if (!d->source && !d->source_file)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "procedure '%s': neither source nor source_file is set", n);
    if (!perma_is_identifier(d->function))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "procedure '%s': function '%s' is not a C identifier", n,
                               d->function ? d->function : "(null)");
    reserved = perma_reserved_name(d->function);
    if (reserved)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "procedure '%s': function name '%s' is %s; rename the function",
                               n, d->function, reserved);
    for (unsigned e = 0; e < PERMA_MAX_EMITS && d->emits[e].target; ++e) {
        if (!perma_is_identifier(d->emits[e].target))
            return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                                   "procedure '%s': emits[%u].target '%s' is not a procedure name",
                                   n, e, d->emits[e].target);
        if (d->emits[e].max_items < 1 || d->emits[e].max_items > PERMA_MAX_EMIT_ITEMS)
            return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                                   "procedure '%s': emits[%u].max_items %u must be in 1..%d",
                                   n, e, d->emits[e].max_items, PERMA_MAX_EMIT_ITEMS);
        for (unsigned f = 0; f < e; ++f)
            if (strcmp(d->emits[f].target, d->emits[e].target) == 0)
                return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                                       "procedure '%s': emits lists target '%s' twice", n, d->emits[e].target);
    }
    if (rt->proc_count == PERMA_MAX_PROCEDURES)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "more than %d procedures", PERMA_MAX_PROCEDURES);
    return PERMA_OK;
}

static perma_status register_call(perma_runtime *rt, const perma_procedure *d, perma_proc *out)
{
    perma_status begun = perma_call_begin(rt, "perma_register", true);
    if (begun != PERMA_OK)
        return begun;
    if (!d || !out)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_register: procedure or out is NULL");
    perma_status st = validate(rt, d);
    if (st != PERMA_OK)
        return st;

    perma_proc_info *p = &rt->procs[rt->proc_count];
    memset(p, 0, sizeof *p);
    char fallback[PERMA_NAME_MAX + 16];
    snprintf(fallback, sizeof fallback, "<procedure %s>", d->name);
    st = load_source(rt, d->source, d->source_file, fallback, &p->source);
    if (st != PERMA_OK)
        return st;
    p->name = copy_string(d->name);
    p->item_type = copy_string(d->item_type);
    p->function = copy_string(d->function);
    p->item_size = d->item_size;
    p->threads_per_item = d->threads_per_item ? d->threads_per_item : 1;
    p->local_bytes_per_item = d->local_bytes_per_item;
    p->priority = d->priority;
    p->cooperative = d->cooperative;
    p->queue_only = d->queue_only;
    bool oom = !p->name || !p->item_type || !p->function;
    for (unsigned e = 0; e < PERMA_MAX_EMITS && d->emits[e].target; ++e) {
        p->emit_target_name[e] = copy_string(d->emits[e].target);
        p->emit_max[e] = d->emits[e].max_items;
        p->emit_count = e + 1;
        oom = oom || !p->emit_target_name[e];
    }
    rt->proc_count++; /* from here on perma_destroy frees it */
    if (oom) {
        rt->proc_count--;
        free(p->name); free(p->item_type); free(p->function);
        free(p->source.text); free(p->source.name);
        for (unsigned e = 0; e < p->emit_count; ++e)
            free(p->emit_target_name[e]);
        memset(p, 0, sizeof *p);
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory registering '%s'", d->name);
    }
    invalidate_build(rt);
    *out = (perma_proc)(rt->proc_count - 1);
    return PERMA_OK;
}

perma_status perma_register(perma_runtime *rt, const perma_procedure *d, perma_proc *out)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_register", register_call(rt, d, out));
}

static perma_status find_call(perma_runtime *rt, const char *name, perma_proc *out)
{
    perma_call_begin(rt, "perma_find", false);
    if (!out)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_find('%s'): out is NULL", name ? name : "(null)");
    for (unsigned i = 0; name && i < rt->proc_count; ++i) {
        if (strcmp(rt->procs[i].name, name) == 0) {
            *out = (perma_proc)i;
            return PERMA_OK;
        }
    }
    return perma_set_error(rt, PERMA_ERR_ARGUMENT, "no procedure named '%s'", name ? name : "(null)");
}

perma_status perma_find(perma_runtime *rt, const char *name, perma_proc *out)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_find", find_call(rt, name, out));
}

static perma_status seed_call(perma_runtime *rt, perma_proc proc, const void *items, size_t count)
{
    perma_status begun = perma_call_begin(rt, "perma_seed", true);
    if (begun != PERMA_OK)
        return begun;
    if (proc < 0 || (unsigned)proc >= rt->proc_count)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_seed: %d is not a registered procedure", proc);
    perma_proc_info *p = &rt->procs[proc];
    if (count == 0)
        return PERMA_OK;
    if (!items)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_seed('%s'): items is NULL", p->name);
    perma_queue_layout layout;
    perma_queue_layout_fill(rt, perma_queue_sets(rt), &layout);
    perma_error error;
    if (perma_queues_check_seeds(&layout, (unsigned)proc, p->seed_count, count, &error) != PERMA_OK)
        return perma_take_error(rt, &error);
    size_t need = (p->seed_count + count) * p->item_size;
    if (need > p->seed_alloc) {
        size_t alloc = p->seed_alloc ? p->seed_alloc : 256;
        while (alloc < need)
            alloc *= 2;
        unsigned char *seeds = realloc(p->seeds, alloc);
        if (!seeds)
            return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory seeding '%s'", p->name);
        p->seeds = seeds;
        p->seed_alloc = alloc;
    }
    memcpy(p->seeds + p->seed_count * p->item_size, items, count * p->item_size);
    p->seed_count += count;
    return PERMA_OK;
}

perma_status perma_seed(perma_runtime *rt, perma_proc proc, const void *items, size_t count)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_seed", seed_call(rt, proc, items, count));
}
