#!/usr/bin/env python3
"""Bucketed Reyes renders on 1 vs 2 devices and ranks, side by side, and the
inputs of the N-node speedup model (docs/scale-out.md).

usage: scale_out.py [--build DIR] [--repeat N] [--size WxH] [--bucket WxH] [--spp N]
                    [--mpirun PATH|none] [--cold-build SECONDS]

Every configuration renders the same image; the rounds interleave the
configurations (round 1: all of them, round 2: all of them, ...) so that
the machine's drifting load hits them alike, and each row reports the best
of its rounds.  Every image is compared with the one-device render, byte
for byte.  `wall` is the whole process (start, MPI start-up, runtime
creation with the kernel from PoCL's cache, the crack-stitching pass,
buckets, PNG); `render` is what reyes-render reports (its start to the
last bucket); `CPU` is the user + system seconds of all its processes,
which a busy machine changes less than wall time.  Then the model's inputs from the one-device run's --stats:
bucket count, per-bucket render times, the fixed part (wall - sum of the
bucket times), the bytes of one tile message, and the per-bucket message
overhead a remote rank sees (turnaround at rank 0 - its render time), each
from the fastest round of its row; mpirun's start-up and finalisation M
(the `mpirun -n 1` row's wall - render, less the one-device row's); and the
model's predicted speedups on warm program caches and, for a first job of a
new program, with a cold build of --cold-build seconds on every node (default
40; benchmarks/cold_farm.py measures one).
"""
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time


def parse_args(argv):
    args = {'build': 'build', 'repeat': 3, 'size': '512x512', 'bucket': '64x64', 'spp': '4',
            'mpirun': None, 'cold-build': '40'}
    i = 1
    while i < len(argv):
        key = argv[i].lstrip('-')
        if key in ('help', 'h'):
            print(__doc__)
            sys.exit(0)
        if key not in args or i + 1 >= len(argv):
            sys.exit('scale_out.py: unknown option or missing value: %s (try --help)' % argv[i])
        args[key] = argv[i + 1]
        i += 2
    args['repeat'] = int(args['repeat'])
    args['cold-build'] = float(args['cold-build'])
    if args['mpirun'] is None:
        args['mpirun'] = next((os.path.join(d, 'mpirun') for d in os.environ.get('PATH', '').split(':')
                               if os.access(os.path.join(d, 'mpirun'), os.X_OK)), 'none')
    return args


def mpirun(args, ranks):
    return [args['mpirun'], '--oversubscribe', '--allow-run-as-root', '--bind-to', 'none',
            '--mca', 'btl', 'self,vader', '--mca', 'oob_tcp_if_include', 'lo', '--timeout', '600',
            '-n', str(ranks)]


ONE_DEVICE = '--devices 0:0 (1 device, 2 groups)'
REMOTE = 'mpirun -n 3 --coordinator-only --devices 0:0/2'


def configurations(args):
    """(label, renderers, command prefix, extra options); ONE_DEVICE and
    REMOTE also write --stats, the model's inputs."""
    rows = [
        ('one device 0:0 (2 groups), no scale-out code', 1, [], []),
        (ONE_DEVICE, 1, [], ['--devices', '0:0']),
        ('--devices 0:0/2.0 (half the CPU, 1 group)', 1, [], ['--devices', '0:0/2.0']),
        ('--devices 0:0/2 (2 sub-devices, 1 group each)', 2, [], ['--devices', '0:0/2']),
    ]
    if args['mpirun'] != 'none':
        rows += [
            ('mpirun -n 1 (rank 0 renders on 0:0)', 1, mpirun(args, 1), []),
            ('mpirun -n 2 --devices 0:0/2 (a half each)', 2, mpirun(args, 2), ['--devices', '0:0/2']),
            ('mpirun -n 2 (0:0 each: 4 groups on 2 cores)', 2, mpirun(args, 2), []),
            (REMOTE, 2, mpirun(args, 3), ['--coordinator-only', '--devices', '0:0/2']),
        ]
    return rows


def render_seconds(output):
    match = re.search(r'micropolygons, ([0-9.]+) s', output)
    return float(match.group(1)) if match else float('nan')


def main(argv):
    args = parse_args(argv)
    program = os.path.join(args['build'], 'examples', 'reyes', 'reyes-render')
    if not os.access(program, os.X_OK):
        sys.exit('scale_out.py: %s not found (build first, or pass --build DIR)' % program)
    common = ['--size', args['size'], '--bucket', args['bucket'], '--spp', args['spp']]
    rows = configurations(args)
    wall = {r[0]: [] for r in rows}
    render = {r[0]: [] for r in rows}
    cpu = {r[0]: [] for r in rows}
    with tempfile.TemporaryDirectory(prefix='perma-scale-') as tmp:
        reference = os.path.join(tmp, 'reference.png')
        subprocess.run([program, '-o', reference] + common, check=True, capture_output=True)
        identical = {r[0]: True for r in rows}
        stats = {}  # label -> (wall, --stats of that round) for the best round
        for _ in range(args['repeat']):
            for label, _, prefix, extra in rows:
                out_png = os.path.join(tmp, 'out.png')
                if label in (ONE_DEVICE, REMOTE):
                    extra = extra + ['--stats', os.path.join(tmp, 'stats.json')]
                start, before = time.monotonic(), resource.getrusage(resource.RUSAGE_CHILDREN)
                result = subprocess.run(prefix + [program, '-o', out_png] + common + extra,
                                        capture_output=True, text=True)
                elapsed, after = time.monotonic() - start, resource.getrusage(resource.RUSAGE_CHILDREN)
                cpu[label].append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
                if result.returncode != 0:
                    sys.exit('scale_out.py: %s failed:\n%s%s' % (label, result.stdout, result.stderr))
                wall[label].append(elapsed)
                render[label].append(render_seconds(result.stdout))
                with open(out_png, 'rb') as a, open(reference, 'rb') as b:
                    identical[label] = identical[label] and a.read() == b.read()
                if label in (ONE_DEVICE, REMOTE) and (label not in stats or elapsed < stats[label][0]):
                    with open(os.path.join(tmp, 'stats.json')) as f:
                        stats[label] = (elapsed, json.load(f))
    # The model's inputs, from the fastest round: per-bucket times on one
    # whole device, and a remote rank's turnaround at rank 0 against its
    # render time.
    one_wall, one = stats[ONE_DEVICE]
    remote = stats[REMOTE][1] if REMOTE in stats else None
    gaps = []

    base = min(wall[rows[0][0]])
    print('%s, %s buckets, spp %s; best of %d interleaved rounds\n' % (args['size'], args['bucket'],
                                                                    args['spp'], args['repeat']))
    base_cpu = min(cpu[rows[0][0]])
    print('| configuration | renderers | wall s | render s | wall vs one device | CPU s | CPU vs one device | image |')
    print('| --- | ---: | ---: | ---: | ---: | ---: | ---: | --- |')
    for label, renderers, _, _ in rows:
        w, r, c = min(wall[label]), min(render[label]), min(cpu[label])
        print('| %s | %d | %.2f | %.2f | %.2fx | %.2f | %.2fx | %s |'
              % (label, renderers, w, r, base / w, c, c / base_cpu,
                 'identical' if identical[label] else 'DIFFERS'))
    times = one['item_seconds']
    width, height = (int(v) for v in args['bucket'].split('x'))
    tile_bytes = 24 + 4 * width * height
    print('\nmodel inputs (--devices 0:0 and --coordinator-only rows, their fastest rounds, --stats):')
    print('  buckets B = %d, per-bucket render time: mean %.1f ms, median %.1f ms, max %.1f ms, sum %.2f s'
          % (len(times), 1e3 * statistics.mean(times), 1e3 * statistics.median(times), 1e3 * max(times),
             sum(times)))
    renderer = one['renderers'][0]
    print('  wall %.2f s, fixed part (wall - sum of buckets) %.2f s, of which making the renderer %.2f s '
          'and, to its first bucket, building the program (from PoCL\'s cache) and the stitching pass %.2f s'
          % (one_wall, one_wall - sum(times), renderer['create_seconds'], renderer['first_seconds']))
    print('  tile message: %d bytes (24-byte header + 4 bytes per pixel), request/answer 4 bytes each'
          % tile_bytes)
    if remote:
        gaps = [t - r for t, r, who in zip(remote['item_turnaround'], remote['item_seconds'],
                                           remote['item_renderer']) if who > 0]
        if gaps:
            print('  remote rank, per bucket: turnaround - render time: mean %.2f ms, median %.2f ms'
                  % (1e3 * statistics.mean(gaps), 1e3 * statistics.median(gaps)))
    # The model (docs/scale-out.md): N nodes with one such device each,
    # buckets handed out one at a time, started by mpirun (M) after a build
    # of C seconds on every node (in parallel; 0 on warm caches).
    # T(1) = C + F + S; T(N) between M + C + F + max((S + B m) / N, t_max)
    # and M + C + F + (S + B m) / N + t_max.
    fixed, total, longest = one_wall - sum(times), sum(times), max(times)
    start_up = 0.0
    mpi_one = 'mpirun -n 1 (rank 0 renders on 0:0)'
    if mpi_one in wall:
        start_up = max(0.0, (min(wall[mpi_one]) - min(render[mpi_one]))
                       - (min(wall[ONE_DEVICE]) - min(render[ONE_DEVICE])))
        print('  mpirun start-up and finalisation M = %.2f s (wall - render of the mpirun -n 1 row, less the '
              'one-device row\'s)' % start_up)
    links = [('m measured here (shared memory): %.2f ms' % (1e3 * statistics.mean(gaps)) if gaps
              else 'm = 1 ms (not measured)', statistics.mean(gaps) if gaps else 1e-3),
             ('1 GbE: m = 2 x 50 us + %d B at 117 MB/s' % tile_bytes, 2 * 50e-6 + tile_bytes / 117e6),
             ('InfiniBand: m = 2 x 2 us + %d B at 10 GB/s' % tile_bytes, 2 * 2e-6 + tile_bytes / 10e9)]
    for cold in (0.0, args['cold-build']):
        print('\npredicted speedup T(1) / T(N), lower - upper bound, %s:\n'
              % ('warm program caches' if cold == 0.0 else 'a new program: a %g s build on every node' % cold))
        print('| N | ' + ' | '.join(name for name, _ in links) + ' |')
        print('| ---: | ' + ' | '.join('---' for _ in links) + ' |')
        for n in (1, 2, 4, 8, 16, 32, 64):
            cells = []
            for _, m in links:
                spread = (total + len(times) * m) / n if n > 1 else total
                launch = start_up if n > 1 else 0.0
                best = launch + cold + fixed + max(spread, longest)
                worst = launch + cold + fixed + spread + (longest if n > 1 else 0.0)
                cells.append('%.2f - %.2f' % ((cold + fixed + total) / worst, (cold + fixed + total) / best))
            print('| %d | %s |' % (n, ' | '.join(cells)))
    return 0 if all(identical.values()) else 1


if __name__ == '__main__':
    sys.exit(main(sys.argv))
