/* Adaptive Simpson integration, one interval per item (perma-bench plain,
 * benchmarks/plain_simpson.c).  The host defines SIMPSON_MAX_DEPTH in
 * front of this source. */

#ifdef PLAIN_COUNT_ATOMIC
/* OpenCL 1.2 has no atomic add on double: the usual compare-and-swap loop. */
void simpson_atomic_add(volatile __global double *sum, double value)
{
    volatile __global ulong *bits = (volatile __global ulong *)sum;
    ulong seen = *bits, old;
    do {
        old = seen;
        seen = atom_cmpxchg(bits, old, as_ulong(as_double(old) + value));
    } while (seen != old);
}
#endif

/* The one place this workload adds to its results: the accepted intervals,
 * the sum of their areas and, as an exact check that every accepted area
 * is bit for bit the sequential one, the sum of their bit patterns; three
 * reductions.  With --count atomic global atomics, all groups on one word. */
void simpson_count(perma_ctx *ctx, double area)
{
#ifndef PLAIN_COUNT_ATOMIC
    reduce_simpson_accepted(ctx, 1);
    reduce_simpson_area(ctx, area);
    reduce_simpson_area_bits(ctx, as_ulong(area));
#else
    atom_inc(&ctx->buf.simpson_accepted[0]);
    simpson_atomic_add(&ctx->buf.simpson_area[0], area);
    atom_add(&ctx->buf.simpson_area_bits[0], as_ulong(area));
#endif
}

void simpson(perma_ctx *ctx, __local const struct simpson_interval *s)
{
    double area;
    struct simpson_interval halves[2];
    if (simpson_step(s->a, s->b, s->fa, s->fm, s->fb, s->whole, s->eps, s->depth, SIMPSON_MAX_DEPTH, &area,
                     halves)) {
        simpson_count(ctx, area);
        return;
    }
    emit_simpson(ctx, &halves[0]);
    emit_simpson(ctx, &halves[1]);
}
