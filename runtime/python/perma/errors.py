"""perma's status codes as exceptions.

Every failing call raises a subclass of PermaError named after its status
(PERMA_ERR_BUILD: BuildError), carrying the status and libperma's message.
The binding's own checks of Python arguments raise ArgumentError, as the
library does for a bad argument.
"""
import builtins
import enum

from ._capi import lib


class Status(enum.IntEnum):
    """perma_status (perma.h)."""
    OK = 0
    ARGUMENT = 1
    NO_PLATFORM = 2
    NO_DEVICE = 3
    OPENCL = 4
    BUILD = 5
    NO_MEMORY = 6
    CAPACITY = 7
    EMIT_LIMIT = 8
    TIMEOUT = 9
    STATE = 10
    IO = 11
    DEVICE = 12


def status_name(status):
    """The C name of a status, e.g. 'PERMA_ERR_BUILD' (perma_status_name)."""
    return lib.perma_status_name(int(status)).decode()


class PermaError(Exception):
    """A perma call failed: .status (Status) and .message (libperma's text)."""
    status = None

    def __init__(self, message):
        super().__init__(message)
        self.message = message

    def __str__(self):
        return self.message


ERRORS = {}  # Status -> its exception class


def _error_class(name, status, *bases):
    """The PermaError subclass of a status (also a subclass of `bases`)."""
    cls = type(name, (PermaError,) + bases,
               {'status': status, '__module__': __name__, '__doc__': 'perma_status %s.' % status_name(status)})
    ERRORS[status] = cls
    return cls


ArgumentError = _error_class('ArgumentError', Status.ARGUMENT, ValueError)
NoPlatformError = _error_class('NoPlatformError', Status.NO_PLATFORM)
NoDeviceError = _error_class('NoDeviceError', Status.NO_DEVICE)
OpenCLError = _error_class('OpenCLError', Status.OPENCL)
BuildError = _error_class('BuildError', Status.BUILD)
NoMemoryError = _error_class('NoMemoryError', Status.NO_MEMORY, MemoryError)
CapacityError = _error_class('CapacityError', Status.CAPACITY)
EmitLimitError = _error_class('EmitLimitError', Status.EMIT_LIMIT)
TimeoutError = _error_class('TimeoutError', Status.TIMEOUT, builtins.TimeoutError)
StateError = _error_class('StateError', Status.STATE)
IOError = _error_class('IOError', Status.IO)
DeviceError = _error_class('DeviceError', Status.DEVICE)


def error(status, message):
    """The exception for a status (PermaError itself for one this binding does not know)."""
    cls = ERRORS.get(status)
    if cls:
        return cls(message)
    unknown = PermaError(message)
    unknown.status = status
    return unknown


def check(status, message):
    """Raise the exception of a failed status; `message` is a callable giving the text."""
    if status != Status.OK:
        raise error(status, message())
