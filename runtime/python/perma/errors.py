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


class ArgumentError(PermaError, ValueError):
    status = Status.ARGUMENT


class NoPlatformError(PermaError):
    status = Status.NO_PLATFORM


class NoDeviceError(PermaError):
    status = Status.NO_DEVICE


class OpenCLError(PermaError):
    status = Status.OPENCL


class BuildError(PermaError):
    status = Status.BUILD


class NoMemoryError(PermaError, MemoryError):
    status = Status.NO_MEMORY


class CapacityError(PermaError):
    status = Status.CAPACITY


class EmitLimitError(PermaError):
    status = Status.EMIT_LIMIT


class TimeoutError(PermaError, builtins.TimeoutError):
    status = Status.TIMEOUT


class StateError(PermaError):
    status = Status.STATE


class IOError(PermaError):
    status = Status.IO


class DeviceError(PermaError):
    status = Status.DEVICE


ERRORS = {cls.status: cls for cls in (ArgumentError, NoPlatformError, NoDeviceError, OpenCLError, BuildError,
                                      NoMemoryError, CapacityError, EmitLimitError, TimeoutError, StateError,
                                      IOError, DeviceError)}


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
