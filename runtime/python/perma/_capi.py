"""The C API of libperma as ctypes declarations: one line per function.

The structures mirror runtime/include/perma.h field by field; the meson test
suite `python` compares their sizes and offsets with the C compiler's
(tests/python/abi_layout.c), so a field added to perma.h without adding it
here fails a test instead of corrupting memory.  Adding a C function to the
binding is one entry in PROTOTYPES and a method that calls it.
"""
import ctypes
from ctypes import POINTER, c_char, c_char_p, c_double, c_int, c_size_t, c_uint, c_uint64, c_void_p

from . import _locate

try:
    from . import _configured  # written by meson into the build tree and the installed package
except ImportError:            # installed with pip, or run from the source tree
    _configured = None


def _version():
    if _configured:
        return _configured.VERSION
    try:
        from importlib.metadata import PackageNotFoundError, version
        return version('perma')
    except (ImportError, PackageNotFoundError):
        return '(source tree)'


VERSION = _version()

NAME_MAX = 63
MAX_EMITS = 8
MAX_DEVICES = 64
MESSAGE_MAX = 1024


class Error(ctypes.Structure):
    _fields_ = [('status', c_int), ('message', c_char * MESSAGE_MAX)]


class Schedule(ctypes.Structure):
    _fields_ = [('technique', c_int), ('strategy', c_int), ('victim', c_int),
                ('local_queue_items', c_uint), ('batch_limit', c_uint), ('donation_threshold', c_uint),
                ('work_first_items', c_uint)]


BUILD_LOG = ctypes.CFUNCTYPE(None, c_void_p, c_char_p)


class Config(ctypes.Structure):
    _fields_ = [('platform_index', c_int), ('device_index', c_int), ('platform_name', c_char_p),
                ('sub_devices', c_uint), ('sub_device', c_uint),
                ('work_groups', c_uint), ('group_size', c_uint), ('items_per_work_item', c_uint),
                ('queue_capacity', c_size_t), ('queue_memory_limit', c_size_t),
                ('time_limit', c_double), ('stall_limit', c_double),
                ('local_memory_limit', c_size_t), ('build_options', c_char_p),
                ('build_log', BUILD_LOG), ('build_log_user', c_void_p),
                ('schedule', Schedule),
                ('trace_path', c_char_p), ('trace_events', c_uint),
                ('progress', c_void_p), ('progress_user', c_void_p), ('progress_interval', c_double)]


class DeviceRef(ctypes.Structure):
    _fields_ = [('platform_index', c_int), ('device_index', c_int),
                ('sub_devices', c_uint), ('sub_device', c_uint)]


class Emit(ctypes.Structure):
    _fields_ = [('target', c_char_p), ('max_items', c_uint)]


class Procedure(ctypes.Structure):
    _fields_ = [('name', c_char_p), ('item_type', c_char_p), ('item_size', c_size_t),
                ('threads_per_item', c_uint), ('local_bytes_per_item', c_size_t),
                ('source', c_char_p), ('source_file', c_char_p), ('function', c_char_p),
                ('emits', Emit * MAX_EMITS), ('priority', c_int), ('cooperative', c_int),
                ('queue_only', c_int)]


class ProcedureStats(ctypes.Structure):
    _fields_ = [('name', c_char_p), ('items', c_uint64), ('batches', c_uint64),
                ('emitted', c_uint64 * MAX_EMITS), ('emit_count', c_uint), ('seeded', c_uint64),
                ('peak_queue_items', c_uint64), ('initial_capacity', c_size_t),
                ('queue_capacity', c_size_t), ('regrowths', c_uint), ('batch_size', c_uint),
                ('batch_cut', c_int), ('batch_cut_emit', c_int), ('stacked_items', c_uint64)]


class GroupStats(ctypes.Structure):
    _fields_ = [('batches', c_uint64), ('items', c_uint64), ('steals', c_uint64),
                ('donations', c_uint64), ('donated_items', c_uint64), ('spills', c_uint64),
                ('idle_polls', c_uint64), ('stacked_items', c_uint64), ('stack_spills', c_uint64),
                ('stack_peak', c_uint)]


class Stats(ctypes.Structure):
    _fields_ = [('seconds', c_double), ('launches', c_uint), ('regrowths', c_uint),
                ('work_groups', c_uint), ('group_size', c_uint), ('procedure_count', c_uint),
                ('peak_queue_bytes', c_size_t), ('queue_memory_limit', c_size_t),
                ('queues_kept', c_uint), ('items', c_uint64), ('steals', c_uint64),
                ('donations', c_uint64), ('spills', c_uint64), ('idle_polls', c_uint64),
                ('overflowed_items', c_uint64), ('technique', c_int), ('strategy', c_int),
                ('stacked_items', c_uint64), ('stack_spills', c_uint64), ('stack_peak', c_uint),
                ('stack_items', c_uint), ('work_groups_reason', c_char_p), ('resident_groups', c_uint),
                ('kernel_local_bytes', c_size_t)]


# Every structure above, by its C name (for the layout test).
STRUCTS = {'perma_error': Error, 'perma_schedule': Schedule, 'perma_config': Config,
           'perma_device_ref': DeviceRef, 'perma_emit': Emit, 'perma_procedure': Procedure,
           'perma_procedure_stats': ProcedureStats, 'perma_group_stats': GroupStats,
           'perma_stats': Stats}

# perma_schedule_set (perma.h) by its C names (the layout test checks the values).
SCHEDULE_SETS = {'PERMA_SCHEDULES_ALL': 0, 'PERMA_SCHEDULES_VICTIMS_ONCE': 1, 'PERMA_SCHEDULES_DEFAULT_VICTIM': 2}
# perma_reduce_op and perma_value_type (perma.h), likewise.
REDUCE_OPS = {'PERMA_REDUCE_SUM': 0, 'PERMA_REDUCE_MIN': 1, 'PERMA_REDUCE_MAX': 2}
VALUE_TYPES = {'PERMA_TYPE_UINT': 0, 'PERMA_TYPE_INT': 1, 'PERMA_TYPE_ULONG': 2, 'PERMA_TYPE_LONG': 3,
               'PERMA_TYPE_FLOAT': 4, 'PERMA_TYPE_DOUBLE': 5}
ENUMS = dict(SCHEDULE_SETS, **REDUCE_OPS, **VALUE_TYPES)

RT = c_void_p  # perma_runtime *
STATUS = c_int

# name: (return type, argument types)
PROTOTYPES = {
    'perma_status_name': (c_char_p, [STATUS]),
    'perma_technique_name': (c_char_p, [c_int]),
    'perma_strategy_name': (c_char_p, [c_int]),
    'perma_victim_name': (c_char_p, [c_int]),
    'perma_schedule_parse': (STATUS, [c_char_p, POINTER(Schedule), POINTER(Error)]),
    'perma_schedule_format': (c_int, [POINTER(Schedule), c_char_p, c_size_t]),
    'perma_schedule_all': (STATUS, [c_int, c_uint, POINTER(Schedule)]),
    'perma_config_init': (None, [POINTER(Config)]),
    'perma_device_list': (STATUS, [c_char_p, POINTER(DeviceRef), c_uint, POINTER(c_uint), POINTER(Error)]),
    'perma_device_ref_format': (c_int, [POINTER(DeviceRef), c_char_p, c_size_t]),
    'perma_config_set_device': (None, [POINTER(Config), POINTER(DeviceRef)]),
    'perma_create': (STATUS, [POINTER(Config), POINTER(RT), POINTER(Error)]),
    'perma_destroy': (None, [RT]),
    'perma_errmsg': (c_char_p, [RT]),
    'perma_add_source': (STATUS, [RT, c_char_p, c_char_p]),
    'perma_register': (STATUS, [RT, POINTER(Procedure), POINTER(c_int)]),
    'perma_find': (STATUS, [RT, c_char_p, POINTER(c_int)]),
    'perma_bind_host': (STATUS, [RT, c_char_p, c_char_p, c_void_p, c_size_t, c_uint]),
    'perma_build': (STATUS, [RT]),
    'perma_seed': (STATUS, [RT, c_int, c_void_p, c_size_t]),
    'perma_declare_reduction': (STATUS, [RT, c_char_p, c_int, c_int, c_void_p]),
    'perma_get_reduction': (STATUS, [RT, c_char_p, c_int, c_void_p]),
    'perma_forget_capacities': (STATUS, [RT]),
    'perma_run': (STATUS, [RT]),
    'perma_get_stats': (STATUS, [RT, POINTER(Stats)]),
    'perma_get_procedure_stats': (STATUS, [RT, c_int, POINTER(ProcedureStats)]),
    'perma_get_work_groups': (STATUS, [RT, POINTER(c_uint), POINTER(c_uint)]),
    'perma_get_group_stats': (STATUS, [RT, c_uint, POINTER(GroupStats)]),
    'perma_print_stats': (None, [RT, c_void_p]),
    'perma_device_summary': (c_char_p, [RT]),
}


def load():
    """libperma (_locate.py says where it looks) with every function of PROTOTYPES declared."""
    lib, path = _locate.load(configured=_configured.library_paths() if _configured else None)
    for name, (restype, argtypes) in PROTOTYPES.items():
        try:
            function = getattr(lib, name)
        except AttributeError:
            raise ImportError('perma: %s has no %s: a libperma older than this package (%s)'
                              % (path, name, VERSION)) from None
        function.restype = restype
        function.argtypes = argtypes
    return lib, path


lib, LIBRARY = load()
