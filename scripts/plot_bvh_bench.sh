#!/usr/bin/env bash
# Plots closest-hit rays/s (incoherent rays, one thread) against triangle count for every
# engine of librt_bench (naive, median BVH, SAH BVH, librt's wide BVH, Embree) into
# docs/bvh_scaling.png.
#
#   bash scripts/plot_bvh_bench.sh [results.csv]
#
# Without an argument it runs the benchmark's incoherent/1t rows first (3 repetitions,
# medians; about two minutes) and keeps the CSV in build/release/bench/. Needs gnuplot
# (Debian: apt-get install gnuplot-nox); no build target runs this script.
set -euo pipefail
cd "$(dirname "$0")/.."

command -v gnuplot >/dev/null || { echo "plot_bvh_bench: gnuplot not found (apt-get install gnuplot-nox)" >&2; exit 1; }

csv=${1:-}
if [ -z "$csv" ]; then
  csv=build/release/bench/bvh_scaling.csv
  ./build/release/bench/librt_bench --benchmark_filter='/incoherent/1t$' \
    --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
    --benchmark_out="$csv" --benchmark_out_format=csv
fi

mkdir -p docs
data=$(mktemp -d)
trap 'rm -rf "$data"' EXIT

# Google Benchmark's CSV: a header line, then one line per row (or per aggregate); the
# user counters are extra columns named in the header. Keep medians when repeated. The
# librt_vs_embree rows carry both librt's and Embree's rates.
awk -F, -v out="$data" '
  NR == FNR { if ($1 ~ /_median"?$/) medians = 1; next }   # first pass: repeated run?
  /^name,/ { for (i = 1; i <= NF; ++i) { h = $i; gsub(/"/, "", h); col[h] = i }; header = 1; next }
  !header { next }
  {
    name = $1; gsub(/"/, "", name)
    if (name ~ /_(mean|stddev|cv)$/) next
    if (medians && name !~ /_median$/) next
    sub(/_median$/, "", name)
    sub(/\/(manual|real)_time$/, "", name)
    split(name, part, "/")             # mesh/engine/incoherent/1t
    if (part[3] != "incoherent" || part[4] != "1t") next
    tris = $(col["tris"])
    if (part[2] == "librt_vs_embree" || part[2] == "librt") {
      print tris, $(col["librt_Mrays"]), part[1] >> (out "/librt.dat")
      if ($(col["embree_Mrays"]) > 0) print tris, $(col["embree_Mrays"]), part[1] >> (out "/embree.dat")
    } else {
      print tris, $(col["Mrays"]), part[1] >> (out "/" part[2] ".dat")
    }
  }' "$csv" "$csv"

for f in "$data"/*.dat; do sort -g -o "$f" "$f"; done

plot=""
for engine in naive median sah librt embree; do
  f="$data/$engine.dat"
  [ -s "$f" ] || continue
  case $engine in
    naive) title="naive loop" ;;
    median) title="binary BVH, median split" ;;
    sah) title="binary BVH, binned SAH" ;;
    librt) title="librt 8-wide BVH" ;;
    embree) title="Embree 3.13" ;;
  esac
  plot+="${plot:+, }'$f' using 1:2 with linespoints lw 2 pt 7 title '$title'"
  [ "$engine" = librt ] && plot+=", '$f' using 1:2:3 with labels offset 0,-1 font ',9' notitle"
done

gnuplot <<EOF
set terminal pngcairo size 900,600 font ',11'
set output 'docs/bvh_scaling.png'
set title 'Closest hit, incoherent rays, one thread (medians when repeated)'
set xlabel 'triangles'
set ylabel 'Mrays/s (thread CPU time)'
set logscale xy
set xrange [500:3e6]
set format x '10^{%T}'
set grid
set key bottom left
plot $plot
EOF
echo "plot_bvh_bench: wrote docs/bvh_scaling.png from $csv"
