#!/usr/bin/env python3
"""Run the Python binding's tests (the meson suite `python`) with pytest.

usage: run_pytest.py TEST_DIR [PYTEST ARGS...]

Exits 77 (meson: skipped) with a message when numpy or pytest is missing
for this Python.
"""
import sys

missing = []
for module in ('numpy', 'pytest'):
    try:
        __import__(module)
    except ImportError:
        missing.append(module)
if missing:
    print('skipped: %s not installed for %s (Debian: apt-get install %s, or .ci/install-deps)'
          % (' and '.join(missing), sys.executable, ' '.join('python3-' + m for m in missing)))
    sys.exit(77)

import pytest  # noqa: E402

# No cache directory in the source tree; -rs lists skipped tests with their reason.
sys.exit(pytest.main(['-p', 'no:cacheprovider', '-rs', '-v'] + sys.argv[1:]))
