#!/bin/sh
# Outputs that are the same file as each other or as an input are refused
# before any work (exit 2, both named), whatever the path says: "./",
# a symbolic link, a hard link, a frame's name, the trace (--trace or
# PERMA_TRACE).  The files are
# left as they were.  PERMA_DEVICE=9:9 makes any work that started fail
# otherwise (exit 1).
# Usage: output_clash.sh REYES_RENDER PERMA_BENCH PERMA_MANDELBROT PERMA_BFS (from the project root)
set -u
# The programs by absolute path: the cases run in a scratch directory.
absolute() { case $1 in /*) echo "$1" ;; *) echo "$PWD/$1" ;; esac; }
R=$(absolute "$1") B=$(absolute "$2") M=$(absolute "$3") F=$(absolute "$4")
dir=$(mktemp -d /tmp/perma-clash-XXXXXX)
trap 'rm -rf "$dir"' EXIT
cp tests/reliability/flat.bpt "$dir/mine.bpt"
ln "$dir/mine.bpt" "$dir/hard.bpt"
echo "an image" > "$dir/x.png"
ln -s x.png "$dir/link.png"
echo "0 1" > "$dir/edges.txt"
passed=0 failed=0
# expect NAME MESSAGE COMMAND...: exit 2, MESSAGE (a fixed string) on stderr.
expect() {
    name=$1 message=$2
    shift 2
    status=0
    (cd "$dir" && PERMA_DEVICE=9:9 "$@") > "$dir/out.txt" 2>&1 || status=$?
    if [ "$status" -eq 2 ] && grep -qF -- "$message" "$dir/out.txt"; then
        passed=$((passed + 1))
    else
        failed=$((failed + 1))
        echo "FAIL $name: expected exit 2 and \"$message\", got exit $status:"
        cat "$dir/out.txt"
    fi
}
expect output_is_stats "--output 'y.png' and --stats 'y.png' are the same file: one would overwrite the other" \
    "$R" --size 16x16 -o y.png --stats y.png
expect output_is_stats_dotted "--output 'x.png' and --stats './x.png' are the same file" \
    "$R" --size 16x16 -o x.png --stats ./x.png
expect output_is_stats_linked "--output 'x.png' and --stats 'link.png' are the same file" \
    "$R" --size 16x16 -o x.png --stats link.png
expect frame_is_stats "--frames 'fr-0001.png' and --stats 'fr-0001.png' are the same file" \
    "$R" --size 16x16 --frames 2 -o fr.png --stats fr-0001.png
expect output_is_model "--output 'mine.bpt' is the same file as the model 'mine.bpt', which it would overwrite" \
    "$R" mine.bpt --size 16x16 -o mine.bpt
expect stats_is_model "--stats 'hard.bpt' is the same file as the model 'mine.bpt', which it would overwrite" \
    "$R" mine.bpt --size 16x16 -o z.png --stats hard.bpt
expect output_is_trace "--output 'x.png' and PERMA_TRACE '$dir/x.png' are the same file" \
    env PERMA_TRACE="$dir/x.png" "$R" --size 16x16 -o x.png
expect bench_csv_is_trace "perma-bench queue: --csv 'q.csv' and PERMA_TRACE './q.csv' are the same file" \
    env PERMA_TRACE=./q.csv "$B" queue --quick --repeat 1 --csv q.csv
expect output_is_trace_option "--output 'x.png' and --trace 'link.png' are the same file" \
    "$R" --size 16x16 -o x.png --trace link.png
expect trace_is_model "--trace 'mine.bpt' is the same file as the model 'mine.bpt', which it would overwrite" \
    "$R" mine.bpt --size 16x16 -o z.png --trace mine.bpt
expect bench_csv_is_trace_option "perma-bench queue: --csv 'q.csv' and --trace './q.csv' are the same file" \
    "$B" queue --quick --repeat 1 --csv q.csv --trace ./q.csv
cp tests/reliability/flat.bpt "$dir/teapot.bpt"
expect bench_csv_is_model "perma-bench reyes: --csv 'teapot.bpt' is the same file as the model '$dir/../$(basename "$dir")/teapot.bpt'" \
    "$B" reyes --quick --repeat 1 --models "$dir/../$(basename "$dir")" --csv teapot.bpt
expect mandelbrot_output_is_trace "perma-mandelbrot: --output 'm.png' and PERMA_TRACE 'm.png' are the same file" \
    env PERMA_TRACE=m.png "$M" -o m.png
expect bfs_output_is_input "perma-bfs: --output 'edges.txt' is the same file as the edge file 'edges.txt'" \
    "$F" edges.txt -o edges.txt
# Nothing was written over: the model, the image, the edges; no new file.
if ! cmp -s tests/reliability/flat.bpt "$dir/mine.bpt" || ! cmp -s tests/reliability/flat.bpt "$dir/teapot.bpt" || [ "$(cat "$dir/x.png")" != "an image" ] \
    || [ "$(cat "$dir/edges.txt")" != "0 1" ] \
    || [ "$(ls "$dir" | tr '\n' ' ')" != "edges.txt hard.bpt link.png mine.bpt out.txt teapot.bpt x.png " ]; then
    failed=$((failed + 1))
    echo "FAIL: files were written:"
    ls -la "$dir"
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
