/*
 * Reductions (perma_declare_reduction): every work-item keeps a private
 * lane of each declared reduction, a few 64-bit words, which reduce_NAME()
 * updates without atomics or barriers; at the end of a launch each
 * work-item folds its lane into its own slot of the reductions buffer
 * (plain loads and stores: nobody else touches the slot, and launches run
 * one after another), and the host combines the slots after the run
 * (runtime/src/reductions.c).  So a reduction costs no global atomic and
 * no barrier per call, and the result does not depend on which work-item
 * ran which item.
 *
 *   sum of uint, int, ulong, long   one word, added modulo 2^64 (the host
 *                                   keeps the low 32 bits for uint and int:
 *                                   the sum modulo 2^32, two's complement)
 *   min, max of every type          one word holding an order key of the
 *                                   value (perma_key_*: unsigned order =
 *                                   value order); NaN is ignored
 *   sum of float, double            an exact fixed-point accumulator of
 *                                   PERMA_EXACT_FLOAT_WORDS or
 *                                   PERMA_EXACT_DOUBLE_WORDS words: the
 *                                   host rounds the exact sum once, so the
 *                                   result has the same bits whatever the
 *                                   order, schedule or device
 *
 * The exact accumulator is a big integer in units of the type's smallest
 * subnormal (2^-149, 2^-1074), in digits of 32 bits kept in signed 64-bit
 * words (digit i weighs 2^(32 i)): an add touches two or three digits by
 * less than 2^33 each, so a digit overflows only after 2^30 adds; the lane
 * propagates its carries every PERMA_EXACT_NORMALIZE adds and before it is
 * folded.  Its last word counts the adds since then (low 32 bits) and
 * holds the infinities and NaNs seen (PERMA_EXACT_*_SEEN, high bits).
 */

/* A kernel's lane: declared and set to the identities at its start, folded
 * into the work-item's slot at its end (perma_reduce_init and
 * perma_reduce_fold are generated, runtime/src/reductions.c).  Without
 * reductions, nothing. */
#if PERMA_NUM_REDUCTIONS
#define PERMA_LANE_BEGIN(lane)              \
    ulong lane[PERMA_REDUCE_WORDS];         \
    perma_reduce_init(lane)
#define PERMA_LANE_END(lane, reductions)                                                                 \
    perma_reduce_fold((reductions) + (get_group_id(0) * PERMA_GROUP_SIZE + get_local_id(0)) * PERMA_REDUCE_WORDS, \
                      lane)
#else
#define PERMA_LANE_BEGIN(lane) ulong *lane = 0
#define PERMA_LANE_END(lane, reductions) (void)(reductions)
#endif

/* PERMA_EXACT_FLOAT_DIGITS, PERMA_EXACT_DOUBLE_DIGITS and the flags:
 * kernels/perma_abi.h.  Adds between two normalizations of a lane. */
#define PERMA_EXACT_NORMALIZE (1u << 29)

/* Propagate the carries of digits[0 .. n-1]: every digit but the last in
 * [0, 2^32), the last signed. */
inline void perma_exact_normalize(ulong *digits, uint n)
{
    for (uint i = 0; i + 1u < n; ++i) {
        long d = (long)digits[i];
        long carry = d >> 32; /* arithmetic: floor(d / 2^32) */
        digits[i] = (ulong)(d - (carry << 32));
        digits[i + 1u] = (ulong)((long)digits[i + 1u] + carry);
    }
}

/* Add (or, negative, subtract) the integer m << shift at digit d. */
inline void perma_exact_add_bits(ulong *digits, uint n, uint d, uint shift, ulong m, int negative)
{
    ulong lo = (m & 0xfffffffful) << shift, hi = (m >> 32) << shift;
    long d0 = (long)(lo & 0xfffffffful), d1 = (long)((lo >> 32) + (hi & 0xfffffffful)), d2 = (long)(hi >> 32);
    if (negative) {
        d0 = -d0;
        d1 = -d1;
        d2 = -d2;
    }
    digits[d] = (ulong)((long)digits[d] + d0);
    if (d + 1u < n)
        digits[d + 1u] = (ulong)((long)digits[d + 1u] + d1);
    if (d + 2u < n)
        digits[d + 2u] = (ulong)((long)digits[d + 2u] + d2);
}

/* Count one add in the control word; normalize before a digit could
 * overflow. */
inline void perma_exact_count(ulong *digits, uint n)
{
    ulong control = digits[n] + 1ul;
    if ((uint)control >= PERMA_EXACT_NORMALIZE) {
        perma_exact_normalize(digits, n);
        control &= ~0xfffffffful;
    }
    digits[n] = control;
}

/* Add float v exactly: digits (PERMA_EXACT_FLOAT_DIGITS) then the control
 * word. */
inline void perma_exact_add_float(ulong *acc, float v)
{
    uint bits = as_uint(v), exponent = (bits >> 23) & 0xffu;
    ulong mantissa = bits & 0x7fffffu;
    if (exponent == 0xffu) {
        acc[PERMA_EXACT_FLOAT_DIGITS] |= mantissa ? PERMA_EXACT_NAN_SEEN
                                       : bits >> 31 ? PERMA_EXACT_NEG_INF_SEEN : PERMA_EXACT_POS_INF_SEEN;
        return;
    }
    if (exponent)
        mantissa |= 0x800000u;
    else
        exponent = 1u; /* subnormal: the same unit as exponent 1 */
    uint p = exponent - 1u; /* the mantissa's unit is 2^(p - 149) */
    perma_exact_add_bits(acc, PERMA_EXACT_FLOAT_DIGITS, p >> 5, p & 31u, mantissa, (int)(bits >> 31));
    perma_exact_count(acc, PERMA_EXACT_FLOAT_DIGITS);
}

/* Fold a lane's exact accumulator (n digits and the control word) into a
 * slot of the reductions buffer; the lane is normalized first, so a slot's
 * digit grows by less than 2^32 per launch. */
inline void perma_exact_fold(__global ulong *slot, ulong *acc, uint n)
{
    perma_exact_normalize(acc, n);
    for (uint i = 0; i < n; ++i)
        slot[i] = (ulong)((long)slot[i] + (long)acc[i]);
    slot[n] |= acc[n] & ~0xfffffffful;
}

/* Order keys for min and max: unsigned comparison of the keys orders the
 * values (-0.0 below +0.0 for floats). */
inline ulong perma_key_int(int v) { return (ulong)(as_uint(v) ^ 0x80000000u); }
inline ulong perma_key_long(long v) { return as_ulong(v) ^ 0x8000000000000000ul; }
inline ulong perma_key_float(float v)
{
    uint bits = as_uint(v);
    return (ulong)(bits ^ (bits >> 31 ? 0xffffffffu : 0x80000000u));
}

#ifdef PERMA_REDUCE_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
/* Add double v exactly: digits (PERMA_EXACT_DOUBLE_DIGITS) then the
 * control word. */
inline void perma_exact_add_double(ulong *acc, double v)
{
    ulong bits = as_ulong(v);
    uint exponent = (uint)(bits >> 52) & 0x7ffu;
    ulong mantissa = bits & 0xffffffffffffful;
    if (exponent == 0x7ffu) {
        acc[PERMA_EXACT_DOUBLE_DIGITS] |= mantissa ? PERMA_EXACT_NAN_SEEN
                                        : bits >> 63 ? PERMA_EXACT_NEG_INF_SEEN : PERMA_EXACT_POS_INF_SEEN;
        return;
    }
    if (exponent)
        mantissa |= 0x10000000000000ul;
    else
        exponent = 1u;
    uint p = exponent - 1u; /* the mantissa's unit is 2^(p - 1074) */
    perma_exact_add_bits(acc, PERMA_EXACT_DOUBLE_DIGITS, p >> 5, p & 31u, mantissa, (int)(bits >> 63));
    perma_exact_count(acc, PERMA_EXACT_DOUBLE_DIGITS);
}

inline ulong perma_key_double(double v)
{
    ulong bits = as_ulong(v);
    return bits ^ (bits >> 63 ? 0xfffffffffffffffful : 0x8000000000000000ul);
}
#endif
