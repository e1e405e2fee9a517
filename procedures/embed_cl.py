#!/usr/bin/env python3
"""Embed a text file as a C string: embed_cl.py OUT.c VARNAME IN.cl

Writes `const char VARNAME[] = "...";` so OpenCL sources are compiled into
the binary and never read from disk at run time.
"""
import sys


def c_string_lines(text):
    for line in text.splitlines(keepends=True):
        escaped = (line.replace('\\', '\\\\').replace('"', '\\"')
                   .replace('\n', '\\n').replace('\t', '\\t'))
        yield '    "' + escaped + '"\n'


def main(argv):
    if len(argv) != 4:
        sys.stderr.write('usage: embed_cl.py OUT.c VARNAME IN.cl\n')
        return 2
    out_path, name, in_path = argv[1:4]
    with open(in_path, encoding='utf-8') as f:
        text = f.read()
    with open(out_path, 'w', encoding='utf-8') as out:
        out.write('/* Generated from %s by embed_cl.py; do not edit. */\n' % in_path)
        out.write('extern const char %s[];\n' % name)
        out.write('const char %s[] =\n' % name)
        out.writelines(c_string_lines(text) or ['    ""\n'])
        out.write('    "";\n')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
