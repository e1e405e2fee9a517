"""numpy dtypes as OpenCL C declarations (no device needed)."""
import numpy as np
import pytest

import perma


def test_flat_struct():
    node = np.dtype([('depth', np.uint32), ('id', np.uint32)])
    assert perma.cl_declaration('node', node) == 'struct node {\n    uint depth;\n    uint id;\n};\n'


def test_every_scalar():
    names = ['char', 'uchar', 'short', 'ushort', 'int', 'uint', 'long', 'ulong', 'float', 'double']
    types = [np.int8, np.uint8, np.int16, np.uint16, np.int32, np.uint32, np.int64, np.uint64, np.float32,
             np.float64]
    assert [perma.scalar_type(t) for t in types] == names
    assert perma.scalar_type(np.float16) is None  # half needs cl_khr_fp16
    assert perma.scalar_type(np.dtype('>u4')) is None  # not the host's byte order
    assert perma.scalar_type(np.dtype([('a', np.uint32)])) is None


def test_nested_arrays_and_natural_padding():
    mix = np.dtype([('a', np.uint8), ('b', np.float64), ('c', [('x', np.int16), ('y', np.uint8, (3,))], (2,)),
                    ('d', np.float32, (2, 2))], align=True)
    assert perma.cl_declaration('mix', mix) == (
        'struct mix {\n'
        '    uchar a;\n'
        '    double b;\n'
        '    struct {\n'
        '        short x;\n'
        '        uchar y[3];\n'
        '    } c[2];\n'
        '    float d[2][2];\n'
        '};\n')


def test_gaps_become_padding_members():
    spaced = np.dtype({'names': ['a', 'b'], 'formats': [np.uint32, np.uint32], 'offsets': [0, 12], 'itemsize': 24})
    assert perma.cl_declaration('spaced', spaced) == (
        'struct spaced {\n    uint a;\n    uchar perma_pad0[8];\n    uint b;\n    uchar perma_pad1[8];\n};\n')


@pytest.mark.parametrize('dtype, message', [
    (np.dtype([('a', np.uint8), ('b', np.float64)]),
     r'packed\.b is at byte 1, where OpenCL C cannot put it \(after byte 1, at a multiple of 8 bytes\): declare '
     r'the dtype with align=True'),
    (np.dtype({'names': ['a', 'b'], 'formats': [np.uint32, np.uint32], 'offsets': [0, 0]}),
     r'packed\.b is at byte 0, where OpenCL C cannot put it \(after byte 4'),
    (np.dtype({'names': ['a'], 'formats': [np.uint64], 'itemsize': 12}),
     r'packed: itemsize 12 is not a multiple of the struct.s alignment \(8 bytes\)'),
    (np.dtype([('a', np.complex64)]), r'packed\.a: numpy type complex64 has no OpenCL C equivalent'),
    (np.dtype([('a', np.float16)]), r'packed\.a: numpy type float16 has no OpenCL C equivalent'),
    (np.dtype([('a b', np.uint32)]), r"packed: field name 'a b' is not an OpenCL C identifier"),
    (np.dtype(np.uint32), r'struct packed: uint32 is not a structured dtype'),
])
def test_layouts_opencl_c_cannot_match(dtype, message):
    with pytest.raises(perma.ArgumentError, match=message):
        perma.cl_declaration('packed', dtype)
