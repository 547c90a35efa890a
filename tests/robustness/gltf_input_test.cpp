// Bad glTF input: every case throws librt::Error naming the file and the JSON path (or,
// for the container, what is wrong with it), before anything is returned; never a crash,
// hang, stack overflow or an allocation the file's size does not justify.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"

#include <librt/gltf/gltf.h>

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cstring>
#include <string>

using namespace librt;
using librt::testing::error_of;
using librt::testing::get_u32;
using librt::testing::GltfBuilder;
using librt::testing::has;
using librt::testing::ScratchDir;
using librt::testing::set_u32;
using nlohmann::json;
namespace fs = std::filesystem;
namespace lt = librt::testing;

namespace {

/// The error loading `bytes` (written as `name`) gives; checks it names the file and `part`.
std::string load_error(const ScratchDir& dir, const std::string& name, const std::string& bytes,
                       const std::string& part) {
    const fs::path p = dir.path() / name;
    lt::write_file(p, bytes);
    const std::string msg = error_of([&] { (void)load_gltf(p); });
    EXPECT_TRUE(has(msg, p.string() + ": ")) << "file not named in: " << msg;
    EXPECT_TRUE(has(msg, part)) << "expected '" << part << "' in: " << msg;
    return msg;
}

}  // namespace

TEST(BadGltf, NotGltfAndBrokenJson) {
    ScratchDir dir;
    load_error(dir, "a.gltf", "v 0 0 0\nf 1 2 3\n", "not a glTF file");
    load_error(dir, "b.gltf", "{\"asset\": {\"version\": \"2.0\"},\n \"nodes\": [}",
               "broken JSON: parse error at line 2");
    load_error(dir, "c.gltf", "{\"nodes\": []}", "asset: missing");
    load_error(dir, "d.gltf", R"({"asset": {"version": "1.0"}})", "asset.version: '1.0'");
    load_error(dir, "e.glb", "", "not a glTF file");
}

TEST(BadGltf, PathsThatAreNotRegularFiles) {
    ScratchDir dir;
    EXPECT_TRUE(has(error_of([&] { (void)load_gltf(dir.path() / "absent.glb"); }), "no such file"));
    EXPECT_TRUE(has(error_of([&] { (void)load_gltf(dir.path()); }), "is a directory"));
    const fs::path fifo = dir.path() / "pipe.gltf";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    const std::string msg = error_of([&] { (void)load_gltf(fifo); });  // must not block
    EXPECT_TRUE(has(msg, fifo.string() + ": not a regular file")) << msg;
    EXPECT_TRUE(
        has(error_of([&] { (void)load_gltf("/dev/zero"); }), "/dev/zero: not a regular file"));
    // The size limit.
    const fs::path p = dir.path() / "big.glb";
    lt::write_file(p, lt::one_triangle().glb());
    GltfLoadOptions small;
    small.max_file_bytes = 100;
    EXPECT_TRUE(has(error_of([&] { (void)load_gltf(p, small); }), "more than the limit of 100"));
}

TEST(BadGltf, TruncatedGlbAndWrongChunkLengths) {
    ScratchDir dir;
    const std::string good = lt::one_triangle().glb();
    load_error(dir, "t1.glb", good.substr(0, 10), "truncated .glb");
    load_error(dir, "t2.glb", good.substr(0, good.size() - 8),
               "truncated .glb: its header declares");
    const std::uint32_t json_length = get_u32(good, 12);
    std::string wrong = good;
    set_u32(wrong, 12, json_length + 64);  // JSON chunk length too long
    load_error(dir, "t3.glb", wrong, "chunk 0 (JSON) declares");
    // BIN chunk length beyond the file's end, by 8 bytes (tinygltf 2.7 alone would read
    // them: it forgets the chunk header in this check).
    wrong = good;
    const std::size_t bin_at = 20 + json_length;
    set_u32(wrong, bin_at, get_u32(good, bin_at) + 8);
    load_error(dir, "t4.glb", wrong, "chunk 1 (BIN) declares");
    wrong = good;
    set_u32(wrong, 12, json_length + 2);  // not a multiple of 4
    load_error(dir, "t5.glb", wrong, "is not a positive multiple of 4");
    wrong = good;
    set_u32(wrong, 4, 1);
    load_error(dir, "t6.glb", wrong, ".glb version 1");
}

TEST(BadGltf, BuffersAndAccessorsOutOfRange) {
    ScratchDir dir;
    GltfBuilder b = lt::one_triangle();
    // Missing .bin.
    load_error(dir, "m.gltf", b.with_buffer("gone.bin").dump(), "buffers[0].uri: 'gone.bin'");
    // A .bin shorter than byteLength.
    lt::write_file(dir.path() / "short.bin", b.bin.substr(0, 20));
    load_error(dir, "s.gltf", b.with_buffer("short.bin").dump(), "buffers[0]: byteLength 36");
    // A buffer view beyond its buffer.
    GltfBuilder v = b;
    v.doc["bufferViews"][0]["byteLength"] = 4000;
    load_error(dir, "v.glb", v.glb(), "bufferViews[0]: bytes [0, 4000) lie outside buffers[0]");
    // An accessor beyond its buffer view, and a huge declared count: an error, not an
    // allocation.
    for (const std::uint64_t count : {std::uint64_t{4}, std::uint64_t{1} << 40u}) {
        GltfBuilder a = b;
        a.doc["accessors"][0]["count"] = count;
        load_error(dir, "a.glb", a.glb(),
                   "meshes[0].primitives[0].attributes.POSITION: accessors[0]: " +
                       std::to_string(count) + " elements");
    }
    // A huge count with no buffer view (zeros by the spec): refused by the memory bound.
    GltfBuilder z = b;
    z.doc["accessors"][0].erase("bufferView");
    z.doc["accessors"][0]["count"] = std::uint64_t{1} << 40u;
    load_error(dir, "z.glb", z.glb(), "accessors[0]: decoding needs");
    // A sparse index beyond the count.
    GltfBuilder sp = b;
    const int idx = sp.add_view(std::vector<std::uint8_t>{7, 0, 0, 0}.data(), 4);
    sp.doc["accessors"][0]["sparse"] = {
        {"count", 1},
        {"indices", {{"bufferView", idx}, {"componentType", lt::kU8}}},
        {"values", {{"bufferView", 0}}}};
    load_error(dir, "sp.glb", sp.glb(), "accessors[0].sparse.indices: index 7");
}

TEST(BadGltf, IndicesAndReferencesOutOfRange) {
    ScratchDir dir;
    GltfBuilder b = lt::one_triangle();
    GltfBuilder i = b;
    i.doc["meshes"][0]["primitives"][0]["indices"] =
        i.add_accessor(std::vector<std::uint16_t>{0, 1, 3, 0}, lt::kU16, "SCALAR", 3);
    load_error(dir, "i.gltf", i.gltf(),
               "meshes[0].primitives[0].indices: index 3 >= vertex count 3");
    GltfBuilder m = b;
    m.doc["nodes"][0]["mesh"] = 5;
    load_error(dir, "m.gltf", m.gltf(), "nodes[0].mesh: mesh 5 does not exist");
    GltfBuilder mat = b;
    mat.doc["meshes"][0]["primitives"][0]["material"] = 2;
    load_error(dir, "mat.gltf", mat.gltf(), "meshes[0].primitives[0].material: material 2");
    GltfBuilder big = b;
    big.doc["nodes"][0]["mesh"] = 4294967296ull;  // would wrap to 0 in an int
    load_error(dir, "big.gltf", big.gltf(), "nodes[0].mesh: 4294967296 is too large");
    GltfBuilder cam = b;
    cam.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0}, {"znear", 1}}}}};
    load_error(dir, "cam.gltf", cam.gltf(), "cameras[0].perspective.yfov");
    GltfBuilder tex = b;
    tex.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 3}}}}}}};
    load_error(dir, "tex.gltf", tex.gltf(),
               "materials[0].pbrMetallicRoughness.baseColorTexture.index");
    GltfBuilder scene = b;
    scene.doc["scene"] = 4;
    load_error(dir, "scene.gltf", scene.gltf(), "scene: scene 4 does not exist");
}

TEST(BadGltf, NodeGraphCyclesAndSharedChildren) {
    ScratchDir dir;
    GltfBuilder b = lt::one_triangle();
    GltfBuilder cycle = b;  // 0 -> 1 -> 2 -> 1, scene root 0
    cycle.doc["nodes"] = {
        {{"children", {1}}}, {{"children", {2}}, {"mesh", 0}}, {{"children", {1}}}};
    load_error(dir, "cycle.gltf", cycle.gltf(), "already a child");
    GltfBuilder loop = b;  // 1 -> 2 -> 1 with no other parent: a pure cycle
    loop.doc["nodes"] = {{{"mesh", 0}}, {{"children", {2}}}, {{"children", {1}}}};
    load_error(dir, "loop.gltf", loop.gltf(), "the node graph has a cycle");
    GltfBuilder self = b;
    self.doc["nodes"] = {{{"children", {0}}, {"mesh", 0}}};
    load_error(dir, "self.gltf", self.gltf(), "nodes[0].children[0]: node 0 is its own child");
    GltfBuilder twice = b;  // node 2 the child of both 0 and 1
    twice.doc["nodes"] = {{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}};
    twice.doc["scenes"] = {{{"nodes", {0, 1}}}};
    load_error(dir, "twice.gltf", twice.gltf(),
               "nodes[1].children[0]: node 2 is already a child of nodes[0]");
    GltfBuilder root = b;  // a scene root that is someone's child
    root.doc["nodes"] = {{{"children", {1}}}, {{"mesh", 0}}};
    root.doc["scenes"] = {{{"nodes", {0, 1}}}};
    load_error(dir, "root.gltf", root.gltf(), "scenes[0].nodes[1]: node 1 is a child of nodes[0]");
    // A chain of 100,000 nodes: walked without recursion.
    GltfBuilder chain = b;
    chain.doc["nodes"] = json::array();
    for (int k = 0; k < 100000; ++k)
        chain.doc["nodes"].push_back(k + 1 < 100000 ? json{{"children", {k + 1}}}
                                                    : json{{"mesh", 0}});
    const fs::path p = dir.path() / "chain.glb";
    lt::write_file(p, chain.glb());
    EXPECT_EQ(load_gltf(p).instances.size(), 1u);
}

TEST(BadGltf, ExtensionsAndNesting) {
    ScratchDir dir;
    GltfBuilder b = lt::one_triangle();
    b.doc["extensionsUsed"] = {"EXT_lights_image_based"};
    b.doc["extensionsRequired"] = {"EXT_lights_image_based"};
    load_error(dir, "req.gltf", b.gltf(),
               "extensionsRequired[0]: extension 'EXT_lights_image_based' is required but not "
               "supported");
    // Deep nesting where librt reads (tinygltf converts JSON recursively): refused up front,
    // naming where.
    GltfBuilder d = lt::one_triangle();
    std::string deep(100000, '[');
    deep += std::string(100000, ']');
    std::string text = d.with_buffer("").dump();
    text.insert(text.size() - 1, ",\"nodes\":[{\"matrix\":" + deep + "}]");
    load_error(dir, "deep.glb", GltfBuilder::make_glb(text, d.bin), "nodes[0].matrix[0][0][0]");
    load_error(dir, "deep2.glb", GltfBuilder::make_glb(text, d.bin), "nested deeper than 64");
    // In extras (free-form data librt never reads) it is left out while parsing, never
    // built, so it costs nothing and loads.
    std::string extras_text = d.with_buffer("").dump();
    extras_text.insert(extras_text.size() - 1, ",\"extras\":" + deep);
    const fs::path p = dir.write("extras.glb", GltfBuilder::make_glb(extras_text, d.bin));
    EXPECT_EQ(load_gltf(p).triangles_stored(), 1u);
}
