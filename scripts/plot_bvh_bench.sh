#!/usr/bin/env bash
# Charts of librt_bench's JSON output (Google Benchmark's --benchmark_out_format=json):
#   docs/bvh_vs_embree.png  side by side per mesh and row: librt, Embree at its default build
#                           quality and Embree at RTC_BUILD_QUALITY_HIGH (Mrays/s from the
#                           paired rows <mesh>/librt_vs_embree/... and .../librt_vs_embree_hq/...,
#                           the librt bar from the first), and the three engines' build times;
#   docs/bvh_scaling.png    closest-hit rays/s (incoherent, one thread) against triangle count
#                           for every engine (naive, median and SAH binary BVHs, librt, Embree).
#
#   bash scripts/plot_bvh_bench.sh [results.json]
#
# Without an argument it runs librt_bench itself (all rows, 3 repetitions, medians; about
# 10 minutes on 2 busy cores) and keeps the JSON in build/release/bench/. Medians are used when
# the run was repeated. Needs gnuplot (Debian gnuplot-nox, in scripts/setup.sh) and python3
# (its standard library only); no build target runs this script.
set -euo pipefail
cd "$(dirname "$0")/.."

command -v gnuplot >/dev/null || { echo "plot_bvh_bench: gnuplot not found (apt-get install gnuplot-nox)" >&2; exit 1; }
python=python3
[ -x /usr/bin/python3 ] && python=/usr/bin/python3

json=${1:-}
if [ -z "$json" ]; then
  json=build/release/bench/bvh_bench.json
  ./build/release/bench/librt_bench --benchmark_repetitions=3 \
    --benchmark_enable_random_interleaving=true \
    --benchmark_out="$json" --benchmark_out_format=json
fi
[ -s "$json" ] || { echo "plot_bvh_bench: $json is missing or empty" >&2; exit 1; }

mkdir -p docs
data=$(mktemp -d)
trap 'rm -rf "$data"' EXIT

# JSON -> whitespace-separated tables for gnuplot:
#   rays.dat   label librt embree embree_hq     (one line per mesh and ray row)
#   build.dat  mesh  librt_ms embree_ms embree_hq_ms
#   <engine>.dat  triangles Mrays mesh          (incoherent 1t, for the scaling chart)
"$python" - "$json" "$data" <<'EOF'
import json, sys, os
doc = json.load(open(sys.argv[1]))
out = sys.argv[2]
rows = {}          # base name -> counters; medians replace single runs
median_seen = set()
for b in doc.get("benchmarks", []):
    name = b.get("run_name", b["name"])
    for suffix in ("/manual_time", "/real_time"):
        if name.endswith(suffix):
            name = name[: -len(suffix)]
    if b.get("run_type") == "aggregate":
        if b.get("aggregate_name") != "median":
            continue
        median_seen.add(name)
        rows[name] = b
    elif name not in median_seen:
        rows[name] = b   # single runs: the last repetition, unless a median comes

def get(name, key):
    v = rows.get(name, {}).get(key)
    return v if v else None

meshes = []
for name in rows:
    mesh = name.split("/")[0]
    if mesh not in meshes and "/librt_vs_embree/" in name:
        meshes.append(mesh)
order = {"teapot1k": 0, "teapot10k": 1, "teapot100k": 2, "teapot1000k": 3, "bunny": 4, "dragon": 5}
meshes.sort(key=lambda m: order.get(m, 99))
labels = {"incoherent": "incoh.", "anyhit": "any hit", "primary": "primary"}
with open(os.path.join(out, "rays.dat"), "w") as f:
    for mesh in meshes:
        for rays in ("incoherent", "anyhit", "primary"):
            for thr in ("1t", "2t", "4t", "8t"):
                base = f"{mesh}/librt_vs_embree/{rays}/{thr}"
                librt, embree = get(base, "librt_Mrays"), get(base, "embree_Mrays")
                if librt is None:
                    continue
                hq = get(f"{mesh}/librt_vs_embree_hq/{rays}/{thr}", "embree_Mrays")
                label = f'"{mesh} {labels[rays]} {thr}"'
                f.write(f"{label} {librt} {embree or '-'} {hq or '-'}\n")
with open(os.path.join(out, "build.dat"), "w") as f:
    for mesh in meshes:
        librt = get(f"{mesh}/librt_vs_embree/build", "librt_ms")
        if librt is None:
            continue
        embree = get(f"{mesh}/librt_vs_embree/build", "embree_ms")
        hq = get(f"{mesh}/librt_vs_embree_hq/build", "embree_ms")
        f.write(f'"{mesh}" {librt} {embree or "-"} {hq or "-"}\n')
scaling = {}
for name, b in rows.items():
    part = name.split("/")
    if len(part) != 4 or part[2] != "incoherent" or part[3] != "1t" or not b.get("tris"):
        continue
    if part[1] in ("librt_vs_embree", "librt"):
        scaling.setdefault("librt", []).append((b["tris"], b["librt_Mrays"], part[0]))
        if b.get("embree_Mrays"):
            scaling.setdefault("embree", []).append((b["tris"], b["embree_Mrays"], part[0]))
    elif part[1] in ("naive", "median", "sah") and b.get("Mrays"):
        scaling.setdefault(part[1], []).append((b["tris"], b["Mrays"], part[0]))
for engine, pts in scaling.items():
    with open(os.path.join(out, engine + ".dat"), "w") as f:
        for t, m, mesh in sorted(pts):
            f.write(f"{t} {m} {mesh}\n")
EOF

[ -s "$data/rays.dat" ] || { echo "plot_bvh_bench: no librt_vs_embree rows in $json" >&2; exit 1; }

gnuplot <<EOF
set terminal pngcairo size 1400,900 font ',10'
set output 'docs/bvh_vs_embree.png'
set multiplot layout 2,1 title 'librt against Embree 3.13 (default and high build quality); medians of paired rows'
set style data histogram
set style histogram clustered gap 1
set style fill solid 0.85 border -1
set boxwidth 0.9
set datafile missing '-'
set logscale y
set grid ytics
set key top left
set ylabel 'Mrays/s (thread CPU time)'
set xtics rotate by -40 left font ',9'
set rmargin 10
set title 'Rays: closest hit (incoherent, primary) and any hit; 1t = one thread, 2t = per 2 cores'
plot '$data/rays.dat' using 2:xtic(1) title 'librt' lc rgb '#1b9e77', \
     '' using 3 title 'Embree default' lc rgb '#7570b3', \
     '' using 4 title 'Embree high quality' lc rgb '#d95f02'
set title 'Builds (wall time, both cores)'
set ylabel 'ms'
set xtics norotate font ',10'
plot '$data/build.dat' using 2:xtic(1) title 'librt' lc rgb '#1b9e77', \
     '' using 3 title 'Embree default' lc rgb '#7570b3', \
     '' using 4 title 'Embree high quality' lc rgb '#d95f02'
unset multiplot
EOF
echo "plot_bvh_bench: wrote docs/bvh_vs_embree.png from $json"

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
[ -n "$plot" ] || exit 0
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
echo "plot_bvh_bench: wrote docs/bvh_scaling.png from $json"
