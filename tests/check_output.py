#!/usr/bin/env python3
"""Run a program and check its exit code and that its output matches patterns.

usage: check_output.py [--status N] [--expect REGEX ...] [--reject REGEX ...]
                       [--skip-when REGEX ...] -- PROGRAM [ARGS...]

--skip-when: if the output matches REGEX, the test is skipped (exit 77, which
meson reports as SKIP) and the matching line is printed as the reason: for a
check that needs something of the device (a device that splits in two, say)
which the machine may not offer.
"""
import re
import subprocess
import sys


def main(argv):
    if '--' not in argv:
        sys.stderr.write(__doc__)
        return 2
    split = argv.index('--')
    options, command = argv[1:split], argv[split + 1:]
    expected_status, patterns, rejected, skips = 0, [], [], []
    i = 0
    while i < len(options):
        if options[i] == '--status':
            expected_status = int(options[i + 1])
        elif options[i] == '--expect':
            patterns.append(options[i + 1])
        elif options[i] == '--reject':
            rejected.append(options[i + 1])
        elif options[i] == '--skip-when':
            skips.append(options[i + 1])
        else:
            sys.stderr.write('unknown option %s\n' % options[i])
            return 2
        i += 2
    result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    output = result.stdout + result.stderr
    for pattern in skips:
        found = re.search('^.*(' + pattern + ').*$', output, re.MULTILINE)
        if found:
            print('SKIP: %s' % found.group(0))
            return 77
    ok = True
    if result.returncode != expected_status:
        print('exit status %d, expected %d' % (result.returncode, expected_status))
        ok = False
    for pattern in patterns:
        if not re.search(pattern, output, re.MULTILINE):
            print('output does not match %r' % pattern)
            ok = False
    for pattern in rejected:
        if re.search(pattern, output, re.MULTILINE):
            print('output matches %r, which it must not' % pattern)
            ok = False
    if not ok:
        print('--- output of %s ---\n%s' % (' '.join(command), output))
        return 1
    print('1 passed, 0 failed')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
