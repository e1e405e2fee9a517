#!/bin/sh
# Build the libFuzzer targets with clang and fuzz each for a bounded time.
# Any crash, leak, timeout, out-of-memory or sanitizer report fails the run.
#
# Usage: run.sh [SECONDS [WORK_DIR [TARGET ...]]]
#   SECONDS   fuzzing time per target (default 60)
#   WORK_DIR  build and scratch directory (default: a new one under /tmp,
#             removed after a run without failures); it gets the binaries, a
#             copy of the corpus, logs and any crash artifacts.  The source
#             tree is never written to.
#   TARGET    bpt and/or cli (default: both)
# Environment: FUZZ_CC, the clang to use (default clang-14, then clang).
# The targets run one after the other.
# Exit status: 0 all passed, 1 a target failed, 77 clang/libFuzzer missing
# (meson reports the test as skipped).
set -u
seconds=${1:-60}
work=${2:-}
if [ $# -gt 2 ]; then shift 2; else set --; fi
targets=${*:-bpt cli}

here=$(cd "$(dirname "$0")" && pwd -P)
source=$(cd "$here/../.." && pwd -P)

case $seconds in
    ''|*[!0-9]*) echo "run.sh: SECONDS must be a whole number, not '$seconds'" >&2; exit 2 ;;
esac

# ---- Find a clang with libFuzzer, or skip. ----
cc=${FUZZ_CC:-}
if [ -z "$cc" ]; then
    for candidate in clang-14 clang; do
        if command -v "$candidate" >/dev/null 2>&1; then cc=$candidate; break; fi
    done
fi
if [ -z "$cc" ]; then
    echo "SKIP: no clang found (apt-get install clang-14 libclang-rt-14-dev, or set FUZZ_CC)"
    exit 77
fi
made_work=0
if [ -z "$work" ]; then
    work=$(mktemp -d /tmp/perma-fuzz.XXXXXX) || exit 1
    made_work=1
fi
mkdir -p "$work" || exit 1
work=$(cd "$work" && pwd)
probe="$work/probe.c"
printf '%s\n' '#include <stddef.h>' '#include <stdint.h>' \
    'int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n);' \
    'int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }' \
    >"$probe"
if ! "$cc" -fsanitize=fuzzer,address,undefined "$probe" -o "$work/probe" >"$work/probe.log" 2>&1; then
    echo "SKIP: $cc cannot build libFuzzer targets (apt-get install libclang-rt-14-dev):"
    sed 's/^/    /' "$work/probe.log" | head -5
    exit 77
fi

# ---- Build.  Only host-side sources: no OpenCL library is linked. ----
# The same feature macros as meson.build's project arguments.
cflags="-std=c11 -D_POSIX_C_SOURCE=200809L -DCL_TARGET_OPENCL_VERSION=120
 -g -O1 -Wall -Wextra -fsanitize=fuzzer,address,undefined
 -fno-sanitize-recover=all -fno-omit-frame-pointer
 -I$source/procedures -I$source/procedures/device -I$source/procedures/host -I$source/examples/reyes -I$source/runtime/include -I$source/runtime/tools/cli
 -I$source/runtime/src -I$source/kernels"
# The sources and the longest input (-max_len) of a target.
target_sources() {
    case $1 in
        bpt) echo "$here/fuzz_bpt.c $source/procedures/host/reyes_bpt.c"\
                  "$source/procedures/host/reyes_scene.c $source/procedures/host/reyes_error.c" ;;
        cli) echo "$here/fuzz_cli.c $source/examples/reyes/reyes_cli.c"\
                  "$source/examples/reyes/reyes_cli_options.c $source/runtime/tools/cli/perma_cli_parse.c"\
                  "$source/runtime/tools/cli/perma_cli_values.c $source/runtime/tools/cli/perma_cli_help.c"\
                  "$source/procedures/host/reyes_options.c $source/procedures/host/reyes_error.c"\
                  "$source/runtime/src/names.c $source/runtime/src/schedule.c $source/runtime/src/schedule_table.c"\
                  "$source/runtime/src/output_file.c" ;;
    esac
}
target_max_len() {
    case $1 in
        bpt) echo 4096 ;; # a few patches of text
        cli) echo 1024 ;; # up to a few dozen options
    esac
}

for target in $targets; do
    case $target in
        bpt|cli) ;;
        *) echo "run.sh: unknown target '$target' (bpt or cli)" >&2; exit 2 ;;
    esac
    sources=$(target_sources "$target")
    # shellcheck disable=SC2086 # word splitting of the lists is intended
    if ! "$cc" $cflags $sources -lm -o "$work/fuzz_$target" 2>"$work/build_$target.log"; then
        cat "$work/build_$target.log"
        echo "FAIL: fuzz_$target does not build"
        echo "0 passed, 1 failed"
        exit 1
    fi
    [ -s "$work/build_$target.log" ] && cat "$work/build_$target.log" # warnings
done

# ---- Fuzz each target on a copy of its corpus. ----
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:allocator_may_return_null=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
passed=0
failed=0
for target in $targets; do
    corpus="$work/corpus/$target"
    artifacts="$work/artifacts/$target"
    log="$work/fuzz_$target.log"
    mkdir -p "$corpus" "$artifacts"
    cp "$source/tests/fuzz/corpus/$target/"* "$corpus/"
    max_len=$(target_max_len "$target")
    ok=1

    # Reproducers of fixed bugs (crashes/TARGET-*) must stay fixed.
    for input in "$source/tests/fuzz/crashes/$target"-*; do
        [ -f "$input" ] || continue
        if ! "$work/fuzz_$target" -error_exitcode=1 -timeout=10 -rss_limit_mb=2048 \
                "$input" >"$log.replay" 2>&1; then
            echo "FAIL: fuzz_$target crashes again on $input:"
            grep -E 'ERROR|runtime error|SUMMARY' "$log.replay" | head -5 | sed 's/^/    /'
            ok=0
        fi
    done

    echo "fuzz_$target: fuzzing for $seconds s (log: $log)"
    # The corpus grows in $corpus; tests/fuzz/grown/TARGET (what earlier
    # runs found, minimized) is read too, so a run starts where they ended.
    "$work/fuzz_$target" "$corpus" "$here/grown/$target" -dict="$here/$target.dict" \
        -max_total_time="$seconds" -max_len="$max_len" -rss_limit_mb=2048 -timeout=10 \
        -error_exitcode=1 -timeout_exitcode=1 -print_final_stats=1 \
        -artifact_prefix="$artifacts/" >"$log" 2>&1
    status=$?
    # A sanitizer report fails the run even if the exit status missed it.
    if [ $status -ne 0 ] || grep -qE '^(==[0-9]+==ERROR|SUMMARY: )|runtime error:' "$log" \
            || ! grep -q '^Done [0-9]* runs' "$log"; then
        echo "FAIL: fuzz_$target (exit status $status):"
        grep -E 'ERROR|runtime error|SUMMARY|Test unit written|^Done' "$log" | head -10 \
            | sed 's/^/    /'
        ok=0
    else
        sed -n 's/^Done \([0-9]*\) runs.*/    \1 runs, no findings/p' "$log"
    fi
    if [ $ok -eq 1 ]; then passed=$((passed + 1)); else failed=$((failed + 1)); fi
done
echo "$passed passed, $failed failed"
if [ $failed -ne 0 ]; then
    echo "logs and artifacts are in $work"
    exit 1
fi
[ $made_work -eq 1 ] && rm -rf "$work" # a default scratch directory is kept only on failure
exit 0
