#!/bin/sh
# reyes-render under memory limits (ulimit -v, ulimit -d): out of memory,
# named, exit 1; never PoCL's abort, segfault or assertion (exit 134 or
# 139), nor a claim that no OpenCL driver is installed.
# Usage: memory_limit.sh REYES_RENDER
set -eu
render=$1
dir=$(mktemp -d /tmp/perma-memory-XXXXXX)
trap 'rm -rf "$dir"' EXIT
failed=0
# expect LIMIT_OPTION KIB PATTERN ARGS...: exit 1 and PATTERN (grep -E) in the output.
expect() {
    option=$1 kib=$2 pattern=$3
    shift 3
    status=0
    (ulimit "$option" "$kib"; exec "$render" -o "$dir/x.png" "$@") > "$dir/out.txt" 2>&1 || status=$?
    if [ "$status" -ne 1 ] || ! grep -Eq "$pattern" "$dir/out.txt" || grep -q "install an OpenCL driver" "$dir/out.txt"; then
        echo "FAIL: ulimit $option $kib, $*: exit $status, expected 1 and /$pattern/:"
        cat "$dir/out.txt"
        failed=$((failed + 1))
    fi
}
driver="out of memory: the OpenCL driver, to start and run, needs about [0-9]+ MiB"
# Once: exit 1 "no OpenCL platform found; install an OpenCL driver" (200 MB),
# a segfault loading the program (300 MB), PoCL's assertion (400 MB, most tries).
expect -v 200000 "$driver \\(PoCL\\), but the process's address-space limit \\(ulimit -v\\) of 195 MiB" --size 64x64
expect -v 300000 "$driver" --size 64x64
expect -v 400000 "$driver" --size 64x64
expect -d 100000 "$driver \\(PoCL\\), but the process's data limit \\(ulimit -d\\) of 97 MiB" --size 64x64
# A 2 GiB sample buffer beside a 1 GiB image under 2.9 GB: PoCL asserted
# (p->mem_ptr != NULL); now refused before the render starts.
expect -v 3000000 "out of memory for the sample buffer \\(2147483648 bytes, 2048 MiB\\)" --size 16384x16384 --spp 1
if [ "$failed" -ne 0 ]; then
    exit 1
fi
echo "5 passed, 0 failed"
