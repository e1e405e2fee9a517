#!/usr/bin/env python3
"""Print the directory under PREFIX (argv[1]) where this Python finds packages.

The first site-packages or dist-packages entry of sys.path below PREFIX/lib,
or nothing.  meson's python module would install a pure package into
PREFIX/lib/python3/dist-packages on Debian, a directory Debian's python3
searches only for PREFIX /usr: under /usr/local it looks in
/usr/local/lib/python3.X/dist-packages.
"""
import os
import sys

prefix = os.path.normpath(sys.argv[1])
for entry in sys.path:
    if os.path.basename(entry) in ('site-packages', 'dist-packages') \
            and os.path.normpath(entry).startswith(os.path.join(prefix, 'lib') + os.sep):
        print(os.path.normpath(entry))
        break
