#!/bin/sh
# Where the time of each `perma-bench plain` workload goes on the device:
# the procedure's own work, the one function that adds to its results
# (uts_count, simpson_count, queens_count with the reduce_NAME calls they
# make or, with COUNT atomic, their global atomics and simpson_atomic_add),
# and the runtime (the scheduler loop
# and the batch phases: perma_*, emit_*, _pocl_kernel*):
#
#     benchmarks/plain_profile.sh [BUILD_DIR] [SCHEDULE] [REPEAT] [COUNT]
#
# (defaults: build, megakernel/shared, 10, reduce; COUNT is --count).  It
# runs each workload under `perf record` with the batch phases and the
# procedures' functions kept apart (-DPERMA_PROFILE_PHASES through PoCL's
# POCL_EXTRA_BUILD_FLAGS, a fresh program cache so that the megakernel is
# built with it) and counts the samples in the megakernel's shared object.
# The profiled build runs slower than the inlined one (calls instead of
# inlined phases): read the shares, not the absolute times.  The last
# column is what removing the runtime's share would gain at most.
# Needs perf (Debian: linux-perf).
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
schedule=${2:-megakernel/shared}
repeat=${3:-10}
count=${4:-reduce}
bench=$build/benchmarks/perma-bench

command -v perf >/dev/null 2>&1 || { echo "plain_profile.sh: perf not found (apt-get install linux-perf)" >&2; exit 1; }
[ -x "$bench" ] || { echo "plain_profile.sh: $bench not found; build first (ninja -C $build)" >&2; exit 1; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

printf '%-13s %10s %10s %10s   %s\n' workload procedure counting runtime "runtime's largest parts"
for workload in uts-geometric uts-binomial simpson queens sort; do
    PERMA_CACHE_DIR=$scratch/cache POCL_EXTRA_BUILD_FLAGS=-DPERMA_PROFILE_PHASES perf record -q -o "$scratch/perf.data" \
        "$bench" plain --workload "$workload" --only "=$schedule" --repeat "$repeat" --count "$count" \
        >"$scratch/out.txt" 2>&1 ||
        { echo "plain_profile.sh: perma-bench plain --workload $workload failed:" >&2; cat "$scratch/out.txt" >&2; exit 1; }
    perf report -i "$scratch/perf.data" --no-children --sort sym --dsos perma_megakernel.so 2>/dev/null |
        awk -v name="$workload" '
            /^ *[0-9.]+%/ { p = $1; sub("%", "", p); symbol = $3; total += p
                            if (symbol ~ /^(uts_count|simpson_count|simpson_atomic_add|queens_count|reduce_.*|perma_exact_.*)$/) counting += p
                            else if (symbol ~ /^(_pocl_kernel|emit_|perma_)/) { runtime += p; part[symbol] += p }
                            else procedure += p }
            END { if (total == 0) { print name ": no samples in the megakernel"; exit 1 }
                  top = ""
                  for (n = 0; n < 4; ++n) {
                      best = ""; for (s in part) if (best == "" || part[s] > part[best]) best = s
                      if (best == "") break
                      top = top sprintf("%s%s %.1f%%", top == "" ? "" : ", ", best, 100 * part[best] / total)
                      delete part[best]
                  }
                  printf "%-13s %9.1f%% %9.1f%% %9.1f%%   %s\n", name, 100 * procedure / total,
                         100 * counting / total, 100 * runtime / total, top }'
done
