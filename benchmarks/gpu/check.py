#!/usr/bin/env python3
"""The GPU check's run step: correctness and speed of perma on one OpenCL GPU.

usage: run.sh RESULTS [--short] [--dry-run] [--budget S] [--only STEPS] [--skip STEPS]
                      [--opencl-library NAME] [--driver-dir DIR]
       check.py --expected DIR     (pack.sh: the renders to compare with, on this machine)

It runs from a pack (benchmarks/gpu/pack.sh; docs/gpu.md) wherever the pack
was copied.  First it finds the driver's OpenCL library (NAME, default
libnvidia-opencl.so.1, or a versioned file of that name: under DIR, default
/usr/local/nvidia, then the folders of LD_LIBRARY_PATH, ldconfig's cache and
the usual library folders; no ICD file need point to it), writes an ICD
vendors folder naming it, points OCL_ICD_VENDORS at that folder and adds
the library's folder to LD_LIBRARY_PATH, so the pack's ICD loader sees that
driver alone.  Then the steps, each bounded by `timeout` (its own limit,
and what is left of the budget: S seconds in all, default 420 with --short,
450 without) and recorded whatever happens to the others:

  info           perma-info: the device (a GPU unless --dry-run), how perma would use it
  check          perma-info --check: a tree on the device; the work-groups the runtime chose and why
  test_*@SCHED   the runtime's test programs under a schedule: queues (chain,
                 overflow), emits, reductions, regrowth, termination (tree,
                 progress), cooperative items, stealing and donation (tree and
                 chain under those strategies), the watchdog's errors
  render_MODEL   reyes-render of teapot and killeroo at 640x480 (occlusion culling
                 off: the counts do not depend on the order of the groups) against
                 the pack's PoCL render: counts equal within 0.1 %, and at most
                 0.1 % of the pixels differ by more than 2/255 (perma-image-compare)
  bench_WORKLOAD perma-bench tree, queue, pipeline, plain: the megakernel against
                 kernel-per-procedure and bounded-batches (--short: --quick sizes
                 and those three schedules; full: default sizes, every schedule,
                 and tree with one group per compute unit too)
  reyes_speed    perma-bench reyes, the full render of teapot and killeroo at
                 1280x720 and 1920x1080: time per frame, micropolygons per second,
                 against the C reference on the host's cores (full: also the stages
                 under every technique at 1280x720)

--short runs the test programs first, then the renders and the speed steps,
the watchdog's program last (25 s per test: on a discrete GPU its stuck runs
end only by the time limit); the full mode runs the renders and the speed
steps at their default sizes first, then every test program.

--only and --skip take comma-separated step names or prefixes (test_,
bench_tree).  --dry-run checks the check itself on a CPU (the test suite
runs it on PoCL: --opencl-library libpocl.so.2): the device may be a CPU.

RESULTS (a new or empty folder) gets at most 8 files: run-log.txt (everything printed), results.csv
(step, status, seconds, metric, value, unit, detail), table.txt (the table
printed last), perma-info.json, bench.csv (perma-bench's rows of every
bench step), and the GPU's renders gpu-teapot.png and gpu-killeroo.png.
Exit status: 0 every step ok, 1 a step failed, timed out or was skipped for
lack of time, 2 bad usage or no OpenCL library found.
"""
import csv
import glob
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

PACK = os.path.dirname(os.path.abspath(__file__))
BIN = os.path.join(PACK, 'bin')
MODELS = os.path.join(PACK, 'models')
EXPECTED = os.path.join(PACK, 'expected')

# The renders compared with the pack's (pack.sh makes them with --expected).
RENDERS = [('teapot', 640, 480), ('killeroo', 640, 480)]
# Without occlusion culling, whose grids skipped depend on the order the
# groups draw them: the counts are then the same on every run.
RENDER_OPTIONS = ['--occlusion', 'off']
RENDER_TOLERANCE = 2          # per channel, of 255
RENDER_FRACTION = 0.001       # of the pixels that may differ by more
COUNT_TOLERANCE = 0.001       # relative, for splits, grids and micropolygons
COUNTS = ('patches_in', 'splits', 'grids', 'micropolygons', 'culled')

# The runtime's test programs: (program, schedule) in the short mode, and
# what the full mode adds.  A schedule is meson's variant (tests/meson.build).
SCHEDULES = {
    'megakernel-shared': {},
    'megakernel-stealing': {'PERMA_TEST_STRATEGY': 'stealing'},
    'megakernel-donation': {'PERMA_TEST_STRATEGY': 'donation'},
    'megakernel-stealing-donation': {'PERMA_TEST_STRATEGY': 'stealing-donation'},
    'megakernel-stealing-local-queue': {'PERMA_TEST_STRATEGY': 'stealing', 'PERMA_TEST_LOCAL_QUEUE': '256'},
    'kernel-per-procedure': {'PERMA_TEST_TECHNIQUE': 'kernel-per-procedure'},
    'bounded-batches': {'PERMA_TEST_TECHNIQUE': 'bounded-batches', 'PERMA_TEST_BATCH_LIMIT': '100'},
}
SHORT_TESTS = [(name, 'megakernel-shared') for name in
               ('tree', 'chain', 'emits', 'reductions', 'overflow', 'regrowth', 'progress', 'cooperative')] + \
              [('tree', 'megakernel-stealing-donation'), ('chain', 'megakernel-stealing-donation')]
FULL_TESTS = [('tree', s) for s in ('megakernel-stealing', 'megakernel-donation', 'megakernel-stealing-local-queue',
                                    'kernel-per-procedure', 'bounded-batches')] + \
             [('chain', s) for s in ('megakernel-stealing', 'megakernel-donation', 'kernel-per-procedure',
                                     'bounded-batches')] + \
             [('overflow', 'megakernel-stealing-donation'), ('regrowth', 'megakernel-donation'),
              ('api', 'megakernel-shared')]
TEST_TIMEOUT = 240
# The watchdog's test program runs last: its stuck runs end by the stall
# limit only where the host sees the device's memory (a CPU, an integrated
# GPU); elsewhere each would wait for the time limit, so each of its tests
# gets 25 s (Check's timeout) and the program 170 s.
WATCHDOG = ('watchdog', 'megakernel-shared')
WATCHDOG_TEST_TIMEOUT = 25
WATCHDOG_TIMEOUT = 170
# The three techniques, for the short mode's benchmarks.
TECHNIQUES = '=megakernel/shared,kernel-per-procedure,bounded-batches'
REYES_SIZES = ('1280x720', '1920x1080')


def now():
    return time.monotonic()


# The files run.sh writes into RESULTS, and the most the log may hold (a
# result file that comes back from the GPU machine has at most 16 MiB).
RESULT_FILES = ('run-log.txt', 'results.csv', 'table.txt', 'perma-info.json', 'bench.csv', 'gpu-teapot.png',
                'gpu-killeroo.png')
LOG_LIMIT = 15 << 20


class Log:
    """Everything printed goes to stdout and to RESULTS/run-log.txt (its
    first LOG_LIMIT bytes)."""

    def __init__(self, path):
        self.file = open(path, 'w', encoding='utf-8', errors='replace') if path else None
        self.written = 0

    def write(self, text):
        sys.stdout.write(text)
        sys.stdout.flush()
        if self.file and self.written < LOG_LIMIT:
            if self.written + len(text) >= LOG_LIMIT:
                text = text[:LOG_LIMIT - self.written] + '\n[the log stops here: %d bytes]\n' % LOG_LIMIT
            self.file.write(text)
            self.file.flush()
            self.written += len(text)

    def line(self, text=''):
        self.write(text + '\n')


class Result:
    def __init__(self, name):
        self.name = name
        self.status = 'ok'
        self.seconds = 0.0
        self.summary = ''
        self.lines = []      # more lines of the table under this step
        self.metrics = []    # (metric, value, unit, detail)

    def fail(self, status, why):
        if self.status == 'ok':
            self.status = status
        self.summary = (why + '; ' + self.summary) if self.summary else why


class Check:
    def __init__(self, options, log, scratch):
        self.options = options
        self.log = log
        self.scratch = scratch
        self.results = []
        self.env = dict(os.environ)
        self.start = now()
        self.budget = options['budget']
        self.device = {}

    # -- running a program, bounded

    def left(self):
        return self.budget - (now() - self.start)

    def run(self, result, command, limit, env=None, output=None):
        """Run `command` under `timeout` for at most `limit` seconds (and what
        is left of the budget); its output goes to the log (and to `output`,
        a path, if given).  Returns (exit status, output text); status 124
        or 137: it ran out of time."""
        limit = int(min(limit, self.left() - 5))
        if limit < 5:
            result.fail('SKIP', 'no time left in the budget')
            return None, ''
        argv = ['timeout', '--kill-after=10', str(limit)] + command if shutil.which('timeout') else command
        self.log.line('$ ' + ' '.join(command) + '   (at most %d s)' % limit)
        began = now()
        with tempfile.TemporaryFile(mode='w+', encoding='utf-8', errors='replace') as out:
            try:
                process = subprocess.Popen(argv, stdout=out, stderr=subprocess.STDOUT, env=env or self.env,
                                           cwd=self.scratch, start_new_session=True)
            except OSError as e:
                result.fail('ERROR', 'cannot run %s: %s' % (command[0], e))
                return None, ''
            try:
                status = process.wait(timeout=limit + 30)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, 9)
                status = process.wait()
            out.seek(0)
            text = out.read()
        leftovers = kill_leftovers()
        if leftovers:
            text += '(killed %s, left running by the step)\n' % ', '.join(leftovers)
        result.seconds += now() - began
        self.log.write(text if text.endswith('\n') or not text else text + '\n')
        if output:
            with open(output, 'w', encoding='utf-8') as f:
                f.write(text)
        if status in (124, 137, -9):
            result.fail('TIMEOUT', 'stopped after %d s' % limit)
        self.log.line('-> exit status %s after %.1f s' % (status, now() - began))
        return status, text

    def step(self, name, function):
        """Run one step (a function of its Result), whatever happens."""
        if not self.wanted(name):
            return None
        result = Result(name)
        self.log.line()
        self.log.line('== %s' % name)
        try:
            function(result)
        except Exception as e:  # a step's failure is recorded, the others still run
            result.fail('ERROR', '%s: %s' % (type(e).__name__, e))
        self.log.line('== %s: %s %s' % (name, result.status, result.summary))
        self.results.append(result)
        return result

    def wanted(self, name):
        only, skip = self.options['only'], self.options['skip']
        matches = lambda names: any(name == n or name.startswith(n) for n in names)
        return (not only or matches(only)) and not matches(skip)

    # -- the steps

    def info(self, result):
        self.run(result, [os.path.join(BIN, 'perma-info')], 60)
        status, text = self.run(result, [os.path.join(BIN, 'perma-info'), '--json'], 60)
        if status != 0:
            result.fail('FAIL', 'perma-info --json exit status %s' % status)
            return
        shutil.copy(self.write_scratch('perma-info.json', text), os.path.join(self.options['results'], 'perma-info.json'))
        devices = json.loads(text).get('devices', [])
        if not devices:
            result.fail('FAIL', 'no OpenCL device')
            return
        d = self.device = devices[0]
        result.summary = '%s (%s), %s compute units, %s bytes of __local memory; perma: %s' % (
            d.get('name'), d.get('type'), d.get('compute_units'), d.get('local_mem_bytes'), d.get('runtime'))
        for key in ('compute_units', 'local_mem_bytes', 'max_work_group_size'):
            if key in d:
                result.metrics.append((key, d[key], '', d.get('name', '')))
        if not d.get('can_run'):
            result.fail('FAIL', 'perma cannot run on it: %s' % d.get('why_not', '?'))
        if 'GPU' not in str(d.get('type', '')).upper() and not self.options['dry_run']:
            result.fail('FAIL', 'device 0:0 is not a GPU (%s)' % d.get('type'))

    def perma_check(self, result):
        status, text = self.run(result, [os.path.join(BIN, 'perma-info'), '--check'], 180)
        m = re.search(r'^\s*check\s+(.*)$', text, re.M)
        result.summary = m.group(1) if m else 'no check line'
        if status != 0 or not m or not m.group(1).startswith('ok'):
            result.fail('FAIL', 'perma-info --check exit status %s' % status)
        m = re.search(r'on (\d+) work-groups \((.*)\), (\d+) bytes of __local', text)
        if m:
            result.metrics += [('work_groups', int(m.group(1)), 'groups', m.group(2)),
                               ('kernel_local_bytes', int(m.group(3)), 'bytes', 'tree megakernel')]

    def test(self, result, program, schedule):
        env = dict(self.env)
        each, limit = (WATCHDOG_TEST_TIMEOUT, WATCHDOG_TIMEOUT) if (program, schedule) == WATCHDOG else \
            (TEST_TIMEOUT - 20, TEST_TIMEOUT)
        for key in ('PERMA_TEST_TECHNIQUE', 'PERMA_TEST_STRATEGY', 'PERMA_TEST_VICTIM', 'PERMA_TEST_LOCAL_QUEUE',
                    'PERMA_TEST_BATCH_LIMIT'):
            env.pop(key, None)
        env.update(SCHEDULES[schedule])
        env['CK_DEFAULT_TIMEOUT'] = str(each)
        status, text = self.run(result, [os.path.join(BIN, 'test_' + program)], limit, env=env)
        m = re.search(r'(\d+)%: Checks: (\d+), Failures: (\d+), Errors: (\d+)', text)
        if m:
            result.summary = 'Checks: %s, Failures: %s, Errors: %s' % m.group(2, 3, 4)
            result.metrics.append(('checks_passed', int(m.group(2)) - int(m.group(3)) - int(m.group(4)), 'checks',
                                   '%s of %s' % (m.group(1), m.group(2))))
            result.lines = [line for line in text.splitlines() if re.search(r':[FE]:', line)][:8]
        if status != 0:
            result.fail('FAIL', 'exit status %s' % status)

    def render(self, result, model, width, height):
        size = '%dx%d' % (width, height)
        image = os.path.join(self.scratch, 'gpu-%s.png' % model)
        stats_path = os.path.join(self.scratch, 'gpu-%s.json' % model)
        status, _ = self.run(result, [os.path.join(BIN, 'reyes-render'), os.path.join(MODELS, model + '.bpt'),
                                      '--size', size, '-o', image, '--stats', stats_path] + RENDER_OPTIONS, 240)
        if status != 0:
            result.fail('FAIL', 'reyes-render exit status %s' % status)
            return
        shutil.copy(image, self.options['results'])
        with open(stats_path) as f:
            got = json.load(f)
        with open(os.path.join(EXPECTED, '%s-%s.json' % (model, size))) as f:
            want = json.load(f)
        counts = []
        for key in COUNTS:
            a, b = want.get(key, 0), got.get(key, 0)
            counts.append('%s %s' % (key, b if a == b else '%s (PoCL %s)' % (b, a)))
            result.metrics.append((key, b, '', 'PoCL %s' % a))
            if abs(a - b) > COUNT_TOLERANCE * max(a, b, 1):
                result.fail('FAIL', '%s %s, PoCL %s' % (key, b, a))
        status, text = self.run(result, [os.path.join(BIN, 'perma-image-compare'),
                                         os.path.join(EXPECTED, '%s-%s.png' % (model, size)), image,
                                         '--tolerance', str(RENDER_TOLERANCE), '--fraction', str(RENDER_FRACTION)], 60)
        m = re.search(r'(\d+) of (\d+) pixels \(([0-9.]+)%\) differ by more than \d+/255 \(worst (\d+)/255', text)
        if m:
            result.metrics += [('pixels_differing', int(m.group(1)), 'pixels', 'of %s' % m.group(2)),
                               ('worst_difference', int(m.group(4)), '/255', '')]
        if status != 0:
            result.fail('FAIL', 'image: ' + (text.strip().split(': ', 1)[-1] if text else 'exit %s' % status))
        groups = '%s work-groups (%s), %s bytes of __local memory each' % (
            got.get('work_groups'), got.get('work_groups_reason'), got.get('kernel_local_bytes'))
        result.metrics += [('work_groups', got.get('work_groups'), 'groups', got.get('work_groups_reason', '')),
                           ('kernel_local_bytes', got.get('kernel_local_bytes'), 'bytes', 'reyes megakernel'),
                           ('seconds', got.get('seconds'), 's', 'perma_run')]
        result.summary = '%s: %s; image %s; %s; %.4f s' % (
            size, ', '.join(counts), '%s of %s pixels off (worst %s/255)' % m.group(1, 2, 4) if m else '?',
            groups, got.get('seconds', 0))

    def bench(self, result, command, args, limit):
        """perma-bench COMMAND ARGS, its rows summarized (summarize_bench or,
        for reyes, summarize_reyes); a row whose check failed fails the step."""
        path = os.path.join(self.scratch, 'bench-%s.csv' % result.name)
        status, _ = self.run(result, [os.path.join(BIN, 'perma-bench'), command] + args + ['--csv', path], limit)
        if status != 0:
            result.fail('FAIL', 'perma-bench exit status %s' % status)
        if not os.path.exists(path):
            return
        with open(path) as f:
            rows = list(csv.DictReader(f))
        self.bench_rows += [dict(row, step=result.name) for row in rows]
        wrong = [r for r in rows if r.get('check') not in ('ok', '-', '')]
        if wrong:
            result.fail('FAIL', '%d rows WRONG (%s)' % (len(wrong), wrong[0]['variant']))
        (summarize_reyes if command == 'reyes' else summarize_bench)(result, rows)

    # -- the whole check

    def write_scratch(self, name, text):
        path = os.path.join(self.scratch, name)
        with open(path, 'w') as f:
            f.write(text)
        return path

    def run_all(self):
        """--short: correctness first, then the speed at --quick sizes.  Full:
        the speed at the default sizes first, then every test program."""
        short = self.options['short']
        self.bench_rows = []
        self.step('info', self.info)
        self.step('check', self.perma_check)
        tests = SHORT_TESTS + ([] if short else FULL_TESTS) + [WATCHDOG]
        if short:
            self.tests(tests[:-1])
        for model, width, height in RENDERS:
            self.step('render_' + model, lambda r, m=model, w=width, h=height: self.render(r, m, w, h))
        quick = ['--quick', '--only', TECHNIQUES] if short else []
        for command in ('tree', 'queue', 'pipeline', 'plain'):
            self.step('bench_' + command,
                      lambda r, c=command: self.bench(r, c, quick + ['--repeat', '3'], 120 if short else 240))
        sizes = sum([['--size', s] for s in REYES_SIZES], [])
        self.step('reyes_speed', lambda r: self.bench(
            r, 'reyes', ['--models', MODELS, '--workload', 'defaults', '--only', '=megakernel/shared', '--repeat', '3'] + sizes, 240))
        if not short:
            units = self.device.get('compute_units')
            if units:
                self.step('bench_tree_one_group_per_unit', lambda r: self.bench(
                    r, 'tree', ['--only', TECHNIQUES, '--groups', str(min(int(units), 1024)), '--repeat', '3'], 240))
            self.step('reyes_stages', lambda r: self.bench(
                r, 'reyes', ['--models', MODELS, '--workload', 'stages', '--only', TECHNIQUES, '--repeat', '3', '--size', REYES_SIZES[0]], 240))
        self.tests(tests[-1:] if short else tests)
        self.write_results()

    def tests(self, tests):
        for program, schedule in tests:
            self.step('test_%s@%s' % (program, schedule), lambda r, p=program, s=schedule: self.test(r, p, s))

    # -- what comes back

    def write_results(self):
        results = self.options['results']
        with open(os.path.join(results, 'results.csv'), 'w', newline='') as f:
            w = csv.writer(f)
            w.writerow(['step', 'status', 'seconds', 'metric', 'value', 'unit', 'detail'])
            for r in self.results:
                w.writerow([r.name, r.status, '%.1f' % r.seconds, 'summary', '', '', r.summary])
                for metric, value, unit, detail in r.metrics:
                    w.writerow([r.name, r.status, '%.1f' % r.seconds, metric, value, unit, detail])
        if self.bench_rows:
            fields = ['step'] + [k for k in self.bench_rows[0] if k != 'step']
            with open(os.path.join(results, 'bench.csv'), 'w', newline='') as f:
                w = csv.DictWriter(f, fieldnames=fields, extrasaction='ignore')
                w.writeheader()
                w.writerows(self.bench_rows)
        table = io.StringIO()
        d = self.device
        table.write('perma GPU check (%s): %s, %s compute units; %s; %.0f s of %d s\n' % (
            'short' if self.options['short'] else 'full', d.get('name', '?'), d.get('compute_units', '?'),
            self.options['driver'], now() - self.start, self.budget))
        width = max([len(r.name) for r in self.results] + [4])
        table.write('%-*s  %-7s %7s  %s\n' % (width, 'step', 'status', 'seconds', 'result'))
        for r in self.results:
            table.write('%-*s  %-7s %7.1f  %s\n' % (width, r.name, r.status, r.seconds, r.summary))
            for line in r.lines:
                table.write('%-*s  %s\n' % (width + 17, '', line))
        counts = {}
        for r in self.results:
            counts[r.status] = counts.get(r.status, 0) + 1
        table.write('overall: %s\n' % ', '.join('%d %s' % (n, s) for s, n in sorted(counts.items())))
        text = table.getvalue()
        with open(os.path.join(results, 'table.txt'), 'w') as f:
            f.write(text)
        self.log.line()
        self.log.write(text)

    def ok(self):
        return all(r.status == 'ok' for r in self.results)


def kill_leftovers():
    """Kill the pack's programs still running after a step (a test that
    Check put in a process group of its own, and its stuck kernel, outlive
    `timeout`'s signal to the step's group): the next step gets the device
    to itself.  Returns 'NAME (PID)' of each."""
    killed = []
    for entry in os.listdir('/proc'):
        if not entry.isdigit() or int(entry) == os.getpid():
            continue
        try:
            exe = os.readlink('/proc/%s/exe' % entry)
        except OSError:
            continue
        if exe.startswith(BIN + os.sep):
            try:
                os.kill(int(entry), 9)
                killed.append('%s (%s)' % (os.path.basename(exe), entry))
            except OSError:
                pass
    return killed


def rate_text(value):
    value = float(value)
    for unit, scale in (('G', 1e9), ('M', 1e6), ('k', 1e3)):
        if value >= scale:
            return '%.3g%s' % (value / scale, unit)
    return '%.3g' % value


def summarize_bench(result, rows):
    """Per workload: the megakernel's best row against kernel-per-procedure
    and bounded-batches (rate, and the megakernel's factor)."""
    workloads = []
    for row in rows:
        if row['workload'] not in workloads:
            workloads.append(row['workload'])
    parts = []
    for workload in workloads:
        perma = [r for r in rows if r['workload'] == workload and r['group_size'] not in ('0', '')
                 and r['status'] == 'ok']
        mega = [r for r in perma if r['variant'].startswith('megakernel')]
        if not mega:
            continue
        best = max(mega, key=lambda r: float(r['rate'] or 0))
        text = '%s: %s %s/s (%s groups)' % (workload, best['variant'], rate_text(best['rate']), best['work_groups'])
        result.metrics.append(('rate', best['rate'], '%s/s' % best['unit'], '%s: %s, %s groups' % (
            workload, best['variant'], best['work_groups'])))
        for other in ('kernel-per-procedure', 'bounded-batches'):
            rival = [r for r in perma if r['variant'].startswith(other)]
            if rival and float(rival[0]['rate'] or 0) > 0:
                factor = float(best['rate']) / float(rival[0]['rate'])
                text += ', %.2fx %s' % (factor, other)
                result.metrics.append(('megakernel_vs_' + other, '%.3f' % factor, 'x', workload))
        parts.append(text)
    result.lines = parts
    result.summary = result.summary or '%d workloads, %d rows' % (len(workloads), len(rows))


def summarize_reyes(result, rows):
    """Per model and size: the megakernel's full render (time per frame,
    micropolygons per second) against the C reference on the host's cores."""
    parts = []
    for row in rows:
        if 'megakernel' not in row['variant'] or row['status'] != 'ok':
            continue
        seconds, wall = float(row['seconds']), float(row['wall_seconds'] or 0)
        text = '%s, %s: %.2f ms per frame (whole render %.2f ms), %s %s/s, %s groups' % (
            row['workload'], row['variant'], 1e3 * seconds, 1e3 * wall, rate_text(row['rate']), row['unit'],
            row['work_groups'])
        ref = [r for r in rows if r['workload'] == row['workload'] and r['variant'] == 'C reference OpenMP full render']
        if ref and float(ref[0]['seconds']) > 0 and seconds > 0:
            text += ', %.2fx the C reference on %s threads' % (float(ref[0]['seconds']) / seconds, ref[0]['work_groups'])
        parts.append(text)
        result.metrics += [('seconds_per_frame', '%.6f' % seconds, 's', '%s: %s' % (row['workload'], row['variant'])),
                           ('rate', row['rate'], '%s/s' % row['unit'], '%s: %s' % (row['workload'], row['variant']))]
    result.lines = parts
    result.summary = result.summary or '%d renders' % len(parts)


# -- the driver's OpenCL library

def library_folders(driver_dir):
    """Where to look, in order: the driver folder (and its subfolders, two
    levels), LD_LIBRARY_PATH, ldconfig's cache, the usual folders."""
    folders = []
    if os.path.isdir(driver_dir):
        for base, dirs, _ in os.walk(driver_dir):
            if base[len(driver_dir):].count(os.sep) <= 2:
                folders.append(base)
            else:
                dirs[:] = []
    folders += [d for d in os.environ.get('LD_LIBRARY_PATH', '').split(':') if d]
    return folders


def find_library(name, driver_dir):
    for folder in library_folders(driver_dir):
        found = sorted(glob.glob(os.path.join(glob.escape(folder), name + '*')))
        exact = [f for f in found if os.path.basename(f) == name]
        if exact or found:
            return (exact or found)[0]
    try:
        cache = subprocess.run(['ldconfig', '-p'], capture_output=True, text=True, timeout=30).stdout
        for line in cache.splitlines():
            if line.strip().startswith(name) and '=>' in line and 'x86-64' in line:
                return line.split('=>')[1].strip()
    except (OSError, subprocess.SubprocessError):
        pass
    for folder in ('/usr/lib/x86_64-linux-gnu', '/lib/x86_64-linux-gnu', '/usr/lib64', '/lib64', '/usr/lib', '/lib'):
        found = sorted(glob.glob(os.path.join(folder, name + '*')))
        if found:
            return found[0]
    return None


def use_driver(options, scratch, log):
    """The ICD vendors folder naming the driver's library alone."""
    library = find_library(options['library'], options['driver_dir'])
    if not library:
        log.line('run.sh: no %s under %s, LD_LIBRARY_PATH (%s), ldconfig or the usual library folders' % (
            options['library'], options['driver_dir'], os.environ.get('LD_LIBRARY_PATH', '')))
        return None
    library = os.path.abspath(library)
    icd = os.path.join(scratch, 'icd')
    os.makedirs(icd, exist_ok=True)
    with open(os.path.join(icd, 'driver.icd'), 'w') as f:
        f.write(library + '\n')
    os.environ['OCL_ICD_VENDORS'] = icd
    folder = os.path.dirname(library)
    os.environ['LD_LIBRARY_PATH'] = ':'.join([folder] + [d for d in os.environ.get('LD_LIBRARY_PATH', '').split(':')
                                                          if d and d != folder])
    log.line('OpenCL library: %s (OCL_ICD_VENDORS=%s, its folder first in LD_LIBRARY_PATH)' % (library, icd))
    return library


# -- the renders to compare with (pack.sh)

def make_expected(folder):
    os.makedirs(folder, exist_ok=True)
    for model, width, height in RENDERS:
        size = '%dx%d' % (width, height)
        base = os.path.join(folder, '%s-%s' % (model, size))
        done = subprocess.run([os.path.join(BIN, 'reyes-render'), os.path.join(MODELS, model + '.bpt'), '--size',
                               size, '-o', base + '.png', '--stats', base + '.json'] + RENDER_OPTIONS,
                              capture_output=True, text=True)
        sys.stdout.write(done.stdout + done.stderr)
        if done.returncode != 0:
            return 1
    info = subprocess.run([os.path.join(BIN, 'perma-info')], capture_output=True, text=True)
    device = re.search(r'^device 0:0\s+(.*)$', info.stdout, re.M)
    platform = re.search(r'^\s*platform\s+(.*)$', info.stdout, re.M)
    with open(os.path.join(folder, 'device.txt'), 'w') as f:
        f.write('device: %s, %s\n' % (device.group(1) if device else '?', platform.group(1) if platform else '?'))
        f.write(info.stdout)
    return 0


# -- the command line

def usage(message):
    sys.stderr.write('run.sh: %s (see --help)\n' % message)
    return 2


def parse(argv):
    options = {'results': None, 'short': False, 'dry_run': False, 'budget': None, 'only': [], 'skip': [],
               'library': 'libnvidia-opencl.so.1', 'driver_dir': '/usr/local/nvidia'}
    values = {'--budget': 'budget', '--only': 'only', '--skip': 'skip', '--opencl-library': 'library',
              '--driver-dir': 'driver_dir'}
    i = 0
    while i < len(argv):
        arg = argv[i]
        if arg in ('-h', '--help'):
            print(__doc__.strip())
            return None
        if arg in ('--short', '--dry-run'):
            options[arg[2:].replace('-', '_')] = True
        elif arg in values:
            if i + 1 >= len(argv):
                raise ValueError('%s needs a value' % arg)
            i += 1
            key = values[arg]
            if key in ('only', 'skip'):
                options[key] = [s for s in argv[i].split(',') if s]
            elif key == 'budget':
                if not re.fullmatch(r'[0-9]+', argv[i]) or not 30 <= int(argv[i]) <= 3600:
                    raise ValueError("--budget '%s': expected a whole number of seconds in 30..3600" % argv[i])
                options[key] = int(argv[i])
            else:
                options[key] = argv[i]
        elif arg.startswith('-'):
            raise ValueError("unknown option '%s'" % arg)
        elif options['results'] is None:
            options['results'] = arg
        else:
            raise ValueError("one RESULTS folder only ('%s', then '%s')" % (options['results'], arg))
        i += 1
    if options['results'] is None:
        raise ValueError('RESULTS (the folder for the results) is missing')
    if options['budget'] is None:
        options['budget'] = 420 if options['short'] else 450
    return options


def main(argv):
    if len(argv) >= 3 and argv[1] == '--expected':
        return make_expected(argv[2])
    try:
        options = parse(argv[1:])
    except ValueError as e:
        return usage(str(e))
    if options is None:
        return 0
    results = options['results']
    os.makedirs(results, exist_ok=True)
    others = sorted(set(os.listdir(results)) - set(RESULT_FILES))
    if others:
        return usage("RESULTS '%s' holds other files (%s): give a new or empty folder" % (results, ', '.join(others[:3])))
    log = Log(os.path.join(results, 'run-log.txt'))
    scratch = tempfile.mkdtemp(prefix='perma-gpu-check.')
    try:
        log.line('perma GPU check: %s, budget %d s, pack %s' % ('short' if options['short'] else 'full',
                                                                  options['budget'], PACK))
        with open(os.path.join(PACK, 'PACK_INFO')) as f:
            log.write(f.read())
        library = use_driver(options, scratch, log)
        if not library:
            return 2
        options['driver'] = os.path.basename(library)
        os.environ['PERMA_CACHE_DIR'] = os.path.join(scratch, 'program-cache')
        os.environ.pop('PERMA_DEVICE', None)
        check = Check(options, log, scratch)
        check.run_all()
        return 0 if check.ok() else 1
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == '__main__':
    sys.exit(main(sys.argv))
