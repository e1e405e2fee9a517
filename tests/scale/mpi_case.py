#!/usr/bin/env python3
"""MPI tests of reyes-render and perma-queens (docs/scale-out.md).

usage: mpi_case.py CASE --mpirun MPIRUN|none --program PATH [--ranks N] [--workdir DIR]

Each case runs mpirun over loopback only (shared memory and self, the
runtime's own traffic on lo), every rank unbound, with a time limit, and
checks the result against a single-process run.  Without Open MPI
(--mpirun none: built with -Dmpi=disabled or mpirun not found) the case
is skipped (exit 77) with a message saying why.

Cases:
  buckets      reyes-render --bucket over N ranks: the one-process PNG bytes,
               and rank 0's --progress lines for the whole job
  frames       reyes-render --frames over N ranks: each frame's bytes, and
               rank 0's --progress lines
  bad-device   rank 1 on a missing device: exit 1, rank 0 names rank 1's error
  killed-rank  rank 1 killed mid-render: the job ends, rank 0 says so
  stuck-rank   rank 1 stopped mid-render: rank 0's --rank-timeout ends the job
  queens       perma-queens over N ranks, all work starting on rank 0: the
               known and the sequential count, every other rank stole work
  queens-bad-device  a rank of perma-queens on a missing device: exit 1,
               rank 0 names it
"""
import os
import re
import subprocess
import sys
import tempfile

SKIP = 77
LIMIT = 120  # seconds for one mpirun: the whole job, kill included


def mpirun_command(mpirun, ranks):
    return [mpirun, '--oversubscribe', '--allow-run-as-root', '--bind-to', 'none',
            '--mca', 'btl', 'self,vader', '--mca', 'oob_tcp_if_include', 'lo',
            '--timeout', str(LIMIT), '-n', str(ranks)]


def run(command, cwd, limit=LIMIT + 30):
    """Run; returns (exit status, output).  A job past the limit fails."""
    try:
        result = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=limit)
    except subprocess.TimeoutExpired as e:
        out = (e.stdout or b'').decode(errors='replace') + (e.stderr or b'').decode(errors='replace')
        raise SystemExit('FAIL: %s ran past %d s:\n%s' % (' '.join(command), limit, out))
    return result.returncode, result.stdout + result.stderr


def expect(condition, message, output=''):
    if not condition:
        raise SystemExit('FAIL: %s\n--- output ---\n%s' % (message, output))


def read(path):
    with open(path, 'rb') as f:
        return f.read()


def splittable(program, cwd):
    """Whether device 0:0 splits into two equal sub-devices (perma-info)."""
    info = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(program))), 'runtime', 'perma-info')
    if not os.path.exists(info):
        return False
    status, _ = run([info, '--devices', '0:0/2'], cwd, 120)
    return status == 0


RENDER = ['--size', '96x64', '--bucket', '16x16']


def expect_progress(out, count, unit):
    """Rank 0 alone drew the progress of the whole job: its first line, its
    last at 100 %, every line well formed, the items done never going back."""
    lines = re.findall(r'^reyes-render: (\d+)/(\d+) (\w+), ([0-9.]+)%, [0-9.]+ s elapsed(, about .* left)?$', out,
                       re.M)
    expect(len(re.findall(r'^reyes-render: \d+/', out, re.M)) == len(lines), 'a malformed progress line', out)
    expect(len(re.findall(r'^reyes-render: 0/%d %s, 0\.0%%' % (count, unit), out, re.M)) == 1,
           'not one progress line at the start (rank 0 only)', out)
    done = [int(line[0]) for line in lines]
    expect(done == sorted(done) and all(int(l[1]) == count and l[2] == unit for l in lines),
           'progress lines out of order or of the wrong job', out)
    expect(re.search(r'^reyes-render: %d/%d %s, 100\.0%%, [0-9.]+ s elapsed$' % (count, count, unit), out, re.M),
           'no progress line for the whole job at the end', out)


def case_buckets(args, tmp):
    alone = os.path.join(tmp, 'alone.png')
    spread = os.path.join(tmp, 'spread.png')
    status, out = run([args.program, '-o', alone] + RENDER, tmp)
    expect(status == 0, 'the one-process render failed', out)
    # Two ranks: rank 0 only coordinates, so every tile comes by message;
    # three: all render, on the halves of the CPU where it splits.
    if args.ranks == 2:
        extra = ['--coordinator-only']
    else:
        extra = ['--devices', '0:0/2'] if splittable(args.program, tmp) else []
    status, out = run(mpirun_command(args.mpirun, args.ranks) + [args.program, '-o', spread, '--progress'] + RENDER
                      + extra, tmp)
    expect(status == 0, 'mpirun -n %d failed' % args.ranks, out)
    expect_progress(out, 24, 'buckets')
    expect(read(alone) == read(spread), 'the %d-rank PNG differs from the one-process PNG' % args.ranks, out)
    expect(re.search(r'24 buckets on %d ranks' % args.ranks, out), 'no summary line', out)
    taken = [int(n) for n in re.findall(r'rank \d+, device \S+: (\d+) buckets', out)]
    renderers = args.ranks - (1 if extra == ['--coordinator-only'] else 0)
    expect(len(taken) == renderers and sum(taken) == 24, 'the ranks did not take 24 buckets', out)
    print(out)


def case_frames(args, tmp):
    frames = ['--frames', '3', '--orbit', '60', '--size', '64x48']
    status, out = run([args.program, '-o', os.path.join(tmp, 'alone.png')] + frames, tmp)
    expect(status == 0, 'the one-process frames failed', out)
    status, out = run(mpirun_command(args.mpirun, args.ranks)
                      + [args.program, '-o', os.path.join(tmp, 'spread.png'), '--coordinator-only', '--progress']
                      + frames, tmp)
    expect(status == 0, 'mpirun -n %d failed' % args.ranks, out)
    expect_progress(out, 3, 'frames')
    for f in range(1, 4):
        a, b = ('%s/%s-%04d.png' % (tmp, name, f) for name in ('alone', 'spread'))
        expect(read(a) == read(b), 'frame %d differs' % f, out)
    expect(re.search(r'3 frames on %d ranks' % args.ranks, out), 'no summary line', out)
    print(out)


def case_bad_device(args, tmp):
    out_png = os.path.join(tmp, 'bad.png')
    render = [args.program, '-o', out_png] + RENDER
    command = (mpirun_command(args.mpirun, 1) + render + [':', '-n', '1', 'env', 'PERMA_DEVICE=9:9']
               + render)
    status, out = run(command, tmp)
    expect(status == 1, 'exit status %d, expected 1' % status, out)
    expect(re.search(r"rank 1: --devices: device list '9:9': OpenCL platform 9 requested", out),
           "rank 0 did not report rank 1's error", out)
    expect(not os.path.exists(out_png), 'an image was written', out)
    print(out)


# Long enough that a rank killed after 3 s is killed mid-render (about
# 11 s in one process): 1024x768 at the default shading rate, or even with
# fixed 16x16 grids, finished in under 2.5 s on 2 ranks.
BIG = ['--size', '2048x1536', '--bucket', '32x32', '--spp', '16', '--grid', '16']


def case_killed_rank(args, tmp):
    render = [args.program, '-o', os.path.join(tmp, 'big.png')] + BIG
    command = mpirun_command(args.mpirun, 1) + render + [':', '-n', '1', 'timeout', '-s', 'KILL', '3'] + render
    status, out = run(command, tmp)
    expect(status != 0, 'the job succeeded', out)
    expect(re.search(r'rank 0: the job was stopped \(SIGTERM from mpirun: a rank died', out),
           'rank 0 did not say why the job stopped', out)
    expect(not os.path.exists(os.path.join(tmp, 'big.png')), 'an image was written', out)
    print(out)


def case_stuck_rank(args, tmp):
    render = [args.program, '-o', os.path.join(tmp, 'big.png'), '--rank-timeout', '3'] + BIG
    stop_later = ['sh', '-c', '"$@" & pid=$!; sleep 2; kill -STOP $pid; wait $pid', 'sh']
    command = mpirun_command(args.mpirun, 1) + render + [':', '-n', '1'] + stop_later + render
    status, out = run(command, tmp)
    expect(status != 0, 'the job succeeded', out)
    expect(re.search(r'rank 1 has (held bucket \d+|sent nothing) for more than 3 s \(--rank-timeout\); '
                     r'aborting the job', out), 'rank 0 did not name the stuck rank', out)
    print(out)


def case_queens(args, tmp):
    # Rank 0 starts with every subtree: the others only get work by asking.
    command = mpirun_command(args.mpirun, args.ranks) + [args.program, '--n', '12', '--depth', '3',
                                                         '--chunk', '4', '--start', 'rank0']
    status, out = run(command, tmp)
    expect(status == 0, 'mpirun -n %d perma-queens failed' % args.ranks, out)
    expect(re.search(r'^12-queens: 14200 solutions, 856189 nodes in .* on %d ranks .*sequential count agrees'
                     % args.ranks, out, re.M), 'wrong count', out)
    ranks = re.findall(r'^  rank \d+: (\d+) subtrees, (\d+) solutions, .* stole (\d+) times', out, re.M)
    expect(len(ranks) == args.ranks, 'not one line per rank', out)
    expect(sum(int(r[0]) for r in ranks) == 756, 'the ranks did not count the 756 subtrees', out)
    expect(sum(int(r[1]) for r in ranks) == 14200, 'the ranks\' solutions do not add up', out)
    expect(all(int(r[0]) > 0 for r in ranks), 'a rank counted no subtree (no stealing?)', out)
    expect(all(int(r[2]) > 0 for r in ranks[1:]), 'a rank other than 0 never stole', out)
    print(out)


def case_queens_bad_device(args, tmp):
    queens = [args.program, '--n', '10']
    command = mpirun_command(args.mpirun, 1) + queens + [':', '-n', '1'] + queens + ['--devices', '8:8']
    status, out = run(command, tmp)
    expect(status == 1, 'exit status %d, expected 1' % status, out)
    expect(re.search(r"rank 1: --devices: device list '8:8': OpenCL platform 8 requested", out),
           "rank 0 did not report rank 1's error", out)
    print(out)


CASES = {'buckets': case_buckets, 'frames': case_frames, 'bad-device': case_bad_device,
         'killed-rank': case_killed_rank, 'stuck-rank': case_stuck_rank, 'queens': case_queens,
         'queens-bad-device': case_queens_bad_device}


class Args:
    pass


def main(argv):
    if len(argv) < 2 or argv[1] not in CASES:
        sys.stderr.write(__doc__)
        return 2
    args = Args()
    args.case, args.mpirun, args.program, args.ranks = argv[1], None, None, 2
    i = 2
    while i + 1 < len(argv):
        key, value = argv[i], argv[i + 1]
        if key == '--mpirun':
            args.mpirun = value
        elif key == '--program':
            args.program = value
        elif key == '--ranks':
            args.ranks = int(value)
        else:
            sys.stderr.write('unknown option %s\n' % key)
            return 2
        i += 2
    if not args.mpirun or args.mpirun == 'none':
        print('SKIP: Open MPI is not available (built with -Dmpi=disabled, or libopenmpi-dev or '
              'mpirun not installed): install openmpi-bin libopenmpi-dev (.ci/install-deps) and '
              'reconfigure')
        return SKIP
    with tempfile.TemporaryDirectory(prefix='perma-mpi-') as tmp:
        CASES[args.case](args, tmp)
    print('1 passed, 0 failed')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
