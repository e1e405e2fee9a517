"""The ctypes mirrors of perma.h's structures have the C compiler's layout."""
import ctypes
import json
import os
import subprocess

import pytest

from perma import _capi


@pytest.fixture(scope='module')
def c_layout():
    program = os.environ.get('PERMA_ABI_LAYOUT')
    if not program:
        pytest.skip('PERMA_ABI_LAYOUT (the abi_layout program meson builds) is not set')
    return json.loads(subprocess.run([program], check=True, capture_output=True, text=True).stdout)


@pytest.mark.parametrize('name', sorted(_capi.STRUCTS))
def test_struct_layout(c_layout, name):
    struct = _capi.STRUCTS[name]
    offsets = {field: getattr(struct, field).offset for field, _ in struct._fields_}
    assert offsets == c_layout[name]['fields']
    assert ctypes.sizeof(struct) == c_layout[name]['size']


def test_every_struct_is_mirrored(c_layout):
    assert sorted(c_layout) == sorted(_capi.STRUCTS)


def test_enum_values():
    program = os.environ.get('PERMA_ABI_LAYOUT')
    if not program:
        pytest.skip('PERMA_ABI_LAYOUT (the abi_layout program meson builds) is not set')
    values = json.loads(subprocess.run([program, '--enums'], check=True, capture_output=True, text=True).stdout)
    assert values == _capi.ENUMS
