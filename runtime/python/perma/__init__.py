"""perma from Python: procedures in OpenCL C, items and buffers as numpy arrays.

    import numpy as np, perma
    node = np.dtype([('depth', np.uint32)])
    with perma.Runtime() as rt:
        rt.add_type('node', node)                  # struct node { uint depth; };
        split = rt.register('split', SOURCE, item=node, emits={'split': 2})
        rt.declare_reduction('leaves', 'sum', np.uint32)  # reduce_leaves(ctx, v)
        # rt.bind('values', array): a numpy array as ctx->buf.values
        rt.seed(split, np.array([(20,)], node))
        stats = rt.run()                           # rt.reduction('leaves') == 2**20
        print(stats['items'], stats['procedures']['split']['emitted'])

Failures raise a PermaError subclass named after the status (BuildError
for PERMA_ERR_BUILD) carrying .status and .message.  The package finds
libperma as _locate.py says (PERMA_LIBRARY, meson's record, pkg-config, an
installed prefix).  docs/python.md has the whole story;
runtime/include/perma.h documents each call underneath.
"""
from ._capi import VERSION as __version__
from .cltypes import cl_declaration, scalar_type
from .devices import Device, devices
from .errors import (ArgumentError, BuildError, CapacityError, DeviceError, EmitLimitError, IOError,
                     NoDeviceError, NoMemoryError, NoPlatformError, OpenCLError, PermaError, StateError, Status,
                     TimeoutError, status_name)
from .runtime import Procedure, Runtime
from .schedule import all_schedules, schedule_label
