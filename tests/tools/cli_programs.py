#!/usr/bin/env python3
"""Every program answers its command line the same way (perma_cli.h).

usage: cli_programs.py VERSION NAME PROGRAM [NAME PROGRAM ...]

For each program: --help exits 0 with a usage line naming it and the
--help and --version rows; --version exits 0 with "NAME VERSION"; an
unknown option, and a bad value of its own (CASES), exit 2 with one line
on stderr, "PROGRAM: MESSAGE (see --help)".  perma-bench's commands too.
"""
import re
import subprocess
import sys

# A bad value of each program and the message it must give.
CASES = {
    'perma-info': (['--devices'], "--devices needs a value LIST"),
    'perma-collatz': (['0'], "N '0': expected a whole number in 1..1000000"),
    'perma-bfs': (['--groups', '0'], "--groups '0': expected a whole number in 1..4096"),
    'perma-mandelbrot': (['--size', '0x1'], "--size '0x1': expected WxH with sides in 1..16384"),
    'perma-queens': (['--n', '17'], "--n '17': expected a whole number in 1..16"),
    'reyes-render': (['--fov', '180'], "--fov '180': expected a number > 0.5 and < 179"),
    'perma-bench': (['nosuch'], "COMMAND 'nosuch': expected queue, tree, pipeline"),
    'reyes-quality': (['--size', '0', 'builtin'], "--size '0': expected a whole number in 16..4096"),
    'perma-image-compare': (['--tolerance', '256'], "--tolerance '256': expected a whole number in 0..255"),
}
BENCH_COMMANDS = {
    'queue': (['--generators', '0'], "--generators '0': expected a whole number in 1..1048576"),
    'tree': (['--shape', 'x'], "--shape 'x': expected both, geometric or binomial"),
    'pipeline': (['--rounds', '0'], "--rounds '0': expected a whole number in 1..4096"),
    'reyes': (['--bound', '0.1'], "--bound '0.1': expected a number >= 0.5"),
}


def run(command):
    result = subprocess.run(command, capture_output=True, text=True, timeout=60)
    return result.returncode, result.stdout, result.stderr


def check(name, command, version, bad, failures):
    """The checks of one program (`command` is its argv before options);
    True if it passed them."""
    before = len(failures)

    def fail(what, status, out, err):
        failures.append('%s: %s (exit status %d)\nstdout:\n%s\nstderr:\n%s' % (name, what, status, out, err))

    status, out, err = run(command + ['--help'])
    usage = re.search(r'^usage: (\S*/)?%s ' % re.escape(name), out, re.M)
    if status != 0 or not usage or '-h, --help' not in out or '--version' not in out or err:
        fail('--help', status, out, err)
    status, out, err = run(command + ['--version'])
    if status != 0 or not re.match(r'%s %s' % (re.escape(name), re.escape(version)), out):
        fail('--version', status, out, err)
    for arguments, message in [(['--no-such-option'], "unknown option '--no-such-option'"), bad]:
        status, out, err = run(command + arguments)
        said = re.fullmatch(r'(\S*/)?%s: %s.* \(see --help\)\n' % (re.escape(name), re.escape(message)), err)
        if status != 2 or not said:
            fail(' '.join(arguments), status, out, err)
    return len(failures) == before


def main(argv):
    if len(argv) < 4 or len(argv) % 2:
        sys.stderr.write(__doc__)
        return 2
    version, failures, results = argv[1], [], []
    for name, program in zip(argv[2::2], argv[3::2]):
        results.append(check(name, [program], version, CASES[name], failures))
        if name == 'perma-bench':
            for command, bad in BENCH_COMMANDS.items():
                results.append(check('perma-bench ' + command, [program, command], version, bad, failures))
    for failure in failures:
        print(failure)
    print('%d of %d programs answer --help, --version and bad usage alike' % (sum(results), len(results)))
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
