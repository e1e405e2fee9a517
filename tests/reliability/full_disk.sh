#!/bin/sh
# Outputs on a full disk, simulated by a file size limit (ulimit -f, with
# SIGXFSZ ignored so that a write fails with EFBIG instead of killing the
# process; unprivileged, unlike a small tmpfs): no partial file is left,
# an earlier file at the path is unchanged, the message names the file and
# the reason, and a group (image and --stats) is written both or neither.
# Usage: full_disk.sh REYES_RENDER
set -eu
render=$1
dir=$(mktemp -d /tmp/perma-full-XXXXXX)
trap 'rm -rf "$dir"' EXIT
failed=0
fail() {
    echo "FAIL: $1"
    cat "$dir/out.txt"
    failed=$((failed + 1))
}
# The limit applies to every file the process writes, the OpenCL
# driver's too: PoCL writes a program's source to a temporary file at
# every build from source, even when its kernel cache has the result. So
# the programs are built first, unlimited, into a private perma cache
# that keeps PoCL's programs too (PERMA_CACHE_MIN_SECONDS=0), and the
# limited runs load them from there as binaries.
PERMA_CACHE_DIR="$dir/cache"
PERMA_CACHE_MIN_SECONDS=0
export PERMA_CACHE_DIR PERMA_CACHE_MIN_SECONDS
"$render" --size 32x32 -o "$dir/warm.png" > /dev/null
"$render" --size 32x32 --frames 2 -o "$dir/warm.png" > /dev/null
rm -f "$dir"/warm*

# limited ARGS...: reyes-render ARGS under a limit of 1 block (512 or 1024
# bytes); its output passes through a pipe, which the limit does not cut.
limited() {
    (trap '' XFSZ; ulimit -f 1; status=0; "$render" "$@" || status=$?; echo "$status" > "$dir/status") 2>&1 \
        | cat > "$dir/out.txt"
    status=$(cat "$dir/status")
    rm "$dir/status"
}
leftovers() {
    ls "$dir" | grep -c '\.tmp$' || true
}

echo "an earlier image" > "$dir/x.png"
limited --size 128x128 -o "$dir/x.png"
[ "$status" -eq 1 ] || fail "PNG: exit $status, expected 1"
grep -q "writing '$dir/x.png' failed: File too large (the file there before is unchanged)" "$dir/out.txt" \
    || fail "PNG: no message naming the file and the reason"
[ "$(cat "$dir/x.png")" = "an earlier image" ] || fail "PNG: the earlier file was changed"
[ "$(leftovers)" -eq 0 ] || fail "PNG: a temporary file was left"

# The image fits the limit, the statistics do not: neither is written.
limited --size 1x1 -o "$dir/tiny.png" --stats "$dir/tiny.json"
[ "$status" -eq 1 ] || fail "stats: exit $status, expected 1"
grep -q "writing '$dir/tiny.json' failed: File too large (no file was written); so $dir/tiny.png was not written either" \
    "$dir/out.txt" || fail "stats: no message naming both files"
[ ! -e "$dir/tiny.png" ] && [ ! -e "$dir/tiny.json" ] || fail "stats: a file was written"
[ "$(leftovers)" -eq 0 ] || fail "stats: a temporary file was left"

# Frames: the first frame that does not fit ends the job, and no frame
# file is partial.
limited --size 128x128 --frames 2 -o "$dir/f.png"
[ "$status" -eq 1 ] || fail "frames: exit $status, expected 1"
grep -q "frame 1: writing '$dir/f-0001.png' failed: File too large" "$dir/out.txt" \
    || fail "frames: no message naming the frame"
[ ! -e "$dir/f-0001.png" ] && [ ! -e "$dir/f-0002.png" ] || fail "frames: a partial frame was left"
[ "$(leftovers)" -eq 0 ] || fail "frames: a temporary file was left"

# Frames that fit and --stats that does not (over 1 KiB: 24 frames): the
# message says which files were written.
limited --size 8x8 --frames 24 -o "$dir/g.png" --stats "$dir/g.json"
[ "$status" -eq 1 ] || fail "frames and stats: exit $status, expected 1"
grep -q "writing '$dir/g.json' failed: File too large (no file was written); the 24 frames $dir/g-0001.png .. $dir/g-0024.png were written" \
    "$dir/out.txt" || fail "frames and stats: no message saying what was written"
[ -s "$dir/g-0024.png" ] && [ ! -e "$dir/g.json" ] || fail "frames and stats: not the frames without the statistics"
[ "$(leftovers)" -eq 0 ] || fail "frames and stats: a temporary file was left"

if [ "$failed" -ne 0 ]; then
    exit 1
fi
echo "4 passed, 0 failed"
