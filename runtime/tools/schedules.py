#!/usr/bin/env python3
"""Every schedule of the schedule table (runtime/src/schedules.def), in the
order of perma_schedule_all, for meson at configure time (before libperma
exists) and for scripts.

    schedules.py [MODE]           one canonical label a line
    schedules.py --variants MODE  one test variant a line: NAME|ENV,ENV,...

MODE (default 'all') is the perma_schedule_set: which victims get a
schedule of their own: 'all' (every schedule), 'once' (the other victims
only under the first stealing strategy: the victim code is the same under
every stealing strategy) or 'default' (the default victim only).  A
variant's NAME is the label's parts joined with '-', leaving out the
default victim ('megakernel-stealing', 'megakernel-stealing-round-robin');
its ENV sets PERMA_TEST_TECHNIQUE / _STRATEGY / _VICTIM where they are not
the first (default) name.

The python suite checks that the labels equal perma_schedule_all's.
"""
import os
import re
import sys

DEF = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src', 'schedules.def')
ROW = re.compile(r'^PERMA_(TECHNIQUE|STRATEGY|VICTIM)_ROW\((.*)\)\s*$')


def rows():
    """{'TECHNIQUE': [(name, fields...)], ...} in file order, from the rows' C arguments."""
    table = {'TECHNIQUE': [], 'STRATEGY': [], 'VICTIM': []}
    with open(DEF, encoding='utf-8') as f:
        for line in f:
            match = ROW.match(line)
            if match:
                fields = [field.strip() for field in re.findall(r'"[^"]*"|[^,]+', match.group(2))]
                table[match.group(1)].append([field.strip('"') for field in fields[1:]])
    return table


def schedules():
    """(technique, strategy or None, victim or None, is the victim the default) in perma_schedule_all's order."""
    table = rows()
    victims = [row[0] for row in table['VICTIM']]
    for technique in table['TECHNIQUE']:
        if technique[1] != '1':  # the label takes no strategy
            yield technique[0], None, None
            continue
        for strategy in table['STRATEGY']:
            for victim in (victims if strategy[1] == '1' else [None]):
                yield technique[0], strategy[0], victim


def label(technique, strategy, victim):
    return '/'.join(part for part in (technique, strategy, victim) if part)


def selected(mode):
    """schedules() of a mode, with whether each victim is the default."""
    table = rows()
    first_victim = table['VICTIM'][0][0]
    stealing = [row[0] for row in table['STRATEGY'] if row[1] == '1']
    for technique, strategy, victim in schedules():
        other_victim = victim not in (None, first_victim)
        if other_victim and (mode == 'default' or (mode == 'once' and strategy != stealing[0])):
            continue
        yield (technique, strategy, victim), other_victim


def variants(mode):
    first = {kind: rows[0][0] for kind, rows in rows().items()}
    for (technique, strategy, victim), other_victim in selected(mode):
        parts = [technique, strategy, victim if other_victim else None]
        env = ['PERMA_TEST_%s=%s' % (kind, value)
               for kind, value in (('TECHNIQUE', technique), ('STRATEGY', strategy), ('VICTIM', victim))
               if value not in (None, first[kind])]
        yield '-'.join(part for part in parts if part), env


MODES = ('all', 'once', 'default')


def main(argv):
    if argv[1:2] == ['--variants'] and len(argv) == 3 and argv[2] in MODES:
        for name, env in variants(argv[2]):
            print('%s|%s' % (name, ','.join(env)))
    elif len(argv) <= 2 and argv[1:] in ([], ['all'], ['once'], ['default']):
        for schedule, _ in selected(argv[1] if len(argv) == 2 else 'all'):
            print(label(*schedule))
    else:
        sys.stderr.write('usage: schedules.py [all|once|default] | --variants all|once|default\n')
        return 2
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
