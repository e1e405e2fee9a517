#!/usr/bin/env python3
"""Write a man page (section 1) from a program's --help text.

usage: help_to_man.py --name NAME --summary TEXT --source TEXT --output FILE
                      [--see-also TEXT] -- COMMAND [ARGS...]

Runs `COMMAND ARGS... --help` (a lone COMMAND runs with NAME as argv[0], so
that a usage line printing argv[0] names the installed program) and turns
its text into roff:

  - the "usage:" line and the indented lines right after it: SYNOPSIS;
  - a line "NAME:" at the left margin ("options:", "commands:"): a
    subsection, whose indented lines "TERM   TEXT" become tagged paragraphs
    (TEXT starting at the column most items of the list use, or after two
    spaces), a line indented to that column continuing the previous one;
  - a line at the left margin starting "exit status" (any case), and the
    lines after it up to a blank line: EXIT STATUS;
  - everything else: DESCRIPTION, one paragraph per block of lines.

A program whose --help fails (exit status not 0, or no usage line) fails
the build rather than installing an empty page.
"""
import collections
import re
import subprocess
import sys


def escape(text):
    """Roff-safe text: backslashes, and a leading control character."""
    text = text.replace('\\', '\\e')
    return '\\&' + text if text.startswith(('.', "'")) else text


def term(text):
    """An option or command as roff: bold names, hyphens as minus signs."""
    return '\\fB' + escape(text).replace('-', '\\-') + '\\fR'


def split_item(line, column):
    """(term, text) of an indented list line; text '' if it has none."""
    if column and len(line) > column and line[column - 1] == ' ' and line[column] != ' ' \
            and line[:column].strip():
        return line[:column].strip(), line[column:].strip()
    match = re.match(r'\s*(\S.*?)\s{2,}(\S.*)$', line)
    return (match.group(1), match.group(2)) if match else (line.strip(), '')


def text_column(lines):
    """The column where most "TERM  TEXT" lines of a list start their text."""
    columns = collections.Counter()
    for line in lines:
        match = re.match(r'(\s+\S.*?\s{2,})\S', line)
        if match:
            columns[len(match.group(1))] += 1
    return columns.most_common(1)[0][0] if columns else 0


def blocks(lines):
    """Split lines into blocks separated by blank lines and by headings."""
    block = []
    for line in lines:
        if not line.strip():
            if block:
                yield block
            block = []
        elif re.match(r'[A-Za-z][\w -]*:$', line) and block:
            yield block
            block = [line]
        else:
            block.append(line)
    if block:
        yield block


def convert(help_text, name, summary, source, see_also):
    lines = help_text.expandtabs().rstrip().split('\n')
    usage_at = next((i for i, line in enumerate(lines) if line.lower().startswith('usage:')), None)
    if usage_at is None:
        raise ValueError('%s --help has no "usage:" line' % name)
    end = usage_at + 1
    while end < len(lines) and lines[end].startswith(' ') and lines[end].strip() \
            and not lines[end].strip().startswith('-'):
        end += 1
    synopsis = [lines[usage_at][len('usage:'):].strip()] + [line.strip() for line in lines[usage_at + 1:end]]
    rest = lines[:usage_at] + lines[end:]

    out = ['.TH %s 1 "" "%s" "User Commands"' % (name.upper(), escape(source)),
           '.SH NAME', '%s \\- %s' % (escape(name).replace('-', '\\-'), escape(summary)),
           '.SH SYNOPSIS']
    for i, line in enumerate(synopsis):
        if i:
            out.append('.br')
        words = line.split(' ', 1)
        out.append(term(words[0]) + (' ' + escape(words[1]) if len(words) > 1 else ''))
    description, exit_status = describe(rest)
    out += ['.SH DESCRIPTION'] + description
    if exit_status:
        text = re.sub(r'(?i)^exit status:?\s*', '', ' '.join(exit_status))
        out += ['.SH EXIT STATUS', escape(text[:1].upper() + text[1:])]
    if see_also:
        # \% keeps a word whole: no program name or path split at a line end.
        out += ['.SH SEE ALSO', ' '.join('\\%' + escape(word).replace('-', '\\-') for word in see_also.split())]
    return '\n'.join(out) + '\n'


def describe(lines):
    """The roff of the help text besides the usage, and its exit status lines."""
    out, exit_status = [], []
    for block in blocks(lines):
        heading = re.match(r'([A-Za-z][\w -]*):$', block[0])
        if heading:
            out.append('.SS %s' % escape(heading.group(1).capitalize()))
            block = block[1:]
        column = text_column(block)
        state, item_indent = None, 0
        for line in block:
            indent = len(line) - len(line.lstrip())
            if state == 'exit' or (not indent and line.lower().startswith('exit status')):
                exit_status.append(line.strip())
                state = 'exit'
            elif not indent:
                if state != 'text':
                    out.append('.PP')
                out.append(escape(line.strip()))
                state = 'text'
            elif state == 'list' and (indent >= column if column else
                                      indent > item_indent and not line.lstrip().startswith('-')):
                out.append(escape(line.strip()))
            else:
                item, text = split_item(line, column)
                out += ['.TP', term(item)] + ([escape(text)] if text else [])
                state, item_indent = 'list', indent
    return out, exit_status


def main(argv):
    options = {'--name': None, '--summary': None, '--source': None, '--output': None, '--see-also': ''}
    if '--' not in argv:
        sys.stderr.write(__doc__)
        return 2
    split = argv.index('--')
    args, command = argv[1:split], argv[split + 1:]
    for i in range(0, len(args) - 1, 2):
        if args[i] not in options:
            sys.stderr.write('help_to_man.py: unknown option %s\n' % args[i])
            return 2
        options[args[i]] = args[i + 1]
    if not command or None in options.values():
        sys.stderr.write(__doc__)
        return 2
    name = options['--name']
    if len(command) == 1:
        result = subprocess.run([name, '--help'], executable=command[0], capture_output=True, text=True)
    else:
        result = subprocess.run(command + ['--help'], capture_output=True, text=True)
    if result.returncode != 0:
        sys.stderr.write('help_to_man.py: %s --help exited with status %d:\n%s%s'
                         % (' '.join(command), result.returncode, result.stdout, result.stderr))
        return 1
    try:
        page = convert(result.stdout, name, options['--summary'], options['--source'], options['--see-also'])
    except ValueError as error:
        sys.stderr.write('help_to_man.py: %s\n' % error)
        return 1
    with open(options['--output'], 'w', encoding='utf-8') as f:
        f.write(page)
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
