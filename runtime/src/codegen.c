/* Generating the megakernel's OpenCL C from the registered procedures:
 * constants and tables, the user's sources with #line directives, typed
 * emit helpers, the dispatch switch and the scheduler loop. */
#include "abi.h"
#include "barriers.h"
#include "codegen.h"
#include "executor.h"
#include "schedule_table.h"
#include "strbuf.h"

#include <string.h>

extern const char perma_kernel_abi[];
extern const char perma_kernel_prelude[];
extern const char perma_kernel_queue[];
extern const char perma_kernel_emit[];
extern const char perma_kernel_batch[];
extern const char perma_kernel_scheduler[];
extern const char perma_kernel_host_steps[];
extern const char perma_kernel_relayout[];
extern const char perma_kernel_reduce[];
extern const char perma_kernel_work_first[];

#define GENERATED_NAME "perma-generated.cl"

/* Point compiler messages back at the generated text after a user source. */
static void resume_generated(perma_strbuf *sb)
{
    perma_strbuf_printf(sb, "\n#line %zu \"" GENERATED_NAME "\"\n", sb->lines + 3);
}

static void append_user_source(perma_strbuf *sb, const perma_source_text *src)
{
    perma_strbuf_printf(sb, "#line 1 \"%s\"\n", src->name);
    perma_strbuf_append(sb, src->text);
    resume_generated(sb);
}

static void append_uint_table(perma_strbuf *sb, const char *name, const unsigned *values, unsigned n)
{
    perma_strbuf_printf(sb, "__constant uint %s[%u] = {", name, n);
    for (unsigned i = 0; i < n; ++i)
        perma_strbuf_printf(sb, "%s%u", i ? ", " : " ", values[i]);
    perma_strbuf_append(sb, " };\n");
}

static void append_tables(perma_runtime *rt, perma_strbuf *sb)
{
    unsigned n = rt->proc_count, me = rt->build.max_edges;
    unsigned v[PERMA_MAX_PROCEDURES] = { 0 };
    unsigned edges[PERMA_MAX_PROCEDURES * PERMA_MAX_EMITS];
#define PER_PROC(table, expr)                  \
    do {                                       \
        for (unsigned i = 0; i < n; ++i) {     \
            const perma_proc_info *p = &rt->procs[i]; \
            (void)p;                           \
            v[i] = (expr);                     \
        }                                      \
        append_uint_table(sb, table, v, n);    \
    } while (0)
#define PER_EDGE(table, expr)                                  \
    do {                                                       \
        memset(edges, 0, sizeof edges);                        \
        for (unsigned i = 0; i < n; ++i)                       \
            for (unsigned e = 0; e < rt->procs[i].emit_count; ++e) { \
                const perma_proc_info *p = &rt->procs[i];      \
                edges[i * me + e] = (expr);                    \
            }                                                  \
        append_uint_table(sb, table, edges, n * me);           \
    } while (0)

    append_uint_table(sb, "perma_order", rt->build.order, n);
    PER_PROC("perma_max_batch", p->max_batch);
    PER_PROC("perma_item_words", (unsigned)(p->item_size / 4));
    PER_PROC("perma_items_off", p->items_off);
    PER_PROC("perma_counters_off", p->counters_off);
    PER_PROC("perma_lane_counts_off", p->lane_counts_off);
    PER_PROC("perma_lane_items", p->lane_items);
    PER_PROC("perma_edge_count", p->emit_count);
    PER_PROC("perma_lq_off", p->lq_off);
    PER_PROC("perma_simple", p->simple ? 1u : 0u);
    PER_PROC("perma_scratch_off", p->scratch_off);
    PER_PROC("perma_scratch_words", p->scratch_words);
    /* Stack room an item of a stackable procedure needs (work-first),
     * PERMA_WF_NEVER for the others. */
    PER_PROC("perma_wf_need", p->stackable ? p->wf_need : 0xffffffffu);
    PER_EDGE("perma_edge_target", (unsigned)p->emit_target[e]);
    PER_EDGE("perma_edge_max", p->emit_max[e]);
    PER_EDGE("perma_edge_stage", p->stage_off[e]);
#undef PER_PROC
#undef PER_EDGE

    /* perma_edge_index[proc * n + target]: which edge of proc goes to target. */
    perma_strbuf_printf(sb, "__constant int perma_edge_index[%u] = {", n * n);
    for (unsigned i = 0; i < n; ++i) {
        for (unsigned t = 0; t < n; ++t) {
            int edge = -1;
            for (unsigned e = 0; e < rt->procs[i].emit_count; ++e)
                if ((unsigned)rt->procs[i].emit_target[e] == t)
                    edge = (int)e;
            perma_strbuf_printf(sb, "%s%d", i + t ? ", " : " ", edge);
        }
    }
    perma_strbuf_append(sb, " };\n");
}

static void append_buffers(perma_runtime *rt, perma_strbuf *sb)
{
    perma_strbuf_append(sb, "typedef struct perma_buffers {\n");
    for (unsigned i = 0; i < rt->buffer_count; ++i)
        perma_strbuf_printf(sb, "    %s %s;\n", rt->buffers[i].type, rt->buffers[i].name);
    /* The watch page, for perma_stop_requested (kernels/perma_prelude.cl). */
    perma_strbuf_append(sb, "    volatile __global uint *perma_watch_page;\n");
    perma_strbuf_append(sb, "} perma_buffers;\n");
}

/* PERMA_SWITCH_WORDS(words, call): `call` with PERMA_WORDS a constant equal
 * to `words` for every item size of the program, so the copies of the
 * batch code (kernels/perma_batch.cl) compile to fixed moves per size. */
static void append_word_switch(perma_runtime *rt, perma_strbuf *sb)
{
    perma_strbuf_append(sb, "#define PERMA_SWITCH_WORDS(words, call) switch (words) {");
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        unsigned words = (unsigned)(rt->procs[i].item_size / 4);
        bool seen = false;
        for (unsigned j = 0; j < i; ++j)
            seen = seen || rt->procs[j].item_size == rt->procs[i].item_size;
        if (!seen)
            perma_strbuf_printf(sb, " case %uu: { const uint PERMA_WORDS = %uu; call; break; }", words, words);
    }
    perma_strbuf_append(sb, " default: { const uint PERMA_WORDS = (words); call; break; } }\n");
}

static void append_kernel_params(perma_runtime *rt, perma_strbuf *sb)
{
    perma_strbuf_append(sb, "#define PERMA_BUFFER_PARAMS");
    for (unsigned i = 0; i < rt->buffer_count; ++i)
        perma_strbuf_printf(sb, " , %s perma_arg_%s", rt->buffers[i].type, rt->buffers[i].name);
    perma_strbuf_append(sb, "\n#define PERMA_BIND_BUFFERS(b) do {");
    for (unsigned i = 0; i < rt->buffer_count; ++i)
        perma_strbuf_printf(sb, " (b).%s = perma_arg_%s;", rt->buffers[i].name, rt->buffers[i].name);
    perma_strbuf_append(sb, " (b).perma_watch_page = abort_flag; } while (0)\n");
}

/* One emit helper per procedure that something emits into.  It hands
 * perma_emit the item as may-alias words (kernels/perma_prelude.cl,
 * perma_item_word: why not as uint); an item type aligned to less than 4
 * bytes is first copied by its own type into a union with such words, so
 * the words are aligned (the branch not taken is compiled away). */
static void append_emit_helpers(perma_runtime *rt, perma_strbuf *sb)
{
    for (unsigned t = 0; t < rt->proc_count; ++t) {
        bool targeted = false;
        for (unsigned i = 0; i < rt->proc_count; ++i)
            for (unsigned e = 0; e < rt->procs[i].emit_count; ++e)
                targeted = targeted || (unsigned)rt->procs[i].emit_target[e] == t;
        if (!targeted)
            continue;
        const perma_proc_info *p = &rt->procs[t];
        const char *type = p->item_type;
        /* Forced inline only where it can push: elsewhere the compiler's
         * choice, as for the procedures (a forced one makes its caller big
         * enough that the procedure is no longer inlined into the dispatch). */
        perma_strbuf_printf(sb, "%s int emit_%s(perma_ctx *ctx, const %s *item)\n{\n",
                            p->stackable ? "PERMA_INLINE" : "inline", p->name, type);
        /* Work-first: onto the work-item's stack, stored by its own type. */
        if (p->stackable)
            perma_strbuf_printf(sb,
                                "    if (ctx->wf_room) {\n"
                                "        *(__local %s *)perma_wf_push(ctx, %uu) = *item;\n"
                                "        return 1;\n"
                                "    }\n",
                                type, t);
        perma_strbuf_printf(sb,
                            "    if (__alignof__(%s) %% 4u == 0u)\n"
                            "        return perma_emit(ctx, %uu, (const perma_item_word *)item);\n"
                            "    union { %s item; perma_item_word words[%zu]; } copy;\n"
                            "    copy.item = *item;\n"
                            "    return perma_emit(ctx, %uu, copy.words);\n"
                            "}\n",
                            type, t, type, p->item_size / 4, t);
    }
}

/* Procedure sources, each once even if several procedures share it; no
 * barrier in one that only non-cooperative procedures use (barriers.c).
 * Whether a procedure is inlined into the dispatch is the compiler's
 * choice: forcing every function of the sources inline tripled the cold
 * build of the Reyes megakernel (7 s to 20 s of CPU), and a forward
 * declaration of the procedure alone cannot name an item type its own
 * source declares. */
static void append_procedure_sources(perma_runtime *rt, perma_strbuf *sb)
{
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        const perma_source_text *src = &rt->procs[i].source;
        bool duplicate = false, cooperative = false;
        for (unsigned j = 0; j < rt->proc_count; ++j) {
            bool same = perma_same_source(&rt->procs[j].source, src);
            duplicate = duplicate || (same && j < i);
            cooperative = cooperative || (same && rt->procs[j].cooperative);
        }
        if (duplicate)
            continue;
        if (!cooperative)
            perma_barriers_forbid(rt, i, sb);
        append_user_source(sb, src);
        if (!cooperative)
            perma_barriers_allow(sb);
    }
}

/* After an item of stackable procedure p (index i) that ran with stack
 * room: its pushes per edge, from the stack above `sp` (at most the
 * declared maximum each, else the run fails), added to its counters. */
static void append_pushes_counted(const perma_proc_info *p, unsigned i, perma_strbuf *sb, const char *indent)
{
    if (p->emit_count == 1) {
        perma_strbuf_printf(sb, "%suint count_0 = ctx->wf_sp - sp;\n", indent);
    } else {
        for (unsigned e = 0; e < p->emit_count; ++e)
            perma_strbuf_printf(sb, "%suint count_%u = 0u;\n", indent, e);
        perma_strbuf_printf(sb, "%sfor (uint i = sp; i < ctx->wf_sp; ++i) {\n", indent);
        for (unsigned e = 0; e < p->emit_count; ++e)
            perma_strbuf_printf(sb, "%s    count_%u += procs[i] == %uu;\n", indent, e, (unsigned)p->emit_target[e]);
        perma_strbuf_printf(sb, "%s}\n", indent);
    }
    for (unsigned e = 0; e < p->emit_count; ++e)
        perma_strbuf_printf(sb,
                            "%sif (count_%u > %uu)\n"
                            "%s    atomic_cmpxchg(ctx->error_code, 0u, PERMA_EMIT_ERROR_LIMIT | %uu);\n"
                            "%spushed_%u_%u += count_%u;\n",
                            indent, e, p->emit_max[e], indent, e, indent, i, e, e);
}

/* Work-first (kernels/perma_work_first.cl): every simple procedure's batch
 * items and the work-item's stack in one loop, so each procedure has one
 * call site.  A stack item runs with room for the largest declared emits of
 * any stackable procedure (PERMA_WF_NEED, a constant: no table load per
 * item).  It asks for no work-item function (get_group_id and the like):
 * PoCL inlines every function that does into the kernel, where its locals
 * would live in per-work-item context arrays.  The stack's top item runs
 * first while it has room for its emits and the batch's budget lasts, then
 * the next batch item; a finished item's slot is freed when the items above
 * it are done.  When another group is idle (PERMA_CTL_HUNGRY: a word
 * written rarely, so its load per item stays in the cache) a stack that has
 * something to give stops, so that the batch ends and work-item 0 gives
 * (perma_wf_relieve) without waiting for the budget: a coarse item's group
 * shares at once.  The counts of what ran and was pushed stay in private
 * variables (constant indices) and reach the group's counters once per
 * batch. */
static void append_run_simple(perma_runtime *rt, perma_strbuf *sb)
{
    perma_strbuf_append(sb,
        "__attribute__((noinline, flatten)) void perma_run_simple(uint lid, __global uint *ctl,\n"
        "                                                         __local perma_group_mem *mem, const perma_ctx *caller)\n"
        "{\n"
        "    perma_ctx context = *caller; /* its own copies: the fields can live in registers */\n"
        "    perma_ctx *ctx = &context;\n"
        "#if PERMA_NUM_REDUCTIONS\n"
        "    ulong lane[PERMA_REDUCE_WORDS];\n"
        "    for (uint w = 0; w < PERMA_REDUCE_WORDS; ++w)\n"
        "        lane[w] = caller->reduce[w];\n"
        "    ctx->reduce = lane;\n"
        "#endif\n"
        "    const uint batch_proc = mem->batch[PERMA_B_PROC];\n"
        "    const uint run = perma_simple[batch_proc] ? perma_batch_run(mem) : 0u;\n"
        "    __local uint *items = perma_batch_items(mem);\n"
        "    __local uint *arena = mem->arena;\n"
        "    __local uint *own = mem->wf_own + lid * PERMA_MAX_EDGES;\n"
        "    __local uint *procs = mem->wf_procs + lid * PERMA_WORK_FIRST;\n"
        "    __local uint *slots = mem->wf_slots + lid * (PERMA_WORK_FIRST * PERMA_WF_SLOT_WORDS);\n"
        "    ctx->thread = 0u;\n"
        "    ctx->threads = 1u;\n"
        "    ctx->active = 1u;\n"
        "    ctx->lane = lid;\n"
        "    ctx->item_emit_counts = own;\n"
        "    ctx->wf_procs = procs;\n"
        "    ctx->wf_slots = slots;\n"
        "    uint sp = mem->wf_sp[lid], peak = sp, slot = lid, budget = PERMA_WF_BUDGET;\n"
        "    /* The group's record in the watch page names the procedure running\n"
        "     * (the watchdog's message, if one never returns). */\n"
        "    volatile __global uint *watch = ctx->buf.perma_watch_page + PERMA_WATCH_RECORDS +\n"
        "                                    ctx->group * PERMA_WATCH_GROUP_WORDS + PERMA_WATCH_RUNNING;\n"
        "    uint shown = batch_proc;\n");
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        const perma_proc_info *p = &rt->procs[i];
        if (!p->stackable)
            continue;
        perma_strbuf_printf(sb, "    uint ran_%u = 0u;\n", i);
        for (unsigned e = 0; e < p->emit_count; ++e)
            perma_strbuf_printf(sb, "    uint pushed_%u_%u = 0u;\n", i, e);
    }
    perma_strbuf_append(sb,
        "    for (;;) {\n"
        "        /* The stack, depth first: its top item runs in place. */\n"
        "        ctx->slot = lid;\n"
        "        ctx->scratch = (__local void *)0;\n"
        "        ctx->lane_counts = (__local uint *)0;\n"
        "        ctx->wf_room = 1u;\n"
        "        while (sp > 0u) {\n"
        "            const uint q = procs[sp - 1u];\n"
        "            if (q & PERMA_WF_DONE) {\n"
        "                --sp; /* its items ran: the slot is free */\n"
        "                continue;\n"
        "            }\n"
        "            if (budget == 0u || PERMA_WORK_FIRST - sp < PERMA_WF_NEED ||\n"
        "                (perma_load_int(ctl + PERMA_CTL_HUNGRY) > 0 && sp > 1u && budget < PERMA_WF_BUDGET))\n"
        "                break;\n"
        "            --budget;\n"
        "            const uint top = sp - 1u;\n"
        "            procs[top] = q | PERMA_WF_DONE;\n"
        "            __local const uint *item = slots + top * PERMA_WF_SLOT_WORDS;\n"
        "            ctx->wf_sp = sp;\n"
        "            ctx->proc = q;\n"
        "            if (q != shown) {\n"
        "                atomic_xchg(watch, q + 1u);\n"
        "                shown = q;\n"
        "            }\n"
        "            switch (q) {\n");
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        const perma_proc_info *p = &rt->procs[i];
        if (!p->stackable)
            continue;
        perma_strbuf_printf(sb, "            case %u: {\n                %s(ctx, (__local const %s *)item);\n", i,
                            p->function, p->item_type);
        append_pushes_counted(p, i, sb, "                ");
        perma_strbuf_printf(sb, "                ++ran_%u;\n                break;\n            }\n", i);
    }
    perma_strbuf_append(sb,
        "            }\n"
        "            if (ctx->wf_sp == sp) {\n"
        "                sp = top; /* it pushed nothing: its slot is free now */\n"
        "            } else {\n"
        "                sp = ctx->wf_sp;\n"
        "                peak = max(peak, sp);\n"
        "            }\n"
        "        }\n"
        "        /* The batch's next item. */\n"
        "        if (slot >= run)\n"
        "            break;\n"
        "        const uint q = batch_proc;\n"
        "        __local const uint *item = items + slot * perma_item_words[q];\n"
        "        ctx->slot = slot;\n"
        "        ctx->scratch = (__local void *)(arena + perma_scratch_off[q] + slot * perma_scratch_words[q]);\n"
        "        ctx->lane_counts = arena + perma_lane_counts_off[q] + lid * perma_edge_count[q];\n"
        "        ctx->wf_room = PERMA_WORK_FIRST - sp >= perma_wf_need[q] ? 1u : 0u;\n"
        "        ctx->wf_sp = sp;\n"
        "        ctx->proc = q;\n"
        "        slot += PERMA_GROUP_SIZE;\n"
        "        switch (q) {\n");
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        const perma_proc_info *p = &rt->procs[i];
        if (!p->simple)
            continue;
        perma_strbuf_printf(sb, "        case %u:\n            %s(ctx, (__local const %s *)item);\n", i, p->function,
                            p->item_type);
        /* Its emits went onto the stack (room) or to the staging. */
        if (p->stackable && p->emit_count) {
            perma_strbuf_append(sb, "            if (ctx->wf_room) {\n");
            append_pushes_counted(p, i, sb, "                ");
            perma_strbuf_append(sb, "            } else {\n");
        }
        for (unsigned e = 0; e < p->emit_count; ++e)
            perma_strbuf_printf(sb, "            own[%u] = 0u;\n", e);
        if (p->stackable && p->emit_count)
            perma_strbuf_append(sb, "            }\n");
        perma_strbuf_append(sb, "            break;\n");
    }
    perma_strbuf_append(sb,
        "        }\n"
        "        sp = ctx->wf_sp;\n"
        "        peak = max(peak, sp);\n"
        "    }\n");
    perma_strbuf_append(sb,
        "    mem->wf_sp[lid] = sp;\n"
        "#if PERMA_NUM_REDUCTIONS\n"
        "    for (uint w = 0; w < PERMA_REDUCE_WORDS; ++w)\n"
        "        caller->reduce[w] = lane[w];\n"
        "#endif\n");
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        const perma_proc_info *p = &rt->procs[i];
        if (!p->stackable)
            continue;
        perma_strbuf_printf(sb, "    if (ran_%u)\n        atomic_add(mem->wf_ran + %u, ran_%u);\n", i, i, i);
        for (unsigned e = 0; e < p->emit_count; ++e)
            perma_strbuf_printf(sb, "    if (pushed_%u_%u)\n        atomic_add(mem->wf_pushed + %u, pushed_%u_%u);\n", i,
                                e, i * rt->build.max_edges + e, i, e);
    }
    perma_strbuf_append(sb,
        "    atomic_max(mem->stats + PERMA_NUM_PROCS * PERMA_STAT_PROC_WORDS + PERMA_GSTAT_WF_PEAK, peak);\n"
        "}\n");
}

/* The dispatch switch.  Each case sets the per-item fields of the context
 * with the procedure's constants (threads per item, arena offsets), so the
 * compiler folds them into the procedure's code after inlining.  A
 * procedure of one thread per item that is not cooperative runs item
 * lid, lid + group size, ... of its batch in work-item lid (batches of such
 * procedures may be larger than the group). */
static void append_dispatch(perma_runtime *rt, perma_strbuf *sb)
{
    perma_strbuf_append(sb, "PERMA_PHASE void perma_dispatch(uint lid, __global uint *ctl, __local perma_group_mem *mem,\n"
                            "                             __global uint *stage, ulong *lane, perma_buffers buf)\n"
                            "{\n"
                            "    (void)ctl;\n"
                            "    const uint proc = mem->batch[PERMA_B_PROC];\n"
                            "    const uint run = perma_batch_run(mem);\n"
                            "    __local uint *arena = mem->arena;\n"
                            "    __local uint *items = perma_batch_items(mem);\n"
                            "    __local uint *counts = arena + perma_counters_off[proc];\n"
                            "    perma_ctx context;\n"
                            "    perma_ctx *ctx = &context;\n"
                            "    ctx->group = get_group_id(0);\n"
                            "    ctx->stage = stage;\n"
                            "#if PERMA_NUM_REDUCTIONS\n"
                            "    ctx->reduce = lane;\n"
                            "#else\n"
                            "    (void)lane;\n"
                            "#endif\n"
                            "    ctx->error_code = &mem->error_code;\n"
                            "    ctx->buf = buf;\n");
    if (rt->build.wf_items) /* emits of the procedures below are staged */
        perma_strbuf_append(sb, "    ctx->wf_room = 0u;\n");
    perma_strbuf_append(sb, "    switch (proc) {\n");
    for (unsigned i = 0; i < rt->proc_count; ++i) {
        const perma_proc_info *p = &rt->procs[i];
        unsigned tpi = p->threads_per_item;
        if (p->simple && rt->build.wf_items)
            continue; /* perma_run_simple, below */
        if (p->simple) {
            /* Lane staging only when the layout gave it lanes (layout.c). */
            char lanes[64] = "0";
            if (p->lane_items)
                snprintf(lanes, sizeof lanes, "arena + %uu + lid * %uu", p->lane_counts_off, p->emit_count);
            perma_strbuf_printf(sb,
                                "    case %u:\n"
                                "        ctx->proc = %uu;\n"
                                "        ctx->thread = 0u;\n"
                                "        ctx->threads = 1u;\n"
                                "        ctx->active = 1u;\n"
                                "        ctx->lane = lid;\n"
                                "        ctx->lane_counts = %s;\n"
                                "        for (uint slot = lid; slot < run; slot += PERMA_GROUP_SIZE) {\n"
                                "            ctx->slot = slot;\n"
                                "            ctx->scratch = (__local void *)(arena + %uu + slot * %uu);\n"
                                "            ctx->item_emit_counts = counts + slot * %uu;\n"
                                "            %s(ctx, (__local const %s *)(items + slot * %zuu));\n"
                                "        }\n"
                                "        break;\n",
                                i, i, lanes, p->scratch_off, p->scratch_words,
                                p->emit_count, p->function, p->item_type, p->item_size / 4);
            continue;
        }
        perma_strbuf_printf(sb,
                            "    case %u: {\n"
                            "        const uint slot = lid / %uu;\n"
                            "        ctx->proc = %uu;\n"
                            "        ctx->thread = lid %% %uu;\n"
                            "        ctx->threads = %uu;\n"
                            "        ctx->active = slot < run ? 1u : 0u;\n"
                            "        ctx->slot = ctx->active ? slot : 0u;\n"
                            "        ctx->scratch = (__local void *)(arena + %uu + ctx->slot * %uu);\n"
                            "        ctx->item_emit_counts = counts + ctx->slot * %uu;\n"
                            "        ctx->lane_counts = 0;\n"
                            "        ctx->lane = lid;\n"
                            "        %s%s(ctx, (__local const %s *)(items + ctx->slot * %zuu));\n"
                            "        break;\n"
                            "    }\n",
                            i, tpi, i, tpi, tpi, p->scratch_off, p->scratch_words, p->emit_count,
                            p->cooperative ? "" : "if (ctx->active) ", p->function, p->item_type, p->item_size / 4);
    }
    perma_strbuf_append(sb, "    }\n");
    if (rt->build.wf_items)
        perma_strbuf_append(sb, "    perma_run_simple(lid, ctl, mem, ctx);\n");
    perma_strbuf_append(sb, "}\n");
}

perma_status perma_generate_program(perma_runtime *rt, const perma_strbuf *reduce_constants,
                                    const perma_strbuf *reduce_helpers, perma_strbuf *sb)
{
    /* The strategy's parts the scheduler compiles in (kernels/perma_scheduler.cl);
     * with one queue set there is nobody to steal from or donate to.  The
     * table's row was looked up with the layout (perma_build_layout). */
    const perma_strategy_info *strategy = rt->build.strategy;
    bool distributed = rt->build.queue_sets > 1 && strategy;
    bool item_barrier = false;
    for (unsigned i = 0; i < rt->proc_count; ++i)
        item_barrier = item_barrier || !rt->procs[i].simple;
    perma_strbuf_printf(sb, "#line 1 \"" GENERATED_NAME "\"\n"
                            "/* perma megakernel, generated for %u procedure(s). */\n"
                            "#define PERMA_GROUP_SIZE %uu\n"
                            "#define PERMA_ITEM_BARRIER %d\n"
                            "#define PERMA_NUM_PROCS %uu\n"
                            "#define PERMA_MAX_EDGES %uu\n"
                            "#define PERMA_ARENA_WORDS %uu\n"
                            "#define PERMA_STAGE_WORDS %uu\n"
                            "#define PERMA_QUEUE_SETS %uu\n"
                            "#define PERMA_STEALING %d\n"
                            "#define PERMA_DONATION %d\n"
                            "#define PERMA_VICTIM_ROUND_ROBIN %d\n"
                            "#define PERMA_DONATION_THRESHOLD %uu\n"
                            "#define PERMA_LOCAL_QUEUE %uu\n"
                            "#define PERMA_LQ_WORDS %uu\n"
                            "#define PERMA_TRACE_EVENTS %uu\n"
                            "#define PERMA_WORK_FIRST %uu\n"
                            "#define PERMA_WF_SLOT_WORDS %uu\n"
                            "#define PERMA_WF_BUDGET %uu\n"
                            "#define PERMA_WF_NEED %uu\n"
                            "#define PERMA_WF_NEVER 0xffffffffu\n",
                        rt->proc_count, rt->group_size, item_barrier, rt->proc_count, rt->build.max_edges,
                        rt->build.arena_words, rt->build.stage_words, rt->build.queue_sets,
                        distributed && strategy->steals, distributed && strategy->donates,
                        rt->config.schedule.victim == PERMA_VICTIM_ROUND_ROBIN, rt->config.schedule.donation_threshold,
                        rt->build.local_queue_items, rt->build.lq_words ? rt->build.lq_words : 1u,
                        rt->build.device_trace_events, rt->build.wf_items,
                        rt->build.wf_slot_words ? rt->build.wf_slot_words : 1u, rt->build.wf_budget, rt->build.wf_need);
    if (reduce_constants->length)
        perma_strbuf_append(sb, reduce_constants->data);
    perma_strbuf_append(sb, perma_kernel_abi);
    perma_abi_append_struct_checks(sb);
    resume_generated(sb);
    perma_strbuf_append(sb, perma_kernel_prelude);
    resume_generated(sb);
    perma_strbuf_append(sb, perma_kernel_queue);
    resume_generated(sb);
    perma_strbuf_append(sb, perma_kernel_reduce);
    resume_generated(sb);
    for (unsigned i = 0; i < rt->source_count; ++i)
        append_user_source(sb, &rt->sources[i]);
    append_buffers(rt, sb);
    append_tables(rt, sb);
    perma_strbuf_append(sb, perma_kernel_emit);
    resume_generated(sb);
    append_emit_helpers(rt, sb);
    if (reduce_helpers->length)
        perma_strbuf_append(sb, reduce_helpers->data);
    /* Procedures are inlined into the dispatch (a call per item otherwise,
     * and the case's constants fold into their emits); a profile of the
     * phases keeps them apart instead. */
    perma_strbuf_append(sb, "#ifdef PERMA_PROFILE_PHASES\n"
                            "#pragma clang attribute push (__attribute__((noinline)), apply_to = function)\n"
                            "#endif\n");
    append_procedure_sources(rt, sb);
    perma_strbuf_append(sb, "#ifdef PERMA_PROFILE_PHASES\n#pragma clang attribute pop\n#endif\n");
    perma_abi_append_item_checks(rt, sb);
    perma_abi_append_element_checks(rt, sb);
    resume_generated(sb);
    append_kernel_params(rt, sb);
    append_word_switch(rt, sb);
    perma_strbuf_append(sb, perma_kernel_batch);
    resume_generated(sb);
    perma_strbuf_append(sb, perma_kernel_work_first);
    resume_generated(sb);
    if (rt->build.wf_items)
        append_run_simple(rt, sb);
    append_dispatch(rt, sb);
    perma_strbuf_append(sb, perma_kernel_scheduler);
    resume_generated(sb);
    perma_strbuf_append(sb, perma_kernel_host_steps);
    resume_generated(sb);
    perma_strbuf_append(sb, perma_kernel_relayout);
    if (sb->failed || reduce_constants->failed || reduce_helpers->failed)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory generating the program");
    return PERMA_OK;
}
