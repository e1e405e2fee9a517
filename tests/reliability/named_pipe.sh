#!/bin/sh
# A model read from a named pipe renders like the same file (a pipe is the
# one kind of file besides a regular one that reyes-render reads).
# Usage: named_pipe.sh REYES_RENDER (from the project root)
set -eu
dir=$(mktemp -d /tmp/perma-pipe-XXXXXX)
trap 'rm -rf "$dir"' EXIT
mkfifo "$dir/model.bpt"
cat tests/reliability/degenerate.bpt > "$dir/model.bpt" &
status=0
"$1" -o "$dir/x.png" --size 32x32 "$dir/model.bpt" > "$dir/out.txt" 2>&1 || status=$?
wait
if [ "$status" -ne 0 ] || ! grep -q "3 patches" "$dir/out.txt" || [ ! -s "$dir/x.png" ]; then
    echo "expected a render of 3 patches from the pipe, got exit $status:"
    cat "$dir/out.txt"
    exit 1
fi
echo "1 passed, 0 failed"
