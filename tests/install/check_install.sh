#!/bin/sh
# `meson install` into a scratch directory, then:
#   - the library, perma.h, perma.pc, the command-line engine
#     (libperma-cli.a, perma_cli.h, perma-cli.pc) and the programs under
#     their perma- names (no generic name such as `collatz` in bin/);
#   - every installed program runs (--help, --version) without
#     LD_LIBRARY_PATH, loading the installed libperma (its rpath), also
#     after the whole tree is moved elsewhere;
#   - a man page per program, the README, docs and example sources under
#     share/doc/perma;
#   - the Python package from the installed tree: it loads the installed
#     library and counts the example's tree (numpy permitting);
#   - a program outside the project builds and runs three ways, as
#     docs/writing-procedures.md shows:
#       1. against the installed tree with pkg-config;
#       2. against the build tree with meson's uninstalled pkg-config file;
#       3. against the build tree with plain -I/-L flags.
# Usage: check_install.sh BUILD_DIR SOURCE_DIR PYTHON
set -eu
build=$1
source=$2
python=$3
dest=$(mktemp -d)
trap 'rm -rf "$dest"' EXIT
unset LD_LIBRARY_PATH PERMA_LIBRARY
meson install -C "$build" --destdir "$dest" --no-rebuild --quiet >/dev/null
option() {
    meson introspect "$build" --buildoptions | python3 -c \
      'import json,sys; print([o["value"] for o in json.load(sys.stdin) if o["name"]==sys.argv[1]][0])' "$1"
}
prefix=$(option prefix)
version=$(meson introspect "$build" --projectinfo | python3 -c 'import json,sys; print(json.load(sys.stdin)["version"])')
pc=$(find "$dest" -name perma.pc | head -n 1)
[ -n "$pc" ] || { echo "perma.pc was not installed"; exit 1; }
programs="perma-info reyes-render perma-bench perma-queens perma-collatz perma-bfs perma-mandelbrot perma-trace-to-svg"
for program in $programs; do
    [ -x "$dest$prefix/bin/$program" ] || { echo "$program was not installed in $prefix/bin"; exit 1; }
done
for generic in collatz bfs mandelbrot; do
    [ ! -e "$dest$prefix/bin/$generic" ] || { echo "$prefix/bin/$generic: a generic name was installed"; exit 1; }
done
[ -f "$dest$prefix/include/perma.h" ] || { echo "perma.h was not installed"; exit 1; }
[ -f "$dest$prefix/include/perma_cli.h" ] || { echo "perma_cli.h was not installed"; exit 1; }
[ -n "$(find "$dest" -name 'libperma-cli.a')" ] || { echo "libperma-cli.a was not installed"; exit 1; }
[ -n "$(find "$dest" -name perma-cli.pc)" ] || { echo "perma-cli.pc was not installed"; exit 1; }

# Each program (of $1/bin) answers --help and --version, exit status 0,
# without LD_LIBRARY_PATH; the compiled ones load libperma from below $1.
run_programs() {
    for program in $programs; do
        "$1/bin/$program" --help > "$dest/out.txt" 2>&1 \
            || { echo "$1/bin/$program --help failed:"; cat "$dest/out.txt"; exit 1; }
        grep -Eq "usage: (.*/)?$program( |\$)" "$dest/out.txt" || { echo "$program --help:"; cat "$dest/out.txt"; exit 1; }
        "$1/bin/$program" --version > "$dest/out.txt" 2>&1 \
            || { echo "$1/bin/$program --version failed:"; cat "$dest/out.txt"; exit 1; }
        grep -q "^$program $version" "$dest/out.txt" || { echo "$program --version:"; cat "$dest/out.txt"; exit 1; }
        if [ "$program" != perma-trace-to-svg ]; then
            loaded=$(ldd "$1/bin/$program" | sed -n 's/.*libperma[.]so[.0-9]* => \([^ ]*\).*/\1/p')
            case "$loaded" in
                "$1"/*) ;;
                *) echo "$1/bin/$program loads libperma from '$loaded', not from below $1"; exit 1 ;;
            esac
        fi
    done
}
run_programs "$dest$prefix"

# A man page per program; the README, every document and the examples.
mandir=$dest$prefix/$(option mandir)
docdir=$dest$prefix/$(option datadir)/doc/perma
for program in $programs; do
    page=$mandir/man1/$program.1
    [ -f "$page" ] || { echo "no man page $page"; exit 1; }
    name_line="$(echo "$program" | sed 's/-/\\-/g') \- "  # perma\-info \- ...
    grep -qF "$name_line" "$page" || { echo "$page has no NAME line:"; head "$page"; exit 1; }
    if command -v groff > /dev/null; then
        warnings=$(groff -man -Tutf8 -ww -z "$page" 2>&1)
        [ -z "$warnings" ] || { echo "groff warns about $page: $warnings"; exit 1; }
    fi
done
for file in README.md docs/writing-procedures.md docs/python.md examples/hello/collatz.c \
            examples/python/uts_count.py examples/reyes/reyes_render_main.c; do
    [ -f "$docdir/$file" ] || { echo "$file was not installed in $docdir"; exit 1; }
done
for doc in "$source"/docs/*.md "$source"/docs/*.png; do
    [ -f "$docdir/docs/$(basename "$doc")" ] || { echo "docs/$(basename "$doc") was not installed in $docdir"; exit 1; }
done
[ ! -e "$docdir/examples/meson.build" ] || { echo "$docdir/examples/meson.build: a build file was installed"; exit 1; }

# The Python package (under $1) imports and loads the library below $1;
# with numpy and a second argument "count", it counts the example's tree.
run_python() {
    package=$(find "$1" -path '*/perma/__init__.py' | head -n 1)
    [ -n "$package" ] || { echo "the Python package was not installed below $1"; exit 1; }
    if ! "$python" -c 'import numpy' 2>/dev/null; then
        echo "numpy is missing for $python: the installed Python package was not run"
        return
    fi
    PYTHONPATH=$(dirname "$(dirname "$package")") "$python" -c '
import sys, perma
assert perma.__file__.startswith(sys.argv[1]), perma.__file__
assert perma._capi.lib._name.startswith(sys.argv[1]), perma._capi.lib._name
assert perma.__version__ == sys.argv[2], perma.__version__
assert perma.schedule_label("megakernel") == "megakernel/shared"
' "$1" "$version"
    [ "${2:-}" = count ] || return 0
    PYTHONPATH=$(dirname "$(dirname "$package")") "$python" "$docdir/examples/python/uts_count.py" 6 \
        > "$dest/out.txt" 2>&1 || { echo "the installed uts_count.py failed:"; cat "$dest/out.txt"; exit 1; }
    grep -q "^numpy counts the same" "$dest/out.txt" || { echo "uts_count.py:"; cat "$dest/out.txt"; exit 1; }
}
run_python "$dest$prefix" count

# Moved elsewhere, the tree still runs.
mv "$dest$prefix" "$dest/moved"
run_programs "$dest/moved"
run_python "$dest/moved"
mv "$dest/moved" "$dest$prefix"

# Run the collatz example built as $1 (with $2 as LD_LIBRARY_PATH).
run_collatz() {
    LD_LIBRARY_PATH="$2" "$1" 1000 > "$dest/out.txt"
    grep -q "longest: 178 steps" "$dest/out.txt" || { echo "$1 gave:"; cat "$dest/out.txt"; exit 1; }
    # Its command line through the engine: bad usage exits 2 saying why.
    status=0
    LD_LIBRARY_PATH="$2" "$1" 0 > "$dest/out.txt" 2>&1 || status=$?
    [ "$status" = 2 ] && grep -q "N '0': expected a whole number in 1..1000000 (see --help)" "$dest/out.txt" \
        || { echo "$1 0 exited with $status:"; cat "$dest/out.txt"; exit 1; }
}

# 1. The installed tree, through pkg-config (perma-cli requires perma).
(
    export PKG_CONFIG_PATH="$(dirname "$pc")"
    export PKG_CONFIG_SYSROOT_DIR="$dest"
    cc -std=c11 -Wall -Wextra -Werror -o "$dest/collatz-installed" "$source/examples/hello/collatz.c" \
       $(pkg-config --cflags --libs perma-cli)
)
run_collatz "$dest/collatz-installed" "$(dirname "$(find "$dest" -name 'libperma.so*' | head -n 1)")"

# 2. The build tree, through meson's uninstalled pkg-config file.
(
    export PKG_CONFIG_PATH="$build/meson-uninstalled"
    cc -std=c11 -Wall -Wextra -Werror -o "$dest/collatz-uninstalled" "$source/examples/hello/collatz.c" \
       $(pkg-config --cflags --libs perma-cli)
)
run_collatz "$dest/collatz-uninstalled" "$build/runtime"

# 3. The build tree with plain flags: the headers in the source tree, the
#    libraries in the build tree (rpath instead of LD_LIBRARY_PATH).
cc -std=c11 -Wall -Wextra -Werror -o "$dest/collatz-plain" "$source/examples/hello/collatz.c" \
   -I"$source/runtime/include" -I"$source/runtime/tools/cli" -L"$build/runtime/tools/cli" -L"$build/runtime" \
   -Wl,-rpath,"$build/runtime" -lperma-cli -lperma -lOpenCL
run_collatz "$dest/collatz-plain" ""
echo "programs, man pages, docs, the Python package and 3 builds passed"
