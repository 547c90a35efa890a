#!/usr/bin/env bash
# rt_render and scene files that reach outside their directory: an OBJ whose mtllib and a
# glTF whose image lie outside the scene's directory tree are refused (exit 1, the file and
# the line or JSON path named, nothing written); --allow-outside-files renders both.
# Usage: rt_render_untrusted_test.sh <rt_render> <scratch directory>
set -euo pipefail
app=$1
dir=$2
rm -rf "$dir"
mkdir -p "$dir/scene" "$dir/out"
fail() { echo "FAIL: $*" >&2; exit 1; }

printf 'newmtl red\nKd 1 0 0\n' >"$dir/outside.mtl"
printf 'mtllib ../outside.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nusemtl red\nf 1 2 3\n' >"$dir/scene/quad.obj"
# One triangle (positions in a data: URI) whose texture's image is a file beside the
# scene's directory, not in it.
cat >"$dir/scene/tri.gltf" <<'JSON'
{"asset":{"version":"2.0"},
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
 "bufferViews":[{"buffer":0,"byteLength":36}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
 "images":[{"uri":"../outside.png"}],
 "textures":[{"source":0}],
 "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
 "nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}]}
JSON
cp "$dir/outside.mtl" "$dir/outside.png"  # not an image: a warning once it may be read

check_refused() {  # scene, expected text
    local status=0
    "$app" "$1" --size 16x16 --spp 1 -q -o "$dir/out/refused.png" 2>"$dir/err.txt" >/dev/null ||
        status=$?
    [ "$status" -eq 1 ] || fail "$1: exit status $status, expected 1"
    grep -qF -- "$2" "$dir/err.txt" || fail "$1: message: $(cat "$dir/err.txt")"
    grep -qF -- "--allow-outside-files" "$dir/err.txt" || fail "$1: no hint: $(cat "$dir/err.txt")"
    [ -z "$(ls -A "$dir/out")" ] || fail "$1: refused, yet wrote $(ls -A "$dir/out")"
}
check_refused "$dir/scene/quad.obj" "quad.obj:1: mtllib '../outside.mtl' leads outside"
check_refused "$dir/scene/tri.gltf" "tri.gltf: images[0].uri: '../outside.png': leads outside"

for scene in quad.obj tri.gltf; do
    "$app" "$dir/scene/$scene" --allow-outside-files --size 16x16 --spp 1 -q \
        -o "$dir/out/$scene.png" 2>"$dir/err.txt" >/dev/null ||
        fail "$scene --allow-outside-files: $(cat "$dir/err.txt")"
    [ -s "$dir/out/$scene.png" ] || fail "$scene --allow-outside-files: no image"
done
echo "rt_render_untrusted_test: passed"
