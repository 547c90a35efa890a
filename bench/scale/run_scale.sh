#!/ usr / bin / env bash
#Issue 40 item 3's figures : the 100M - triangle instanced forest and the 10M - triangle teapot,
#librt against Embree(paired builds, memory per triangle, rays), each engine's own peak
#RSS(one engine per process, builds only), librt's build scaling, and rt_render on the
#forest written as glTF into a temporary directory(removed at the end; never committed).
#
#bash bench / scale / run_scale.sh[out_dir](default : build / release / bench / scale)
#
#From the worktree root after a release build(librt_scale_bench, rt_render).About 10 to 15
#minutes on 2 busy cores; peak memory stays under 3 GiB(the 10M teapot with both engines).
set - euo pipefail cd "$(dirname " $0 ")/../.."

    bench = build / release / bench / librt_scale_bench render =
                build / release / apps / rt_render out = $ {
    1 : -build / release / bench / scale
}
export LIBRT_DATA_DIR = $ {
LIBRT_DATA_DIR:
    -../ shared / data
}
for
    exe in
        "$bench"
        "$render";
do [-x "$exe"] || {
        echo "run_scale: $exe not built (cmake --build --preset release)" > &2;
        exit 1;
    }
done[-x / usr / bin / time] || {
    echo "run_scale: /usr/bin/time not found (apt-get install time)" > &2;
    exit 1;
}
mkdir -p "$out"

#Each engine alone, builds only : the process 's peak RSS is that engine' s.
for scene in forest teapot;
do
  for
      engine in librt embree;
do
/ usr / bin / time - v "$bench" --scene "$scene" --engines "$engine" --reps 1 --no - trace >
        "$out/$scene.$engine.peak.txt" 2 >
        "$out/$scene.$engine.time.txt" echo "$scene $engine: $(grep -E '^peak RSS:' " $out /
            $scene.$engine.peak.txt
            ")"
            "(time -v: $(grep 'Maximum resident' " $out /
            $scene.$engine.time.txt " | awk '{print $NF}') KiB)" done done

#Paired builds and rays; the teapot's build scaling.
                                    "$bench" --scene forest-- reps 3 |
    tee
    "$out/forest.txt"
    "$bench" --scene teapot-- reps 3 --scaling |
    tee "$out/teapot.txt"

#rt_render on the forest : max RSS must stay under 4 GB.
    gltf =
    $(mktemp - d) trap 'rm -rf "$gltf"' EXIT "$bench" --write - gltf "$gltf" / usr / bin / time -
                v
                "$render"
                "$gltf/forest.gltf" --size 320x240 --spp 4 -
                o "$out/forest.png" 2 >
            "$out/render.time.txt" |
        tee "$out/render.txt" grep - E 'triangles stored|peak memory' "$out/render.time.txt" ||
    true rss = $(grep 'Maximum resident' "$out/render.time.txt" | awk '{print $NF}') echo
    "rt_render forest 320x240 4 spp: max RSS $((rss / 1024)) MiB (limit 4096)"
        ["$rss" - lt $((4 * 1024 * 1024))]
