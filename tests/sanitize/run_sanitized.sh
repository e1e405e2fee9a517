#!/bin/sh
# Build a copy of the project with AddressSanitizer and UBSan (host code) in
# BUILD_DIR/sanitize and run a cross-section of the tests there: every
# runtime test under several techniques and strategies, the Reyes host and
# render tests, the examples.  Any sanitizer report fails the test.
# Usage: run_sanitized.sh SOURCE_DIR BUILD_DIR
set -eu
source=$1
dir=$2/sanitize
if [ ! -f "$dir/build.ninja" ]; then
    meson setup "$dir" "$source" -Db_sanitize=address,undefined -Db_lundef=false \
        -Dsanitize_suite=false >/dev/null
fi
export LSAN_OPTIONS="suppressions=$source/tests/sanitize/lsan.supp:print_suppressions=0"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# meson test builds what these tests need (their executables and what
# they depend on), not the whole project: the benchmarks, other examples
# and the man pages are not sanitized here.
meson test -C "$dir" --print-errorlogs \
    tree@megakernel-shared tree@megakernel-stealing-donation chain@megakernel-stealing \
    chain@kernel-per-procedure overflow@megakernel-shared overflow@megakernel-stealing-local-queue \
    overflow@bounded-batches cooperative@megakernel-shared trace@megakernel-stealing \
    registration@megakernel-shared build_errors@megakernel-shared device_open@megakernel-shared \
    config@megakernel-shared emits@megakernel-shared watchdog@megakernel-shared progress@megakernel-shared progress@kernel-per-procedure reductions@megakernel-shared \
    reductions@kernel-per-procedure bind faults cache output \
    devices collatz_example perma_info_json queens_count cli cli_programs \
    $(meson test -C "$dir" --list 2>/dev/null | sed -n 's/^perma:reyes \/ //p')
