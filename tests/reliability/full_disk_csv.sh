#!/bin/sh
# perma-bench --csv on a full disk (a file size limit, SIGXFSZ ignored):
# exit 1 naming the file and the reason; the CSV there before unchanged.
# Usage: full_disk_csv.sh PERMA_BENCH
set -eu
dir=$(mktemp -d /tmp/perma-csv-XXXXXX)
trap 'rm -rf "$dir"' EXIT
# Build the queue programs first, unlimited (the driver caches them on disk).
"$1" queue --quick --repeat 1 --only shared > /dev/null
echo "an earlier table" > "$dir/rows.csv"
# The output passes through a pipe, which the limit does not cut.
(trap '' XFSZ; ulimit -f 1; status=0
 "$1" queue --quick --repeat 1 --only shared --csv "$dir/rows.csv" || status=$?
 echo "$status" > "$dir/status") 2>&1 | cat > "$dir/out.txt"
status=$(cat "$dir/status")
rm "$dir/status"
if [ "$status" -ne 1 ] || ! grep -q "perma-bench: --csv: writing '$dir/rows.csv' failed: File too large (the file there before is unchanged)" "$dir/out.txt" \
    || [ "$(cat "$dir/rows.csv")" != "an earlier table" ] || ls "$dir" | grep -q '\.tmp$'; then
    echo "expected exit 1, the reason and the earlier CSV unchanged; got exit $status:"
    cat "$dir/out.txt"
    ls -la "$dir"
    exit 1
fi
echo "1 passed, 0 failed"
