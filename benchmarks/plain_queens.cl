/* N-Queens, one partial board per item (perma-bench plain,
 * benchmarks/plain_queens.c).  The host defines QUEENS_N and
 * QUEENS_CUTOFF in front of this source: a board with QUEENS_CUTOFF queens
 * is solved inside its item, boards with fewer emit a child per free
 * column. */

/* The one place this workload adds to its results: a reduction; with
 * --count atomic a global atomic, all groups on one word. */
void queens_count(perma_ctx *ctx, uint solutions)
{
#ifndef PLAIN_COUNT_ATOMIC
    reduce_queens_solutions(ctx, solutions);
#else
    atom_add(&ctx->buf.queens_solutions[0], (ulong)solutions);
#endif
}

void queens(perma_ctx *ctx, __local const struct queens_board *b)
{
    if (b->row >= QUEENS_CUTOFF) {
        queens_count(ctx, queens_solve(QUEENS_N, b->row, b->columns, b->left, b->right));
        return;
    }
    uint free = queens_free(QUEENS_N, b->columns, b->left, b->right);
    while (free) {
        uint bit = free & (0u - free);
        free ^= bit;
        struct queens_board next = queens_place(QUEENS_N, b->row, b->columns, b->left, b->right, bit);
        emit_queens(ctx, &next);
    }
}
