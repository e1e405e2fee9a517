/* Typed host arrays (PERMA_BIND_HOST_ARRAY, PERMA_BIND_HOST_POINTER): the
 * OpenCL C type and the byte count come from the C declaration, double
 * precision and 64-bit atomics reach the device (the example of
 * docs/writing-procedures.md, section 12), and a struct the device lays out
 * otherwise fails the build naming the buffer.  The compile-time rejections
 * are tests/runtime/bind_types_compile.py. */
#include <stdint.h>

/* The struct types the program binds, named for the device (before perma.h). */
struct pair {
    int32_t key;
    float value;
};
#define PERMA_HOST_TYPE_NAMES struct pair: "struct pair",

#include "perma_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

START_TEST(c_types_map_to_opencl_names)
{
    ck_assert_str_eq(PERMA_CL_TYPE_NAME((int32_t)0), "int");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME((uint32_t)0), "uint");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME((int64_t)0), "long");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME((uint64_t)0), "ulong");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME((size_t)0), "ulong");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME((int8_t)0), "char");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME((uint8_t)0), "uchar");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME((int16_t)0), "short");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME((uint16_t)0), "ushort");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME(0.0f), "float");
    ck_assert_str_eq(PERMA_CL_TYPE_NAME(0.0), "double");
    const double constant = 1.0; /* qualifiers do not matter */
    ck_assert_str_eq(PERMA_CL_TYPE_NAME(constant), "double");
    cl_float4 f4 = { { 0 } };
    ck_assert_str_eq(PERMA_CL_TYPE_NAME(f4), "float4");
    cl_uint2 u2 = { { 0 } };
    ck_assert_str_eq(PERMA_CL_TYPE_NAME(u2), "uint2");
    struct pair p = { 0, 0 };
    ck_assert_str_eq(PERMA_CL_TYPE_NAME(p), "struct pair");
}
END_TEST

/* Double precision and 64-bit atomics: the pragmas, and what the device
 * must offer (perma-info: "double (cl_khr_fp64)", "64-bit base"). */
static const char *types_source =
    "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n"
    "#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable\n"
    "#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable\n"
    "struct pair { int key; float value; };\n";

static const char *weigh_source =
    "void weigh(perma_ctx *ctx, __local const uint *index)\n"
    "{\n"
    "    uint i = *index;\n"
    "    double w = ctx->buf.weights[i];                  /* double: cl_khr_fp64 */\n"
    "    ctx->buf.scaled[i] = w * ctx->buf.pairs[i].value;\n"
    "    atom_add(&ctx->buf.total[0], (long)ctx->buf.pairs[i].key * 1000000007L); /* 64-bit atomic */\n"
    "    atom_max(&ctx->buf.largest[0], ctx->buf.stamps[i]);     /* 64-bit extended atomic */\n"
    "    ctx->buf.bytes[i] = (uchar)(ctx->buf.pairs[i].key & 0xff);\n"
    "}\n";

#define COUNT 1000

static perma_runtime *weigh_runtime(perma_proc *id)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    ck_assert_perma_ok(rt, perma_add_source(rt, types_source, "types.cl"));
    perma_procedure weigh = { .name = "weigh", .item_type = "uint", .item_size = 4, .source = weigh_source,
                              .source_file = "weigh.cl", .function = "weigh" };
    ck_assert_perma_ok(rt, perma_register(rt, &weigh, id));
    return rt;
}

START_TEST(typed_arrays_reach_the_device)
{
    perma_proc id;
    perma_runtime *rt = weigh_runtime(&id);
    double weights[COUNT], scaled[COUNT];
    int64_t total[1] = { 0 };
    uint64_t stamps[COUNT], largest[1] = { 0 };
    uint8_t bytes[COUNT];
    struct pair *pairs = malloc(COUNT * sizeof *pairs);
    uint32_t indexes[COUNT];
    int64_t expected_total = 0;
    for (uint32_t i = 0; i < COUNT; ++i) {
        weights[i] = 1.0 + i * 1e-9; /* only double keeps the 1e-9 steps */
        pairs[i] = (struct pair){ (int32_t)i * 3 - 1000, 0.5f + (float)i };
        stamps[i] = ((uint64_t)i << 40) | 7u;
        indexes[i] = i;
        expected_total += (int64_t)pairs[i].key * 1000000007LL;
    }
    ck_assert_perma_ok(rt, PERMA_BIND_HOST_ARRAY(rt, "weights", weights, PERMA_READ));
    ck_assert_perma_ok(rt, PERMA_BIND_HOST_ARRAY(rt, "scaled", scaled, PERMA_WRITE));
    ck_assert_perma_ok(rt, PERMA_BIND_HOST_ARRAY(rt, "total", total, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, PERMA_BIND_HOST_ARRAY(rt, "stamps", stamps, PERMA_READ));
    ck_assert_perma_ok(rt, PERMA_BIND_HOST_ARRAY(rt, "largest", largest, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, PERMA_BIND_HOST_ARRAY(rt, "bytes", bytes, PERMA_WRITE));
    ck_assert_perma_ok(rt, PERMA_BIND_HOST_POINTER(rt, "pairs", pairs, COUNT, PERMA_READ));
    /* The types made: PERMA_READ alone is a const pointer, and a rebinding
     * must keep the type, so only the exact string is accepted. */
    ck_assert_int_eq(perma_bind_host(rt, "weights", "__global double *", weights, sizeof weights, PERMA_READ),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "was bound as '__global const double *'");
    ck_assert_perma_ok(rt, perma_bind_host(rt, "weights", "__global const double *", weights, sizeof weights,
                                           PERMA_READ));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "pairs", "__global const struct pair *", pairs,
                                           COUNT * sizeof *pairs, PERMA_READ));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "total", "__global long *", total, sizeof total, PERMA_READ_WRITE));

    ck_assert_perma_ok(rt, perma_seed(rt, id, indexes, COUNT));
    ck_assert_perma_ok(rt, perma_run(rt));
    for (uint32_t i = 0; i < COUNT; ++i) {
        double want = weights[i] * (double)pairs[i].value;
        ck_assert_msg(scaled[i] == want, "scaled[%u] = %.17g, expected %.17g", i, scaled[i], want);
        ck_assert_uint_eq(bytes[i], (uint8_t)(pairs[i].key & 0xff));
    }
    ck_assert_msg(total[0] == expected_total, "total %lld, expected %lld", (long long)total[0],
                  (long long)expected_total);
    ck_assert_uint_eq(largest[0], stamps[COUNT - 1]);
    free(pairs);
    perma_destroy(rt);
}
END_TEST

START_TEST(bad_typed_bindings_are_refused)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    float values[4] = { 0 };
    ck_assert_int_eq(perma_bind_host_array(rt, "v", NULL, values, 4, sizeof values[0], PERMA_READ),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "buffer 'v': element type '(null)' is not an OpenCL C type name");
    ck_assert_int_eq(perma_bind_host_array(rt, "v", "float *", values, 4, sizeof values[0], PERMA_READ),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "element type 'float *' is not an OpenCL C type name");
    ck_assert_int_eq(perma_bind_host_array(rt, "v", "float", values, 0, sizeof values[0], PERMA_READ),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "buffer 'v': 0 elements of 4 bytes is not a size");
    ck_assert_int_eq(perma_bind_host_array(rt, "v", "float", values, SIZE_MAX / 2, 4, PERMA_READ),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "is not a size");
    ck_assert_int_eq(perma_bind_host_array(rt, "v", "float", values, 4, sizeof values[0], 0), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "buffer 'v': flags 0 must be PERMA_READ, PERMA_WRITE or both");
    ck_assert_perma_ok(rt, PERMA_BIND_HOST_ARRAY(rt, "v", values, PERMA_READ_WRITE));
    double wider[4] = { 0 };
    ck_assert_perma_ok(rt, perma_bind_host_array(rt, "w", "struct blob", values, 2, 8, PERMA_READ_WRITE));
    ck_assert_int_eq(perma_bind_host_array(rt, "w", "struct blob", wider, 2, 16, PERMA_READ_WRITE),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "buffer 'w' was bound with elements of 8 bytes and cannot be rebound with 16");
    perma_destroy(rt);
}
END_TEST

/* The device's struct pair has a third member: 12 bytes there, 8 here. */
START_TEST(element_size_differing_on_the_device_fails_the_build)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    ck_assert_perma_ok(rt, perma_add_source(rt, "struct pair { int key; float value; float extra; };", "types.cl"));
    perma_procedure p = { .name = "noop", .item_type = "uint", .item_size = 4,
                          .source = "void noop(perma_ctx *c, __local const uint *x) { (void)c; (void)x; }\n",
                          .function = "noop" };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    struct pair pairs[3] = { { 0, 0 } };
    ck_assert_perma_ok(rt, PERMA_BIND_HOST_ARRAY(rt, "pairs", pairs, PERMA_READ));
    ck_assert_int_eq(perma_build(rt), PERMA_ERR_BUILD);
    ck_assert_contains(perma_errmsg(rt), "buffer 'pairs': its host elements are 8 bytes (PERMA_BIND_HOST_ARRAY), "
                                         "but sizeof(struct pair) is 12 bytes on the device");
    perma_destroy(rt);
}
END_TEST

/* The element type a binding names against the host's sizes, where the
 * runtime knows the type's size (the built-in scalars and vectors): a
 * byte count that is no whole number of elements, typed elements of
 * another size (they were accepted, and the device read and wrote past
 * the end). */
START_TEST(element_types_are_checked_against_the_sizes)
{
    perma_runtime *rt = test_runtime(64, 0, 0);
    uint8_t bytes[6] = { 0 };
    ck_assert_int_eq(perma_bind_host(rt, "b", "__global uint *", bytes, sizeof bytes, PERMA_READ_WRITE),
                     PERMA_ERR_ARGUMENT);
    ck_assert_str_eq(perma_errmsg(rt), "buffer 'b': 6 bytes is not a whole number of 'uint' elements (4 bytes "
                                       "each), which type '__global uint *' points to");
    ck_assert_int_eq(perma_bind_host(rt, "b", "__global const unsigned short *", bytes, 5, PERMA_READ),
                     PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "5 bytes is not a whole number of 'ushort' elements (2 bytes each)");
    ck_assert_int_eq(perma_bind_host(rt, "b", "__global float3 *", bytes, 4, PERMA_READ), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "'float3' elements (16 bytes each)");
    ck_assert_int_eq(perma_bind_host_array(rt, "b", "uint", bytes, 4, 1, PERMA_READ_WRITE), PERMA_ERR_ARGUMENT);
    ck_assert_str_eq(perma_errmsg(rt), "buffer 'b': element type 'uint' is 4 bytes on the device, but the host's "
                                       "elements are 1 bytes");
    ck_assert_int_eq(perma_bind_host_array(rt, "b", "double", bytes, 1, 4, PERMA_READ), PERMA_ERR_ARGUMENT);
    ck_assert_contains(perma_errmsg(rt), "element type 'double' is 8 bytes on the device");
    /* Whole elements, and types whose size only the device knows, pass. */
    ck_assert_perma_ok(rt, perma_bind_host(rt, "b", "__global uchar *", bytes, sizeof bytes, PERMA_READ_WRITE));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "c", "__global const struct thing *", bytes, 6, PERMA_READ));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "d", "__global ushort *", bytes, 6, PERMA_READ));
    perma_destroy(rt);
}
END_TEST

/* A procedure that writes `over` elements past the end of its buffer of
 * 16 uints. */
static perma_status run_writing_past(unsigned over, uint32_t out[16], perma_runtime **rt_out)
{
    setenv("PERMA_CHECK_BOUNDS", "1", 1);
    perma_runtime *rt = test_runtime(64, 0, 0);
    unsetenv("PERMA_CHECK_BOUNDS");
    char source[512];
    snprintf(source, sizeof source,
             "void fill(perma_ctx *ctx, __local const uint *i)\n"
             "{\n"
             "    for (uint k = 0; k < 16u + %uu; ++k)\n"
             "        ctx->buf.out[k] = *i + k;\n"
             "}\n", over);
    perma_procedure p = { .name = "fill", .item_type = "uint", .item_size = 4, .source = source,
                          .source_file = "fill.cl", .function = "fill" };
    perma_proc id;
    ck_assert_perma_ok(rt, perma_register(rt, &p, &id));
    ck_assert_perma_ok(rt, perma_bind_host(rt, "out", "__global uint *", out, 16 * sizeof *out, PERMA_READ_WRITE));
    uint32_t seed = 100;
    ck_assert_perma_ok(rt, perma_seed(rt, id, &seed, 1));
    *rt_out = rt;
    return perma_run(rt);
}

/* PERMA_CHECK_BOUNDS=1: guard words after every host buffer, checked
 * after the run; a write past the end fails the run naming the buffer
 * (it returned PERMA_OK and the process crashed later), one within the
 * bounds runs exactly as without the check. */
START_TEST(checked_bounds_name_the_buffer_written_past)
{
    uint32_t out[16] = { 0 };
    perma_runtime *rt;
    ck_assert_int_eq(run_writing_past(3, out, &rt), PERMA_ERR_DEVICE);
    ck_assert_str_eq(perma_errmsg(rt), "buffer 'out' (64 bytes): a procedure wrote past its end: 3 of the 1024 guard "
                                       "words after it changed, the first at byte 64 (element type '__global uint "
                                       "*'; PERMA_CHECK_BOUNDS)");
    perma_destroy(rt);
    ck_assert_perma_ok(NULL, run_writing_past(0, out, &rt));
    for (uint32_t k = 0; k < 16; ++k)
        ck_assert_uint_eq(out[k], 100 + k);
    perma_destroy(rt);
}
END_TEST

int main(void)
{
    Suite *s = suite_create("bind");
    TCase *tc = tcase_create("bind");
    tcase_set_timeout(tc, PERMA_TEST_TIMEOUT);
    tcase_add_test(tc, c_types_map_to_opencl_names);
    tcase_add_test(tc, typed_arrays_reach_the_device);
    tcase_add_test(tc, bad_typed_bindings_are_refused);
    tcase_add_test(tc, element_size_differing_on_the_device_fails_the_build);
    tcase_add_test(tc, element_types_are_checked_against_the_sizes);
    tcase_add_test(tc, checked_bounds_name_the_buffer_written_past);
    suite_add_tcase(s, tc);
    return test_run_suite(s) ? EXIT_FAILURE : EXIT_SUCCESS;
}
