#!/usr/bin/env python3
"""Summarise a perma trace (Chrome trace event JSON) and draw it as an SVG timeline.

usage: perma-trace-to-svg TRACE.json [OUT.svg] [--title TEXT] [--json]

Prints, for each run in the file, per procedure: the time its batches kept
work-groups busy, its share of the run's group time, its batches and items,
and the batches taken by stealing and the donations; then the share of the
group time no batch ran (idle).  Work of the work-first stacks as a whole
(batches that only ran stacks, shares the stacks gave another group) is
listed as the procedure "(stacks)".  --json prints the same as one JSON object.
With OUT.svg it also draws one row per track (work-group, or host steps) of
every run, one box per batch, coloured by procedure.  The same file opens
in Perfetto (ui.perfetto.dev) or chrome://tracing.  A run writes a trace when
PERMA_TRACE names a file (or perma_config.trace_path; reyes-render and
perma-bench take --trace FILE).  Installed as perma-trace-to-svg; in the
source tree runtime/tools/trace_to_svg.py.

exit status: 0 ok, 1 a trace that cannot be read or has no events, 2 bad usage
"""
import json
import sys

# meson writes perma's version here in the installed copy (perma-trace-to-svg).
VERSION = '@VERSION@'

PALETTE = ['#4e79a7', '#f28e2b', '#e15759', '#76b7b2', '#59a14f', '#edc948', '#b07aa1', '#ff9da7',
           '#9c755f', '#bab0ac']


class Run:
    """One perma_run: its process metadata and its batches."""

    def __init__(self, pid):
        self.pid = pid
        self.name = 'run %d' % pid
        self.start_us = None
        self.seconds = None
        self.groups = None
        self.schedule = ''
        self.tracks = {}       # tid -> name
        self.events = []

    def span(self):
        """Start and length of the run in microseconds: its own, else its batches'."""
        if self.start_us is not None and self.seconds is not None:
            return self.start_us, self.seconds * 1e6
        start = min(e['ts'] for e in self.events)
        return start, max(e['ts'] + e['dur'] for e in self.events) - start

    def summary(self):
        start, length = self.span()
        tracks = self.groups if self.groups else max(len(self.tracks), 1)
        procedures = {}
        for e in self.events:
            p = procedures.setdefault(e['name'], {'busy_seconds': 0.0, 'batches': 0, 'items': 0, 'steals': 0,
                                                  'donations': 0, 'donated_items': 0})
            kind = e['args'].get('kind', 'run')
            if kind == 'donate':
                p['donations'] += 1
                p['donated_items'] += e['args']['items']
            else:
                p['batches'] += 1
                p['items'] += e['args']['items']
                p['steals'] += kind == 'steal'
            p['busy_seconds'] += e['dur'] * 1e-6
        capacity = tracks * length * 1e-6
        busy = sum(p['busy_seconds'] for p in procedures.values())
        for p in procedures.values():
            p['share'] = p['busy_seconds'] / capacity if capacity > 0 else 0.0
        return {'run': self.pid, 'name': self.name, 'schedule': self.schedule, 'start_seconds': start * 1e-6,
                'seconds': length * 1e-6, 'tracks': tracks, 'procedures': procedures,
                'idle_share': max(0.0, 1.0 - busy / capacity) if capacity > 0 else 0.0}


def read_runs(path):
    with open(path, encoding='utf-8') as f:
        trace = json.load(f)
    runs = {}
    for e in trace['traceEvents']:
        run = runs.setdefault(e.get('pid', 1), Run(e.get('pid', 1)))
        if e.get('ph') == 'M' and e.get('name') == 'process_name':
            args = e.get('args', {})
            run.name = args.get('name', run.name)
            run.start_us = args.get('start_us')
            run.seconds = args.get('seconds')
            run.groups = args.get('work_groups')
            run.schedule = args.get('schedule', '')
        elif e.get('ph') == 'M' and e.get('name') == 'thread_name':
            run.tracks[e['tid']] = e['args']['name']
        elif e.get('ph') == 'X':
            run.events.append(e)
    return trace, [runs[pid] for pid in sorted(runs) if runs[pid].events]


def print_summary(summaries, out):
    for s in summaries:
        out.write('%s: %.6f s from %.6f s, %d track(s)\n' % (s['name'], s['seconds'], s['start_seconds'],
                                                           s['tracks']))
        out.write('  %-20s %10s %7s %9s %12s %8s %10s\n' % ('procedure', 'busy s', 'share', 'batches', 'items',
                                                           'steals', 'donations'))
        for name, p in s['procedures'].items():
            out.write('  %-20s %10.6f %6.1f%% %9d %12d %8d %10d\n' % (name, p['busy_seconds'], 100 * p['share'],
                                                                     p['batches'], p['items'], p['steals'],
                                                                     p['donations']))
        out.write('  %-20s %10s %6.1f%%\n' % ('idle', '', 100 * s['idle_share']))


def draw(runs, trace, path, title):
    rows = [(run, tid) for run in runs for tid in sorted({e['tid'] for e in run.events})]
    events = [e for run in runs for e in run.events]
    procs = []
    for e in events:
        if e['name'] not in procs:
            procs.append(e['name'])
    start = min(e['ts'] for e in events)
    end = max(e['ts'] + e['dur'] for e in events)
    width, left, row, top = 1200, 170, 34, 50
    scale = (width - left - 20) / max(end - start, 1e-9)
    height = top + row * len(rows) + 40 + 18 * len(procs)
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" '
           'font-size="12">' % (width, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="10" y="22" font-size="15">%s</text>' % title,
           '<text x="10" y="40" fill="#555">%d run(s), %d batches, %.3f ms; clock: %s</text>'
           % (len(runs), len(events), (end - start) / 1000, trace.get('otherData', {}).get('clock', ''))]
    index = {}
    for i, (run, tid) in enumerate(rows):
        y = top + i * row
        index[(run.pid, tid)] = y
        label = '%s%s' % ('run %d, ' % run.pid if len(runs) > 1 else '', run.tracks.get(tid, 'track %d' % tid))
        out.append('<text x="10" y="%d">%s</text>' % (y + row // 2 + 4, label))
        out.append('<rect x="%d" y="%d" width="%d" height="%d" fill="#f3f3f3"/>'
                   % (left, y + 4, width - left - 20, row - 8))
    for run in runs:
        for e in run.events:
            y = index[(run.pid, e['tid'])]
            x = left + (e['ts'] - start) * scale
            w = max(e['dur'] * scale, 0.5)
            colour = PALETTE[procs.index(e['name']) % len(PALETTE)]
            opacity = '0.55' if e['args'].get('kind') == 'steal' else '1'
            out.append('<rect x="%.2f" y="%d" width="%.2f" height="%d" fill="%s" fill-opacity="%s"/>'
                       % (x, y + 6, w, row - 12, colour, opacity))
    y = top + row * len(rows) + 24
    totals = {}
    for e in events:
        count, items = totals.get(e['name'], (0, 0))
        totals[e['name']] = (count + 1, items + e['args']['items'])
    for i, name in enumerate(procs):
        count, items = totals[name]
        out.append('<rect x="10" y="%d" width="12" height="12" fill="%s"/>'
                   % (y + 18 * i - 10, PALETTE[i % len(PALETTE)]))
        out.append('<text x="28" y="%d">%s: %d batches, %d items</text>' % (y + 18 * i, name, count, items))
    out.append('</svg>')
    with open(path, 'w', encoding='utf-8') as f:
        f.write('\n'.join(out) + '\n')


def main(argv):
    args = argv[1:]
    if args in (['--help'], ['-h']):
        sys.stdout.write(__doc__)
        return 0
    if args == ['--version']:
        print('perma-trace-to-svg %s' % ('(source tree)' if VERSION.startswith('@') else VERSION))
        return 0
    title = None
    if '--title' in args:
        i = args.index('--title')
        if i + 1 >= len(args):
            sys.stderr.write(__doc__)
            return 2
        title = args[i + 1]
        del args[i:i + 2]
    as_json = '--json' in args
    args = [a for a in args if a != '--json']
    if not args or len(args) > 2 or any(a.startswith('--') for a in args):
        sys.stderr.write(__doc__)
        return 2
    try:
        trace, runs = read_runs(args[0])
    except (OSError, ValueError, KeyError) as error:
        sys.stderr.write('perma-trace-to-svg: cannot read %s: %s\n' % (args[0], error))
        return 1
    if not runs:
        sys.stderr.write('no events in %s\n' % args[0])
        return 1
    summaries = [run.summary() for run in runs]
    if as_json:
        json.dump({'runs': summaries}, sys.stdout, indent=1)
        sys.stdout.write('\n')
    else:
        print_summary(summaries, sys.stdout)
    if len(args) == 2:
        draw(runs, trace, args[1], title if title is not None else args[0])
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
