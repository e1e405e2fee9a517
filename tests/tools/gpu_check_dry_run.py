#!/usr/bin/env python3
"""The GPU check on this machine's PoCL, so that it keeps working (docs/gpu.md).

usage: gpu_check_dry_run.py SOURCE_ROOT BUILD_ROOT MODELS_DIR

Packs the test suite's build (benchmarks/gpu/pack.sh --build-dir) into a
scratch folder and checks the pack: programs and libraries in bin/ with a
search path of $ORIGIN, every library a program loads found there (or a
base system one), the models, PoCL's renders to compare with, its size
printed.  Then runs its run.sh in the short mode as a dry run, with PoCL's
library written into the ICD vendors folder as a GPU driver's would be (the
watchdog's test program is left out: the suite runs it, and it waits ~40 s
for its limits), and checks that every step ran and passed, the table
ends the output, and RESULTS holds the results and nothing else.  Also:
run.sh's bad usage (exit 2) and a driver library it cannot find (exit 2,
named).  Exit status 0 passed, 1 failed, 77 skipped (no PoCL).
"""
import csv
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile

RESULT_FILES = {'run-log.txt', 'results.csv', 'table.txt', 'perma-info.json', 'bench.csv', 'gpu-teapot.png',
                'gpu-killeroo.png'}


def fail(message):
    print('FAIL: ' + message)
    sys.exit(1)


def run(command, timeout):
    print('$ ' + ' '.join(command))
    done = subprocess.run(command, capture_output=True, text=True, timeout=timeout)
    print(done.stdout + done.stderr)
    return done.returncode, done.stdout, done.stderr


def rpath(path):
    out = subprocess.run(['readelf', '-d', path], capture_output=True, text=True).stdout
    m = re.search(r'\((RPATH|RUNPATH)\)\s+Library (?:rpath|runpath): \[(.*)\]', out)
    return (m.group(1), m.group(2)) if m else None


def main(argv):
    source, build, models = argv[1:4]
    if not glob.glob('/usr/lib/x86_64-linux-gnu/libpocl.so.2*') and not glob.glob('/usr/lib*/libpocl.so.2*'):
        print('SKIP: no libpocl.so.2 (PoCL) for the dry run')
        return 77
    scratch = tempfile.mkdtemp(prefix='perma-gpu-dry-run.')
    try:
        pack = os.path.join(scratch, 'pack')
        status, out, _ = run([os.path.join(source, 'benchmarks', 'gpu', 'pack.sh'), '--build-dir', build,
                              '--models', models, pack], 300)
        if status != 0:
            fail('pack.sh exit status %d' % status)
        m = re.search(r'^== .*pack: (\d+) KiB \((\d+) bytes; at most 67108864', out, re.M)
        if not m:
            fail('pack.sh did not print the pack\'s size')
        for name in ('run.sh', 'check.py', 'PACK_INFO', 'models/teapot.bpt', 'models/killeroo.bpt',
                     'expected/teapot-640x480.png', 'expected/teapot-640x480.json',
                     'expected/killeroo-640x480.png', 'expected/killeroo-640x480.json', 'bin/libperma.so.0',
                     'bin/libOpenCL.so.1', 'bin/libhwloc.so.15', 'bin/libpng16.so.16'):
            if not os.path.exists(os.path.join(pack, name)):
                fail('the pack has no %s' % name)
        for program in ('perma-info', 'perma-bench', 'reyes-render', 'perma-image-compare', 'test_tree',
                        'test_regrowth', 'test_watchdog'):
            found = rpath(os.path.join(pack, 'bin', program))
            if found != ('RPATH', '$ORIGIN'):
                fail('bin/%s: search path %s, expected RPATH $ORIGIN' % (program, found))
        with open(os.path.join(pack, 'PACK_INFO')) as f:
            info = f.read()
        if not re.search(r'^needs: GLIBC_2\.\d+ \(glibc\) or newer', info, re.M):
            fail('PACK_INFO does not say which glibc the pack needs:\n' + info)

        # Bad usage, and no driver library: exit 2, saying why.
        run_sh = os.path.join(pack, 'run.sh')
        status, _, err = run([run_sh], 60)
        if status != 2 or 'RESULTS (the folder for the results) is missing' not in err:
            fail('run.sh without RESULTS: exit %d, %r' % (status, err))
        status, _, err = run([run_sh, os.path.join(scratch, 'r'), '--budget', '5'], 60)
        if status != 2 or "--budget '5': expected a whole number of seconds in 30..3600" not in err:
            fail('run.sh --budget 5: exit %d, %r' % (status, err))
        taken = os.path.join(scratch, 'taken')
        os.makedirs(taken)
        open(os.path.join(taken, 'notes.txt'), 'w').close()
        status, _, err = run([run_sh, taken, '--short'], 60)
        if status != 2 or "holds other files (notes.txt): give a new or empty folder" not in err:
            fail('run.sh into a folder of other files: exit %d, %r' % (status, err))
        status, out, _ = run([run_sh, os.path.join(scratch, 'none'), '--opencl-library', 'libnosuch-opencl.so.1',
                              '--driver-dir', os.path.join(scratch, 'nodriver')], 60)
        if status != 2 or 'run.sh: no libnosuch-opencl.so.1 under ' not in out:
            fail('run.sh with no driver library: exit %d' % status)

        # The dry run, from a copy of the pack elsewhere (it runs wherever it is).
        moved = os.path.join(scratch, 'elsewhere', 'pack')
        shutil.copytree(pack, moved, symlinks=True)
        shutil.rmtree(pack)
        results = os.path.join(scratch, 'results')
        status, out, _ = run([os.path.join(moved, 'run.sh'), results, '--short', '--dry-run', '--opencl-library',
                              'libpocl.so.2', '--skip', 'test_watchdog'], 240)
        if status != 0:
            fail('the dry run: exit status %d' % status)
        if not re.search(r'^OpenCL library: /\S*libpocl\.so\.2\S* \(OCL_ICD_VENDORS=', out, re.M):
            fail('the dry run did not name the ICD vendors folder it wrote')
        lines = out.rstrip('\n').split('\n')
        if not re.fullmatch(r'overall: \d+ ok', lines[-1]):
            fail('the output does not end with the table\'s overall line: %r' % lines[-1])
        got = set(os.listdir(results))
        if got != RESULT_FILES:
            fail('RESULTS holds %s, expected %s' % (sorted(got), sorted(RESULT_FILES)))
        with open(os.path.join(results, 'results.csv')) as f:
            rows = list(csv.DictReader(f))
        steps = {row['step'] for row in rows}
        wanted = {'info', 'check', 'test_tree@megakernel-shared', 'test_regrowth@megakernel-shared',
                  'test_tree@megakernel-stealing-donation', 'render_teapot', 'render_killeroo', 'bench_tree',
                  'bench_queue', 'bench_pipeline', 'bench_plain', 'reyes_speed'}
        if not wanted <= steps or 'test_watchdog@megakernel-shared' in steps:
            fail('results.csv has the steps %s' % sorted(steps))
        bad = [row for row in rows if row['status'] != 'ok']
        if bad:
            fail('steps not ok: %s' % bad[0])
        metrics = {(row['step'], row['metric']): row for row in rows}
        for key in (('render_killeroo', 'pixels_differing'), ('render_killeroo', 'micropolygons'),
                    ('render_teapot', 'work_groups'), ('check', 'work_groups'), ('reyes_speed', 'seconds_per_frame'),
                    ('bench_tree', 'megakernel_vs_kernel-per-procedure')):
            if key not in metrics:
                fail('results.csv has no %s of %s' % (key[1], key[0]))
        if metrics[('render_killeroo', 'pixels_differing')]['value'] != '0':
            fail('the same OpenCL rendered killeroo differently: %s' % metrics[('render_killeroo', 'pixels_differing')])
        with open(os.path.join(results, 'table.txt')) as f:
            table = f.read()
        if not out.rstrip('\n').endswith(table.rstrip('\n')):
            fail('table.txt is not the end of the output')
        print('PASS: pack and dry run')
        return 0
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


if __name__ == '__main__':
    sys.exit(main(sys.argv))
