#!/usr/bin/env python3
"""reyes-render interrupted (SIGINT, SIGTERM, SIGHUP) in one process says so
and what is written, and still ends by the signal (it ended by it without
a word): "interrupted by SIGINT; no image written" during a render, and
"interrupted by SIGTERM; N of M frames written: f-0001.png to f-NNNN.png"
naming exactly the frames on disk; no temporary file is left.

usage: interrupted.py REYES_RENDER
"""
import glob
import os
import signal
import subprocess
import sys
import tempfile
import time


def stop(command, cwd, number, ready):
    """Start `command`, send signal `number` once ready() holds (at most 120 s
    on), return (status, stderr)."""
    job = subprocess.Popen(command, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while job.poll() is None and time.time() < deadline and not ready():
        time.sleep(0.05)
    if job.poll() is None:
        job.send_signal(number)
    try:
        _, err = job.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        job.kill()
        _, err = job.communicate()
    return job.returncode, err


def main():
    render = os.path.abspath(sys.argv[1])
    failures = []
    with tempfile.TemporaryDirectory(prefix='perma-interrupt-') as work:
        # A render of many seconds, stopped a second in (building or rendering).
        for number in (signal.SIGINT, signal.SIGHUP):
            started = time.time()
            status, err = stop([render, '--size', '4096x4096', '--spp', '16', '-o', 'big.png', '--stats', 'big.json'],
                               work, number, lambda: time.time() - started > 1.0)
            expected = '%s: interrupted by %s; no image written' % (render, signal.Signals(number).name)
            if status != -number or expected not in err or os.listdir(work):
                failures.append('%s: expected death by the signal, "%s" and no file; got status %s, files %s, '
                                'stderr:\n%s' % (signal.Signals(number).name, expected, status, os.listdir(work), err))
        # Frames, stopped once some are written.
        status, err = stop([render, '--size', '32x32', '--frames', '2000', '-o', 'f.png'], work, signal.SIGTERM,
                           lambda: os.path.exists(os.path.join(work, 'f-0003.png')))
        frames = sorted(os.path.basename(p) for p in glob.glob(os.path.join(work, 'f-*.png')))
        count = len(frames)
        expected = '%s: interrupted by SIGTERM; %d of 2000 frames written: f-0001.png to %s' % (
            render, count, frames[-1] if frames else '?')
        complete = frames == ['f-%04d.png' % (k + 1) for k in range(count)]
        if status != -signal.SIGTERM or expected not in err or not complete or count < 3 or \
                sorted(os.listdir(work)) != frames:
            failures.append('frames: expected death by SIGTERM and "%s" with exactly those files; got status %s, '
                            'files %s, stderr:\n%s' % (expected, status, sorted(os.listdir(work)), err))
    for failure in failures:
        print('FAIL ' + failure)
    print('%d passed, %d failed' % (3 - len(failures), len(failures)))
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main())
