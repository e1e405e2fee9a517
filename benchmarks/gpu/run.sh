#!/bin/sh
# run.sh RESULTS [--short] [options]: the GPU check, from the pack it is in
# (benchmarks/gpu/pack.sh made it; docs/gpu.md).  The steps are check.py's
# (run.sh --help lists them and the options); this finds a Python 3 for it.
here=$(cd "$(dirname "$0")" && pwd)
for python in python3 python3.12 python3.11 python3.10 python; do
    if command -v "$python" >/dev/null 2>&1 && "$python" -c 'import sys; sys.exit(sys.version_info < (3, 6))' 2>/dev/null; then
        exec "$python" "$here/check.py" "$@"
    fi
done
echo "run.sh: no Python 3 found (python3 on PATH): the check's steps are a Python script, $here/check.py" >&2
exit 2
