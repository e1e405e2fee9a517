/* Reductions (perma_declare_reduction, reduce_NAME): sums, minima and
 * maxima of every value type over a binary tree, equal to the host's
 * computation under every technique and strategy (the test runs under
 * each, tests/meson.build); float and double sums exact (the same bits as
 * the host's exact sum rounded once, so the same bits whatever the order);
 * the rounding and special values of exact sums; and the errors, by status
 * and message. */
#include "perma_test.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- every type over a tree ---- */

/* Node id (heap numbering: root 1, children 2i, 2i+1) down to depth
 * `target`; every node reduces values derived from its id. */
#define TREE_TYPES "struct rnode { uint depth; uint target; uint id; uint pad; };\n"
#define TREE_SOURCE                                                                     \
    "float rvalue_float(uint id)\n"                                                     \
    "{\n"                                                                               \
    "    return (float)((int)(id % 2001u) - 1000) * ldexp(1.0f, (int)(id % 41u) - 20);\n" \
    "}\n"                                                                               \
    "double rvalue_double(uint id)\n"                                                   \
    "{\n"                                                                               \
    "    return (double)((int)(id * 7919u % 200001u) - 100000) * ldexp(1.0, (int)(id % 61u) - 30);\n" \
    "}\n"                                                                               \
    "void rtree(perma_ctx *ctx, __local const struct rnode *n)\n"                       \
    "{\n"                                                                               \
    "    uint id = n->id, h = id * 2654435761u;\n"                                      \
    "    reduce_nodes(ctx, 1u);\n"                                                      \
    "    reduce_id_sum(ctx, (ulong)id * 4000000000ul);\n"                               \
    "    reduce_signed_sum(ctx, (int)(id % 7u) - 3);\n"                                 \
    "    reduce_long_sum(ctx, (id & 1u) ? -(long)id * 1000003l : (long)id * 999983l);\n" \
    "    reduce_int_min(ctx, (int)h);\n"                                                \
    "    reduce_int_max(ctx, (int)h);\n"                                                \
    "    reduce_uint_min(ctx, h);\n"                                                    \
    "    reduce_ulong_max(ctx, (ulong)h << 20);\n"                                      \
    "    reduce_long_min(ctx, -(long)h * (long)id);\n"                                  \
    "    reduce_depth_max(ctx, n->depth);\n"                                            \
    "    reduce_float_sum(ctx, rvalue_float(id));\n"                                    \
    "    reduce_double_sum(ctx, rvalue_double(id));\n"                                  \
    "    reduce_float_min(ctx, rvalue_float(id));\n"                                    \
    "    reduce_double_max(ctx, rvalue_double(id));\n"                                  \
    "    if (n->depth < n->target) {\n"                                                 \
    "        struct rnode child = { n->depth + 1u, n->target, 2u * id, 0u };\n"         \
    "        emit_rtree(ctx, &child);\n"                                                \
    "        child.id += 1u;\n"                                                         \
    "        emit_rtree(ctx, &child);\n"                                                \
    "    }\n"                                                                           \
    "}\n"

struct rnode {
    uint32_t depth, target, id, pad;
};

static float rvalue_float(uint32_t id)
{
    return (float)((int)(id % 2001u) - 1000) * ldexpf(1.0f, (int)(id % 41u) - 20);
}

static double rvalue_double(uint32_t id)
{
    return (double)((int)(id * 7919u % 200001u) - 100000) * ldexp(1.0, (int)(id % 61u) - 30);
}

/* The tree's results, computed on the host; the float and double sums
 * exactly (in units of 2^-20 and 2^-30, as 128-bit integers), then
 * rounded once. */
typedef struct tree_results {
    uint32_t nodes;
    uint64_t id_sum;
    int32_t signed_sum;
    int64_t long_sum;
    int32_t int_min, int_max;
    uint32_t uint_min;
    uint64_t ulong_max;
    int64_t long_min;
    uint32_t depth_max;
    float float_sum, float_min;
    double double_sum, double_max;
} tree_results;

static void expected_results(uint32_t depth, tree_results *x)
{
    memset(x, 0, sizeof *x);
    x->int_min = INT32_MAX;
    x->int_max = INT32_MIN;
    x->uint_min = UINT32_MAX;
    x->long_min = INT64_MAX;
    x->float_min = INFINITY;
    x->double_max = -INFINITY;
    __int128 float_units = 0, double_units = 0;
    uint32_t last = (2u << depth) - 1;
    for (uint32_t id = 1; id <= last; ++id) {
        uint32_t h = id * 2654435761u, d = 31 - (uint32_t)__builtin_clz(id);
        x->nodes += 1;
        x->id_sum += (uint64_t)id * 4000000000u;
        x->signed_sum = (int32_t)((uint32_t)x->signed_sum + (uint32_t)((int)(id % 7u) - 3));
        x->long_sum += (id & 1u) ? -(int64_t)id * 1000003 : (int64_t)id * 999983;
        if ((int32_t)h < x->int_min)
            x->int_min = (int32_t)h;
        if ((int32_t)h > x->int_max)
            x->int_max = (int32_t)h;
        if (h < x->uint_min)
            x->uint_min = h;
        if ((uint64_t)h << 20 > x->ulong_max)
            x->ulong_max = (uint64_t)h << 20;
        if (-(int64_t)h * id < x->long_min)
            x->long_min = -(int64_t)h * id;
        if (d > x->depth_max)
            x->depth_max = d;
        float_units += (__int128)((int)(id % 2001u) - 1000) * ((__int128)1 << (id % 41u));
        double_units += (__int128)((int)(id * 7919u % 200001u) - 100000) * ((__int128)1 << (id % 61u));
        if (rvalue_float(id) < x->float_min)
            x->float_min = rvalue_float(id);
        if (rvalue_double(id) > x->double_max)
            x->double_max = rvalue_double(id);
    }
    /* One rounding each: the 128-bit integers convert to the nearest
     * float (double), then scale exactly. */
    x->float_sum = ldexpf((float)float_units, -20);
    x->double_sum = ldexp((double)double_units, -30);
}

static void declare(perma_runtime *rt, const char *name, perma_reduce_op op, perma_value_type type, void *result)
{
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, name, op, type, result));
}

START_TEST(every_type_over_a_tree)
{
    enum { DEPTH = 12 };
    perma_runtime *rt = test_runtime(64, 2, 0);
    tree_results got, want;
    memset(&got, 0xa5, sizeof got);
    declare(rt, "nodes", PERMA_REDUCE_SUM, PERMA_TYPE_UINT, &got.nodes);
    declare(rt, "id_sum", PERMA_REDUCE_SUM, PERMA_TYPE_ULONG, &got.id_sum);
    declare(rt, "signed_sum", PERMA_REDUCE_SUM, PERMA_TYPE_INT, &got.signed_sum);
    declare(rt, "long_sum", PERMA_REDUCE_SUM, PERMA_TYPE_LONG, &got.long_sum);
    declare(rt, "int_min", PERMA_REDUCE_MIN, PERMA_TYPE_INT, &got.int_min);
    declare(rt, "int_max", PERMA_REDUCE_MAX, PERMA_TYPE_INT, &got.int_max);
    declare(rt, "uint_min", PERMA_REDUCE_MIN, PERMA_TYPE_UINT, &got.uint_min);
    declare(rt, "ulong_max", PERMA_REDUCE_MAX, PERMA_TYPE_ULONG, &got.ulong_max);
    declare(rt, "long_min", PERMA_REDUCE_MIN, PERMA_TYPE_LONG, &got.long_min);
    declare(rt, "depth_max", PERMA_REDUCE_MAX, PERMA_TYPE_UINT, &got.depth_max);
    declare(rt, "float_sum", PERMA_REDUCE_SUM, PERMA_TYPE_FLOAT, &got.float_sum);
    declare(rt, "double_sum", PERMA_REDUCE_SUM, PERMA_TYPE_DOUBLE, &got.double_sum);
    declare(rt, "float_min", PERMA_REDUCE_MIN, PERMA_TYPE_FLOAT, &got.float_min);
    declare(rt, "double_max", PERMA_REDUCE_MAX, PERMA_TYPE_DOUBLE, &got.double_max);
    ck_assert_perma_ok(rt, perma_add_source(rt, "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n" TREE_TYPES,
                                            "rtree_types.cl"));
    perma_procedure tree = { .name = "rtree", .item_type = "struct rnode", .item_size = sizeof(struct rnode),
                             .source = TREE_SOURCE, .source_file = "rtree.cl", .function = "rtree",
                             .emits = { { "rtree", 2 } } };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &tree, &id));
    expected_results(DEPTH, &want);
    double first_double = 0;
    float first_float = 0;
    for (int run = 0; run < 2; ++run) {
        struct rnode root = { 0, DEPTH, 1, 0 };
        ck_assert_perma_ok(rt, perma_seed(rt, id, &root, 1));
        ck_assert_perma_ok(rt, perma_run(rt));
        ck_assert_uint_eq(got.nodes, want.nodes);
        ck_assert_uint_eq(got.id_sum, want.id_sum);
        ck_assert_int_eq(got.signed_sum, want.signed_sum);
        ck_assert_int_eq(got.long_sum, want.long_sum);
        ck_assert_int_eq(got.int_min, want.int_min);
        ck_assert_int_eq(got.int_max, want.int_max);
        ck_assert_uint_eq(got.uint_min, want.uint_min);
        ck_assert_uint_eq(got.ulong_max, want.ulong_max);
        ck_assert_int_eq(got.long_min, want.long_min);
        ck_assert_uint_eq(got.depth_max, DEPTH);
        /* Bit for bit: exact, so the order of the adds cannot show. */
        ck_assert_msg(memcmp(&got.float_sum, &want.float_sum, sizeof got.float_sum) == 0, "float sum %a, want %a",
                      (double)got.float_sum, (double)want.float_sum);
        ck_assert_msg(memcmp(&got.double_sum, &want.double_sum, sizeof got.double_sum) == 0,
                      "double sum %a, want %a", got.double_sum, want.double_sum);
        ck_assert_msg(got.float_min == want.float_min, "float min %a, want %a", (double)got.float_min,
                      (double)want.float_min);
        ck_assert_msg(got.double_max == want.double_max, "double max %a, want %a", got.double_max, want.double_max);
        if (run == 1) {
            ck_assert_msg(memcmp(&first_double, &got.double_sum, sizeof first_double) == 0 &&
                              memcmp(&first_float, &got.float_sum, sizeof first_float) == 0,
                          "a second run gave other bits");
        }
        first_double = got.double_sum;
        first_float = got.float_sum;
        /* perma_get_reduction reads the same results. */
        uint64_t ids;
        double d;
        ck_assert_perma_ok(rt, perma_get_reduction(rt, "id_sum", PERMA_TYPE_ULONG, &ids));
        ck_assert_uint_eq(ids, want.id_sum);
        ck_assert_perma_ok(rt, perma_get_reduction(rt, "double_sum", PERMA_TYPE_DOUBLE, &d));
        ck_assert(memcmp(&d, &want.double_sum, sizeof d) == 0);
    }
    perma_destroy(rt);
}
END_TEST

/* ---- exact sums: rounding, special values; min and max of floats ---- */

#define VALUE_SOURCE                                                                   \
    "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n"                                   \
    "struct rvalue { double d; float f; uint pad; };\n"                                \
    "void rvalue(perma_ctx *ctx, __local const struct rvalue *v)\n"                     \
    "{\n"                                                                               \
    "    reduce_dsum(ctx, v->d);\n"                                                     \
    "    reduce_fsum(ctx, v->f);\n"                                                     \
    "    reduce_dmin(ctx, v->d);\n"                                                     \
    "    reduce_fmax(ctx, v->f);\n"                                                     \
    "}\n"

struct rvalue {
    double d;
    float f;
    uint32_t pad;
};

typedef struct value_runtime {
    perma_runtime *rt;
    perma_proc proc;
    double dsum, dmin;
    float fsum, fmax;
} value_runtime;

static void value_open(value_runtime *v)
{
    memset(v, 0, sizeof *v);
    v->rt = test_runtime(64, 2, 0);
    declare(v->rt, "dsum", PERMA_REDUCE_SUM, PERMA_TYPE_DOUBLE, &v->dsum);
    declare(v->rt, "fsum", PERMA_REDUCE_SUM, PERMA_TYPE_FLOAT, &v->fsum);
    declare(v->rt, "dmin", PERMA_REDUCE_MIN, PERMA_TYPE_DOUBLE, &v->dmin);
    declare(v->rt, "fmax", PERMA_REDUCE_MAX, PERMA_TYPE_FLOAT, &v->fmax);
    perma_procedure p = { .name = "rvalue", .item_type = "struct rvalue", .item_size = sizeof(struct rvalue),
                          .source = VALUE_SOURCE, .source_file = "rvalue.cl", .function = "rvalue" };
    ck_assert_perma_ok(v->rt, perma_register(v->rt, &p, &v->proc));
}

/* Run the doubles (and each as a float) `copies` times over, spread over
 * the batch (the same multiset whatever order the groups take them in). */
static void value_run(value_runtime *v, const double *values, unsigned count, unsigned copies)
{
    struct rvalue *items = calloc((size_t)count * copies, sizeof *items);
    for (unsigned c = 0; c < copies; ++c)
        for (unsigned i = 0; i < count; ++i)
            items[c * count + i] = (struct rvalue){ values[i], (float)values[i], 0 };
    ck_assert_perma_ok(v->rt, perma_seed(v->rt, v->proc, items, (size_t)count * copies));
    free(items);
    ck_assert_perma_ok(v->rt, perma_run(v->rt));
}

static void expect_bits(double got, double want, const char *what)
{
    ck_assert_msg(memcmp(&got, &want, sizeof got) == 0 || (isnan(got) && isnan(want)), "%s: %a, want %a", what, got,
                  want);
}

START_TEST(exact_sums_round_once)
{
    value_runtime v;
    value_open(&v);
    /* Cancellation: a naive sum gives 0 or 2 depending on the order. */
    const double cancel[] = { DBL_MAX / 2, 1.0, -DBL_MAX / 2, 1.0 };
    value_run(&v, cancel, 4, 50);
    expect_bits(v.dsum, 100.0, "cancellation");
    /* float: DBL_MAX/2 is +inf and -inf: NaN. */
    ck_assert(isnan(v.fsum));
    /* Ties to even: 1 + 2^-53 is halfway between 1 and the next double. */
    const double tie[] = { 1.0, 0x1p-53 };
    value_run(&v, tie, 2, 1);
    expect_bits(v.dsum, 1.0, "tie rounds to even");
    const double above[] = { 1.0, 0x1p-53, 0x1p-1074 };
    value_run(&v, above, 3, 1);
    expect_bits(v.dsum, 1.0 + 0x1p-52, "just above the tie rounds up");
    const double below_odd[] = { 1.0 + 0x1p-52, 0x1p-53 };
    value_run(&v, below_odd, 2, 1);
    expect_bits(v.dsum, 1.0 + 0x1p-51, "a tie next to an odd mantissa rounds up");
    /* Subnormals add exactly; a float sum of them is 0. */
    const double tiny[] = { 0x1p-1074 };
    value_run(&v, tiny, 1, 3);
    expect_bits(v.dsum, 3 * 0x1p-1074, "subnormals");
    expect_bits(v.fsum, 0.0, "float of doubles below its range");
    /* Overflow of the exact sum: the tie at DBL_MAX + half an ulp rounds
     * to the even 2^1024, which is infinite. */
    const double huge[] = { DBL_MAX, 0x1p970 };
    value_run(&v, huge, 2, 1);
    expect_bits(v.dsum, INFINITY, "overflow rounds to infinity");
    const double less_huge[] = { DBL_MAX, 0x1p969 };
    value_run(&v, less_huge, 2, 1);
    expect_bits(v.dsum, DBL_MAX, "below the tie stays finite");
    /* Special values. */
    const double inf[] = { INFINITY, 1.0, -5.0 };
    value_run(&v, inf, 3, 1);
    expect_bits(v.dsum, INFINITY, "+inf");
    expect_bits(v.fsum, INFINITY, "float +inf");
    const double both[] = { INFINITY, -INFINITY };
    value_run(&v, both, 2, 1);
    ck_assert(isnan(v.dsum));
    const double nan[] = { 1.0, NAN, 2.0 };
    value_run(&v, nan, 3, 1);
    ck_assert(isnan(v.dsum));
    /* min and max ignore NaN; -0.0 is below +0.0. */
    expect_bits(v.dmin, 1.0, "min ignores NaN");
    expect_bits(v.fmax, 2.0f, "max ignores NaN");
    const double zeros[] = { 0.0, -0.0, 0.0 };
    value_run(&v, zeros, 3, 20);
    expect_bits(v.dmin, -0.0, "min of zeros");
    expect_bits(v.fmax, 0.0f, "max of zeros");
    expect_bits(v.dsum, 0.0, "a zero sum is +0.0");
    /* Mixed signs and magnitudes: the exact sum is 117440500.625 + 7 *
     * 2^-40, which rounds to 117440500.625 as a double and to 117440504 as
     * a float (its ulp there is 8). */
    const double mixed[] = { -3.0, 0.375, 0x1p-40, 16777216.0, 1.0 };
    value_run(&v, mixed, 5, 7);
    expect_bits(v.dsum, 117440500.625, "mixed");
    expect_bits(v.fsum, 117440504.0f, "float mixed");
    const double negative[] = { -16777216.0, -0.375, 0x1p-40 };
    value_run(&v, negative, 3, 7);
    expect_bits(v.dsum, -117440514.625, "negative");
    expect_bits(v.fsum, -117440512.0f, "float negative");
    /* With no item at all: the identities. */
    value_run(&v, NULL, 0, 0);
    expect_bits(v.dsum, 0.0, "empty sum");
    expect_bits(v.dmin, INFINITY, "empty min");
    expect_bits(v.fmax, -INFINITY, "empty max");
    perma_destroy(v.rt);
}
END_TEST

/* ---- errors ---- */

START_TEST(declaration_errors)
{
    perma_runtime *rt = test_runtime(64, 1, 0);
    uint32_t u;
    ck_assert_int_eq(perma_declare_reduction(rt, "2count", PERMA_REDUCE_SUM, PERMA_TYPE_UINT, &u), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "name '2count' is not a C identifier");
    ck_assert_int_eq(perma_declare_reduction(rt, NULL, PERMA_REDUCE_SUM, PERMA_TYPE_UINT, &u), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "name '(null)'");
    ck_assert_int_eq(perma_declare_reduction(rt, "count", (perma_reduce_op)7, PERMA_TYPE_UINT, &u), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "perma_declare_reduction('count'): op 7 is not PERMA_REDUCE_SUM");
    ck_assert_int_eq(perma_declare_reduction(rt, "count", PERMA_REDUCE_SUM, (perma_value_type)42, &u),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "perma_declare_reduction('count'): type 42 is not a perma_value_type");
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, "count", PERMA_REDUCE_SUM, PERMA_TYPE_UINT, &u));
    ck_assert_int_eq(perma_declare_reduction(rt, "count", PERMA_REDUCE_MAX, PERMA_TYPE_UINT, NULL), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "reduction 'count' is already declared");
    char name[16];
    for (unsigned i = 1; i < PERMA_MAX_REDUCTIONS; ++i) {
        snprintf(name, sizeof name, "r%u", i);
        ck_assert_perma_ok(rt, perma_declare_reduction(rt, name, PERMA_REDUCE_MAX, PERMA_TYPE_LONG, NULL));
    }
    ck_assert_int_eq(perma_declare_reduction(rt, "one_more", PERMA_REDUCE_SUM, PERMA_TYPE_UINT, NULL),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "perma_declare_reduction('one_more'): more than 32 reductions");
    ck_assert_str_eq(perma_reduce_op_name(PERMA_REDUCE_MIN), "min");
    ck_assert_str_eq(perma_value_type_name(PERMA_TYPE_DOUBLE), "double");
    ck_assert_ptr_null(perma_value_type_name((perma_value_type)6));
    perma_destroy(rt);
}
END_TEST

/* A procedure that emits one item more than it declares when told to: a
 * run that fails. */
#define COUNTED_SOURCE                                                                 \
    "void counted(perma_ctx *ctx, __local const uint *x)\n"                            \
    "{\n"                                                                               \
    "    reduce_count(ctx, 1u);\n"                                                      \
    "    uint child = 0u;\n"                                                            \
    "    for (uint i = 0; i < *x; ++i)\n"                                               \
    "        emit_counted(ctx, &child);\n"                                              \
    "}\n"

START_TEST(reading_errors)
{
    perma_runtime *rt = test_runtime(64, 1, 0);
    uint32_t count = 7, value;
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, "count", PERMA_REDUCE_SUM, PERMA_TYPE_UINT, &count));
    ck_assert_int_eq(perma_get_reduction(rt, "count", PERMA_TYPE_UINT, &value), PERMA_ERR_STATE);
    ck_assert_contains(perma_errmsg(rt), "perma_get_reduction('count'): no result: no run has succeeded");
    perma_procedure p = { .name = "counted", .item_type = "uint", .item_size = 4, .source = COUNTED_SOURCE,
                          .source_file = "counted.cl", .function = "counted", .emits = { { "counted", 1 } } };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    uint32_t seeds[3] = { 1, 0, 0 };
    ck_assert_perma_ok(rt, perma_seed(rt, id, seeds, 3));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(count, 4);
    ck_assert_perma_ok(rt, perma_get_reduction(rt, "count", PERMA_TYPE_UINT, &value));
    ck_assert_uint_eq(value, 4);
    /* Type mismatch, unknown name, no place to put it. */
    uint64_t wide;
    ck_assert_int_eq(perma_get_reduction(rt, "count", PERMA_TYPE_ULONG, &wide), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "perma_get_reduction('count'): the reduction is of type uint, not ulong");
    ck_assert_int_eq(perma_get_reduction(rt, "counts", PERMA_TYPE_UINT, &value), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "no reduction named 'counts' is declared");
    ck_assert_int_eq(perma_get_reduction(rt, "count", PERMA_TYPE_UINT, NULL), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "out is NULL");
    /* A run that fails leaves no result, and the host variable as it was. */
    seeds[0] = 2;
    ck_assert_perma_ok(rt, perma_seed(rt, id, seeds, 1));
    ck_assert_int_eq(perma_run(rt), PERMA_ERR_EMIT_LIMIT);
    ck_assert_int_eq(perma_get_reduction(rt, "count", PERMA_TYPE_UINT, &value), PERMA_ERR_STATE);
    ck_assert_contains(perma_errmsg(rt), "or the last run failed");
    ck_assert_uint_eq(count, 4);
    /* A reduction declared after a run rebuilds the program. */
    int32_t low = 0;
    ck_assert_perma_ok(rt, perma_declare_reduction(rt, "unused_min", PERMA_REDUCE_MIN, PERMA_TYPE_INT, &low));
    seeds[0] = 1;
    ck_assert_perma_ok(rt, perma_seed(rt, id, seeds, 1));
    ck_assert_perma_ok(rt, perma_run(rt));
    ck_assert_uint_eq(count, 2);
    ck_assert_int_eq(low, INT32_MAX); /* no value: the identity */
    perma_destroy(rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("reductions");
    TCase *tc = tcase_create("reductions");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, every_type_over_a_tree);
    tcase_add_test(tc, exact_sums_round_once);
    tcase_add_test(tc, declaration_errors);
    tcase_add_test(tc, reading_errors);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
