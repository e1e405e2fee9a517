#!/bin/sh
# run_on.sh IMPLEMENTATION PROGRAM [ARGS...]
#
# Run a test program on one OpenCL implementation, or skip it (exit 77,
# which meson reports as SKIP) with a message when that implementation is
# not installed.
#
#   intel     Intel's OpenCL CPU runtime from .ci/install-deps: the ICD
#             loader is pointed at PERMA_INTEL_ICD_DIR (written by meson,
#             holding intel.icd with the absolute path of PERMA_INTEL_LIB,
#             and pocl.icd) and PERMA_DEVICE=intel selects it, so a test
#             that cannot find it fails rather than running elsewhere.
#   oclgrind  the Oclgrind simulator with its data-race detector, one
#             compute unit (perma then runs one work-group unless a test
#             asks for more), one thread.  PERMA_RACE_CHECK is defined for
#             the device code (see perma_load in kernels/perma_prelude.cl).
#             Any report in Oclgrind's log fails the test and is printed.
set -eu
implementation=$1
shift
case $implementation in
intel)
    lib=${PERMA_INTEL_LIB:?}
    if [ ! -e "$lib" ]; then
        echo "SKIP: Intel's OpenCL CPU runtime is not installed ($lib is missing); sh .ci/install-deps installs it"
        exit 77
    fi
    OCL_ICD_VENDORS=${PERMA_INTEL_ICD_DIR:?}
    PERMA_DEVICE=intel
    export OCL_ICD_VENDORS PERMA_DEVICE
    exec "$@"
    ;;
oclgrind)
    if ! command -v oclgrind >/dev/null 2>&1; then
        echo "SKIP: oclgrind is not installed (Debian package oclgrind; sh .ci/install-deps installs it)"
        exit 77
    fi
    log=$(mktemp "${TMPDIR:-/tmp}/perma-oclgrind.XXXXXX")
    trap 'rm -f "$log"' EXIT
    # PERMA_DEVICE could name another platform; under oclgrind only its own exists.
    unset PERMA_DEVICE
    status=0
    oclgrind --data-races --compute-units 1 --num-threads 1 --log "$log" \
        --build-options -DPERMA_RACE_CHECK=1 "$@" || status=$?
    if [ -s "$log" ]; then
        echo "Oclgrind reported:"
        cat "$log"
        [ "$status" -ne 0 ] || status=1
    else
        echo "Oclgrind: no data race, invalid access or barrier divergence reported"
    fi
    exit "$status"
    ;;
*)
    echo "run_on.sh: unknown implementation '$implementation' (intel or oclgrind)" >&2
    exit 2
    ;;
esac
