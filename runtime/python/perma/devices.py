"""OpenCL devices as perma names them: 'P:D', or 'P:D/N.K' for part K of N."""
import collections
from ctypes import byref, c_uint, create_string_buffer

from . import _capi
from ._capi import lib
from .errors import ArgumentError, check


class Device(collections.namedtuple('Device', 'platform device sub_devices sub_device')):
    """One device (perma_device_ref): platform and device index, and with
    sub_devices >= 2 the part sub_device of the device split equally."""

    def as_ref(self):
        return _capi.DeviceRef(self.platform, self.device, self.sub_devices, self.sub_device)

    def __str__(self):
        text = create_string_buffer(64)
        lib.perma_device_ref_format(byref(self.as_ref()), text, len(text))
        return text.value.decode()


def devices(spec=None):
    """The devices of a device list (perma_device_list): 'P:D', 'NAME[:D]',
    'P:D/N', 'P:D/N.K', 'all', comma-separated; None: PERMA_DEVICE, else 0:0."""
    if spec is not None and not isinstance(spec, str):
        raise ArgumentError("a device list is text such as '0:0', 'pocl' or 'all', not %r" % (spec,))
    refs = (_capi.DeviceRef * _capi.MAX_DEVICES)()
    count, error = c_uint(), _capi.Error()
    status = lib.perma_device_list(spec.encode() if spec is not None else None, refs, _capi.MAX_DEVICES,
                                   byref(count), byref(error))
    check(status, lambda: error.message.decode(errors='replace'))
    return [Device(r.platform_index, r.device_index, r.sub_devices, r.sub_device) for r in refs[:count.value]]
