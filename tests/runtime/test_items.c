/* Items of every kind of type arrive as they were emitted: a family of
 * item types (float, double, long, short and char fields, vectors such as
 * float4, double2 and float3, arrays, mixed and padded layouts, 4 to 128
 * bytes, aligned to 2 to 16 bytes), each with a procedure that fills one
 * private item, emits it, changes some of its fields (in a different order
 * for each child) and emits it again.  Every node checks its own fields
 * against what its id says they must be, and sums their bits into a
 * reduction that the host computes too; so an emit that copies an item
 * before its last changes (the compiler moving a word copy ahead of a
 * store to a double field, which C's aliasing rules allow) fails here.
 * Runs under every schedule (tests/meson.build), on Intel's runtime and
 * under Oclgrind (tests/portability).  Also the report's reduced case, and
 * a bound buffer of structs written by the leaves. */
#include "perma_test.h"

#include <inttypes.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the family of item types ---- */

typedef enum { K_CHAR, K_UCHAR, K_SHORT, K_USHORT, K_INT, K_UINT, K_LONG, K_ULONG, K_FLOAT, K_DOUBLE } kind;

typedef struct component {
    const char *access; /* how the procedure names it in its item: "v.s1", "a[2]" */
    kind kind;
} component;

#define MAX_COMPONENTS 20

typedef struct item_type {
    const char *name;   /* struct tag and procedure name */
    const char *fields; /* the struct's body; every type has fields `id` and `depth` */
    size_t size;        /* sizeof on the device (the runtime checks it) */
    component components[MAX_COMPONENTS];
} item_type;

static const item_type item_types[] = {
    { "sd", "double x, y, h; uint depth; uint id;", 32,
      { { "x", K_DOUBLE }, { "y", K_DOUBLE }, { "h", K_DOUBLE } } },
    { "fl", "float a; uint id; uint depth; float b;", 16, { { "a", K_FLOAT }, { "b", K_FLOAT } } },
    { "ul", "ulong a; ushort b; uchar c; uchar depth; uint id;", 16,
      { { "a", K_ULONG }, { "b", K_USHORT }, { "c", K_UCHAR } } },
    /* 4 bytes, aligned to 2: the emit reads it as bytes */
    { "c4", "ushort id; uchar depth; char c;", 4, { { "c", K_CHAR } } },
    { "f4", "float4 v; uint id; uint depth; uint pad0; uint pad1;", 32,
      { { "v.s0", K_FLOAT }, { "v.s1", K_FLOAT }, { "v.s2", K_FLOAT }, { "v.s3", K_FLOAT } } },
    { "d2", "double2 v; uint id; uint depth; char c;", 32,
      { { "v.s0", K_DOUBLE }, { "v.s1", K_DOUBLE }, { "c", K_CHAR } } },
    { "ar", "uchar a[3]; uchar depth; ushort id; ushort s;", 8,
      { { "a[0]", K_UCHAR }, { "a[1]", K_UCHAR }, { "a[2]", K_UCHAR }, { "s", K_USHORT } } },
    { "big", "double v[12]; uint id; uint depth; float f[6];", 128,
      { { "v[0]", K_DOUBLE }, { "v[1]", K_DOUBLE }, { "v[2]", K_DOUBLE }, { "v[3]", K_DOUBLE },
        { "v[4]", K_DOUBLE }, { "v[5]", K_DOUBLE }, { "v[6]", K_DOUBLE }, { "v[7]", K_DOUBLE },
        { "v[8]", K_DOUBLE }, { "v[9]", K_DOUBLE }, { "v[10]", K_DOUBLE }, { "v[11]", K_DOUBLE },
        { "f[0]", K_FLOAT }, { "f[1]", K_FLOAT }, { "f[2]", K_FLOAT }, { "f[3]", K_FLOAT },
        { "f[4]", K_FLOAT }, { "f[5]", K_FLOAT } } },
    /* padding between every field */
    { "mix", "char c; double d; short s; float f; uint id; uchar depth;", 32,
      { { "c", K_CHAR }, { "d", K_DOUBLE }, { "s", K_SHORT }, { "f", K_FLOAT } } },
    { "f3", "float3 p; uint id; uint depth;", 32, { { "p.s0", K_FLOAT }, { "p.s1", K_FLOAT }, { "p.s2", K_FLOAT } } },
    { "lg", "long l; int i; uint id; short s; uchar depth; uchar u;", 24,
      { { "l", K_LONG }, { "i", K_INT }, { "s", K_SHORT }, { "u", K_UCHAR } } },
    { "vi", "ulong2 w; int2 v; uint id; uint depth;", 32,
      { { "w.s0", K_ULONG }, { "w.s1", K_ULONG }, { "v.s0", K_INT }, { "v.s1", K_INT } } },
};
#define TYPE_COUNT (sizeof item_types / sizeof *item_types)

static unsigned component_count(const item_type *t)
{
    unsigned n = 0;
    while (n < MAX_COMPONENTS && t->components[n].access)
        ++n;
    return n;
}

/* Every node has 4 children (ids 4 id + 1 .. 4 id + 4, root 0) down to
 * `depth`.  Component j of node id holds value(kind, u, j), u = id for the
 * even components and id >> 2 for the odd ones ("slow": the first three
 * children share it, so the procedure changes them only before the first
 * and the last emit). */
#define CHILDREN 4u
static const char *const device_types[] = { "char", "uchar", "short", "ushort", "int", "uint", "long", "ulong",
                                            "float", "double" };
/* The value as OpenCL C, of `u` (a uint expression) and j. */
static void device_value(char *out, size_t size, kind k, const char *u, unsigned j)
{
    switch (k) {
    case K_CHAR: case K_UCHAR:
        snprintf(out, size, "(%s)((%s) * 37u + %uu)", device_types[k], u, j * 11u);
        break;
    case K_SHORT: case K_USHORT:
        snprintf(out, size, "(%s)((%s) * 40503u + %uu)", device_types[k], u, j * 101u);
        break;
    case K_INT: case K_UINT:
        snprintf(out, size, "(%s)((%s) * 2654435761u + %uu)", device_types[k], u, j * 97u);
        break;
    case K_LONG: case K_ULONG:
        snprintf(out, size, "(%s)((ulong)(%s) * 0x9E3779B97F4A7C15ul + %uul)", device_types[k], u, j);
        break;
    case K_FLOAT:
        snprintf(out, size, "(float)(((%s) * 7u + %uu) %% 1048576u) * 0.5f", u, j);
        break;
    case K_DOUBLE:
        snprintf(out, size, "(double)((%s) * 13u + %uu) * 0.25 + 0.125", u, j);
        break;
    }
}

/* The same value's bits on the host, zero-extended. */
static uint64_t host_bits(kind k, uint32_t u, unsigned j)
{
    switch (k) {
    case K_CHAR: case K_UCHAR:
        return (uint8_t)(u * 37u + j * 11u);
    case K_SHORT: case K_USHORT:
        return (uint16_t)(u * 40503u + j * 101u);
    case K_INT: case K_UINT:
        return (uint32_t)(u * 2654435761u + j * 97u);
    case K_LONG: case K_ULONG:
        return (uint64_t)u * 0x9E3779B97F4A7C15ull + j;
    case K_FLOAT: {
        float f = (float)((u * 7u + j) % 1048576u) * 0.5f;
        uint32_t bits;
        memcpy(&bits, &f, sizeof bits);
        return bits;
    }
    case K_DOUBLE: {
        double d = (double)(u * 13u + j) * 0.25 + 0.125;
        uint64_t bits;
        memcpy(&bits, &d, sizeof bits);
        return bits;
    }
    }
    return 0;
}

/* The bits of a component's value `v` on the device, zero-extended. */
static const char *device_bits(kind k)
{
    switch (k) {
    case K_CHAR: case K_UCHAR: return "(ulong)(uchar)(%s)";
    case K_SHORT: case K_USHORT: return "(ulong)(ushort)(%s)";
    case K_INT: case K_UINT: return "(ulong)(uint)(%s)";
    case K_LONG: case K_ULONG: return "(ulong)(%s)";
    case K_FLOAT: return "(ulong)as_uint(%s)";
    case K_DOUBLE: return "as_ulong(%s)";
    }
    return "";
}

static int slow(unsigned j)
{
    return j % 2u == 1u;
}

/* The order in which child k sets the components: forward, backward, even
 * ones first, odd ones first. */
static unsigned order(unsigned k, unsigned i, unsigned n)
{
    switch (k % 4u) {
    case 0: return i;
    case 1: return n - 1u - i;
    case 2: return i < (n + 1u) / 2u ? 2u * i : 2u * (i - (n + 1u) / 2u) + 1u;
    default: return i < n / 2u ? 2u * i + 1u : 2u * (i - n / 2u);
    }
}

static void append(char **text, size_t *length, const char *format, ...) __attribute__((format(printf, 3, 4)));
static void append(char **text, size_t *length, const char *format, ...)
{
    va_list args;
    va_start(args, format);
    int n = vsnprintf(NULL, 0, format, args);
    va_end(args);
    *text = realloc(*text, *length + (size_t)n + 1);
    ck_assert_ptr_nonnull(*text);
    va_start(args, format);
    vsnprintf(*text + *length, (size_t)n + 1, format, args);
    va_end(args);
    *length += (size_t)n;
}

/* The procedure of type t (index ti): check and sum the node's components,
 * then, above the leaves, emit its 4 children from one private item. */
static char *procedure_source(const item_type *t, unsigned ti)
{
    char *s = NULL;
    size_t len = 0;
    unsigned n = component_count(t);
    char value[160], bits[200], u[64];
    append(&s, &len, "void %s(perma_ctx *ctx, __local const struct %s *p)\n{\n", t->name, t->name);
    /* The root (id 0) is all zeros: not checked. */
    append(&s, &len, "    uint id = p->id, depth = p->depth, bad = 0u;\n    ulong sum = 0ul;\n    if (id != 0u) {\n");
    for (unsigned j = 0; j < n; ++j) {
        const component *c = &t->components[j];
        device_value(value, sizeof value, c->kind, slow(j) ? "id >> 2" : "id", j);
        char expression[64];
        snprintf(expression, sizeof expression, "p->%s", c->access);
        snprintf(bits, sizeof bits, device_bits(c->kind), expression);
        append(&s, &len, "        bad += p->%s != %s;\n        sum += %s * %uul;\n", c->access, value, bits, j + 1u);
    }
    append(&s, &len, "    }\n");
    append(&s, &len, "    reduce_%s_sum(ctx, sum);\n    reduce_%s_nodes(ctx, 1u);\n", t->name, t->name);
    append(&s, &len, "    if (bad)\n        reduce_bad_type(ctx, %uu);\n", ti + 1u);
    if (strcmp(t->name, "sd") == 0) /* the leaves of sd also write a bound buffer of structs */
        append(&s, &len, "    if (depth == ITEMS_DEPTH)\n        ctx->buf.sd_leaves[id - ITEMS_FIRST_LEAF] = *p;\n");
    append(&s, &len, "    if (depth == ITEMS_DEPTH)\n        return;\n");
    append(&s, &len, "    struct %s c = *p;\n    c.depth = depth + 1u;\n", t->name);
    for (unsigned k = 0; k < CHILDREN; ++k) {
        append(&s, &len, "    c.id = id * %uu + %uu;\n", CHILDREN, k + 1u);
        snprintf(u, sizeof u, "(id * %uu + %uu)", CHILDREN, k + 1u);
        for (unsigned i = 0; i < n; ++i) {
            unsigned j = order(k, i, n);
            if (slow(j) && k != 0 && k != CHILDREN - 1u)
                continue; /* unchanged since the previous emit */
            char su[80];
            snprintf(su, sizeof su, "%s >> 2", u);
            device_value(value, sizeof value, t->components[j].kind, slow(j) ? su : u, j);
            append(&s, &len, "    c.%s = %s;\n", t->components[j].access, value);
        }
        append(&s, &len, "    emit_%s(ctx, &c);\n", t->name);
    }
    append(&s, &len, "}\n");
    return s;
}

/* Nodes and the sum of their components' bits, as the procedure computes
 * them, over the whole tree. */
static void host_tree(const item_type *t, unsigned depth, uint32_t id, unsigned level, uint64_t *sum,
                      uint32_t *nodes)
{
    unsigned n = component_count(t);
    for (unsigned j = 0; j < n && id != 0; ++j)
        *sum += host_bits(t->components[j].kind, slow(j) ? id >> 2 : id, j) * (j + 1u);
    *nodes += 1;
    if (level < depth)
        for (unsigned k = 0; k < CHILDREN; ++k)
            host_tree(t, depth, id * CHILDREN + k + 1u, level + 1u, sum, nodes);
}

/* ---- the reduced case from the report ---- */

/* The procedure of the report, word for word, for DEPTH 1 and DEPTH 2:
 * the four leaves' sum of x + 10 y is 11.0 (DEPTH 1) and 66.0 (DEPTH 2). */
#define REPORT_SOURCE(D)                                                                              \
    "void pd" #D "(perma_ctx *ctx, __local const struct d *p)\n"                                      \
    "{\n"                                                                                             \
    "    double x0 = p->x, y0 = p->y, h = p->h, m = 0.5 * h;\n"                                       \
    "    if (p->depth == " #D ") { reduce_sd" #D "(ctx, x0 + 10.0 * y0); reduce_n" #D "(ctx, 1u); return; }\n" \
    "    struct d k = { x0, y0, m, p->depth + 1u, 0u };\n"                                            \
    "    emit_pd" #D "(ctx, &k);\n"                                                                   \
    "    k.x = x0 + m; emit_pd" #D "(ctx, &k);\n"                                                     \
    "    k.y = y0 + m; emit_pd" #D "(ctx, &k);\n"                                                     \
    "    k.x = x0;     emit_pd" #D "(ctx, &k);\n"                                                     \
    "}\n"

struct d {
    double x, y, h;
    uint32_t depth, pad;
};

struct sd {
    double x, y, h;
    uint32_t depth, id;
};

/* The tree's depth: PERMA_TEST_ITEMS_DEPTH (Oclgrind runs a smaller one), else 5. */
static unsigned tree_depth(void)
{
    const char *v = getenv("PERMA_TEST_ITEMS_DEPTH");
    return v && *v ? (unsigned)strtoul(v, NULL, 10) : 5u;
}

/* Register the types item_types[which[0..count-1]] and, for each depth in
 * report_depths[0..reports-1], the report's procedure; seed them, run, and
 * check every result exactly. */
static void check_items(const unsigned *which, unsigned count, const unsigned *report_depths, unsigned reports)
{
    const unsigned depth = tree_depth();
    uint32_t first_leaf = 0, level_size = 1;
    for (unsigned l = 0; l < depth; ++l) {
        first_leaf += level_size;
        level_size *= CHILDREN;
    }
    const uint32_t leaves = level_size;

    /* The variant's schedule, with a local queue of at most 32 items: 16
     * procedures of up to 128-byte items must fit 64 KiB of __local memory. */
    perma_config config;
    perma_config_init(&config);
    config.time_limit = 120;
    test_apply_variant(&config);
    if (config.schedule.local_queue_items > 32)
        config.schedule.local_queue_items = 32;
    perma_runtime *rt = NULL;
    perma_error error;
    perma_status st = perma_create(&config, &rt, &error);
    ck_assert_msg(st == PERMA_OK, "perma_create: %s", error.message);
    char defines[256];
    snprintf(defines, sizeof defines,
             "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n#define ITEMS_DEPTH %uu\n#define ITEMS_FIRST_LEAF %uu\n"
             "struct d { double x, y, h; uint depth; uint pad; };\n",
             depth, first_leaf);
    ck_assert_perma_ok(rt, perma_add_source(rt, defines, "items_defines.cl"));
    for (unsigned i = 0; i < TYPE_COUNT; ++i) {
        char decl[256];
        snprintf(decl, sizeof decl, "struct %s { %s };\n", item_types[i].name, item_types[i].fields);
        ck_assert_perma_ok(rt, perma_add_source(rt, decl, "items_types.cl"));
    }

    /* The bound buffer the sd leaves write (bound whether or not sd runs). */
    struct sd *sd_leaves = calloc(leaves, sizeof *sd_leaves);
    ck_assert_ptr_nonnull(sd_leaves);
    ck_assert_perma_ok(rt, perma_bind_host(rt, "sd_leaves", "__global struct sd *", sd_leaves,
                                           leaves * sizeof *sd_leaves, PERMA_READ_WRITE));

    char *sources[TYPE_COUNT] = { NULL };
    uint64_t sums[TYPE_COUNT] = { 0 };
    uint32_t nodes[TYPE_COUNT] = { 0 };
    uint32_t bad_type = 0;
    unsigned char root[128];
    memset(root, 0, sizeof root);
    bool sd_runs = false;
    for (unsigned w = 0; w < count; ++w) {
        unsigned i = which[w];
        const item_type *t = &item_types[i];
        sd_runs = sd_runs || strcmp(t->name, "sd") == 0;
        sources[i] = procedure_source(t, i);
        char type[32], name[32];
        snprintf(type, sizeof type, "struct %s", t->name);
        perma_procedure p = { .name = t->name, .item_type = type, .item_size = t->size, .source = sources[i],
                              .function = t->name, .emits = { { t->name, CHILDREN } } };
        perma_proc id;
        ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
        snprintf(name, sizeof name, "%s_sum", t->name);
        ck_assert_perma_ok(rt, perma_declare_reduction(rt, name, PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &sums[i]));
        snprintf(name, sizeof name, "%s_nodes", t->name);
        ck_assert_perma_ok(rt, perma_declare_reduction(rt, name, PERMA_REDUCE_SUM, PERMA_TYPE_UINT, &nodes[i]));
        ck_assert_perma_ok(rt, perma_seed(rt, id, root, 1)); /* id 0, depth 0, every value 0 */
    }
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, "bad_type", PERMA_REDUCE_MAX, PERMA_TYPE_UINT, &bad_type));

    /* The report's procedure: the leaves' sum of x + 10 y. */
    static const char *const report_sources[] = { NULL, REPORT_SOURCE(1), REPORT_SOURCE(2) };
    double report_sums[3] = { 0, 0, 0 };
    uint32_t report_leaves[3] = { 0, 0, 0 };
    const struct d report_root = { 0, 0, 1, 0, 0 };
    for (unsigned r = 0; r < reports; ++r) {
        unsigned D = report_depths[r];
        char name[16], sum_name[16], n_name[16];
        snprintf(name, sizeof name, "pd%u", D);
        snprintf(sum_name, sizeof sum_name, "sd%u", D);
        snprintf(n_name, sizeof n_name, "n%u", D);
        perma_procedure p = { .name = name, .item_type = "struct d", .item_size = sizeof(struct d),
                              .source = report_sources[D], .function = name, .emits = { { name, 4 } } };
        perma_proc id;
        ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
        ck_assert_perma_ok(rt, perma_declare_reduction(rt, sum_name, PERMA_REDUCE_SUM, PERMA_TYPE_DOUBLE,
                                                       &report_sums[D]));
        ck_assert_perma_ok(rt, perma_declare_reduction(rt, n_name, PERMA_REDUCE_SUM, PERMA_TYPE_UINT,
                                                       &report_leaves[D]));
        ck_assert_perma_ok(rt, perma_seed(rt, id, &report_root, 1));
    }

    ck_assert_perma_ok(rt, perma_run(rt));

    /* Every type, then one message listing each that is wrong. */
    char failures[4096] = "";
    size_t used = 0;
    for (unsigned w = 0; w < count && used < sizeof failures; ++w) {
        unsigned i = which[w];
        uint64_t want_sum = 0;
        uint32_t want_nodes = 0;
        host_tree(&item_types[i], depth, 0, 0, &want_sum, &want_nodes);
        if (sums[i] != want_sum || nodes[i] != want_nodes)
            used += (size_t)snprintf(failures + used, sizeof failures - used,
                                     " struct %s (%zu bytes): %" PRIu32 " nodes (want %" PRIu32 "), sum %016" PRIx64
                                     " (want %016" PRIx64 ");",
                                     item_types[i].name, item_types[i].size, nodes[i], want_nodes, sums[i], want_sum);
    }
    ck_assert_msg(bad_type == 0 && used == 0, "items arrived changed (first type with a wrong field: %u):%s",
                  bad_type, failures);

    /* 11 and 66: the four (sixteen) leaves' x + 10 y. */
    for (unsigned r = 0; r < reports; ++r) {
        unsigned D = report_depths[r];
        double want = D == 1 ? 11.0 : 66.0;
        ck_assert_msg(report_sums[D] == want && report_leaves[D] == (D == 1 ? 4u : 16u),
                      "report's case, DEPTH %u: sum %.17g over %u leaves (want %g over %u)", D, report_sums[D],
                      report_leaves[D], want, D == 1 ? 4u : 16u);
    }

    /* The bound buffer of structs: leaf id's fields, as the device wrote them. */
    for (uint32_t l = 0; l < leaves && sd_runs; ++l) {
        uint32_t id = first_leaf + l;
        const struct sd *got = &sd_leaves[l];
        for (unsigned j = 0; j < 3; ++j) {
            double v = j == 0 ? got->x : j == 1 ? got->y : got->h;
            uint64_t bits;
            memcpy(&bits, &v, sizeof bits);
            ck_assert_msg(bits == host_bits(K_DOUBLE, slow(j) ? id >> 2 : id, j),
                          "sd_leaves[%u] component %u: %.17g", l, j, v);
        }
        ck_assert_uint_eq(got->id, id);
        ck_assert_uint_eq(got->depth, depth);
    }

    for (unsigned i = 0; i < TYPE_COUNT; ++i)
        free(sources[i]);
    free(sd_leaves);
    perma_destroy(rt);
}

/* Every type and the report's case at both depths in one program: what
 * runs under every schedule. */
START_TEST(items_arrive_as_emitted)
{
    unsigned all[TYPE_COUNT];
    for (unsigned i = 0; i < TYPE_COUNT; ++i)
        all[i] = i;
    const unsigned depths[] = { 1, 2 };
    check_items(all, TYPE_COUNT, depths, 2);
}
END_TEST

/* Each type, and the report's case at each depth, in a program of its own:
 * PoCL 3.1 moved the emit's copy ahead of the stores only where the
 * procedure was the program's one (inlined into the dispatch), so this is
 * the case that failed before items were copied as may-alias words. */
START_TEST(items_arrive_as_emitted_one_procedure_per_program)
{
    for (unsigned i = 0; i < TYPE_COUNT; ++i)
        check_items(&i, 1, NULL, 0);
    for (unsigned D = 1; D <= 2; ++D)
        check_items(NULL, 0, &D, 1);
}
END_TEST

/* PERMA_TEST_ITEMS_ALONE=1: the programs of one procedure each, else all
 * in one (tests/meson.build runs both). */
int main(void)
{
    const char *alone = getenv("PERMA_TEST_ITEMS_ALONE");
    const TTest *const together[] = { items_arrive_as_emitted };
    const TTest *const separate[] = { items_arrive_as_emitted_one_procedure_per_program };
    if (alone && *alone == '1')
        return test_main("items", separate, 1);
    return test_main("items", together, 1);
}
