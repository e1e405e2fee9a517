"""Schedule labels: 'megakernel/stealing/round-robin+local32', 'bounded-batches/p=64', ..."""
from ctypes import byref, create_string_buffer

from . import _capi
from ._capi import lib
from .errors import ArgumentError, check


def parse_schedule(label):
    """The perma_schedule of a label; ArgumentError naming the bad part."""
    if not isinstance(label, str):
        raise ArgumentError('a schedule is a label such as "megakernel/stealing", not %r' % (label,))
    schedule, error = _capi.Schedule(), _capi.Error()
    status = lib.perma_schedule_parse(label.encode(), byref(schedule), byref(error))
    check(status, lambda: error.message.decode(errors='replace'))
    return schedule


def format_schedule(schedule):
    """The canonical label of a perma_schedule."""
    text = create_string_buffer(128)
    lib.perma_schedule_format(byref(schedule), text, len(text))
    return text.value.decode()


# perma_schedule_set by the names of runtime/tools/schedules.py's modes.
SCHEDULE_SETS = {'all': _capi.SCHEDULE_SETS['PERMA_SCHEDULES_ALL'],
                 'once': _capi.SCHEDULE_SETS['PERMA_SCHEDULES_VICTIMS_ONCE'],
                 'default': _capi.SCHEDULE_SETS['PERMA_SCHEDULES_DEFAULT_VICTIM']}


def all_schedules(which='all'):
    """The canonical labels of every schedule (perma_schedule_all), in order;
    which='once' names the other victims only under the first stealing
    strategy, which='default' the default victim only."""
    if which not in SCHEDULE_SETS:
        raise ArgumentError('which schedules: one of %s, not %r' % (', '.join(SCHEDULE_SETS), which))
    labels, schedule = [], _capi.Schedule()
    while lib.perma_schedule_all(SCHEDULE_SETS[which], len(labels), byref(schedule)) == 0:
        labels.append(format_schedule(schedule))
    return labels


def schedule_label(label):
    """The canonical form of a label: schedule_label('megakernel') == 'megakernel/shared'."""
    return format_schedule(parse_schedule(label))
