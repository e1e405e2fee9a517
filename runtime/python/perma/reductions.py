"""Reductions by numpy type: the perma_reduce_op and perma_value_type of a declaration.

A reduction is declared with an op ('sum', 'min', 'max') and a numpy scalar
type; procedures call reduce_NAME(ctx, value) with a value of that type's
OpenCL C type, and the host reads the result after a run as a numpy scalar
of that type (perma.h, Reductions, has the exact semantics).
"""
import numpy as np

from ._capi import REDUCE_OPS, VALUE_TYPES
from .errors import ArgumentError

OPS = {'sum': REDUCE_OPS['PERMA_REDUCE_SUM'], 'min': REDUCE_OPS['PERMA_REDUCE_MIN'],
       'max': REDUCE_OPS['PERMA_REDUCE_MAX']}
TYPES = {np.dtype(np.uint32): VALUE_TYPES['PERMA_TYPE_UINT'], np.dtype(np.int32): VALUE_TYPES['PERMA_TYPE_INT'],
         np.dtype(np.uint64): VALUE_TYPES['PERMA_TYPE_ULONG'], np.dtype(np.int64): VALUE_TYPES['PERMA_TYPE_LONG'],
         np.dtype(np.float32): VALUE_TYPES['PERMA_TYPE_FLOAT'],
         np.dtype(np.float64): VALUE_TYPES['PERMA_TYPE_DOUBLE']}


def reduce_op(op, name):
    """The perma_reduce_op of 'sum', 'min' or 'max'."""
    if not isinstance(op, str) or op not in OPS:
        raise ArgumentError("reduction '%s': op %r is not one of %s" % (name, op, ', '.join(OPS)))
    return OPS[op]


def value_type(dtype, name):
    """(numpy dtype, perma_value_type) of a reduction's numpy scalar type."""
    given = dtype
    try:
        dtype = np.dtype(dtype) if dtype is not None else None  # np.dtype(None) would be float64
    except TypeError:
        dtype = None
    if dtype not in TYPES:
        raise ArgumentError("reduction '%s': type %r is not one of numpy's uint32, int32, uint64, int64, float32 "
                            "or float64" % (name, given))
    return dtype, TYPES[dtype]
