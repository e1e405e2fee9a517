#!/bin/sh
# Run the three benchmarks and regenerate the plots of docs/benchmarks.md:
#
#     benchmarks/plot.sh [BUILD_DIR]        (default BUILD_DIR: build)
#
# Writes benchmarks/results/{tree,queue,pipeline}.{txt,csv} (the tables and
# CSV of this run, plus machine.txt) and docs/benchmarks-{tree,queue,pipeline}.svg.
# PLOT_ONLY=1 skips the runs and redraws from the existing CSV files;
# REPEAT=N sets --repeat (default 5); QUICK=1 uses the small --quick sizes.
# Needs gnuplot (apt-get install gnuplot-nox).
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
bench=$build/benchmarks/perma-bench
results=$root/benchmarks/results
docs=$root/docs
repeat=${REPEAT:-5}

command -v gnuplot >/dev/null 2>&1 || { echo "plot.sh: gnuplot not found (apt-get install gnuplot-nox)" >&2; exit 1; }
mkdir -p "$results"

if [ "${PLOT_ONLY:-0}" != 1 ]; then
    [ -x "$bench" ] || { echo "plot.sh: $bench not found; build first (ninja -C $build)" >&2; exit 1; }
    {
        date -u '+%Y-%m-%d %H:%M UTC'
        uname -srm
        grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'
        echo "online CPUs: $(nproc)"
        echo "perma commit: $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown)"
    } > "$results/machine.txt"
    for b in tree queue pipeline; do
        echo "plot.sh: running perma-bench $b (repeat $repeat)" >&2
        # A wrong result makes perma-bench exit 1; keep the tables anyway.
        "$bench" "$b" ${QUICK:+--quick} --repeat "$repeat" --csv "$results/$b.csv" > "$results/$b.txt" || \
            echo "plot.sh: perma-bench $b reported a failure, see $results/$b.txt" >&2
    done
fi

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# CSV columns: 3 variant, 4 group size, 5 work-groups, 6 status, 11 rate,
# 12 speedup vs sequential, 17 peak item bytes.  Fields never hold commas.
# Rows of the first workload give the variant order; n/a rows plot as 0.
awk -F, 'NR > 1 { gsub(/"/, "");
    v = $3; if (!(v in seen)) { seen[v] = 1; order[++n] = v }
    s = ($6 == "ok") ? $12 : 0
    if ($2 ~ /^geometric/) geo[v] = s; else bin[v] = s }
    END { for (i = 1; i <= n; ++i) { v = order[i]; if (v ~ /^sequential/) continue
          printf "\"%s\" %s %s\n", v, (v in geo) ? geo[v] : 0, (v in bin) ? bin[v] : 0 } }' \
    "$results/tree.csv" > "$tmp/tree.dat"

# Queue: empty tasks per second with 2 work-groups, per group size; the
# baselines become horizontal lines.
awk -F, 'NR > 1 { gsub(/"/, "")
    if ($4 == 0) { printf "%s %s\n", ($3 ~ /^sequential/) ? "seq" : ($3 ~ /one producer/) ? "omp1" : "ompg", $11 > "'"$tmp"'/queue_base.dat"; next }
    if ($5 != 2) next
    v = $3; if (!(v in seen)) { seen[v] = 1; order[++n] = v }
    r[v, $4] = ($6 == "ok") ? $11 : 0 }
    END { for (i = 1; i <= n; ++i) { v = order[i]
          printf "\"%s\" %s %s %s\n", v, r[v, 32] + 0, r[v, 64] + 0, r[v, 128] + 0 } }' \
    "$results/queue.csv" > "$tmp/queue.dat"
seq_rate=$(awk '$1 == "seq" { print $2 }' "$tmp/queue_base.dat")
omp1_rate=$(awk '$1 == "omp1" { print $2 }' "$tmp/queue_base.dat")
ompg_rate=$(awk '$1 == "ompg" { print $2 }' "$tmp/queue_base.dat")
queue_top=$(awk '{ if ($2 > m) m = $2 } END { print m * 3 / 1e6 }' "$tmp/queue_base.dat" "$tmp/queue.dat")

# Pipeline: peak bytes of waiting items, default order vs upstream first.
awk -F, 'NR > 1 { gsub(/"/, "")
    v = $3; sub(/ \((down|up)stream first\)/, "", v)
    if (!(v in seen)) { seen[v] = 1; order[++n] = v }
    b = ($6 == "ok") ? $17 : 0
    if ($2 ~ /downstream/) down[v] = b; else up[v] = b }
    END { for (i = 1; i <= n; ++i) { v = order[i]
          printf "\"%s\" %s %s\n", v, (v in down) ? down[v] : 0, (v in up) ? up[v] : 0 } }' \
    "$results/pipeline.csv" > "$tmp/pipeline.dat"

# Reference values are drawn as arrows: gnuplot's histogram style does not
# plot constant functions as flat lines.
gnuplot <<EOF
set terminal svg size 1000,600 font "sans,11" background "white"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.85 border -1
set boxwidth 0.9
set bmargin 12
set rmargin 4
set xtics rotate by -30 left noenhanced nomirror
set grid ytics
set key top left noenhanced

set output "$docs/benchmarks-tree.svg"
set title "tree: speedup over sequential C (higher is better; 2 cores)"
set ylabel "sequential time / variant time"
set yrange [0:*]
set arrow 1 from graph 0, first 1 to graph 1, first 1 nohead lw 2 lc rgb "black"
set label 1 "sequential C" at graph 0.99, first 1 right offset 0,0.7
set arrow 2 from graph 0, first 1.6 to graph 1, first 1.6 nohead lw 2 dt 2 lc rgb "red"
set label 2 "target 1.6x" at graph 0.99, first 1.6 right offset 0,0.7 tc rgb "red"
plot "$tmp/tree.dat" using 2:xtic(1) title "geometric", "" using 3 title "binomial"
unset arrow
unset label

set output "$docs/benchmarks-queue.svg"
set title "queue: empty tasks per second, 2 work-groups (higher is better; log scale)"
set ylabel "million tasks / s"
set logscale y
set yrange [0.1:${queue_top:-1000}]
set arrow 1 from graph 0, first ${omp1_rate:-0}/1e6 to graph 1, first ${omp1_rate:-0}/1e6 nohead lw 2 lc rgb "red"
set label 1 "OpenMP tasks, one producer" at graph 0.99, first ${omp1_rate:-0}/1e6 right offset 0,0.7 tc rgb "red"
set arrow 2 from graph 0, first ${ompg_rate:-0}/1e6 to graph 1, first ${ompg_rate:-0}/1e6 nohead lw 2 dt 2 lc rgb "red"
set label 2 "OpenMP tasks, generator tasks" at graph 0.99, first ${ompg_rate:-0}/1e6 right offset 0,-0.7 tc rgb "red"
set arrow 3 from graph 0, first ${seq_rate:-0}/1e6 to graph 1, first ${seq_rate:-0}/1e6 nohead lw 2 lc rgb "black"
set label 3 "sequential C FIFO loop" at graph 0.99, first ${seq_rate:-0}/1e6 right offset 0,0.7
plot "$tmp/queue.dat" using (\$2/1e6):xtic(1) title "group size 32", "" using (\$3/1e6) title "64", \
     "" using (\$4/1e6) title "128"
unset arrow
unset label

set output "$docs/benchmarks-pipeline.svg"
set title "pipeline: peak bytes of waiting items (lower is better; log scale)"
set ylabel "bytes"
set yrange [1000:*]
plot "$tmp/pipeline.dat" using 2:xtic(1) title "downstream first (default)", "" using 3 title "upstream first (priorities)"
EOF
echo "plot.sh: wrote $docs/benchmarks-tree.svg, benchmarks-queue.svg, benchmarks-pipeline.svg" >&2
