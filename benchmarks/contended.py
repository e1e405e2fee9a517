#!/usr/bin/env python3
"""perma-bench on a contended machine (docs/benchmarks.md, docs/reliability.md).

Two modes:

  contended.py --ratio [--hogs 6] [--rounds 5] [--build build]
      Times `perma-bench pipeline --quick --repeat 1` (the meson test
      bench_pipeline_quick) alternately alone and with HOGS CPU-bound
      processes on the same cores, and prints the medians and their ratio.

  contended.py --stress [--minutes 15] [--slots 3] [--hogs 2] [--bound 100]
      Runs the tree, queue and pipeline benchmarks (--quick, whole or one
      variant at a time) over and over, SLOTS at a time, next to HOGS
      CPU-bound processes, and bounds each run: a run past BOUND seconds is
      reported with the last lines it printed, its threads' states and (when
      gdb is installed) every thread's stack, then killed.  Exit status 1 if
      any run failed or passed its bound.  This is how the cause of issue
      23.6 was found (a run stuck for minutes in perma_build, asking PoCL for
      a program binary).

Both leave the machine as they found it (every process they start is
stopped at the end).
"""
import argparse
import os
import random
import shutil
import signal
import statistics
import subprocess
import sys
import time

SCHEDULES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "runtime", "tools", "schedules.py")
BENCHMARKS = ["pipeline", "tree", "queue"]


def start_hogs(count):
    return [subprocess.Popen(["sh", "-c", "while :; do :; done"]) for _ in range(count)]


def stop(processes):
    for p in processes:
        if p.poll() is None:
            p.kill()
    for p in processes:
        p.wait()


def timed(command):
    start = time.monotonic()
    result = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    seconds = time.monotonic() - start
    if result.returncode != 0:
        sys.exit("%s failed (status %d): %s" % (" ".join(command), result.returncode, result.stderr[-2000:]))
    return seconds


def ratio(args, bench):
    command = [bench, "pipeline", "--quick", "--repeat", "1"]
    timed(command)  # warm-up: PoCL's kernel cache
    alone, loaded = [], []
    for _ in range(args.rounds):
        alone.append(timed(command))
        hogs = start_hogs(args.hogs)
        try:
            time.sleep(0.2)
            loaded.append(timed(command))
        finally:
            stop(hogs)
    a, l = statistics.median(alone), statistics.median(loaded)
    print("command: %s" % " ".join(command))
    print("load average before: %s" % " ".join("%.2f" % x for x in os.getloadavg()))
    print("alone:         median %.2f s (%s)" % (a, ", ".join("%.2f" % x for x in alone)))
    print("with %d hogs:   median %.2f s (%s)" % (args.hogs, l, ", ".join("%.2f" % x for x in loaded)))
    print("ratio: %.2fx" % (l / a))
    return 0


def thread_report(pid):
    lines = []
    try:
        for tid in sorted(os.listdir("/proc/%d/task" % pid), key=int):
            with open("/proc/%d/task/%s/stat" % (pid, tid)) as f:
                fields = f.read().rsplit(")", 1)[1].split()
            lines.append("thread %s: state %s, %s CPU ticks" % (tid, fields[0], int(fields[11]) + int(fields[12])))
    except OSError:
        pass
    if shutil.which("gdb"):
        result = subprocess.run(["gdb", "-p", str(pid), "-batch", "-ex", "thread apply all bt 25"],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        lines += [l for l in result.stdout.splitlines() if l.startswith(("#", "Thread "))]
    return "\n".join(lines)


def schedules():
    """The schedules perma-bench measures (the runtime's schedule table, the
    victims under one stealing strategy): as --only text a label also
    selects its rows with options (+local256, /p=4096)."""
    return subprocess.run([sys.executable, SCHEDULES, "once"], check=True, stdout=subprocess.PIPE,
                          text=True).stdout.split()


def stress(args, bench):
    commands = [[bench, b, "--quick", "--repeat", "1"] for b in BENCHMARKS]
    commands += [[bench, b, "--quick", "--repeat", "1", "--only", v] for b in BENCHMARKS for v in schedules()]
    rng = random.Random(args.seed)
    hogs = start_hogs(args.hogs)
    running = {}
    runs = failures = 0
    end = time.monotonic() + 60 * args.minutes
    try:
        while time.monotonic() < end or running:
            while len(running) < args.slots and time.monotonic() < end:
                command = rng.choice(commands)
                p = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
                running[p] = (command, time.monotonic())
            for p, (command, started) in list(running.items()):
                name = " ".join(command[1:])
                if p.poll() is not None:
                    runs += 1
                    out = p.stdout.read()
                    if p.returncode != 0:
                        failures += 1
                        print("FAILED (status %d): %s\n%s" % (p.returncode, name, out[-3000:]), flush=True)
                    del running[p]
                elif time.monotonic() - started > args.bound:
                    report = thread_report(p.pid)
                    p.send_signal(signal.SIGTERM)  # perma-bench says what it was doing
                    try:
                        out = p.communicate(timeout=5)[0]
                    except subprocess.TimeoutExpired:
                        p.kill()
                        out = p.communicate()[0]
                    runs += 1
                    failures += 1
                    print("PAST ITS BOUND (%g s): %s\n%s\n%s" % (args.bound, name, out[-3000:], report), flush=True)
                    del running[p]
            time.sleep(0.05)
    finally:
        stop(list(running) + hogs)
    print("%d runs, %d failed or passed the %g s bound, %d at a time next to %d CPU hogs, load average %s"
          % (runs, failures, args.bound, args.slots, args.hogs, " ".join("%.1f" % x for x in os.getloadavg())))
    return 1 if failures else 0


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--ratio", action="store_true")
    mode.add_argument("--stress", action="store_true")
    parser.add_argument("--build", default="build")
    parser.add_argument("--hogs", type=int)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--minutes", type=float, default=15)
    parser.add_argument("--slots", type=int, default=3)
    parser.add_argument("--bound", type=float, default=100)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    bench = os.path.join(args.build, "benchmarks", "perma-bench")
    if not os.access(bench, os.X_OK):
        sys.exit("contended.py: %s is not built" % bench)
    if args.ratio:
        args.hogs = 6 if args.hogs is None else args.hogs
        return ratio(args, bench)
    args.hogs = 2 if args.hogs is None else args.hogs
    return stress(args, bench)


if __name__ == "__main__":
    sys.exit(main())
