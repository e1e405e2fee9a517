#!/usr/bin/env python3
"""Make an ELF program or library find its libraries beside itself.

usage: set_rpath.py FILE...

Rewrites, in place, the library search path a 64-bit little-endian ELF file
carries (DT_RUNPATH or DT_RPATH, as meson's build leaves it, e.g.
"$ORIGIN/../runtime") to "$ORIGIN", as a DT_RPATH: the dynamic loader then
looks for the program's libraries, and for their libraries in turn, in the
program's own folder first (a DT_RUNPATH would serve only the program's own
libraries).  The new path is written over the old one's characters, so the
file keeps its size (what chrpath does; no patchelf is needed).  A file
without a search path is left alone and named (a library loaded by a
program of the folder needs none); a path shorter than "$ORIGIN" is an
error.  Exit status: 0 done, 1 a file could not be rewritten, 2 bad usage.
"""
import struct
import sys

ORIGIN = b'$ORIGIN'
DT_NULL, DT_STRTAB, DT_STRSZ, DT_RPATH, DT_RUNPATH = 0, 5, 10, 15, 29
# Tags whose value is an offset into the dynamic string table.
STRING_TAGS = (1, 14, DT_RPATH, DT_RUNPATH)  # DT_NEEDED, DT_SONAME
PT_LOAD, PT_DYNAMIC = 1, 2


class ElfError(Exception):
    pass


def program_headers(data):
    if data[:4] != b'\x7fELF' or data[4] != 2 or data[5] != 1:
        raise ElfError('not a 64-bit little-endian ELF file')
    phoff, = struct.unpack_from('<Q', data, 0x20)
    phentsize, phnum = struct.unpack_from('<HH', data, 0x36)
    for i in range(phnum):
        p_type, _flags, p_offset, p_vaddr, _paddr, p_filesz = struct.unpack_from('<IIQQQQ', data, phoff + i * phentsize)
        yield p_type, p_offset, p_vaddr, p_filesz


def file_offset(headers, address):
    for p_type, p_offset, p_vaddr, p_filesz in headers:
        if p_type == PT_LOAD and p_vaddr <= address < p_vaddr + p_filesz:
            return address - p_vaddr + p_offset
    raise ElfError('address 0x%x is in no loaded segment' % address)


def set_origin(path):
    """Rewrite path's search path to $ORIGIN; returns what it was (None: none)."""
    with open(path, 'rb') as f:
        data = bytearray(f.read())
    headers = list(program_headers(data))
    dynamic = [h for h in headers if h[0] == PT_DYNAMIC]
    if not dynamic:
        raise ElfError('no dynamic section (a static program?)')
    _, offset, _, size = dynamic[0]
    entries = []
    for at in range(offset, offset + size, 16):
        tag, value = struct.unpack_from('<qQ', data, at)
        if tag == DT_NULL:
            break
        entries.append((at, tag, value))
    values = {tag: value for _, tag, value in entries}
    paths = [(at, tag, value) for at, tag, value in entries if tag in (DT_RPATH, DT_RUNPATH)]
    if not paths:
        return None
    strtab = file_offset(headers, values[DT_STRTAB])
    at, tag, start = paths[0]
    end = data.index(b'\0', strtab + start) - strtab
    old = bytes(data[strtab + start:strtab + end])
    if len(old) < len(ORIGIN):
        raise ElfError("its search path '%s' is shorter than %s" % (old.decode(errors='replace'), ORIGIN.decode()))
    for _, other_tag, value in entries:
        if other_tag in STRING_TAGS and start < value <= end and (other_tag, value) != (tag, start):
            raise ElfError('another entry shares the characters of its search path')
    data[strtab + start:strtab + end] = ORIGIN + b'\0' * (len(old) - len(ORIGIN))
    struct.pack_into('<q', data, at, DT_RPATH)
    for other_at, _, _ in paths[1:]:  # a second entry would be searched too: point it at the same path
        struct.pack_into('<qQ', data, other_at, DT_RPATH, start)
    with open(path, 'r+b') as f:
        f.write(data)
    return old.decode(errors='replace')


def main(argv):
    if len(argv) < 2 or argv[1] in ('-h', '--help'):
        print(__doc__.strip())
        return 0 if len(argv) >= 2 else 2
    status = 0
    for path in argv[1:]:
        try:
            old = set_origin(path)
        except (OSError, ElfError) as e:
            print('set_rpath.py: %s: %s' % (path, e), file=sys.stderr)
            status = 1
            continue
        print('%s: %s' % (path, "'%s' -> '$ORIGIN'" % old if old is not None else 'no search path (left alone)'))
    return status


if __name__ == '__main__':
    sys.exit(main(sys.argv))
