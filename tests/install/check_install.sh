#!/bin/sh
# `meson install` into a scratch directory: the library, perma.h, perma.pc
# and the programs under their perma- names (no generic name such as
# `collatz` in bin/).  Then a program outside the project builds and runs
# three ways, as docs/writing-procedures.md shows:
#   1. against the installed tree with pkg-config;
#   2. against the build tree with meson's uninstalled pkg-config file;
#   3. against the build tree with plain -I/-L flags.
# Usage: check_install.sh BUILD_DIR SOURCE_DIR
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
for program in perma-info reyes-render perma-bench perma-queens perma-collatz perma-bfs perma-mandelbrot; do
    [ -x "$dest$prefix/bin/$program" ] || { echo "$program was not installed in $prefix/bin"; exit 1; }
done
for generic in collatz bfs mandelbrot; do
    [ ! -e "$dest$prefix/bin/$generic" ] || { echo "$prefix/bin/$generic: a generic name was installed"; exit 1; }
done
[ -f "$dest$prefix/include/perma.h" ] || { echo "perma.h was not installed"; exit 1; }

# Run the collatz example built as $1 (with $2 as LD_LIBRARY_PATH).
run_collatz() {
    LD_LIBRARY_PATH="$2" "$1" 1000 > "$dest/out.txt"
    grep -q "longest: 178 steps" "$dest/out.txt" || { echo "$1 gave:"; cat "$dest/out.txt"; exit 1; }
}

# 1. The installed tree, through pkg-config.
(
    export PKG_CONFIG_PATH="$(dirname "$pc")"
    export PKG_CONFIG_SYSROOT_DIR="$dest"
    cc -std=c11 -Wall -Wextra -Werror -o "$dest/collatz-installed" "$source/examples/hello/collatz.c" \
       $(pkg-config --cflags --libs perma)
)
run_collatz "$dest/collatz-installed" "$(dirname "$(find "$dest" -name 'libperma.so*' | head -n 1)")"

# 2. The build tree, through meson's uninstalled pkg-config file.
(
    export PKG_CONFIG_PATH="$build/meson-uninstalled"
    cc -std=c11 -Wall -Wextra -Werror -o "$dest/collatz-uninstalled" "$source/examples/hello/collatz.c" \
       $(pkg-config --cflags --libs perma)
)
run_collatz "$dest/collatz-uninstalled" "$build/runtime"

# 3. The build tree with plain flags: the header in the source tree, the
#    library in the build tree (rpath instead of LD_LIBRARY_PATH).
cc -std=c11 -Wall -Wextra -Werror -o "$dest/collatz-plain" "$source/examples/hello/collatz.c" \
   -I"$source/runtime/include" -L"$build/runtime" -Wl,-rpath,"$build/runtime" -lperma -lOpenCL
run_collatz "$dest/collatz-plain" ""
echo "3 passed, 0 failed"
