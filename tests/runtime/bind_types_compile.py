#!/usr/bin/env python3
"""PERMA_BIND_HOST_ARRAY at compile time: every supported element type
compiles without a warning, and an unsupported type or a pointer where an
array belongs does not compile, with a message that says why.

usage: bind_types_compile.py INCLUDE_DIR CC [CC ARGS...]
"""
import os
import re
import subprocess
import sys
import tempfile

PRELUDE = '''#include <stdint.h>
struct pair { int32_t key; float value; };
#define PERMA_HOST_TYPE_NAMES struct pair: "struct pair",
#include <perma.h>
'''

GOOD = PRELUDE + '''
int bind_all(perma_runtime *rt)
{
    static char c[2]; static signed char sc[2]; static unsigned char uc[2];
    static short s[2]; static unsigned short us[2]; static int i[2]; static unsigned u[2];
    static long l[2]; static unsigned long ul[2]; static long long ll[2]; static unsigned long long ull[2];
    static float f[2]; static double d[2]; static int64_t i64[2]; static size_t z[2];
    static cl_float2 f2[2]; static cl_float4 f4[2]; static cl_float8 f8[2]; static cl_float16 f16[2];
    static cl_double2 d2[2]; static cl_double4 d4[2]; static cl_int2 i2[2]; static cl_int4 i4[2];
    static cl_uint2 u2[2]; static cl_uint4 u4[2]; static cl_uchar4 uc4[2]; static struct pair p[2];
    struct pair *heap = 0;
    return PERMA_BIND_HOST_ARRAY(rt, "c", c, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "sc", sc, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "uc", uc, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "s", s, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "us", us, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "i", i, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "u", u, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "l", l, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "ul", ul, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "ll", ll, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "ull", ull, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "f", f, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "d", d, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "i64", i64, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "z", z, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "f2", f2, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "f4", f4, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "f8", f8, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "f16", f16, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "d2", d2, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "d4", d4, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "i2", i2, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "i4", i4, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "u2", u2, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "u4", u4, PERMA_READ) + PERMA_BIND_HOST_ARRAY(rt, "uc4", uc4, PERMA_READ)
         + PERMA_BIND_HOST_ARRAY(rt, "p", p, PERMA_READ_WRITE)
         + PERMA_BIND_HOST_POINTER(rt, "heap", heap, 10, PERMA_READ_WRITE);
}
'''

# name, source, what the compiler must say
BAD = [
    ('unsupported struct', PRELUDE + '''
struct other { int x; };
int bind(perma_runtime *rt) { static struct other o[2]; return PERMA_BIND_HOST_ARRAY(rt, "o", o, PERMA_READ); }
''', r"_Generic|generic association|not compatible with any"),
    ('pointer element', PRELUDE + '''
int bind(perma_runtime *rt) { static float *rows[2]; return PERMA_BIND_HOST_ARRAY(rt, "rows", rows, PERMA_READ); }
''', r"_Generic|generic association|not compatible with any"),
    ('two-dimensional array', PRELUDE + '''
int bind(perma_runtime *rt) { static float grid[4][4]; return PERMA_BIND_HOST_ARRAY(rt, "g", grid, PERMA_READ); }
''', r"_Generic|generic association|not compatible with any"),
    ('pointer instead of an array', PRELUDE + '''
int bind(perma_runtime *rt, float *values) { return PERMA_BIND_HOST_ARRAY(rt, "v", values, PERMA_READ); }
''', r"PERMA_BIND_HOST_ARRAY needs an array; use PERMA_BIND_HOST_POINTER"),
]


def compile_source(compiler, include, directory, name, source):
    path = os.path.join(directory, name + '.c')
    with open(path, 'w', encoding='utf-8') as f:
        f.write(source)
    command = compiler + ['-std=c11', '-Wall', '-Wextra', '-Werror', '-I', include, '-c', path,
                          '-o', os.path.join(directory, name + '.o')]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    return result.returncode, result.stdout + result.stderr


def main(argv):
    if len(argv) < 3:
        sys.stderr.write(__doc__)
        return 2
    include, compiler = argv[1], argv[2:]
    failures = 0
    with tempfile.TemporaryDirectory() as directory:
        status, output = compile_source(compiler, include, directory, 'good', GOOD)
        if status != 0:
            print('the supported types did not compile cleanly:\n' + output)
            failures += 1
        for i, (name, source, pattern) in enumerate(BAD):
            status, output = compile_source(compiler, include, directory, 'bad%d' % i, source)
            if status == 0:
                print('%s: compiled, but must not' % name)
                failures += 1
            elif not re.search(pattern, output):
                print('%s: the compiler did not say %r:\n%s' % (name, pattern, output))
                failures += 1
            else:
                print('%s: refused: %s' % (name, next((line for line in output.splitlines()
                                                        if re.search(pattern, line)), '').strip()))
    print('%d passed, %d failed' % (1 + len(BAD) - failures, failures))
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
