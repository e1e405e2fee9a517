"""numpy dtypes as OpenCL C types.

A structured dtype becomes a struct declaration laid out exactly as numpy
lays it out: each field where OpenCL C puts it (every scalar aligned to its
size, as C does), explicit padding members where the dtype leaves gaps, and
an ArgumentError naming the field where no OpenCL C struct can match (a
packed dtype with a misaligned field: declare it with align=True).
"""
import re

import numpy as np

from .errors import ArgumentError

SCALARS = {('i', 1): 'char', ('u', 1): 'uchar', ('i', 2): 'short', ('u', 2): 'ushort',
           ('i', 4): 'int', ('u', 4): 'uint', ('i', 8): 'long', ('u', 8): 'ulong',
           ('f', 4): 'float', ('f', 8): 'double'}  # no half: a struct member needs cl_khr_fp16
IDENTIFIER = re.compile(r'[A-Za-z_][A-Za-z0-9_]*$')
INDENT = '    '


def _round_up(value, align):
    return (value + align - 1) // align * align


def scalar_type(dtype):
    """The OpenCL C scalar type of a numpy scalar dtype ('uint' for uint32), or None."""
    dtype = np.dtype(dtype)
    if dtype.fields is not None or dtype.subdtype is not None:
        return None
    if dtype.itemsize > 1 and not dtype.isnative:
        return None
    return SCALARS.get((dtype.kind, dtype.itemsize))


SIZES = {name: size for (_, size), name in SCALARS.items()}
SIZES['half'] = 2
VECTOR = re.compile(r'(%s)(2|3|4|8|16)?$' % '|'.join(sorted(SIZES, key=len, reverse=True)))
QUALIFIERS = {'__global', 'global', '__constant', 'constant', 'const', 'volatile', 'restrict', '__restrict'}


def builtin_size(name):
    """Bytes of a built-in OpenCL C scalar or vector type ('uint' 4, 'float3' 16), or None."""
    match = VECTOR.match(name)
    if not match:
        return None
    lanes = int(match.group(2) or 1)
    return SIZES[match.group(1)] * (4 if lanes == 3 else lanes)


def pointee(pointer_type):
    """The element type an OpenCL C pointer type points to ('uint' for '__global const uint *'), or None."""
    head, star, rest = pointer_type.partition('*')
    if not star or '*' in rest:
        return None
    words = [word for word in head.split() if word not in QUALIFIERS]
    if len(words) == 2 and words[0] in ('unsigned', 'signed') and words[1] in ('char', 'short', 'int', 'long'):
        return ('u' if words[0] == 'unsigned' else '') + words[1]
    if len(words) == 2 and words[0] == 'struct':
        return 'struct ' + words[1]
    return words[0] if len(words) == 1 else None


def _member_type(dtype, where, depth):
    """(declaration head, alignment, nested lines) of one element type."""
    scalar = scalar_type(dtype)
    if scalar:
        return scalar, dtype.itemsize, []
    if dtype.fields is not None:
        lines, align = _members(dtype, where, depth + 1)
        return 'struct', align, lines
    raise ArgumentError('%s: numpy type %s has no OpenCL C equivalent (signed or unsigned integers of '
                        '1, 2, 4 or 8 bytes, float32 or float64, native byte order, or a structured dtype of '
                        'those)' % (where, dtype))


def _members(dtype, where, depth):
    """The member lines of a struct laid out as `dtype`, and its alignment."""
    if not dtype.names:
        raise ArgumentError('%s: a structured dtype needs at least one field' % where)
    fields = sorted((dtype.fields[name][1], name, dtype.fields[name][0]) for name in dtype.names)
    lines, offset, align, pads = [], 0, 1, 0
    pad = INDENT * depth + 'uchar perma_pad%d[%d];'
    for at, name, ftype in fields:
        field = '%s.%s' % (where, name)
        if not IDENTIFIER.match(name):
            raise ArgumentError("%s: field name '%s' is not an OpenCL C identifier" % (where, name))
        base, shape = ftype.subdtype if ftype.subdtype else (ftype, ())
        head, member_align, nested = _member_type(base, field, depth)
        if at < offset or at % member_align:
            raise ArgumentError('%s is at byte %d, where OpenCL C cannot put it (after byte %d, at a '
                                'multiple of %d bytes): declare the dtype with align=True, or move the field'
                                % (field, at, offset, member_align))
        if at > _round_up(offset, member_align):  # a gap OpenCL C would not leave
            lines.append(pad % (pads, at - offset))
            pads += 1
        dims = ''.join('[%d]' % n for n in shape)
        if nested:
            lines += [INDENT * depth + 'struct {'] + nested + [INDENT * depth + '} %s%s;' % (name, dims)]
        else:
            lines.append(INDENT * depth + '%s %s%s;' % (head, name, dims))
        offset = at + ftype.itemsize
        align = max(align, member_align)
    if dtype.itemsize > _round_up(offset, align):
        lines.append(pad % (pads, dtype.itemsize - offset))
    if _round_up(dtype.itemsize, align) != dtype.itemsize:
        raise ArgumentError('%s: itemsize %d is not a multiple of the struct\'s alignment (%d bytes), as '
                            'OpenCL C sizes a struct: declare the dtype with align=True'
                            % (where, dtype.itemsize, align))
    return lines, align


def cl_declaration(name, dtype):
    """'struct NAME { ... };' for a structured dtype, laid out as numpy lays it out."""
    dtype = np.dtype(dtype)
    if not IDENTIFIER.match(name):
        raise ArgumentError("struct name '%s' is not an OpenCL C identifier" % name)
    if dtype.fields is None:
        raise ArgumentError('struct %s: %s is not a structured dtype (give one with named fields)' % (name, dtype))
    lines, _ = _members(dtype, name, 1)
    return 'struct %s {\n%s\n};\n' % (name, '\n'.join(lines))
