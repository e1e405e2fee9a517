#!/usr/bin/env python3
"""The documents read as reference: README.md and docs/*.md.

usage: docs_check.py SOURCE_ROOT

Each page is at most 600 lines; names no commit hash, issue number or
machine load (the measurement history lives in dated notes under
benchmarks/results/); and each relative link names a file that exists.
Prints every finding as FILE:LINE: what, and exits 1 when there is one.
"""
import os
import re
import sys

MAX_LINES = 600
# A commit hash: 7 to 40 hex digits with both a digit and a letter, as a word.
HASH = re.compile(r'(?<![\w.#/-])(?=[0-9a-f]*[a-f])(?=[0-9a-f]*[0-9])[0-9a-f]{7,40}(?![\w-])')
ISSUE = re.compile(r'\b[Ii]ssues? ?#?[0-9]+|\bwip-[0-9]+')
LOAD = re.compile(r'\bload (average )?(of |about |is )?[0-9]|\bloaded machine|\bload [0-9.]+ (to|-)')
LINK = re.compile(r'\]\(([^)\s]+)\)')


def pages(root):
    docs = os.path.join(root, 'docs')
    return [os.path.join(root, 'README.md')] + sorted(
        os.path.join(docs, name) for name in os.listdir(docs) if name.endswith('.md'))


def check(path, root):
    findings = []
    with open(path, encoding='utf-8') as f:
        lines = f.read().split('\n')
    if lines and lines[-1] == '':
        lines.pop()
    where = os.path.relpath(path, root)
    if len(lines) > MAX_LINES:
        findings.append('%s: %d lines, at most %d' % (where, len(lines), MAX_LINES))
    for number, line in enumerate(lines, 1):
        for pattern, what in ((HASH, 'a commit hash'), (ISSUE, 'an issue number'), (LOAD, 'the machine load')):
            found = pattern.search(line)
            if found:
                findings.append('%s:%d: %s (%r)' % (where, number, what, found.group(0)))
        for target in LINK.findall(line):
            if re.match(r'[a-z]+:|#', target):
                continue
            file = os.path.normpath(os.path.join(os.path.dirname(path), target.split('#')[0]))
            if not os.path.exists(file):
                findings.append('%s:%d: the link %s names no file' % (where, number, target))
    return findings


def main(argv):
    if len(argv) != 2:
        sys.stderr.write(__doc__)
        return 2
    findings = [f for page in pages(argv[1]) for f in check(page, argv[1])]
    for finding in findings:
        print(finding)
    if findings:
        return 1
    print('%d pages: at most %d lines, no history, every relative link found' % (len(pages(argv[1])), MAX_LINES))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
