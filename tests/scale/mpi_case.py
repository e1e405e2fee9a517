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
  mismatch     ranks started with another size, another model, a model file
               that differs between working directories: every rank refuses
               (exit 2), rank 0 names the setting, no image
  killed-rank  rank 1 killed mid-render: the job ends, rank 0 says so
  killed-frames  rank 1 killed during --frames: rank 0 lists exactly the
               frame files written, numbered as the files are
  interrupted  mpirun sent SIGINT, then SIGTERM: rank 0 says the job was
               interrupted, not that a rank died
  stuck-rank   rank 1 stopped mid-render: rank 0's --rank-timeout ends the job
  stuck-coordinator  rank 0 stopped mid-render: rank 1's --rank-timeout ends
               the job
  queens       perma-queens over N ranks, all work starting on rank 0: the
               known and the sequential count, every other rank stole work
  queens-bad-device  a rank of perma-queens on a missing device: exit 1,
               rank 0 names it
  queens-killed  a rank of perma-queens killed: rank 0 says so
  queens-stuck   a rank of perma-queens stopped: --rank-timeout ends the job
"""
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time

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
    # A rank draws its first line at once and then at most every 2 s, so
    # one rank's start shows 0 done under 2 s elapsed; a later 0 % line is
    # the same rank still waiting for its first bucket (a slow compile).
    starts = re.findall(r'^reyes-render: 0/%d %s, 0\.0%%, ([0-9.]+) s elapsed' % (count, unit), out, re.M)
    expect(len([s for s in starts if float(s) < 2.0]) == 1, 'not one progress line at the start (rank 0 only)', out)
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
        # Every rank renders, each tracing to its own file (--trace: FILE-rankN).
        extra = ['--devices', '0:0/2'] if splittable(args.program, tmp) else []
        extra += ['--trace', os.path.join(tmp, 'trace.json')]
    status, out = run(mpirun_command(args.mpirun, args.ranks) + [args.program, '-o', spread, '--progress'] + RENDER
                      + extra, tmp)
    expect(status == 0, 'mpirun -n %d failed' % args.ranks, out)
    expect_progress(out, 24, 'buckets')
    expect(read(alone) == read(spread), 'the %d-rank PNG differs from the one-process PNG' % args.ranks, out)
    expect(re.search(r'24 buckets on %d ranks' % args.ranks, out), 'no summary line', out)
    taken = [int(n) for n in re.findall(r'rank \d+, device \S+: (\d+) buckets', out)]
    renderers = args.ranks - (1 if extra == ['--coordinator-only'] else 0)
    expect(len(taken) == renderers and sum(taken) == 24, 'the ranks did not take 24 buckets', out)
    if '--trace' in extra:
        traces = sorted(f for f in os.listdir(tmp) if f.startswith('trace'))
        expect(traces == ['trace-rank%d.json' % r for r in range(args.ranks)],
               'expected a trace per rank, found %s' % traces, out)
        # A bucket whose patches all fall outside it dices nothing, so a rank
        # may trace no dice batch; every rank that rendered traced its bound
        # batches, and every grid was diced once: the ranks' traced dice
        # items add up to the job's grid count.
        grids = int(re.search(r'on %d ranks, (\d+) grids' % args.ranks, out).group(1))
        diced = 0
        for rank, buckets in enumerate(taken):
            events = json.loads(read(os.path.join(tmp, traces[rank])))['traceEvents']
            batches = [e for e in events if e.get('ph') == 'X']
            expect(not buckets or batches, 'rank %d rendered %d buckets but traced no batch' % (rank, buckets), out)
            diced += sum(e['args']['items'] for e in batches if e.get('name') == 'dice')
        expect(diced == grids, 'the traces hold %d dice items for %d grids' % (diced, grids), out)
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


# Long enough that a rank killed or stopped after 2-3 s is killed mid-render:
# about 16 s on 2 ranks of a 2-core machine (at --spp 16 it ended in 4 s and
# raced the interrupted case's signal in CI).  Every case stops it within
# seconds, so the size costs nothing when the tests pass.
BIG = ['--size', '2048x1536', '--bucket', '32x32', '--spp', '64', '--grid', '16']


def write_model(path, z):
    """A one-patch .bpt model: the unit square at height z."""
    with open(path, 'w') as f:
        f.write('1\n3 3\n')
        for r in range(4):
            for c in range(4):
                f.write('%g %g %g\n' % (c / 3.0, r / 3.0, z))


def case_mismatch(args, tmp):
    out_png = os.path.join(tmp, 'mixed.png')
    # The command: rank 1 with a larger size and bucket (rank 0
    # crashed delivering its tile).
    small = [args.program, '--size', '64x64', '--bucket', '64x64', '--coordinator-only', '-o', out_png]
    large = [args.program, '--size', '1024x1024', '--bucket', '1024x1024', '--coordinator-only', '-o', out_png]
    status, out = run(mpirun_command(args.mpirun, 1) + small + [':', '-n', '1'] + large, tmp)
    expect(status == 2, 'different sizes: exit status %d, expected 2' % status, out)
    expect(re.search(r'rank 1 has --size 1024x1024 where rank 0 has 64x64 \(and 1 more setting\)', out),
           'rank 0 did not name the differing size', out)
    expect('nothing rendered' in out and not os.path.exists(out_png), 'an image was written', out)
    # Two models (a mixed image, exit 0, before).
    write_model(os.path.join(tmp, 'a.bpt'), 0.0)
    write_model(os.path.join(tmp, 'b.bpt'), 0.5)
    render = [args.program, '--size', '32x32', '-o', out_png]
    status, out = run(mpirun_command(args.mpirun, 1) + render + ['a.bpt', ':', '-n', '1'] + render + ['b.bpt'],
                      tmp)
    expect(status == 2, 'different models: exit status %d, expected 2' % status, out)
    expect(re.search(r'rank 1 has model 1 b\.bpt \(1 patches\) where rank 0 has a\.bpt \(1 patches\)', out),
           'rank 0 did not name the differing model', out)
    expect(not os.path.exists(out_png), 'an image was written', out)
    # One path, other contents (a model that differs between nodes).
    for name, z in (('one', 0.0), ('two', 0.25)):
        os.mkdir(os.path.join(tmp, name))
        write_model(os.path.join(tmp, name, 'm.bpt'), z)
    status, out = run(mpirun_command(args.mpirun, 1) + ['-wdir', os.path.join(tmp, 'one')] + render + ['m.bpt']
                      + [':', '-n', '1', '-wdir', os.path.join(tmp, 'two')] + render + ['m.bpt'], tmp)
    expect(status == 2, 'different model contents: exit status %d, expected 2' % status, out)
    expect(re.search(r"rank 1's model 1 m\.bpt \(1 patches\) differs from rank 0's in its contents", out),
           'rank 0 did not name the model whose contents differ', out)
    expect(not os.path.exists(out_png), 'an image was written', out)
    print(out)


def case_killed_rank(args, tmp):
    render = [args.program, '-o', os.path.join(tmp, 'big.png')] + BIG
    command = mpirun_command(args.mpirun, 1) + render + [':', '-n', '1', 'timeout', '-s', 'KILL', '3'] + render
    status, out = run(command, tmp)
    expect(status != 0, 'the job succeeded', out)
    expect(re.search(r'rank 0: the job was stopped by mpirun after rank 1 ended early .*; no image written', out),
           'rank 0 did not say why the job stopped', out)
    expect(not os.path.exists(os.path.join(tmp, 'big.png')), 'an image was written', out)
    print(out)


def frame_files(tmp):
    return sorted(f for f in os.listdir(tmp) if re.match(r'k-\d{4}\.png$', f))


def case_killed_frames(args, tmp):
    # Rank 1 is killed once three frames are written; rank 0 must list the
    # frames written, by the numbers of their files.
    frames = [args.program, '-o', 'k.png', '--frames', '400', '--size', '96x64']
    keep_pid = ['sh', '-c', '"$@" & echo $! > rank1.pid; wait $!', 'sh']
    command = mpirun_command(args.mpirun, 1) + frames + [':', '-n', '1'] + keep_pid + frames
    job = subprocess.Popen(command, cwd=tmp, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    deadline = time.time() + LIMIT
    while len(frame_files(tmp)) < 3 and job.poll() is None and time.time() < deadline:
        time.sleep(0.05)
    with open(os.path.join(tmp, 'rank1.pid')) as f:
        os.kill(int(f.read()), signal.SIGKILL)
    out, _ = job.communicate(timeout=LIMIT)
    expect(job.returncode != 0, 'the job succeeded', out)
    said = re.search(r'rank 0: the job was stopped by mpirun after rank 1 ended early .*?; (\d+) of 400 frames '
                     r'written: ([^;\n]*)', out)
    expect(said, 'rank 0 did not say which frames were written', out)
    listed = set()
    for part in said.group(2).split(', '):
        ends = re.findall(r'k-(\d{4})\.png', part)
        expect(len(ends) in (1, 2), 'not a frame or a range of frames: %r' % part, out)
        listed.update(range(int(ends[0]), int(ends[-1]) + 1))
    on_disk = {int(f[2:6]) for f in frame_files(tmp)}
    expect(len(listed) == int(said.group(1)) and len(listed) >= 2, 'the count does not match the list', out)
    # Every frame said to be written is there; at most one more file (a
    # frame being written when the job was stopped).
    expect(listed <= on_disk and len(on_disk - listed) <= 1,
           'frames listed %s, on disk %s' % (sorted(listed), sorted(on_disk)), out)
    held = re.search(r'rank 1 held frame (\d+)', out)
    if held:
        expect(int(held.group(1)) not in listed, 'rank 1 held a frame said to be written', out)
    print(out)


def case_interrupted(args, tmp):
    # The signal goes out once rank 0 prints its first --progress line: it
    # renders then, its handler installed.  A fixed sleep raced the job's
    # end on a fast run.
    render = [args.program, '-o', os.path.join(tmp, 'big.png'), '--progress'] + BIG
    for number in (signal.SIGINT, signal.SIGTERM):
        job = subprocess.Popen(mpirun_command(args.mpirun, 2) + render, cwd=tmp, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
        lines = []
        rendering = threading.Event()

        def collect():
            for line in job.stdout:
                lines.append(line)
                if re.match(r'reyes-render: \d+/\d+ buckets', line):
                    rendering.set()
            rendering.set()  # the job ended: stop waiting

        reader = threading.Thread(target=collect)
        reader.start()
        rendering.wait(LIMIT)
        expect(job.poll() is None, 'the job ended before its first progress line was read', ''.join(lines))
        job.send_signal(number)
        job.wait(LIMIT)
        reader.join(LIMIT)
        out = ''.join(lines)
        expect(job.returncode != 0, 'the job succeeded', out)
        expect(re.search(r'rank 0: the job was interrupted \(SIGTERM from mpirun: mpirun was sent SIGINT or '
                         r'SIGTERM', out), 'rank 0 did not say the job was interrupted (%s)' % number.name, out)
        expect(not re.search(r'died|ended early', out), 'rank 0 blamed a rank (%s)' % number.name, out)
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


def case_stuck_coordinator(args, tmp):
    # Rank 0 only coordinates, so rank 1 waits on it after every bucket.
    render = [args.program, '-o', os.path.join(tmp, 'big.png'), '--rank-timeout', '3', '--coordinator-only'] + BIG
    stop_later = ['sh', '-c', '"$@" & pid=$!; sleep 2; kill -STOP $pid; wait $pid', 'sh']
    command = mpirun_command(args.mpirun, 1) + stop_later + render + [':', '-n', '1'] + render
    start = time.time()
    status, out = run(command, tmp, 60)
    expect(status != 0, 'the job succeeded', out)
    expect(re.search(r'rank 1: (rank 0 has not answered for more than 3 s|the ranks did not all (start|finish) '
                     r'.*within 3 s) \(--rank-timeout', out), 'rank 1 did not say that rank 0 is silent', out)
    expect(not os.path.exists(os.path.join(tmp, 'big.png')), 'an image was written', out)
    print(out)
    print('ended after %.1f s' % (time.time() - start))


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


# Long enough that a rank is still searching when the cases below stop or
# kill it 1.5 s in (15 queens take under 2 s on 2 ranks of an idle
# machine), and short enough that rank 0 runs out of its own share and
# asks the stopped rank for work within seconds (it notices a silent rank
# only then).
QUEENS_LONG = ['--n', '16', '--rank-timeout', '3']


def case_queens_killed(args, tmp):
    queens = [args.program] + QUEENS_LONG
    command = mpirun_command(args.mpirun, 1) + queens + [':', '-n', '1', 'timeout', '-s', 'KILL', '1.5'] + queens
    status, out = run(command, tmp)
    expect(status != 0, 'the job succeeded', out)
    expect(re.search(r'rank 0: the job was stopped by mpirun after rank 1 ended early .*; the search did not '
                     r'finish', out), 'rank 0 did not say why the search stopped', out)
    print(out)


def case_queens_stuck(args, tmp):
    queens = [args.program] + QUEENS_LONG
    stop_later = ['sh', '-c', '"$@" & pid=$!; sleep 1.5; kill -STOP $pid; wait $pid', 'sh']
    start = time.time()
    status, out = run(mpirun_command(args.mpirun, 1) + queens + [':', '-n', '1'] + stop_later + queens, tmp, 60)
    expect(status != 0, 'the job succeeded', out)
    # Stopped mid-search (the usual case), while starting, or at the end.
    expect(re.search(r'rank 0: (rank 1 has not answered a request for work for more than 3 s|not every rank '
                     r'.* within 3 s|the ranks did not all .* within 3 s) \(--rank-timeout', out),
           'rank 0 did not say that rank 1 is silent', out)
    print(out)
    print('ended after %.1f s' % (time.time() - start))


def case_queens_bad_device(args, tmp):
    queens = [args.program, '--n', '10']
    command = mpirun_command(args.mpirun, 1) + queens + [':', '-n', '1'] + queens + ['--devices', '8:8']
    status, out = run(command, tmp)
    expect(status == 1, 'exit status %d, expected 1' % status, out)
    expect(re.search(r"rank 1: --devices: device list '8:8': OpenCL platform 8 requested", out),
           "rank 0 did not report rank 1's error", out)
    print(out)


CASES = {'buckets': case_buckets, 'frames': case_frames, 'bad-device': case_bad_device,
         'mismatch': case_mismatch, 'killed-rank': case_killed_rank, 'killed-frames': case_killed_frames,
         'interrupted': case_interrupted, 'stuck-rank': case_stuck_rank,
         'stuck-coordinator': case_stuck_coordinator, 'queens': case_queens,
         'queens-bad-device': case_queens_bad_device, 'queens-killed': case_queens_killed,
         'queens-stuck': case_queens_stuck}


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
