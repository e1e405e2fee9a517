"""Struct items with float64 fields arrive as they were emitted: a procedure
that fills one item, emits it, changes a field and emits it again (the
pattern of docs/writing-procedures.md) gets every change, on a runtime of
its own (one procedure per program, where PoCL once moved the emit's copy
ahead of the stores)."""
import numpy as np

import perma

CELL = np.dtype([('x', np.float64), ('y', np.float64), ('h', np.float64),
                 ('depth', np.uint32), ('id', np.uint32)], align=True)
DEPTH = 3

QUARTER = """
// A square cell [x, x + h) x [y, y + h) split into four, DEPTH levels
// deep; each leaf writes itself to leaves[id].
void quarter(perma_ctx *ctx, __local const struct cell *c)
{
    double x0 = c->x, y0 = c->y, m = 0.5 * c->h;
    if (c->depth == %du) {
        ctx->buf.leaves[c->id] = *c;
        return;
    }
    struct cell k = { x0, y0, m, c->depth + 1u, 4u * c->id };
    emit_quarter(ctx, &k);
    k.x = x0 + m; k.id += 1u; emit_quarter(ctx, &k);
    k.y = y0 + m; k.id += 1u; emit_quarter(ctx, &k);
    k.x = x0;     k.id += 1u; emit_quarter(ctx, &k);
}
""" % DEPTH


def expected_leaves():
    out = np.zeros(4 ** DEPTH, CELL)

    def visit(x, y, h, depth, ident):
        if depth == DEPTH:
            out[ident] = (x, y, h, depth, ident)
            return
        m = 0.5 * h
        for k, (cx, cy) in enumerate([(x, y), (x + m, y), (x + m, y + m), (x, y + m)]):
            visit(cx, cy, m, depth + 1, 4 * ident + k)

    visit(0.0, 0.0, 1.0, 0, 0)
    return out


def test_float64_fields_changed_between_emits_arrive_changed():
    with perma.Runtime() as rt:
        rt.add_source('#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n', 'fp64.cl')
        rt.add_type('cell', CELL)
        quarter = rt.register('quarter', QUARTER, item=CELL, emits={'quarter': 4})
        leaves = np.zeros(4 ** DEPTH, CELL)
        rt.bind('leaves', leaves, access='write')
        rt.seed(quarter, np.array([(0.0, 0.0, 1.0, 0, 0)], CELL))
        rt.run()
    want = expected_leaves()
    assert leaves.tobytes() == want.tobytes(), (leaves[:4], want[:4])
    # The leaves tile the unit square: x + 10 y summed as in the report.
    assert float(np.sum(leaves['x'] + 10 * leaves['y'])) == float(np.sum(want['x'] + 10 * want['y']))
