"""perma.Runtime: one perma_runtime, its procedures, buffers and runs."""
import ctypes
from ctypes import byref, c_int, c_uint

import numpy as np

from . import _capi
from ._capi import lib
from .cltypes import builtin_size, cl_declaration, pointee, scalar_type
from .devices import Device, devices
from .errors import ArgumentError, StateError, check
from .reductions import reduce_op, value_type
from .schedule import parse_schedule
from .stats import group_stats_dict, procedure_stats_dict, stats_dict, stats_text

# perma_bind_host flags, by the names bind() takes.
ACCESS = {'read': 1, 'write': 2, 'readwrite': 3}

# perma_config fields a Runtime takes as keyword arguments (0 or None: perma's default).
CONFIG_OPTIONS = ('work_groups', 'group_size', 'items_per_work_item', 'queue_capacity', 'queue_memory_limit',
                  'time_limit', 'stall_limit', 'local_memory_limit', 'build_options', 'trace_path',
                  'trace_events')


def _count(value, what):
    """A non-negative whole number for an unsigned C field (ctypes would wrap -1 silently)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
        raise ArgumentError('%s must be a whole number >= 0, not %r' % (what, value))
    return int(value)


def _bytes(text, what):
    if text is None:
        return None
    if not isinstance(text, str):
        raise ArgumentError('%s must be a string, not %s' % (what, type(text).__name__))
    return text.encode()


class Procedure:
    """A registered procedure: its handle, name, item dtype and emit targets."""

    def __init__(self, handle, name, dtype, item_type, emits):
        self.handle = handle
        self.name = name
        self.dtype = dtype
        self.item_type = item_type
        self.emits = emits  # ((target, max_items), ...) in declaration order

    def __repr__(self):
        return '<perma.Procedure %s: %s items (%d bytes)>' % (self.name, self.item_type, self.dtype.itemsize)


class Runtime:
    """A perma runtime on one device (perma_create).

    schedule: a label, e.g. 'megakernel/stealing' (None: megakernel/shared);
    device: 'P:D', 'P:D/N.K', 'intel', 'pocl', ... or a perma.Device
    (None: PERMA_DEVICE, else 0:0); build_log: a callable taking the text of
    compiler messages (None: stderr); the other keywords set the perma_config
    field of that name (perma.h), 0 or None leaving perma's default.
    """

    def __init__(self, schedule=None, device=None, *, build_log=None, **options):
        self._handle = None
        unknown = sorted(set(options) - set(CONFIG_OPTIONS))
        if unknown:
            raise ArgumentError('Runtime(): unknown option %s (options: %s)'
                                % (', '.join(unknown), ', '.join(CONFIG_OPTIONS + ('build_log',))))
        config = _capi.Config()
        lib.perma_config_init(byref(config))
        if schedule is not None:
            config.schedule = parse_schedule(schedule)
        if device is not None:
            ref = device if isinstance(device, Device) else self._one_device(device)
            lib.perma_config_set_device(byref(config), byref(ref.as_ref()))
        for name, value in options.items():
            if name in ('build_options', 'trace_path'):
                value = _bytes(value, name)
            elif value is None:
                continue
            elif name in ('time_limit', 'stall_limit'):
                if isinstance(value, bool) or not isinstance(value, (int, float)) or not value >= 0:
                    raise ArgumentError('Runtime(): %s must be a number of seconds >= 0, not %r' % (name, value))
            else:
                value = _count(value, 'Runtime(): ' + name)
            setattr(config, name, value)
        self._build_log = None
        if build_log is not None:
            if not callable(build_log):
                raise ArgumentError('Runtime(): build_log must be callable')
            self._build_log = _capi.BUILD_LOG(lambda user, text: build_log(text.decode(errors='replace')))
            config.build_log = self._build_log
        handle, error = _capi.RT(), _capi.Error()
        status = lib.perma_create(byref(config), byref(handle), byref(error))
        check(status, lambda: error.message.decode(errors='replace'))
        self._handle = handle
        self._buffers = {}      # name -> the numpy array perma copies from and to
        self._types = []        # (dtype, OpenCL type) declared with add_type
        self._reductions = {}   # name -> (dtype, perma_value_type) declared with declare_reduction
        self.procedures = {}    # name -> Procedure

    @staticmethod
    def _one_device(text):
        found = devices(text)
        if len(found) != 1:
            raise ArgumentError("device '%s' names %d devices (%s); a runtime runs on one"
                                % (text, len(found), ', '.join(str(d) for d in found)))
        return found[0]

    # -- lifetime

    def close(self):
        """Release the runtime (perma_destroy); later calls raise StateError."""
        if self._handle is not None:
            lib.perma_destroy(self._handle)
            self._handle = None
        self._buffers = {}

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        if getattr(self, '_handle', None) is not None and lib is not None:
            self.close()

    def _rt(self):
        if self._handle is None:
            raise StateError('the runtime is closed')
        return self._handle

    def _check(self, status):
        check(status, lambda: lib.perma_errmsg(self._handle).decode(errors='replace'))

    # -- sources and procedures

    def add_source(self, source, file=None):
        """Add OpenCL C visible to every procedure (item types, helpers); `file` names it in messages."""
        self._check(lib.perma_add_source(self._rt(), _bytes(source, 'source'), _bytes(file, 'file')))

    def add_type(self, name, dtype):
        """Declare 'struct NAME' laid out as the structured dtype; returns 'struct NAME'.

        Procedures whose items, and buffers whose elements, have this dtype
        then need no item_type or type of their own."""
        dtype = np.dtype(dtype)
        self.add_source(cl_declaration(name, dtype), '<dtype %s>' % name)
        self._types.append((dtype, 'struct ' + name))
        return 'struct ' + name

    def cl_type(self, dtype):
        """The OpenCL C type of a dtype: a scalar's, or the struct add_type declared for it."""
        dtype = np.dtype(dtype)
        scalar = scalar_type(dtype)
        if scalar:
            return scalar
        for declared, name in self._types:
            if declared == dtype:
                return name
        raise ArgumentError('dtype %s has no OpenCL C type here: declare it with add_type(name, dtype) '
                            'or give the type' % (dtype,))

    def register(self, name, source=None, *, item, function=None, item_type=None, emits=None,
                 threads_per_item=1, local_bytes_per_item=0, priority=0, cooperative=False, queue_only=False,
                 source_file=None):
        """Register a procedure (perma_register); returns its Procedure.

        item: the numpy dtype of one item (its itemsize is the item_size the
        device checks against sizeof(item_type) at build); item_type: its
        OpenCL C type (default: cl_type(item)); function: default `name`;
        emits: {target: most items per input item}; source: OpenCL C text,
        or source_file a file to read; queue_only: its items always go
        through the queues, never depth first from a work-item's stack
        (perma_procedure.queue_only)."""
        dtype = np.dtype(item)
        item_type = item_type if item_type is not None else self.cl_type(dtype)
        emits = tuple((emits or {}).items())
        if len(emits) > _capi.MAX_EMITS:
            raise ArgumentError('procedure %s: %d emit targets, at most %d' % (name, len(emits), _capi.MAX_EMITS))
        what = 'procedure %s: ' % name
        d = _capi.Procedure(name=_bytes(name, 'name'), item_type=_bytes(item_type, 'item_type'),
                            item_size=dtype.itemsize,
                            threads_per_item=_count(threads_per_item, what + 'threads_per_item'),
                            local_bytes_per_item=_count(local_bytes_per_item, what + 'local_bytes_per_item'),
                            source=_bytes(source, 'source'),
                            source_file=_bytes(source_file, 'source_file'),
                            function=_bytes(function if function is not None else name, 'function'),
                            priority=priority, cooperative=1 if cooperative else 0,
                            queue_only=1 if queue_only else 0)
        for i, (target, max_items) in enumerate(emits):
            d.emits[i] = _capi.Emit(_bytes(target, 'emit target'), _count(max_items, what + 'emits[%r]' % target))
        handle = c_int()
        self._check(lib.perma_register(self._rt(), byref(d), byref(handle)))
        procedure = Procedure(handle.value, name, dtype, item_type, emits)
        self.procedures[name] = procedure
        return procedure

    def find(self, name):
        """The Procedure registered under `name` (perma_find)."""
        handle = c_int()
        self._check(lib.perma_find(self._rt(), _bytes(name, 'name'), byref(handle)))
        return self.procedures[name]

    # -- buffers, seeds, runs

    def bind(self, name, array, *, access='readwrite', type=None):
        """Bind a numpy array as ctx->buf.NAME (perma_bind_host).

        access 'read' copies it to the device before each run, 'write' back
        after each run, 'readwrite' both; type: the OpenCL C type (default
        '__global T *' with T = cl_type(array.dtype), const for 'read').
        The runtime keeps the array (it must stay C-contiguous in place);
        binding the name again swaps it."""
        if access not in ACCESS:
            raise ArgumentError("buffer '%s': access %r is not one of %s" % (name, access, ', '.join(ACCESS)))
        if not isinstance(array, np.ndarray):
            raise ArgumentError("buffer '%s': expected a numpy array, not %s" % (name, builtin_type(array).__name__))
        if not array.flags.c_contiguous:
            raise ArgumentError("buffer '%s': the array is not C-contiguous (np.ascontiguousarray makes a copy "
                                "to bind)" % name)
        if access != 'read' and not array.flags.writeable:
            raise ArgumentError("buffer '%s': the array is read-only, but access '%s' writes it" % (name, access))
        if type is None:
            type = '__global %s%s *' % ('const ' if access == 'read' else '', self.cl_type(array.dtype))
        else:
            self._check_element_type(name, array, type)
        self._check(lib.perma_bind_host(self._rt(), _bytes(name, 'name'), _bytes(type, 'type'),
                                        array.ctypes.data_as(ctypes.c_void_p), array.nbytes, ACCESS[access]))
        self._buffers[name] = array

    def _check_element_type(self, name, array, type):
        """The elements `type` points to must be the size of the array's (where that size is known here)."""
        element = pointee(type)
        size = builtin_size(element) if element else None
        for dtype, declared in self._types:
            if declared == element:
                size = dtype.itemsize
        if size is not None and size != array.dtype.itemsize:
            raise ArgumentError("buffer '%s': type '%s' points to %s, %d bytes each, but the array's elements are "
                                "%s, %d bytes each: give the type of the array's elements, or bind a view of it "
                                "(array.view(...))" % (name, type, element, size, array.dtype, array.dtype.itemsize))

    def seed(self, procedure, items):
        """Queue items (an array of the procedure's dtype, or what converts to one) for the next run."""
        procedure = self._procedure(procedure)
        if isinstance(items, np.ndarray) and items.dtype != procedure.dtype:
            raise ArgumentError('seed %s: the items have dtype %s, the procedure takes %s'
                                % (procedure.name, items.dtype, procedure.dtype))
        items = np.ascontiguousarray(items, dtype=procedure.dtype)
        self._check(lib.perma_seed(self._rt(), procedure.handle, items.ctypes.data_as(ctypes.c_void_p),
                                   items.size))

    def declare_reduction(self, name, op, dtype):
        """Declare reduction NAME (perma_declare_reduction) before the run that uses it.

        Procedures call reduce_NAME(ctx, value) with a value of dtype's
        OpenCL C type; op is 'sum', 'min' or 'max'; dtype one of numpy's
        uint32, int32, uint64, int64, float32, float64.  The result of each
        run: reduction(name), or stats()['reductions'][name]."""
        code = reduce_op(op, name)
        dtype, vtype = value_type(dtype, name)
        self._check(lib.perma_declare_reduction(self._rt(), _bytes(name, 'name'), code, vtype, None))
        self._reductions[name] = (dtype, vtype)

    def reduction(self, name):
        """The last run's result of reduction NAME as a numpy scalar of its type (perma_get_reduction)."""
        dtype, vtype = self._reductions.get(name, (np.dtype(np.uint32), 0))  # unknown: libperma names it
        out = np.zeros(1, dtype)
        self._check(lib.perma_get_reduction(self._rt(), _bytes(name, 'name'), vtype,
                                            out.ctypes.data_as(ctypes.c_void_p)))
        return out[0]

    def _procedure(self, procedure):
        if isinstance(procedure, str):
            return self.find(procedure)
        if not isinstance(procedure, Procedure) or self.procedures.get(procedure.name) is not procedure:
            raise ArgumentError('%r is not a procedure of this runtime' % (procedure,))
        return procedure

    def build(self):
        """Generate and compile the megakernel now (perma_run does it when needed)."""
        self._check(lib.perma_build(self._rt()))

    def run(self):
        """Run until no work is left (perma_run); bound arrays are written back.  Returns stats()."""
        self._check(lib.perma_run(self._rt()))
        return self.stats()

    def forget_capacities(self):
        """Start the next run's queues from the configured capacity again."""
        self._check(lib.perma_forget_capacities(self._rt()))

    # -- what the device is and what the last run did

    @property
    def work_groups(self):
        """(work-groups, work-items per group) the runs use."""
        groups, size = c_uint(), c_uint()
        self._check(lib.perma_get_work_groups(self._rt(), byref(groups), byref(size)))
        return groups.value, size.value

    @property
    def device_summary(self):
        """One line: the device and the work-group count chosen."""
        return lib.perma_device_summary(self._rt()).decode(errors='replace')

    def procedure_stats(self, procedure):
        """The last run's counters of one procedure, as a dict."""
        procedure = self._procedure(procedure)
        out = _capi.ProcedureStats()
        self._check(lib.perma_get_procedure_stats(self._rt(), procedure.handle, byref(out)))
        return procedure_stats_dict(out, procedure)

    def group_stats(self, group):
        """The last run's load-balancing counters of persistent group `group`, as a dict."""
        out = _capi.GroupStats()
        self._check(lib.perma_get_group_stats(self._rt(), group, byref(out)))
        return group_stats_dict(out)

    def stats(self):
        """The last run's statistics as a dict, with 'procedures' (by name), 'groups' (a list) and
        'reductions' (by name; empty when no run has succeeded since the last declaration)."""
        out = _capi.Stats()
        self._check(lib.perma_get_stats(self._rt(), byref(out)))
        result = stats_dict(out)
        result['procedures'] = {name: self.procedure_stats(p) for name, p in self.procedures.items()}
        result['groups'] = [self.group_stats(g) for g in range(self.work_groups[0])]
        try:
            result['reductions'] = {name: self.reduction(name) for name in self._reductions}
        except StateError:
            result['reductions'] = {}
        return result

    def stats_text(self):
        """The last run's statistics as perma_print_stats writes them."""
        return stats_text(self._rt())


builtin_type = type
