/* The one-item work of perma-dispatch-shapes, written once in the common
 * subset of C and OpenCL C (after benchmarks/plain_work.h): the host checks
 * the device's results with the same functions. */
#ifndef DISPATCH_SHAPES_WORK_H
#define DISPATCH_SHAPES_WORK_H

/* Two hashes of the key (a UTS node's work). */
PLAIN_FN ulong shapes_item(ulong key) { return splitmix64(key) ^ splitmix64(key + 1u); }

/* A loop whose trip count differs per item: 0-7 hashes. */
PLAIN_FN ulong shapes_item_loop(ulong key)
{
    uint k = (uint)(splitmix64(key) & 7u);
    ulong acc = 0;
    for (uint i = 0; i < k; ++i)
        acc ^= splitmix64(key + i);
    return acc;
}

PLAIN_FN ulong shapes_bits(double d)
{
    union { double d; ulong u; } x;
    x.d = d;
    return x.u;
}

/* An adaptive Simpson step's shape: evaluations of the integrand (floor,
 * divisions), one of two results. */
PLAIN_FN ulong shapes_item_double(ulong key)
{
    double a = (double)(key & 0xffffffu) * 0x1p-24, b = a + 0x1p-20, m = 0.5 * (a + b);
    double fa = simpson_f(a), fm = simpson_f(m), fb = simpson_f(b);
    double whole = simpson_rule(a, b, fa, fm, fb), left = simpson_rule(a, m, fa, simpson_f(0.5 * (a + m)), fm);
    return left * 2.0 <= whole ? shapes_bits(left) : shapes_bits(whole);
}

#endif
