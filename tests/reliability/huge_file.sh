#!/bin/sh
# A model file larger than any model may be (a sparse 5 GiB file, no disk
# space used) is refused before it is read: exit 1 and a message naming it.
# Usage: huge_file.sh REYES_RENDER
set -eu
file=$(mktemp /tmp/perma-huge-XXXXXX.bpt)
trap 'rm -f "$file"' EXIT
truncate -s 5G "$file"
status=0
"$1" -o /dev/null "$file" > /tmp/perma-huge-out.txt 2>&1 || status=$?
if [ "$status" -ne 1 ] || ! grep -q "$file: file of 5368709120 bytes is larger than" /tmp/perma-huge-out.txt; then
    echo "expected exit 1 and a message naming $file, got $status:"
    cat /tmp/perma-huge-out.txt
    exit 1
fi
echo "1 passed, 0 failed"
