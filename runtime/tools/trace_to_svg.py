#!/usr/bin/env python3
"""Draw a perma trace (Chrome trace event JSON) as an SVG timeline.

usage: perma-trace-to-svg TRACE.json OUT.svg [--title TEXT]

One row per track (work-group or host steps), one box per batch, coloured by
procedure; a legend lists the procedures with their batch and item counts.
The same file opens in Perfetto (ui.perfetto.dev) or chrome://tracing.
A run writes a trace when PERMA_TRACE names a file (or perma_config.trace_path).
Installed as perma-trace-to-svg; in the source tree runtime/tools/trace_to_svg.py.

exit status: 0 ok, 1 a trace without events, 2 bad usage
"""
import json
import sys

# meson writes perma's version here in the installed copy (perma-trace-to-svg).
VERSION = '@VERSION@'

PALETTE = ['#4e79a7', '#f28e2b', '#e15759', '#76b7b2', '#59a14f', '#edc948', '#b07aa1', '#ff9da7',
           '#9c755f', '#bab0ac']


def main(argv):
    if len(argv) == 2 and argv[1] in ('--help', '-h'):
        sys.stdout.write(__doc__)
        return 0
    if len(argv) == 2 and argv[1] == '--version':
        print('perma-trace-to-svg %s' % ('(source tree)' if VERSION.startswith('@') else VERSION))
        return 0
    if len(argv) < 3:
        sys.stderr.write(__doc__)
        return 2
    title = argv[argv.index('--title') + 1] if '--title' in argv else argv[1]
    with open(argv[1], encoding='utf-8') as f:
        trace = json.load(f)
    events = [e for e in trace['traceEvents'] if e.get('ph') == 'X']
    names = {e['tid']: e['args']['name'] for e in trace['traceEvents']
             if e.get('ph') == 'M' and e.get('name') == 'thread_name'}
    if not events:
        sys.stderr.write('no events in %s\n' % argv[1])
        return 1
    tracks = sorted({e['tid'] for e in events})
    procs = []
    totals = {}
    for e in events:
        if e['name'] not in procs:
            procs.append(e['name'])
        count, items = totals.get(e['name'], (0, 0))
        totals[e['name']] = (count + 1, items + e['args']['items'])
    start = min(e['ts'] for e in events)
    end = max(e['ts'] + e['dur'] for e in events)
    width, left, row, top = 1200, 110, 34, 50
    scale = (width - left - 20) / max(end - start, 1e-9)
    height = top + row * len(tracks) + 40 + 18 * len(procs)
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" font-family="sans-serif" '
           'font-size="12">' % (width, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="10" y="22" font-size="15">%s</text>' % title,
           '<text x="10" y="40" fill="#555">clock: %s; %d batches</text>'
           % (trace.get('otherData', {}).get('clock', ''), len(events))]
    for i, tid in enumerate(tracks):
        y = top + i * row
        out.append('<text x="10" y="%d">%s</text>' % (y + row // 2 + 4, names.get(tid, 'track %d' % tid)))
        out.append('<rect x="%d" y="%d" width="%d" height="%d" fill="#f3f3f3"/>'
                   % (left, y + 4, width - left - 20, row - 8))
    for e in events:
        y = top + tracks.index(e['tid']) * row
        x = left + (e['ts'] - start) * scale
        w = max(e['dur'] * scale, 0.5)
        colour = PALETTE[procs.index(e['name']) % len(PALETTE)]
        opacity = '0.55' if e['args'].get('kind') == 'steal' else '1'
        out.append('<rect x="%.2f" y="%d" width="%.2f" height="%d" fill="%s" fill-opacity="%s"/>'
                   % (x, y + 6, w, row - 12, colour, opacity))
    y = top + row * len(tracks) + 24
    for i, name in enumerate(procs):
        count, items = totals[name]
        out.append('<rect x="10" y="%d" width="12" height="12" fill="%s"/>'
                   % (y + 18 * i - 10, PALETTE[i % len(PALETTE)]))
        out.append('<text x="28" y="%d">%s: %d batches, %d items</text>' % (y + 18 * i, name, count, items))
    out.append('</svg>')
    with open(argv[2], 'w', encoding='utf-8') as f:
        f.write('\n'.join(out) + '\n')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
