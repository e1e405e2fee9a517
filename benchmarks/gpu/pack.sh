#!/bin/bash
# pack.sh [--build-dir BUILD] [--models DIR] PACK
#
# Build what the GPU check needs and put it in the folder PACK, which
# runs on its own on a machine that has an OpenCL driver but nothing else
# of perma's (docs/gpu.md): PACK/run.sh RESULTS [--short].
#
#   PACK/run.sh, check.py  the run step (run.sh --help lists its steps)
#   PACK/bin/              the programs (perma-info, perma-bench, reyes-render,
#                          perma-image-compare, the runtime's test programs),
#                          libperma and every library they need that a bare
#                          Ubuntu lacks (the OpenCL ICD loader, hwloc, libpng,
#                          OpenMP, Check's subunit, ...), found with ldd and
#                          found again through a search path of $ORIGIN
#                          (set_rpath.py) wherever PACK is copied
#   PACK/models/           teapot.bpt and killeroo.bpt from ../shared/models
#   PACK/expected/         the renders run.sh compares with: PNG and statistics
#                          made here on PoCL by the packed reyes-render
#   PACK/PACK_INFO         what was packed, from which commit, the glibc it needs
#
# Without --build-dir it configures and builds a release build in
# build-gpu-pack/ (MPI off); --build-dir uses a build that exists (the test
# suite's dry run packs its own build this way).  PACK is made anew
# (refused if it exists and is not an earlier pack, unless empty).  Prints
# PACK's size; more than 64 MiB fails (what reaches the GPU machine).
# Exit status: 0 packed, 1 a step failed, 2 bad usage.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=
models=$root/../shared/models
pack=
limit_bytes=$((64 * 1024 * 1024))

usage() {
    echo "usage: benchmarks/gpu/pack.sh [--build-dir BUILD] [--models DIR] PACK" >&2
    echo "pack.sh: $1" >&2
    exit 2
}
fail() {
    echo "pack.sh: $1" >&2
    exit 1
}

while [ $# -gt 0 ]; do
    case $1 in
    --build-dir) [ $# -ge 2 ] || usage "--build-dir needs a value BUILD"; build=$2; shift 2 ;;
    --models) [ $# -ge 2 ] || usage "--models needs a value DIR"; models=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    -*) usage "unknown option '$1'" ;;
    *) [ -z "$pack" ] || usage "one PACK only ('$pack', then '$1')"; pack=$1; shift ;;
    esac
done
[ -n "$pack" ] || usage "PACK (the folder to make) is missing"
for model in teapot killeroo; do
    [ -f "$models/$model.bpt" ] || fail "$models/$model.bpt is missing (--models DIR: where teapot.bpt and killeroo.bpt are)"
done
if [ -e "$pack" ] && [ ! -f "$pack/PACK_INFO" ] && [ -n "$(ls -A "$pack")" ]; then
    fail "$pack exists and is not a pack: give a new folder"
fi

# The programs, by meson target: the check's tools and the runtime's test
# programs (check.py's TESTS).
tools="perma-info perma-bench reyes-render perma-image-compare"
tests="test_tree test_chain test_emits test_reductions test_overflow test_regrowth test_progress test_watchdog
       test_cooperative test_api"
if [ -z "$build" ]; then
    build=$root/build-gpu-pack
    if [ ! -f "$build/build.ninja" ]; then
        echo "== configuring a release build in $build"
        meson setup "$build" "$root" --buildtype=release -Dmpi=disabled -Dsanitize_suite=false
    fi
    echo "== building"
    # shellcheck disable=SC2086
    meson compile -C "$build" $tools $tests
fi
[ -f "$build/build.ninja" ] || fail "$build is not a meson build folder"

# Where each program is in the build (its folder there; not a nested
# build's, e.g. the sanitized one under sanitize/).
find_built() {
    local found
    case $1 in
    perma-info) found=$build/runtime/$1 ;;
    perma-bench) found=$build/benchmarks/$1 ;;
    reyes-render) found=$build/examples/reyes/$1 ;;
    perma-image-compare) found=$build/benchmarks/gpu/$1 ;;
    *) found=$build/tests/$1 ;;
    esac
    [ -x "$found" ] || fail "$1 is not built in $build (no $found; meson compile -C $build $1)"
    echo "$found"
}

rm -rf "$pack"
mkdir -p "$pack/bin" "$pack/models" "$pack/expected"
pack=$(cd "$pack" && pwd)
echo "== copying the programs, libperma and the fault shim test_regrowth needs"
for program in $tools $tests; do
    cp "$(find_built "$program")" "$pack/bin/$program"
done
cp -L "$build/runtime/libperma.so.0" "$build/tests/libcl_fault.so" "$pack/bin/"
echo "== search paths: \$ORIGIN"
python3 "$here/set_rpath.py" "$pack"/bin/* | sed 's/^/   /'

# Libraries that every Ubuntu has (glibc, the compiler's runtime, zlib):
# never copied, since a newer system's driver may need its own.
base_system='^(linux-vdso\.so|ld-linux-x86-64\.so|libc\.so|libm\.so|libpthread\.so|libdl\.so|librt\.so|libresolv\.so|libgcc_s\.so|libstdc\+\+\.so|libz\.so)'
# Copy every other library the files of bin/ need into bin/, until none is
# missing (a copied library may need more).
copy_libraries() {
    local added=1 file lib path
    while [ "$added" = 1 ]; do
        added=0
        for file in "$pack"/bin/*; do
            while read -r lib path; do
                [ -n "$lib" ] || continue
                if echo "$lib" | grep -Eq "$base_system"; then continue; fi
                [ -e "$pack/bin/$lib" ] && continue
                if [ "$path" = "not" ] || [ ! -e "$path" ]; then fail "$file needs $lib, which ldd cannot find"; fi
                cp -L "$path" "$pack/bin/$lib"
                chmod u+w "$pack/bin/$lib"
                echo "   $lib (from $path)"
                added=1
            done < <(env -u LD_LIBRARY_PATH ldd "$file" 2>/dev/null | awk '$2 == "=>" { print $1, $3 }')
        done
    done
}
echo "== copying the libraries they need"
copy_libraries
# A copied library with a search path of its own would not look beside it.
python3 "$here/set_rpath.py" "$pack"/bin/lib*.so* | grep -- "-> '\$ORIGIN'" | sed 's/^/   /' || true
# Every library a program loads now resolves inside bin/ or is a base
# system one (ldd of a program follows its libraries' needs as the loader
# does, through the program's search path).
for file in "$pack"/bin/*; do
    case $(basename "$file") in lib*.so*) continue ;; esac
    while read -r lib path; do
        if echo "$lib" | grep -Eq "$base_system"; then continue; fi
        [ "$path" = "$pack/bin/$lib" ] || fail "$(basename "$file") finds $lib at $path, not in the pack"
    done < <(env -u LD_LIBRARY_PATH ldd "$file" | awk '$2 == "=>" { print $1, $3 }')
done

echo "== the run step and the models"
cp "$here/run.sh" "$here/check.py" "$pack/"
chmod +x "$pack/run.sh"
cp "$models/teapot.bpt" "$models/killeroo.bpt" "$pack/models/"

# The renders run.sh compares with, made by the packed reyes-render on this
# machine's OpenCL (PoCL), as check.py renders them there.
echo "== expected renders (this machine's OpenCL)"
python3 "$pack/check.py" --expected "$pack/expected"

glibc=$(for f in "$pack"/bin/*; do objdump -T "$f" 2>/dev/null | grep -o 'GLIBC_[0-9.]*'; done | sort -uV | tail -1)
{
    echo "perma GPU check pack"
    echo "made: $(date -u '+%Y-%m-%d %H:%M UTC') on $(uname -n)"
    echo "source: $(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)"
    echo "build: $build"
    echo "needs: ${glibc:-GLIBC_?} (glibc) or newer; an OpenCL driver"
    echo "expected renders: $(sed -n 's/^device: //p' "$pack/expected/device.txt")"
} > "$pack/PACK_INFO"

bytes=$(du -sb "$pack" | cut -f1)
echo "== $pack: $((bytes / 1024)) KiB ($bytes bytes; at most $limit_bytes reach a GPU machine)"
[ "$bytes" -le "$limit_bytes" ] || fail "the pack is $bytes bytes, more than $limit_bytes"
echo "run it there: $(basename "$pack")/run.sh RESULTS --short   (then without --short)"
