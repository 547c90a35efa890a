#!/usr/bin/env bash
# rt_render and scene files that reach outside their directory: an OBJ whose mtllib and a
# glTF whose image lie outside the scene's directory tree are refused (exit 1, the file and
# the line or JSON path named, nothing written); --allow-outside-files renders both. Names
# in those files (a camera's in the summary line, the others in warnings) reach stdout and
# stderr escaped and capped.
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
# Names from the file reach the terminal escaped and capped: a glTF camera, node, light and
# material named with ESC, BEL and CR/LF (and 10,000 bytes), nodes scaled to zero (warnings),
# and an OBJ whose MTL material name holds ESC and BEL and whose texture is missing.
long=$(printf 'n%.0s' $(seq 10000))
evil='x\u001b[31m\u0007\r\nFORGED'
cat >"$dir/scene/names.gltf" <<JSON
{"asset":{"version":"2.0"},
 "extensionsUsed":["KHR_lights_punctual"],
 "extensions":{"KHR_lights_punctual":{"lights":[{"type":"spot","name":"$evil","spot":{}}]}},
 "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}],
 "bufferViews":[{"buffer":0,"byteLength":36}],
 "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
 "materials":[{"name":"$evil","extensions":{"KHR_materials_iridescence":{}}}],
 "images":[{"uri":"missing.png"}],
 "textures":[{"source":0}],
 "cameras":[{"type":"perspective","name":"$evil","perspective":{"yfov":0.7,"znear":0.1}}],
 "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
 "nodes":[{"mesh":0},{"mesh":0,"scale":[0,0,0],"name":"$evil"},{"mesh":0,"scale":[0,0,0],"name":"$long"},
          {"scale":[0,0,0],"extensions":{"KHR_lights_punctual":{"light":0}}},
          {"camera":0,"translation":[0.3,0.3,3]}],
 "scenes":[{"nodes":[0,1,2,3,4]}]}
JSON
printf 'newmtl red\033[31m\aX\nKd 1 0 0\nmap_Kd missing.png\n' >"$dir/scene/names.mtl"
printf 'mtllib names.mtl\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nusemtl red\033[31m\aX\nf 1 2 3\n' \
    >"$dir/scene/names.obj"
check_names() {  # scene, expected text on stderr
    "$app" "$dir/scene/$1" --size 16x16 --spp 1 --threads 1 -o "$dir/out/$1.png" \
        >"$dir/out.txt" 2>"$dir/err.txt" || fail "$1: $(cat "$dir/err.txt")"
    # No ESC, BEL or CR anywhere; no line but the ones rt_render writes.
    if LC_ALL=C grep -q $'[\x01-\x08\x0b-\x1f\x7f]' "$dir/out.txt" "$dir/err.txt"; then
        fail "$1: a control character reached the terminal: $(od -c "$dir/out.txt" "$dir/err.txt" | head -40)"
    fi
    if grep -q '^FORGED' "$dir/out.txt" "$dir/err.txt"; then fail "$1: a forged line"; fi
    grep -qF -- "$2" "$dir/err.txt" || fail "$1: expected '$2' in: $(cat "$dir/err.txt")"
    local longest
    longest=$(cat "$dir/out.txt" "$dir/err.txt" | awk '{ if (length($0) > n) n = length($0) } END { print n }')
    [ "$longest" -lt 1000 ] || fail "$1: a line of $longest bytes: a 10,000-byte name quoted whole"
}
check_names names.gltf "nodes[1] 'x\\x1b[31m\\x07\\r\\nFORGED': its world transform is singular"
grep -qF "camera 'x\\x1b[31m\\x07\\r\\nFORGED' (perspective)" "$dir/out.txt" ||
    fail "names.gltf: the camera's name in the summary: $(cat "$dir/out.txt")"
grep -qF "lights[0] 'x\\x1b[31m\\x07\\r\\nFORGED' placed by nodes[3]" "$dir/err.txt" ||
    fail "names.gltf: the light's name: $(cat "$dir/err.txt")"
grep -qF "materials[0] 'x\\x1b[31m\\x07\\r\\nFORGED': KHR_materials_iridescence is not supported" "$dir/err.txt" ||
    fail "names.gltf: the material's name: $(cat "$dir/err.txt")"
check_names names.obj "names.mtl:1: MTL material 'red\\x1b[31m\\x07X': cannot load texture"
echo "rt_render_untrusted_test: passed"
