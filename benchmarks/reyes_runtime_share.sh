#!/bin/sh
# How much of the megakernel's device time is the runtime's own (scheduler
# loop, emits, batch phases) rather than the Reyes procedures, per workload
# of `perma-bench reyes` (same models, sizes, cameras, bound 8, 16x16 grids,
# 4 spp, no crack fix, megakernel/shared on 2 groups):
#
#     benchmarks/reyes_runtime_share.sh [BUILD_DIR] [MODELS_DIR]
#
# (defaults: build, ../shared/models).  It renders each workload several
# times under `perf record` with the batch phases kept as separate functions
# (-DPERMA_PROFILE_PHASES, through PoCL's POCL_EXTRA_BUILD_FLAGS; the first
# run compiles that megakernel once) and counts the samples of the
# megakernel's shared object: functions named _pocl_kernel*, emit_* and
# perma_* are the runtime's, the rest the procedures'.  Removing the
# runtime's share entirely would make the megakernel at most
# 1 / (1 - share) times faster: docs/reyes-measurements.md uses it to bound the
# megakernel / kernel-per-procedure ratio (issue 13, target 4).
# Needs perf (Debian: linux-perf).
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
models=${2:-$root/../shared/models}
render=$build/examples/reyes/reyes-render

command -v perf >/dev/null 2>&1 || { echo "reyes_runtime_share.sh: perf not found (apt-get install linux-perf)" >&2; exit 1; }
[ -x "$render" ] || { echo "reyes_runtime_share.sh: $render not found; build first (ninja -C $build)" >&2; exit 1; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# model size camera fov frames (frames: about two seconds of rendering each)
for workload in "teapot 512x512 8,-8,6,0,0,1.5 40 40" "teapot 1280x1024 8,-8,6,0,0,1.5 40 12" \
                "killeroo 512x512 8,0,2,0,0,0 45 24" "killeroo 1280x1024 8,0,2,0,0,0 45 12"; do
    set -- $workload
    [ -r "$models/$1.bpt" ] || { echo "reyes_runtime_share.sh: $models/$1.bpt not found, skipped" >&2; continue; }
    POCL_EXTRA_BUILD_FLAGS=-DPERMA_PROFILE_PHASES perf record -q -o "$scratch/perf.data" \
        "$render" "$models/$1.bpt" --size "$2" --camera "$3" --fov "$4" --grid 16 --bound 8 \
        --crack-fix none --spp 4 --schedule megakernel/shared --groups 2 --frames "$5" --orbit 0 \
        -o "$scratch/frame.png" >/dev/null 2>&1 ||
        { echo "reyes_runtime_share.sh: the render of $1 $2 failed" >&2; exit 1; }
    perf report -i "$scratch/perf.data" --no-children --sort sym --dsos perma_megakernel.so 2>/dev/null |
        awk -v name="$1 $2" '
            /^ *[0-9.]+%/ { p = $1; sub("%", "", p); device += p;
                            if ($3 ~ /^(_pocl_kernel|emit_|perma_)/) runtime += p }
            END { if (device == 0) { print name ": no samples in the megakernel"; exit 1 }
                  share = runtime / device;
                  printf "%-20s runtime %.1f%% of the megakernel'"'"'s device time: at most %.2fx faster without it\n",
                         name ":", 100 * share, 1 / (1 - share) }'
done
