/* The host's half of the exact float and double sums (kernels/perma_reduce.cl):
 * adding the slots' fixed-point digits into one total and rounding the
 * total once, to nearest with ties to even, so a float or double sum does
 * not depend on the order its values were added in.
 *
 * A total is an integer in units of the type's smallest subnormal (2^-149
 * or 2^-1074), in digits of 32 bits (digit i weighs 2^(32 i)) kept in
 * signed 64-bit words.  A slot's digits are below 2^32 per launch that
 * folded into it; each is normalized before it is added, so a total's
 * digit stays below 2^32 times the number of slots. */
#include "reductions.h"

#include <float.h>
#include <math.h>

/* Propagate carries: every digit but the last in [0, 2^32), the last
 * signed. */
static void normalize(int64_t *digits, unsigned n)
{
    for (unsigned i = 0; i + 1 < n; ++i) {
        int64_t carry = digits[i] >> 32; /* arithmetic shift: floor division */
        digits[i] -= carry * ((int64_t)1 << 32);
        digits[i + 1] += carry;
    }
}

void perma_exact_total_add(perma_exact_total *total, const uint64_t *slot, unsigned digits)
{
    int64_t lane[PERMA_EXACT_DOUBLE_DIGITS];
    for (unsigned i = 0; i < digits; ++i)
        lane[i] = (int64_t)slot[i];
    normalize(lane, digits);
    for (unsigned i = 0; i < digits; ++i)
        total->digits[i] += lane[i];
    total->flags |= slot[digits] & (PERMA_EXACT_POS_INF_SEEN | PERMA_EXACT_NEG_INF_SEEN | PERMA_EXACT_NAN_SEEN);
}

/* Bit b of a normalized, non-negative total. */
static unsigned bit_at(const int64_t *digits, unsigned b)
{
    return (unsigned)((uint64_t)digits[b / 32] >> (b % 32)) & 1u;
}

/* Whether any bit below b is set. */
static bool any_below(const int64_t *digits, unsigned b)
{
    for (unsigned i = 0; i < b / 32; ++i)
        if (digits[i])
            return true;
    return b % 32 && ((uint64_t)digits[b / 32] & (((uint64_t)1 << (b % 32)) - 1)) != 0;
}

/* Round the total to `precision` significant bits (24 or 53) and return
 * it as a double in units of 2^`unit_exponent` (-149 or -1074), the sign
 * apart: the exact value if it has at most `precision` bits above the
 * smallest subnormal, else rounded to nearest, ties to even. */
static double round_total(perma_exact_total *total, unsigned n, unsigned precision, int unit_exponent, bool *negative)
{
    int64_t *d = total->digits;
    normalize(d, n);
    *negative = d[n - 1] < 0;
    if (*negative) { /* negate, then normalize: the magnitude */
        for (unsigned i = 0; i < n; ++i)
            d[i] = -d[i];
        normalize(d, n);
    }
    int top = -1; /* the highest set bit */
    for (int i = (int)n - 1; i >= 0 && top < 0; --i)
        if (d[i])
            for (int b = 63; b >= 0 && top < 0; --b)
                if ((uint64_t)d[i] >> b & 1u)
                    top = 32 * i + b;
    if (top < 0)
        return 0.0;
    /* The bits kept: [low, top], at most `precision` of them (fewer never:
     * bits below the smallest subnormal do not exist). */
    unsigned low = top + 1 >= (int)precision ? (unsigned)(top + 1 - (int)precision) : 0u;
    uint64_t kept = 0;
    for (int b = top; b >= (int)low; --b)
        kept = kept << 1 | bit_at(d, (unsigned)b);
    if (low > 0) {
        unsigned half = bit_at(d, low - 1);
        bool rest = any_below(d, low - 1);
        if (half && (rest || (kept & 1u)))
            ++kept; /* may carry to 2^precision: still exact in a double */
    }
    return ldexp((double)kept, (int)low + unit_exponent);
}

/* The infinities and NaNs seen decide the result if there were any. */
static bool special(const perma_exact_total *total, double *out)
{
    bool pos = total->flags & PERMA_EXACT_POS_INF_SEEN, neg = total->flags & PERMA_EXACT_NEG_INF_SEEN;
    if ((total->flags & PERMA_EXACT_NAN_SEEN) || (pos && neg))
        *out = NAN;
    else if (pos || neg)
        *out = pos ? INFINITY : -INFINITY;
    else
        return false;
    return true;
}

double perma_exact_total_double(perma_exact_total *total)
{
    double v;
    if (special(total, &v))
        return v;
    bool negative;
    v = round_total(total, PERMA_EXACT_DOUBLE_DIGITS, 53, -1074, &negative);
    return negative ? -v : v;
}

float perma_exact_total_float(perma_exact_total *total)
{
    double v;
    if (special(total, &v))
        return (float)v;
    bool negative;
    v = round_total(total, PERMA_EXACT_FLOAT_DIGITS, 24, -149, &negative);
    /* v has at most 24 significant bits: exact in a float unless it is
     * beyond the float range, which the conversion makes infinite. */
    float f = v > FLT_MAX ? INFINITY : (float)v;
    return negative ? -f : f;
}
