"""Where libperma is: the places the package looks, in order.

1. PERMA_LIBRARY, when set: that file and nothing else;
2. where meson put the library, for the package meson wrote (the build
   tree's copy, or `meson install`'s, also when staged or moved);
3. pkg-config's perma (PKG_CONFIG_PATH, or an install under a prefix
   pkg-config searches): the directories of its -L flags and its libdir;
4. installed prefixes: this Python's (a virtual environment's, say), then
   /usr/local and /usr, each in lib/MULTIARCH, lib64 and lib;
5. the dynamic linker's own search (LD_LIBRARY_PATH, ldconfig's cache).

A package installed with pip has no meson record (2), so it finds the
library by 3-5.  Each place that did not give a library says why, and the
ImportError of load() lists them all.
"""
import ctypes
import ctypes.util
import os
import shutil
import subprocess
import sys
import sysconfig

SONAMES = ('libperma.so.0', 'libperma.so')
DEFAULT_PREFIXES = ('/usr/local', '/usr')


def _lib_subdirs():
    multiarch = sysconfig.get_config_var('MULTIARCH')
    return ([os.path.join('lib', multiarch)] if multiarch else []) + ['lib64', 'lib']


def _files_in(dirs):
    """The libraries in dirs, each directory once (a venv's lib64 is its lib)."""
    seen, files = set(), []
    for d in dirs:
        if os.path.realpath(d) not in seen:
            seen.add(os.path.realpath(d))
            files += [os.path.join(d, name) for name in SONAMES if os.path.isfile(os.path.join(d, name))]
    return files


def pkg_config_dirs(env):
    """(library directories pkg-config gives for perma, why none) with the environment env."""
    program = shutil.which('pkg-config', path=env.get('PATH')) or shutil.which('pkgconf', path=env.get('PATH'))
    if not program:
        return [], 'no pkg-config program on PATH'

    def query(*args):
        try:
            done = subprocess.run([program] + list(args) + ['perma'], env=env, capture_output=True, text=True,
                                  timeout=30)
        except (OSError, subprocess.SubprocessError) as error:
            return None, str(error)
        return (done.stdout.split(), None) if done.returncode == 0 else (None, done.stderr.strip())
    flags, why = query('--libs-only-L')
    if flags is None:
        where = env.get('PKG_CONFIG_PATH')
        return [], 'no package perma (%s)' % ('PKG_CONFIG_PATH=' + where if where else 'PKG_CONFIG_PATH is not set')
    libdir, _ = query('--variable=libdir')
    dirs = [flag[2:] for flag in flags if flag.startswith('-L')] + (libdir or [])
    return dirs, 'perma.pc names %s, where no %s is' % (' and '.join(dirs) or 'no directory', SONAMES[0])


def candidates(env=None, configured=None, prefixes=None):
    """(place, path or None, why) for each place in order; path None: nothing there, for the reason why.

    configured: the meson record's library_paths() (None: none);
    prefixes: the installed prefixes to search (None: sys.prefix, /usr/local, /usr)."""
    env = os.environ if env is None else env
    explicit = env.get('PERMA_LIBRARY')
    if explicit:
        yield 'PERMA_LIBRARY', explicit, None
        return
    yield 'PERMA_LIBRARY', None, 'not set'
    for path in configured or []:
        yield 'meson', path, None
    dirs, why = pkg_config_dirs(env)
    found = _files_in(dirs)
    for path in found:
        yield 'pkg-config', path, None
    if not found:
        yield 'pkg-config', None, why
    if prefixes is None:
        prefixes = [sys.prefix] + [p for p in DEFAULT_PREFIXES if p != sys.prefix]
    found = _files_in([os.path.join(prefix, sub) for prefix in prefixes for sub in _lib_subdirs()])
    for path in found:
        yield 'installed prefix', path, None
    if not found:
        yield 'installed prefix', None, 'no %s in %s under %s' % (SONAMES[0], ', '.join(_lib_subdirs()),
                                                                  ', '.join(prefixes))
    yield 'dynamic linker', ctypes.util.find_library('perma') or SONAMES[0], None


def load(env=None, configured=None, prefixes=None):
    """(the loaded library, its path); ImportError listing every place tried when none loads."""
    tried = []
    for place, path, why in candidates(env, configured, prefixes):
        if path is None:
            tried.append('%s: %s' % (place, why))
            continue
        try:
            return ctypes.CDLL(path), path
        except OSError as error:
            tried.append('%s: %s' % (place, error))
    raise ImportError('perma: cannot load libperma; tried, in order:\n  %s\n'
                      'Install perma (meson install), or set PERMA_LIBRARY to the path of libperma.so '
                      '(build/runtime/libperma.so in a build tree), or add the directory of perma.pc to '
                      'PKG_CONFIG_PATH (build/meson-uninstalled in a build tree)' % '\n  '.join(tried))
