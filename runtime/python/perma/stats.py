"""The statistics structures of a run as dicts."""
import ctypes

from ._capi import lib

BATCH_CUTS = {0: None, 1: 'local-memory', 2: 'room', 3: 'staging'}  # perma_batch_cut


def _fields(struct, skip=()):
    return {name: getattr(struct, name) for name, _ in struct._fields_ if name not in skip}


def _name(function, value):
    text = function(value)
    return text.decode() if text else None


def stats_dict(s):
    out = _fields(s)
    out['technique'] = _name(lib.perma_technique_name, s.technique)
    out['strategy'] = _name(lib.perma_strategy_name, s.strategy)
    out['work_groups_reason'] = (s.work_groups_reason or b'').decode(errors='replace')
    return out


def procedure_stats_dict(s, procedure):
    """emitted: {target: items}; batch_cut: None, 'local-memory', 'room' or 'staging'; batch_cut_emit: the target or None."""
    out = _fields(s, skip=('emitted', 'emit_count'))
    out['name'] = s.name.decode()
    out['emitted'] = {target: s.emitted[i] for i, (target, _) in enumerate(procedure.emits[:s.emit_count])}
    out['batch_cut'] = BATCH_CUTS.get(s.batch_cut, s.batch_cut)
    out['batch_cut_emit'] = procedure.emits[s.batch_cut_emit][0] if 0 <= s.batch_cut_emit < s.emit_count else None
    return out


def group_stats_dict(s):
    return _fields(s)


# perma_print_stats writes to a FILE *: an open_memstream (POSIX) gives one in memory.
_libc = ctypes.CDLL(None)
_libc.open_memstream.restype = ctypes.c_void_p
_libc.open_memstream.argtypes = [ctypes.POINTER(ctypes.c_void_p), ctypes.POINTER(ctypes.c_size_t)]
_libc.fclose.argtypes = [ctypes.c_void_p]
_libc.free.argtypes = [ctypes.c_void_p]


def stats_text(rt):
    buffer, size = ctypes.c_void_p(), ctypes.c_size_t()
    stream = _libc.open_memstream(ctypes.byref(buffer), ctypes.byref(size))
    if not stream:
        raise MemoryError('open_memstream failed')
    lib.perma_print_stats(rt, stream)
    _libc.fclose(stream)
    text = ctypes.string_at(buffer.value, size.value).decode(errors='replace')
    _libc.free(buffer)
    return text
