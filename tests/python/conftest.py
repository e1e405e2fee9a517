"""Fixtures of the Python binding's tests: one set of procedures, built once.

Every test that runs work uses the runtime of `workloads` (or one made by
`make_workloads` with other options: the same program, so perma's program
cache makes it cheap), because PoCL takes seconds to compile a megakernel.
"""
import os

import numpy as np
import pytest

import perma

NODE = np.dtype([('depth', np.uint32), ('id', np.uint32)])
# Fields of every size, a nested struct in an array, padding: laid out as OpenCL C does.
MIX = np.dtype([('index', np.uint32), ('flag', np.uint8), ('value', np.float64),
                ('pair', [('x', np.int16), ('y', np.uint8, (3,))], (2,)), ('big', np.int64),
                ('f', np.float32, (3,))], align=True)
MAX_DEPTH = 12

SPLIT = """
// A binary tree: a node of depth d > 0 has two children of depth d - 1;
// every node adds weights[depth] to weight_sum, every leaf counts itself and
// writes its id + 1 to leaf_ids[id].  The reductions: nodes (ulong sum),
// deepest (uint max), last_id (int min of -id), weight (double sum).
void split(perma_ctx *ctx, __local const struct node *n)
{
    atomic_add(&ctx->buf.weight_sum[0], ctx->buf.weights[n->depth]);
    reduce_nodes(ctx, 1ul);
    reduce_deepest(ctx, n->depth);
    reduce_last_id(ctx, -(int)n->id);
    reduce_weight(ctx, 0.5 * ctx->buf.weights[n->depth]);
    if (n->depth == 0u) {
        atomic_inc(&ctx->buf.leaves[0]);
        ctx->buf.leaf_ids[n->id] = n->id + 1u;
        return;
    }
    struct node child = { n->depth - 1u, 2u * n->id };
    emit_split(ctx, &child);
    child.id += 1u;
    emit_split(ctx, &child);
}
"""
GREEDY = """
// Emits n->depth items into split, but declares at most 1.
void greedy(perma_ctx *ctx, __local const struct node *n)
{
    struct node leaf = { 0u, 0u };
    for (uint i = 0u; i < n->depth; ++i)
        emit_split(ctx, &leaf);
}
"""
COUNTDOWN = """
// A chain of n->depth items, one after another, through the queues (queue_only).
void countdown(perma_ctx *ctx, __local const struct node *n)
{
    if (n->depth == 0u)
        return;
    struct node next = { n->depth - 1u, n->id };
    emit_countdown(ctx, &next);
}
"""
COPY = """
// Copies its item to copies[index].
void copy(perma_ctx *ctx, __local const struct mix *m)
{
    ctx->buf.copies[m->index] = *m;
}
"""


class Workloads:
    """A runtime with the procedures above and their buffers bound."""

    def __init__(self, **options):
        self.rt = perma.Runtime(**options)
        self.rt.add_source('#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n', 'fp64.cl')
        self.rt.add_type('node', NODE)
        self.rt.add_type('mix', MIX)
        self.split = self.rt.register('split', SPLIT, item=NODE, emits={'split': 2}, source_file='split.cl')
        self.greedy = self.rt.register('greedy', GREEDY, item=NODE, emits={'split': 1})
        self.countdown = self.rt.register('countdown', COUNTDOWN, item=NODE, emits={'countdown': 1},
                                          queue_only=True)
        self.copy = self.rt.register('copy', COPY, item=MIX)
        self.leaves = np.zeros(1, np.uint32)
        self.weights = np.arange(1, 33, dtype=np.uint32) ** 2
        self.weight_sum = np.zeros(1, np.uint32)
        self.leaf_ids = np.zeros(1 << MAX_DEPTH, np.uint32)
        self.copies = np.zeros(16, MIX)
        self.rt.bind('leaves', self.leaves)
        self.rt.bind('weights', self.weights, access='read')
        self.rt.bind('weight_sum', self.weight_sum)
        self.rt.bind('leaf_ids', self.leaf_ids, access='write')
        self.rt.bind('copies', self.copies)
        self.rt.declare_reduction('nodes', 'sum', np.uint64)
        self.rt.declare_reduction('deepest', 'max', np.uint32)
        self.rt.declare_reduction('last_id', 'min', np.int32)
        self.rt.declare_reduction('weight', 'sum', np.float64)

    def tree(self, *depths):
        """Run trees of these depths; returns the run's stats."""
        self.leaves[:] = 0
        self.weight_sum[:] = 0
        self.rt.seed(self.split, np.array([(d, 0) for d in depths], NODE))
        return self.rt.run()


@pytest.fixture(scope='session')
def make_workloads():
    made = []

    def make(**options):
        made.append(Workloads(**options))
        return made[-1]
    yield make
    for w in made:
        w.rt.close()


@pytest.fixture(scope='session')
def workloads(make_workloads):
    w = make_workloads()
    w.rt.build()
    return w


@pytest.fixture(scope='session')
def source_root():
    return os.environ.get('PERMA_SOURCE_ROOT', os.path.join(os.path.dirname(__file__), '..', '..'))
