/* Reductions (perma_declare_reduction): declaring them, their part of the
 * generated program, and their results.
 *
 * Every work-item keeps a lane: reduce_words 64-bit words, each reduction
 * at its offset (kernels/perma_reduce.cl says what the words hold).  A
 * launch ends with each work-item folding its lane into its own slot of
 * the reductions buffer; the host fills the slots with the identities
 * before a run and combines them after it, in slot order (which does not
 * matter: every combination here is exact). */
#include "files.h"
#include "internal.h"
#include "reductions.h"
#include "state.h"
#include "strbuf.h"

#include <float.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

static const char *const op_names[] = { "sum", "min", "max" };
static const char *const type_names[] = { "uint", "int", "ulong", "long", "float", "double" };
/* Bytes of a host variable of each type. */
static const size_t type_bytes[] = { 4, 4, 8, 8, 4, 8 };

/* A declared reduction. */
typedef struct perma_reduction {
    char *name;
    perma_reduce_op op;
    perma_value_type type;
    void *result;          /* the host variable every successful run sets, or NULL */
    unsigned offset;       /* its first word in a work-item's lane (64-bit words) */
    unsigned words;        /* its words in a lane */
    union {
        uint32_t u;
        int32_t i;
        uint64_t ul;
        int64_t l;
        float f;
        double d;
    } value;               /* the result of the last run */
} perma_reduction;

struct perma_reductions_state {
    perma_reduction list[PERMA_MAX_REDUCTIONS];
    unsigned count;
    bool valid;            /* the values are those of the last run, which succeeded */
};

perma_status perma_reductions_open(perma_runtime *rt)
{
    rt->reductions = calloc(1, sizeof *rt->reductions);
    if (!rt->reductions)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the reductions");
    return PERMA_OK;
}

const char *perma_reduce_op_name(perma_reduce_op op)
{
    return (unsigned)op < sizeof op_names / sizeof op_names[0] ? op_names[op] : NULL;
}

const char *perma_value_type_name(perma_value_type type)
{
    return (unsigned)type < sizeof type_names / sizeof type_names[0] ? type_names[type] : NULL;
}

static bool is_float_type(perma_value_type type)
{
    return type == PERMA_TYPE_FLOAT || type == PERMA_TYPE_DOUBLE;
}

/* Words of a lane a reduction takes: an exact sum's digits and control
 * word, else one. */
static unsigned lane_words(const perma_reduction *r)
{
    if (r->op != PERMA_REDUCE_SUM || !is_float_type(r->type))
        return 1;
    return (r->type == PERMA_TYPE_FLOAT ? PERMA_EXACT_FLOAT_DIGITS : PERMA_EXACT_DOUBLE_DIGITS) + 1;
}

static perma_reduction *find(perma_runtime *rt, const char *name)
{
    for (unsigned i = 0; name && i < rt->reductions->count; ++i)
        if (strcmp(rt->reductions->list[i].name, name) == 0)
            return &rt->reductions->list[i];
    return NULL;
}

static bool device_has_doubles(const perma_runtime *rt)
{
    cl_device_fp_config config = 0;
    return clGetDeviceInfo(rt->device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof config, &config, NULL) == CL_SUCCESS &&
           config != 0;
}

static perma_status declare_reduction_call(perma_runtime *rt, const char *name, perma_reduce_op op, perma_value_type type,
                                           void *result)
{
    perma_status begun = perma_call_begin(rt, "perma_declare_reduction", true);
    if (begun != PERMA_OK)
        return begun;
    const char *n = name ? name : "(null)";
    if (!perma_is_identifier(name))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "perma_declare_reduction: name '%s' is not a C identifier of at most %d characters", n,
                               PERMA_NAME_MAX);
    if (perma_reserved_name(name))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_declare_reduction: name '%s' is %s; choose another name",
                               n, perma_reserved_name(name));
    if (find(rt, name))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_declare_reduction: reduction '%s' is already declared",
                               n);
    if (!perma_reduce_op_name(op))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "perma_declare_reduction('%s'): op %d is not PERMA_REDUCE_SUM, PERMA_REDUCE_MIN or "
                               "PERMA_REDUCE_MAX", n, (int)op);
    if (!perma_value_type_name(type))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "perma_declare_reduction('%s'): type %d is not a perma_value_type (PERMA_TYPE_UINT, "
                               "_INT, _ULONG, _LONG, _FLOAT or _DOUBLE)", n, (int)type);
    if (type == PERMA_TYPE_DOUBLE && !device_has_doubles(rt))
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "perma_declare_reduction('%s'): type double, but the device has no double precision "
                               "(cl_khr_fp64)", n);
    if (rt->reductions->count == PERMA_MAX_REDUCTIONS)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_declare_reduction('%s'): more than %d reductions", n,
                               PERMA_MAX_REDUCTIONS);
    perma_reduction *r = &rt->reductions->list[rt->reductions->count];
    memset(r, 0, sizeof *r);
    r->name = strdup(name);
    if (!r->name)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory declaring reduction '%s'", n);
    r->op = op;
    r->type = type;
    r->result = result;
    rt->reductions->count++;
    rt->reductions->valid = false;
    /* reduce_NAME() is part of the program: the next build generates it
     * again (perma_build_program releases the old program first). */
    rt->built = false;
    return PERMA_OK;
}

perma_status perma_declare_reduction(perma_runtime *rt, const char *name, perma_reduce_op op, perma_value_type type,
                                     void *result)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_declare_reduction", declare_reduction_call(rt, name, op, type, result));
}

static perma_status get_reduction_call(perma_runtime *rt, const char *name, perma_value_type type, void *out)
{
    perma_call_begin(rt, "perma_get_reduction", false);
    const char *n = name ? name : "(null)";
    perma_reduction *r = find(rt, name);
    if (!r)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_get_reduction: no reduction named '%s' is declared", n);
    if (type != r->type)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT,
                               "perma_get_reduction('%s'): the reduction is of type %s, not %s", n,
                               type_names[r->type], perma_value_type_name(type) ? perma_value_type_name(type) : "?");
    if (!out)
        return perma_set_error(rt, PERMA_ERR_ARGUMENT, "perma_get_reduction('%s'): out is NULL", n);
    if (!rt->reductions->valid)
        return perma_set_error(rt, PERMA_ERR_STATE,
                               "perma_get_reduction('%s'): no result: no run has succeeded since the reduction was "
                               "declared (or the last run failed)", n);
    memcpy(out, &r->value, type_bytes[type]);
    return PERMA_OK;
}

perma_status perma_get_reduction(perma_runtime *rt, const char *name, perma_value_type type, void *out)
{
    PERMA_EXCLUSIVE_CALL(rt, "perma_get_reduction", get_reduction_call(rt, name, type, out));
}

void perma_reductions_release(perma_runtime *rt)
{
    if (!rt->reductions)
        return;
    for (unsigned i = 0; i < rt->reductions->count; ++i)
        free(rt->reductions->list[i].name);
    free(rt->reductions);
    rt->reductions = NULL;
}

static void lane_layout(perma_runtime *rt)
{
    unsigned offset = 0;
    for (unsigned i = 0; i < rt->reductions->count; ++i) {
        perma_reduction *r = &rt->reductions->list[i];
        r->offset = offset;
        r->words = lane_words(r);
        offset += r->words;
    }
    rt->build.reduce_words = offset;
}

static void append_constants(const perma_runtime *rt, perma_strbuf *sb)
{
    bool doubles = false;
    for (unsigned i = 0; i < rt->reductions->count; ++i)
        doubles = doubles || rt->reductions->list[i].type == PERMA_TYPE_DOUBLE;
    perma_strbuf_printf(sb, "#define PERMA_NUM_REDUCTIONS %uu\n#define PERMA_REDUCE_WORDS %uu\n%s",
                        rt->reductions->count, rt->build.reduce_words ? rt->build.reduce_words : 1u,
                        doubles ? "#define PERMA_REDUCE_DOUBLE 1\n" : "");
}

/* The OpenCL C name of the order key of a value of `type` (min, max). */
static const char *key_function(perma_value_type type)
{
    static const char *const keys[] = { "(ulong)", "perma_key_int", "", "perma_key_long", "perma_key_float",
                                        "perma_key_double" };
    return keys[type];
}

/* A NaN test for min and max of floats, which ignore NaN: on the bits, so
 * that relaxed-math options cannot drop it. */
static const char *nan_test(perma_value_type type)
{
    return type == PERMA_TYPE_FLOAT    ? "    if ((as_uint(value) & 0x7fffffffu) > 0x7f800000u)\n        return;\n"
           : type == PERMA_TYPE_DOUBLE ? "    if ((as_ulong(value) & 0x7ffffffffffffffful) > 0x7ff0000000000000ul)\n"
                                         "        return;\n"
                                       : "";
}

/* The identity of a reduction as its lane's first word (the rest: 0). */
static uint64_t identity(const perma_reduction *r)
{
    static const uint64_t min_identity[] = { UINT32_MAX, UINT32_MAX, UINT64_MAX, UINT64_MAX,
                                             0xff800000u /* key of +inf */, 0xfff0000000000000u };
    static const uint64_t max_identity[] = { 0, 0, 0, 0, 0x007fffffu /* key of -inf */, 0x000fffffffffffffu };
    return r->op == PERMA_REDUCE_MIN ? min_identity[r->type] : r->op == PERMA_REDUCE_MAX ? max_identity[r->type] : 0;
}

static void append_helpers(const perma_runtime *rt, perma_strbuf *sb)
{
    for (unsigned i = 0; i < rt->reductions->count; ++i) {
        const perma_reduction *r = &rt->reductions->list[i];
        const char *type = type_names[r->type];
        perma_strbuf_printf(sb, "inline void reduce_%s(perma_ctx *ctx, %s value)\n{\n    ulong *lane = ctx->reduce + %uu;\n",
                            r->name, type, r->offset);
        if (r->op == PERMA_REDUCE_SUM && is_float_type(r->type))
            perma_strbuf_printf(sb, "    perma_exact_add_%s(lane, value);\n", type);
        else if (r->op == PERMA_REDUCE_SUM)
            perma_strbuf_printf(sb, "    *lane += %s;\n", r->type == PERMA_TYPE_UINT ? "(ulong)value"
                                                         : r->type == PERMA_TYPE_INT ? "(ulong)as_uint(value)"
                                                                                      : "as_ulong(value)");
        else
            perma_strbuf_printf(sb, "%s    ulong key = %s(value);\n    if (key %s *lane)\n        *lane = key;\n",
                                nan_test(r->type), key_function(r->type), r->op == PERMA_REDUCE_MIN ? "<" : ">");
        perma_strbuf_append(sb, "}\n");
    }
    /* The lane's identities, and its fold into a slot. */
    perma_strbuf_append(sb, "inline void perma_reduce_init(ulong *lane)\n{\n");
    for (unsigned i = 0; i < rt->reductions->count; ++i) {
        const perma_reduction *r = &rt->reductions->list[i];
        perma_strbuf_printf(sb, "    lane[%u] = 0x%llxul;\n", r->offset, (unsigned long long)identity(r));
        if (r->words > 1)
            perma_strbuf_printf(sb, "    for (uint i = 1; i < %uu; ++i)\n        lane[%u + i] = 0;\n", r->words,
                                r->offset);
    }
    perma_strbuf_append(sb, "}\ninline void perma_reduce_fold(__global ulong *slot, ulong *lane)\n{\n");
    for (unsigned i = 0; i < rt->reductions->count; ++i) {
        const perma_reduction *r = &rt->reductions->list[i];
        unsigned o = r->offset;
        if (r->words > 1)
            perma_strbuf_printf(sb, "    perma_exact_fold(slot + %u, lane + %u, %uu);\n", o, o, r->words - 1);
        else if (r->op == PERMA_REDUCE_SUM)
            perma_strbuf_printf(sb, "    slot[%u] += lane[%u];\n", o, o);
        else
            perma_strbuf_printf(sb, "    slot[%u] = %s(slot[%u], lane[%u]);\n", o,
                                r->op == PERMA_REDUCE_MIN ? "min" : "max", o, o);
    }
    perma_strbuf_append(sb, "}\n");
}

void perma_reductions_generate(perma_runtime *rt, perma_strbuf *constants, perma_strbuf *helpers)
{
    lane_layout(rt);
    append_constants(rt, constants);
    append_helpers(rt, helpers);
}

/* Words of the reductions buffer: one lane per work-item of every group. */
static size_t slot_count(const perma_runtime *rt)
{
    return (size_t)rt->work_groups * rt->group_size;
}

perma_status perma_reductions_identities(perma_runtime *rt, uint64_t **out, size_t *out_words)
{
    *out = NULL;
    *out_words = 0;
    if (!rt->reductions->count)
        return PERMA_OK;
    size_t words = slot_count(rt) * rt->build.reduce_words;
    uint64_t *slots = calloc(words, sizeof *slots);
    if (!slots)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the reductions");
    for (size_t s = 0; s < slot_count(rt); ++s)
        for (unsigned i = 0; i < rt->reductions->count; ++i)
            slots[s * rt->build.reduce_words + rt->reductions->list[i].offset] = identity(&rt->reductions->list[i]);
    *out = slots;
    *out_words = words;
    return PERMA_OK;
}

/* The value an order key stands for (perma_key_* in kernels/perma_reduce.cl). */
static void decode_key(perma_reduction *r, uint64_t key)
{
    uint32_t k32 = (uint32_t)key;
    switch (r->type) {
    case PERMA_TYPE_UINT: r->value.u = k32; break;
    case PERMA_TYPE_INT: r->value.u = k32 ^ 0x80000000u; break;
    case PERMA_TYPE_ULONG: r->value.ul = key; break;
    case PERMA_TYPE_LONG: r->value.ul = key ^ 0x8000000000000000u; break;
    case PERMA_TYPE_FLOAT: {
        uint32_t bits = k32 >> 31 ? k32 ^ 0x80000000u : ~k32;
        memcpy(&r->value.f, &bits, sizeof bits);
        break;
    }
    case PERMA_TYPE_DOUBLE: {
        uint64_t bits = key >> 63 ? key ^ 0x8000000000000000u : ~key;
        memcpy(&r->value.d, &bits, sizeof bits);
        break;
    }
    }
}

/* Combine reduction r over every slot. */
static void combine(perma_reduction *r, const uint64_t *slots, size_t count, unsigned stride)
{
    if (r->words > 1) {
        perma_exact_total total;
        memset(&total, 0, sizeof total);
        for (size_t s = 0; s < count; ++s)
            perma_exact_total_add(&total, slots + s * stride + r->offset, r->words - 1);
        if (r->type == PERMA_TYPE_FLOAT)
            r->value.f = perma_exact_total_float(&total);
        else
            r->value.d = perma_exact_total_double(&total);
        return;
    }
    uint64_t v = identity(r);
    for (size_t s = 0; s < count; ++s) {
        uint64_t w = slots[s * stride + r->offset];
        v = r->op == PERMA_REDUCE_SUM ? v + w : r->op == PERMA_REDUCE_MIN ? (w < v ? w : v) : (w > v ? w : v);
    }
    if (r->op != PERMA_REDUCE_SUM)
        decode_key(r, v);
    else if (r->type == PERMA_TYPE_UINT || r->type == PERMA_TYPE_INT)
        r->value.u = (uint32_t)v; /* modulo 2^32 */
    else
        r->value.ul = v;
}

perma_status perma_reductions_collect(perma_runtime *rt)
{
    rt->reductions->valid = false;
    if (!rt->reductions->count)
        return PERMA_OK;
    size_t words = slot_count(rt) * rt->build.reduce_words;
    uint64_t *slots = malloc(words * sizeof *slots);
    if (!slots)
        return perma_set_error(rt, PERMA_ERR_NO_MEMORY, "out of memory for the reductions");
    perma_status st = perma_state_read_reductions(rt, slots, words);
    if (st != PERMA_OK) {
        free(slots);
        return st;
    }
    for (unsigned i = 0; i < rt->reductions->count; ++i) {
        perma_reduction *r = &rt->reductions->list[i];
        combine(r, slots, slot_count(rt), rt->build.reduce_words);
        if (r->result)
            memcpy(r->result, &r->value, type_bytes[r->type]);
    }
    free(slots);
    rt->reductions->valid = true;
    return PERMA_OK;
}

void perma_reductions_invalidate(perma_runtime *rt)
{
    rt->reductions->valid = false;
}
