#!/usr/bin/env python3
"""The Python package as a user installs it: pip in a fresh virtual environment.

usage: pip_install.py PYTHON SOURCE_ROOT BUILD_ROOT VERSION

Creates a venv with `PYTHON -m venv`, runs `pip install SOURCE_ROOT/runtime/python`
in it (numpy and the build backend come from the package index), then with the
venv's Python and nothing of the build tree on sys.path:
  - the README's Python example runs, finding libperma through pkg-config
    (PKG_CONFIG_PATH = the build's meson-uninstalled directory), and counts
    its 2^20 leaves with a reduction;
  - the package's version is meson's project version;
  - PERMA_LIBRARY names the library to load;
  - a libperma under the venv's prefix (where `meson install --prefix=$VIRTUAL_ENV`
    puts it) is found with neither;
  - with none of these, the import fails naming every place it tried.
Exits 77 (meson: skipped) when the venv module is missing or the package index
cannot be reached, saying which.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

# pip's messages when the index is out of reach (not when a package is broken).
OFFLINE = re.compile(r'NewConnectionError|Temporary failure in name resolution|Network is unreachable|'
                     r'No matching distribution found for (hatchling|numpy)|ProxyError|Max retries exceeded')


def readme_example(source_root):
    """The first ```python block of README.md's section 'From Python'."""
    with open(os.path.join(source_root, 'README.md'), encoding='utf-8') as f:
        text = f.read()
    section = text[text.index('\n## From Python\n'):]
    start = section.index('```python\n') + len('```python\n')
    return section[start:section.index('\n```\n', start)] + '\n'


def run(command, env):
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=600)
    return done.returncode, done.stdout + done.stderr


def fail(what, output):
    print('FAIL: %s\n%s' % (what, output))
    return 1


def main(python, source_root, build_root, version):
    work = tempfile.mkdtemp(prefix='pip-venv-', dir=os.path.join(build_root, 'tests', 'python'))
    try:
        return check(python, source_root, build_root, version, work)
    finally:
        shutil.rmtree(work, ignore_errors=True)


def check(python, source_root, build_root, version, work):
    env = {k: v for k, v in os.environ.items()
           if k not in ('PYTHONPATH', 'PERMA_LIBRARY', 'PKG_CONFIG_PATH', 'LD_LIBRARY_PATH', 'VIRTUAL_ENV')}
    env['PYTHONDONTWRITEBYTECODE'] = '1'
    venv = os.path.join(work, 'venv')
    status, output = run([python, '-m', 'venv', venv], env)
    if status != 0:
        print('skipped: %s -m venv failed (Debian: apt-get install python3-venv):\n%s' % (python, output))
        return 77
    venv_python = os.path.join(venv, 'bin', 'python')
    status, output = run([venv_python, '-m', 'pip', 'install', '--disable-pip-version-check', '-q',
                          os.path.join(source_root, 'runtime', 'python')], env)
    if status != 0:
        offline = OFFLINE.search(output)
        if offline:
            print('skipped: the package index is out of reach (%s):\n%s' % (offline.group(0), output[-2000:]))
            return 77
        return fail('pip install %s/runtime/python' % source_root, output)
    print('pip installed the package into a venv of %s' % python)

    example = os.path.join(work, 'tree.py')
    with open(example, 'w', encoding='utf-8') as f:
        f.write(readme_example(source_root))
    found = dict(env, PKG_CONFIG_PATH=os.path.join(build_root, 'meson-uninstalled'))
    status, output = run([venv_python, example], found)
    expected = r'^1048576 leaves; 2097151 items in [0-9]+ batches\n$'
    if status != 0 or not re.match(expected, output):
        return fail("the README's Python example (expected %r)" % expected, output)
    print("the README's Python example: " + output.strip())

    where = 'import perma; print(perma.__version__, perma._capi.LIBRARY)'
    library = os.path.join(build_root, 'runtime', 'libperma.so')
    status, output = run([venv_python, '-c', where], found)
    if status != 0 or output.split() != [version, os.path.join(build_root, 'runtime', 'libperma.so.0')]:
        return fail('through pkg-config: expected version %s and the build\'s libperma.so.0' % version, output)
    status, output = run([venv_python, '-c', where], dict(found, PERMA_LIBRARY=library))
    if status != 0 or output.split()[1:] != [library]:
        return fail('PERMA_LIBRARY=%s' % library, output)

    status, output = run([venv_python, '-c', where], env)
    if status == 0:
        print('note: without PERMA_LIBRARY and pkg-config the package found %s (installed on this machine); '
              'not checking the failure message or the venv prefix' % output.split()[1])
        return 0
    tried = [r'ImportError: perma: cannot load libperma; tried, in order:',
             r'  PERMA_LIBRARY: not set', r'  pkg-config: no package perma \(PKG_CONFIG_PATH is not set\)',
             r'  installed prefix: no libperma.so.0 in .*lib64, lib under %s, /usr/local, /usr' % re.escape(venv),
             r'  dynamic linker: libperma.so.0: cannot open shared object file',
             r'Install perma \(meson install\), or set PERMA_LIBRARY']
    missing = [line for line in tried if not re.search('^' + line, output, re.M)]
    if missing:
        return fail('no library anywhere: the message lacks %s' % missing, output)
    prefix_lib = os.path.join(venv, 'lib', 'libperma.so.0')
    os.symlink(os.path.join(build_root, 'runtime', 'libperma.so.0'), prefix_lib)
    status, output = run([venv_python, '-c', where], env)
    same_dir = lambda path: os.path.realpath(os.path.dirname(path)) == os.path.realpath(os.path.dirname(prefix_lib))
    if status != 0 or len(output.split()) != 2 or not same_dir(output.split()[1]):
        return fail('a libperma in the venv prefix (%s)' % prefix_lib, output)
    print('found libperma through pkg-config, PERMA_LIBRARY and the venv prefix; without them the import '
          'fails naming each place it tried')
    return 0


if __name__ == '__main__':
    if len(sys.argv) != 5:
        sys.stderr.write(__doc__)
        sys.exit(2)
    sys.exit(main(*sys.argv[1:]))
