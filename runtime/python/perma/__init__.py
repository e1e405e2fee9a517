"""perma from Python: procedures in OpenCL C, items and buffers as numpy arrays.

    import numpy as np, perma
    node = np.dtype([('depth', np.uint32)])
    with perma.Runtime('megakernel/stealing') as rt:
        rt.add_type('node', node)                  # struct node { uint depth; };
        split = rt.register('split', SOURCE, item=node, emits={'split': 2})
        leaves = np.zeros(1, np.uint32)
        rt.bind('leaves', leaves)                  # ctx->buf.leaves, __global uint *
        rt.seed(split, np.array([(20,)], node))
        stats = rt.run()                           # leaves[0] == 2**20
        print(stats['items'], stats['procedures']['split']['emitted'])

Failures raise a PermaError subclass named after the status (BuildError
for PERMA_ERR_BUILD) carrying .status and .message.  docs/python.md has the
whole story; runtime/include/perma.h documents each call underneath.
"""
from ._capi import VERSION as __version__
from .cltypes import cl_declaration, scalar_type
from .devices import Device, devices
from .errors import (ArgumentError, BuildError, CapacityError, DeviceError, EmitLimitError, IOError,
                     NoDeviceError, NoMemoryError, NoPlatformError, OpenCLError, PermaError, StateError, Status,
                     TimeoutError, status_name)
from .runtime import Procedure, Runtime
from .schedule import all_schedules, schedule_label
