#!/bin/sh
# `meson install` into a scratch directory, then build an out-of-tree program
# with `cc $(pkg-config --cflags --libs perma)` and run it; also check that the
# programs are installed.  Usage: check_install.sh BUILD_DIR SOURCE_DIR
set -eu
build=$1
source=$2
dest=$(mktemp -d)
trap 'rm -rf "$dest"' EXIT
meson install -C "$build" --destdir "$dest" --no-rebuild --quiet >/dev/null
prefix=$(meson introspect "$build" --buildoptions | python3 -c \
  'import json,sys; print([o["value"] for o in json.load(sys.stdin) if o["name"]=="prefix"][0])')
pc=$(find "$dest" -name perma.pc | head -n 1)
[ -n "$pc" ] || { echo "perma.pc was not installed"; exit 1; }
for program in perma-info reyes-render perma-bench; do
    [ -x "$dest$prefix/bin/$program" ] || { echo "$program was not installed in $prefix/bin"; exit 1; }
done
[ -f "$dest$prefix/include/perma.h" ] || { echo "perma.h was not installed"; exit 1; }
export PKG_CONFIG_PATH="$(dirname "$pc")"
export PKG_CONFIG_SYSROOT_DIR="$dest"
cc -std=c11 -Wall -Wextra -Werror -o "$dest/collatz" "$source/examples/hello/collatz.c" \
   $(pkg-config --cflags --libs perma)
libdir=$(dirname "$(find "$dest" -name 'libperma.so*' | head -n 1)")
LD_LIBRARY_PATH="$libdir" "$dest/collatz" 1000 > "$dest/out.txt"
grep -q "longest: 178 steps" "$dest/out.txt" || { echo "the installed program gave:"; cat "$dest/out.txt"; exit 1; }
echo "1 passed, 0 failed"
