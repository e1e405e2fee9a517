/* The program text generated for a small registration (runtime/src/
 * codegen.c): the user's sources once each with #line directives that
 * point compiler messages back at them, typed emit helpers for the
 * procedures that are emitted into, the order table and the dispatch
 * cases.  A runtime is created but the text is not compiled. */
#include "perma_test.h"

#include <stdlib.h>
#include <string.h>

#include "codegen.h"
#include "internal.h"
#include "layout.h"
#include "reductions.h"
#include "strbuf.h"

/* `produce` (uint, in produce.cl) emits up to 2 struct pair into
 * `consume`, a cooperative procedure of 4 threads per item; `count` shares
 * consume's source (pair.cl) and is emitted into by nothing. */
static const char *pair_source =
    "void consume(perma_ctx *c, __local const struct pair *p) { (void)c; (void)p; barrier(CLK_LOCAL_MEM_FENCE); }\n"
    "void count(perma_ctx *c, __local const struct pair *p) { (void)c; (void)p; }\n";

/* Lay out the registered procedures and generate the program text (the
 * caller frees it). */
static char *program_text(perma_runtime *rt)
{
    ck_assert_perma_ok(rt, perma_build_layout(rt));
    perma_strbuf sb, reduce_constants, reduce_helpers;
    perma_strbuf_init(&sb);
    perma_strbuf_init(&reduce_constants);
    perma_strbuf_init(&reduce_helpers);
    perma_reductions_generate(rt, &reduce_constants, &reduce_helpers);
    ck_assert_perma_ok(rt, perma_generate_program(rt, &reduce_constants, &reduce_helpers, &sb));
    perma_strbuf_free(&reduce_constants);
    perma_strbuf_free(&reduce_helpers);
    ck_assert(!sb.failed);
    return sb.data;
}

/* The generated program of that registration (free it). */
static char *generate(perma_runtime *rt)
{
    ck_assert_perma_ok(rt, perma_add_source(rt, "struct pair { uint a, b; };\n", "pair.h"));
    perma_procedure produce = { .name = "produce", .item_type = "uint", .item_size = 4, .threads_per_item = 1,
                                .source_file = "produce.cl", .function = "produce",
                                .source = "void produce(perma_ctx *c, __local const uint *x)\n"
                                          "{\n"
                                          "    struct pair p = { *x, *x };\n"
                                          "    emit_consume(c, &p);\n"
                                          "}\n",
                                .emits = { { "consume", 2 } } };
    perma_procedure consume = { .name = "consume", .item_type = "struct pair", .item_size = 8,
                                .threads_per_item = 4, .cooperative = 1, .source = pair_source,
                                .source_file = "pair.cl", .function = "consume" };
    perma_procedure count = consume;
    count.name = "count";
    count.function = "count";
    count.threads_per_item = 1;
    count.cooperative = 0;
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &produce, &id));
    ck_assert_perma_ok(rt, perma_register(rt, &consume, &id));
    ck_assert_perma_ok(rt, perma_register(rt, &count, &id));
    return program_text(rt);
}

/* A runtime of 2 groups of 8 under the schedule `label` (NULL: the
 * default). */
static perma_runtime *runtime_under(const char *label)
{
    perma_config config;
    perma_config_init(&config);
    config.group_size = 8;
    config.work_groups = 2;
    if (label)
        test_parse_schedule(label, &config.schedule);
    return test_runtime_config(&config);
}

static perma_runtime *runtime(void)
{
    return runtime_under(NULL);
}

/* The number of the line `at` is on (1-based). */
static size_t line_of(const char *text, const char *at)
{
    size_t line = 1;
    for (const char *p = text; p < at; ++p)
        line += *p == '\n';
    return line;
}

START_TEST(generated_text_has_the_expected_functions)
{
    perma_runtime *rt = runtime();
    char *text = generate(rt);
    ck_assert_contains(text, "/* perma megakernel, generated for 3 procedure(s). */");
    /* An emit helper for consume only, typed with its item and index, that
     * reads the item as may-alias words; consume cannot run from a stack,
     * so its helper is inlined where the compiler chooses. */
    ck_assert_contains(text, "\ninline int emit_consume(perma_ctx *ctx, const struct pair *item)\n"
                             "{\n"
                             "    if (__alignof__(struct pair) % 4u == 0u)\n"
                             "        return perma_emit(ctx, 1u, (const perma_item_word *)item);\n"
                             "    union { struct pair item; perma_item_word words[2]; } copy;\n"
                             "    copy.item = *item;\n"
                             "    return perma_emit(ctx, 1u, copy.words);\n"
                             "}\n");
    ck_assert_uint_eq(test_occurrences(text, "inline int emit_"), 1);
    ck_assert_uint_eq(test_occurrences(text, "PERMA_INLINE int emit_"), 0);
    /* The dispatch: produce in lanes over its batch, consume cooperative
     * (every work-item calls it), count guarded by nothing but its loop. */
    ck_assert_contains(text, "PERMA_PHASE void perma_dispatch(");
    ck_assert_contains(text, "            produce(ctx, (__local const uint *)(items + slot * 1u));\n");
    ck_assert_contains(text, "        const uint slot = lid / 4u;\n");
    ck_assert_contains(text, "        consume(ctx, (__local const struct pair *)(items + ctx->slot * 2u));\n");
    ck_assert_contains(text, "            count(ctx, (__local const struct pair *)(items + slot * 2u));\n");
    /* Downstream first: consume and count (depth 1 and 0, count registered
     * later than produce) before produce. */
    ck_assert_contains(text, "__constant uint perma_order[3] = { 1, 2, 0 };");
    free(text);
    perma_destroy(rt);
}
END_TEST

/* The program of `node` (uint), which emits up to 2 of itself, under the
 * schedule `label` (free it). */
static char *generate_tree(const char *label)
{
    perma_runtime *rt = runtime_under(label);
    perma_procedure node = { .name = "node", .item_type = "uint", .item_size = 4, .threads_per_item = 1,
                             .source_file = "node.cl", .function = "node",
                             .source = "void node(perma_ctx *c, __local const uint *x)\n"
                                       "{\n"
                                       "    uint child = *x - 1u;\n"
                                       "    if (*x)\n"
                                       "        emit_node(c, &child);\n"
                                       "}\n",
                             .emits = { { "node", 2 } } };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &node, &id));
    char *text = program_text(rt);
    perma_destroy(rt);
    return text;
}

/* A helper that can push onto a work-first stack is forced inline (the
 * stack loop runs it for every item); without stacks it is a plain inline
 * helper with no push. */
START_TEST(emit_helpers_push_only_with_stacks)
{
    char *text = generate_tree(NULL);
    ck_assert_contains(text, "PERMA_INLINE int emit_node(perma_ctx *ctx, const uint *item)\n"
                             "{\n"
                             "    if (ctx->wf_room) {\n"
                             "        *(__local uint *)perma_wf_push(ctx, 0u) = *item;\n");
    free(text);
    text = generate_tree("megakernel/shared+wf0");
    ck_assert_contains(text, "\ninline int emit_node(perma_ctx *ctx, const uint *item)\n"
                             "{\n"
                             "    if (__alignof__(uint) % 4u == 0u)\n");
    ck_assert_uint_eq(test_occurrences(text, "perma_wf_push(ctx"), 0);
    free(text);
}
END_TEST

START_TEST(user_sources_appear_once_with_their_lines)
{
    perma_runtime *rt = runtime();
    char *text = generate(rt);
    /* pair.cl serves two procedures and appears once; so do the others. */
    ck_assert_uint_eq(test_occurrences(text, "#line 1 \"pair.cl\"\n"), 1);
    ck_assert_uint_eq(test_occurrences(text, "#line 1 \"produce.cl\"\n"), 1);
    ck_assert_uint_eq(test_occurrences(text, "#line 1 \"pair.h\"\n"), 1);
    ck_assert_uint_eq(test_occurrences(text, "void count(perma_ctx *c"), 1);
    /* After each user source the generated text says again which of its
     * own lines follows, and that is true. */
    unsigned checked = 0;
    for (const char *p = text; (p = strstr(p, "\n#line ")) != NULL; ++p) {
        const char *directive = p + 1;
        size_t said;
        char file[64];
        ck_assert_int_eq(sscanf(directive, "#line %zu \"%63[^\"]\"", &said, file), 2);
        if (strcmp(file, "perma-generated.cl") != 0)
            continue;
        ck_assert_uint_eq(said, line_of(text, directive) + 1);
        ++checked;
    }
    ck_assert_uint_ge(checked, 3);
    /* The first line of produce.cl follows its directive. */
    ck_assert_contains(text, "#line 1 \"produce.cl\"\nvoid produce(perma_ctx *c, __local const uint *x)\n");
    free(text);
    perma_destroy(rt);
}
END_TEST

/* The schedule's strategy, victim and donation threshold (/d=N) are the
 * program's constants: what the device's scheduler compiles in. */
START_TEST(schedule_constants_follow_the_label)
{
    static const struct {
        const char *label, *constants;
    } cases[] = {
        { "megakernel/shared", "#define PERMA_QUEUE_SETS 1u\n#define PERMA_STEALING 0\n#define PERMA_DONATION 0\n"
                               "#define PERMA_VICTIM_ROUND_ROBIN 0\n#define PERMA_DONATION_THRESHOLD 0u\n" },
        { "megakernel/donation", "#define PERMA_QUEUE_SETS 2u\n#define PERMA_STEALING 0\n#define PERMA_DONATION 1\n"
                                 "#define PERMA_VICTIM_ROUND_ROBIN 0\n#define PERMA_DONATION_THRESHOLD 0u\n" },
        { "megakernel/donation/d=256", "#define PERMA_DONATION 1\n#define PERMA_VICTIM_ROUND_ROBIN 0\n"
                                       "#define PERMA_DONATION_THRESHOLD 256u\n" },
        { "megakernel/stealing-donation/round-robin/d=1",
          "#define PERMA_STEALING 1\n#define PERMA_DONATION 1\n#define PERMA_VICTIM_ROUND_ROBIN 1\n"
          "#define PERMA_DONATION_THRESHOLD 1u\n" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        perma_runtime *rt = runtime_under(cases[i].label);
        char *text = generate(rt);
        ck_assert_msg(strstr(text, cases[i].constants), "%s: no %s", cases[i].label, cases[i].constants);
        free(text);
        perma_destroy(rt);
    }
}
END_TEST

PERMA_TEST_MAIN("codegen", generated_text_has_the_expected_functions, user_sources_appear_once_with_their_lines,
                schedule_constants_follow_the_label, emit_helpers_push_only_with_stacks)
