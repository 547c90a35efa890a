// Compressed glTF: KHR_draco_mesh_compression, EXT_meshopt_compression, EXT_texture_webp
// and KHR_texture_basisu, on small files the tests encode themselves with the reference
// encoders (Draco's, meshoptimizer's, libwebp's), loaded and compared with the source data;
// corrupt streams must be librt::Errors naming their JSON path.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"
#include "test_support.h"

#include <librt/core/error.h>
#include <librt/gltf/gltf.h>

#include <gtest/gtest.h>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <meshoptimizer.h>
#include <webp/encode.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::GltfBuilder;
using librt::testing::ScratchDir;
using nlohmann::json;
namespace fs = std::filesystem;
namespace lt = librt::testing;

namespace {

/// A 4 x 4 grid of quads on a bumpy surface: 25 vertices with normals and uvs, 32 triangles.
struct Grid {
    std::vector<glm::vec3> p, n;
    std::vector<glm::vec2> uv;
    std::vector<glm::uvec3> tris;
};

Grid grid() {
    Grid g;
    for (int y = 0; y <= 4; ++y) {
        for (int x = 0; x <= 4; ++x) {
            const float h = 0.25f * std::sin(float(x)) * std::cos(float(y));
            g.p.push_back({float(x) * 0.5f, h, float(y) * 0.5f});
            g.n.push_back(glm::normalize(glm::vec3(-0.3f * float(x - 2), 1.0f, 0.2f * float(y))));
            g.uv.push_back({float(x) / 4.0f, float(y) / 4.0f});
        }
    }
    for (unsigned y = 0; y < 4; ++y) {
        for (unsigned x = 0; x < 4; ++x) {
            const unsigned a = y * 5 + x, b = a + 1, c = a + 5, d = c + 1;
            g.tris.push_back({a, c, b});
            g.tris.push_back({b, c, d});
        }
    }
    return g;
}

/// A Draco encoding of the grid (edgebreaker unless `sequential`), with the quantisation
/// bits given, and the unique ids of its POSITION, NORMAL and TEXCOORD attributes.
struct DracoStream {
    std::string bytes;
    int position_id = -1, normal_id = -1, uv_id = -1;
    std::size_t points = 0, faces = 0;
};

DracoStream encode_draco(const Grid& g, bool sequential) {
    draco::TriangleSoupMeshBuilder builder;
    builder.Start(int(g.tris.size()));
    const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    const int nrm = builder.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
    const int tex = builder.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
    for (std::size_t f = 0; f < g.tris.size(); ++f) {
        const glm::uvec3 t = g.tris[f];
        const draco::FaceIndex face(static_cast<std::uint32_t>(f));
        builder.SetAttributeValuesForFace(pos, face, &g.p[t[0]], &g.p[t[1]], &g.p[t[2]]);
        builder.SetAttributeValuesForFace(nrm, face, &g.n[t[0]], &g.n[t[1]], &g.n[t[2]]);
        builder.SetAttributeValuesForFace(tex, face, &g.uv[t[0]], &g.uv[t[1]], &g.uv[t[2]]);
    }
    const std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
    draco::Encoder encoder;
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
    if (sequential) encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
    draco::EncoderBuffer buffer;
    EXPECT_TRUE(encoder.EncodeMeshToBuffer(*mesh, &buffer).ok());
    DracoStream out;
    out.bytes.assign(buffer.data(), buffer.size());
    out.position_id = int(mesh->attribute(pos)->unique_id());
    out.normal_id = int(mesh->attribute(nrm)->unique_id());
    out.uv_id = int(mesh->attribute(tex)->unique_id());
    // The counts the accessors must declare: those of the decoded mesh.
    draco::DecoderBuffer in;
    in.Init(buffer.data(), buffer.size());
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&in);
    EXPECT_TRUE(decoded.ok());
    out.points = decoded.value()->num_points();
    out.faces = decoded.value()->num_faces();
    return out;
}

/// A glTF whose one primitive is the Draco stream (accessors without buffer views).
GltfBuilder draco_file(const DracoStream& s) {
    GltfBuilder b;
    const int view = b.add_view(s.bytes.data(), s.bytes.size());
    auto accessor = [&](int type, const char* kind, std::size_t count) {
        b.doc["accessors"].push_back({{"componentType", type}, {"count", count}, {"type", kind}});
        return int(b.doc["accessors"].size()) - 1;
    };
    const int pos = accessor(lt::kFloat, "VEC3", s.points);
    const int nrm = accessor(lt::kFloat, "VEC3", s.points);
    const int tex = accessor(lt::kFloat, "VEC2", s.points);
    const int idx = accessor(lt::kU32, "SCALAR", s.faces * 3);
    json prim = {
        {"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", tex}}},
        {"indices", idx},
        {"extensions",
         {{"KHR_draco_mesh_compression",
           {{"bufferView", view},
            {"attributes",
             {{"POSITION", s.position_id}, {"NORMAL", s.normal_id}, {"TEXCOORD_0", s.uv_id}}}}}}}};
    b.doc["meshes"] = {{{"primitives", {prim}}}};
    b.doc["nodes"] = {{{"mesh", 0}}};
    b.doc["scenes"] = {{{"nodes", {0}}}};
    b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    return b;
}

GltfScene load_bytes(const ScratchDir& dir, const std::string& name, const std::string& bytes) {
    const fs::path p = dir.path() / name;
    lt::write_file(p, bytes);
    return load_gltf(p);
}

/// The librt::Error message of loading the bytes ("" when it loads).
std::string load_error(const ScratchDir& dir, const std::string& name, const std::string& bytes) {
    try {
        (void)load_bytes(dir, name, bytes);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// Every triangle as its three vertex indices, rotated to start at the smallest (winding kept).
std::set<std::array<unsigned, 3>> triangle_set(const std::vector<glm::uvec3>& tris) {
    std::set<std::array<unsigned, 3>> out;
    for (glm::uvec3 t : tris) {
        while (t[0] > t[1] || t[0] > t[2]) t = glm::uvec3(t[1], t[2], t[0]);
        out.insert({t[0], t[1], t[2]});
    }
    return out;
}

}  // namespace

TEST(GltfDraco, EdgebreakerAndSequentialMatchTheSourceWithinQuantisation) {
    ScratchDir dir;
    const Grid g = grid();
    for (const bool sequential : {false, true}) {
        SCOPED_TRACE(sequential ? "sequential" : "edgebreaker");
        const DracoStream s = encode_draco(g, sequential);
        const GltfScene scene = load_bytes(dir, "draco.glb", draco_file(s).glb());
        ASSERT_EQ(scene.meshes.size(), 1u);
        const GltfPrimitive& prim = scene.meshes[0].primitives.at(0);
        ASSERT_EQ(prim.positions.size(), s.points);
        ASSERT_EQ(prim.normals.size(), s.points);
        ASSERT_EQ(prim.uv0.size(), s.points);
        // Draco reorders points and triangles: each decoded point is matched to the
        // nearest source vertex. Quantisation error bounds: 14 bits over the 2-unit range
        // of the positions, 10-bit octahedral normals, 12 bits over the unit uv range.
        const float pos_tol = 2.0f / float(1 << 14), normal_tol = 4.0f / float(1 << 10),
                    uv_tol = 1.0f / float(1 << 12);
        std::vector<glm::uvec3> mapped;
        std::vector<unsigned> source_of(s.points);
        for (std::size_t i = 0; i < s.points; ++i) {
            std::size_t best = 0;
            for (std::size_t k = 1; k < g.p.size(); ++k)
                if (glm::length(g.p[k] - prim.positions[i]) <
                    glm::length(g.p[best] - prim.positions[i]))
                    best = k;
            source_of[i] = unsigned(best);
            for (int c = 0; c < 3; ++c) {
                EXPECT_NEAR(prim.positions[i][c], g.p[best][c], pos_tol) << "point " << i;
                EXPECT_NEAR(prim.normals[i][c], g.n[best][c], normal_tol) << "point " << i;
            }
            for (int c = 0; c < 2; ++c) EXPECT_NEAR(prim.uv0[i][c], g.uv[best][c], uv_tol);
        }
        for (const glm::uvec3& t : prim.triangles)
            mapped.push_back({source_of[t[0]], source_of[t[1]], source_of[t[2]]});
        EXPECT_EQ(prim.triangles.size(), g.tris.size());
        EXPECT_EQ(triangle_set(mapped), triangle_set(g.tris));
    }
}

TEST(GltfDraco, CorruptStreamsAreErrorsNamingThePrimitive) {
    ScratchDir dir;
    const DracoStream s = encode_draco(grid(), false);
    const std::string where = "meshes[0].primitives[0].extensions.KHR_draco_mesh_compression";
    // Truncated to half: the header parses, the data ends early.
    DracoStream cut = s;
    cut.bytes.resize(s.bytes.size() / 2);
    std::string msg = load_error(dir, "cut.glb", draco_file(cut).glb());
    EXPECT_NE(msg.find(where), std::string::npos) << msg;
    EXPECT_NE(msg.find("cut.glb"), std::string::npos) << msg;
    // Not Draco at all.
    DracoStream junk = s;
    for (char& c : junk.bytes) c = 'x';
    msg = load_error(dir, "junk.glb", draco_file(junk).glb());
    EXPECT_NE(msg.find(where + ": not a Draco stream"), std::string::npos) << msg;
    // Accessors declaring other counts than the stream's: refused before decoding.
    DracoStream more = s;
    more.faces = 1000000;
    msg = load_error(dir, "counts.glb", draco_file(more).glb());
    EXPECT_NE(msg.find(where + ": the Draco stream claims"), std::string::npos) << msg;
    // A stream claiming 2^34 triangles against accessors that say the same: the allowance
    // refuses it before Draco allocates.
    DracoStream huge = s;
    huge.bytes = std::string("DRACO\x02\x02\x01\x00\x00\x00", 11) + "\x80\x80\x80\x80\x40" +
                 "\x80\x80\x80\x80\x40" + std::string(32, '\0');
    huge.faces = std::size_t{1} << 34u;
    huge.points = std::size_t{1} << 34u;
    msg = load_error(dir, "huge.glb", draco_file(huge).glb());
    EXPECT_NE(msg.find(where), std::string::npos) << msg;
    EXPECT_NE(msg.find("more bytes than the loader allows"), std::string::npos) << msg;
    // Random bytes after a valid header: an error or a load, never a crash.
    std::mt19937 rng(38);
    for (int trial = 0; trial < 200; ++trial) {
        DracoStream r = s;
        for (std::size_t k = 16; k < r.bytes.size(); ++k)
            if (rng() % 4 == 0) r.bytes[k] = char(rng() & 0xFFu);
        msg = load_error(dir, "random.glb", draco_file(r).glb());
        if (!msg.empty()) {
            EXPECT_NE(msg.find("random.glb"), std::string::npos) << msg;
        }
    }
}

namespace {

/// A glTF with one triangle mesh whose POSITION and indices views are meshopt streams in
/// buffer 0, standing in buffer 1, the fallback buffer that holds no bytes.
struct MeshoptParts {
    std::string positions, indices;
    std::size_t vertices = 0, index_count = 0;
    const char* index_mode = "TRIANGLES";
};

GltfBuilder meshopt_file(const MeshoptParts& m) {
    GltfBuilder b;
    const std::size_t pos_bytes = m.vertices * 12, idx_bytes = m.index_count * 4;
    b.bin = m.positions;
    while (b.bin.size() % 4 != 0) b.bin.push_back('\0');
    const std::size_t idx_at = b.bin.size();
    b.bin += m.indices;
    json ext_pos = {{"buffer", 0},      {"byteOffset", 0},     {"byteLength", m.positions.size()},
                    {"byteStride", 12}, {"count", m.vertices}, {"mode", "ATTRIBUTES"}};
    json ext_idx = {{"buffer", 0},     {"byteOffset", idx_at},   {"byteLength", m.indices.size()},
                    {"byteStride", 4}, {"count", m.index_count}, {"mode", m.index_mode}};
    b.doc["bufferViews"] = {{{"buffer", 1},
                             {"byteLength", pos_bytes},
                             {"byteStride", 12},
                             {"extensions", {{"EXT_meshopt_compression", ext_pos}}}},
                            {{"buffer", 1},
                             {"byteOffset", pos_bytes},
                             {"byteLength", idx_bytes},
                             {"extensions", {{"EXT_meshopt_compression", ext_idx}}}}};
    b.doc["accessors"] = {
        {{"bufferView", 0}, {"componentType", lt::kFloat}, {"count", m.vertices}, {"type", "VEC3"}},
        {{"bufferView", 1},
         {"componentType", lt::kU32},
         {"count", m.index_count},
         {"type", "SCALAR"}}};
    b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}}}}}};
    b.doc["nodes"] = {{{"mesh", 0}}};
    b.doc["scenes"] = {{{"nodes", {0}}}};
    b.doc["extensionsUsed"] = {"EXT_meshopt_compression"};
    b.doc["extensionsRequired"] = {"EXT_meshopt_compression"};
    return b;
}

/// The .glb of a meshopt file: buffer 0 the BIN chunk, buffer 1 the fallback.
std::string meshopt_glb(const MeshoptParts& m) {
    GltfBuilder b = meshopt_file(m);
    json d = b.with_buffer("");
    d["buffers"].push_back({{"byteLength", m.vertices * 12 + m.index_count * 4},
                            {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
    return GltfBuilder::make_glb(d.dump(), b.bin);
}

MeshoptParts encode_meshopt(const Grid& g, bool sequence) {
    MeshoptParts m;
    m.vertices = g.p.size();
    m.index_count = g.tris.size() * 3;
    std::string out(meshopt_encodeVertexBufferBound(m.vertices, 12), '\0');
    out.resize(meshopt_encodeVertexBuffer(reinterpret_cast<unsigned char*>(out.data()), out.size(),
                                          g.p.data(), m.vertices, 12));
    m.positions = out;
    const auto* idx = reinterpret_cast<const unsigned*>(g.tris.data());
    if (sequence) {
        out.assign(meshopt_encodeIndexSequenceBound(m.index_count, m.vertices), '\0');
        out.resize(meshopt_encodeIndexSequence(reinterpret_cast<unsigned char*>(out.data()),
                                               out.size(), idx, m.index_count));
        m.index_mode = "INDICES";
    } else {
        out.assign(meshopt_encodeIndexBufferBound(m.index_count, m.vertices), '\0');
        out.resize(meshopt_encodeIndexBuffer(reinterpret_cast<unsigned char*>(out.data()),
                                             out.size(), idx, m.index_count));
    }
    m.indices = out;
    return m;
}

}  // namespace

TEST(GltfMeshopt, VerticesAndIndicesRoundTripExactly) {
    ScratchDir dir;
    const Grid g = grid();
    for (const bool sequence : {false, true}) {
        SCOPED_TRACE(sequence ? "INDICES" : "TRIANGLES");
        const GltfScene scene =
            load_bytes(dir, "meshopt.glb", meshopt_glb(encode_meshopt(g, sequence)));
        const GltfPrimitive& prim = scene.meshes.at(0).primitives.at(0);
        ASSERT_EQ(prim.positions.size(), g.p.size());
        for (std::size_t i = 0; i < g.p.size(); ++i) EXPECT_EQ(prim.positions[i], g.p[i]) << i;
        // meshopt_encodeIndexBuffer may rotate a triangle's corners (winding kept).
        EXPECT_EQ(triangle_set(prim.triangles), triangle_set(g.tris));
        EXPECT_EQ(prim.triangles.size(), g.tris.size());
    }
}

TEST(GltfMeshopt, OctahedralFilterDecodesNormals) {
    ScratchDir dir;
    const Grid g = grid();
    MeshoptParts m = encode_meshopt(g, false);
    // Normals as 8-bit octahedral (stride 4), filtered then encoded, as gltfpack writes them.
    std::vector<float> n4;
    for (const glm::vec3& n : g.n) n4.insert(n4.end(), {n.x, n.y, n.z, 0.0f});
    std::vector<std::int8_t> oct(g.n.size() * 4);
    meshopt_encodeFilterOct(oct.data(), g.n.size(), 4, 8, n4.data());
    std::string stream(meshopt_encodeVertexBufferBound(g.n.size(), 4), '\0');
    stream.resize(meshopt_encodeVertexBuffer(reinterpret_cast<unsigned char*>(stream.data()),
                                             stream.size(), oct.data(), g.n.size(), 4));
    GltfBuilder b = meshopt_file(m);
    while (b.bin.size() % 4 != 0) b.bin.push_back('\0');
    const std::size_t at = b.bin.size();
    b.bin += stream;
    const std::size_t fallback = m.vertices * 12 + m.index_count * 4;
    b.doc["bufferViews"].push_back({{"buffer", 1},
                                    {"byteOffset", fallback},
                                    {"byteLength", g.n.size() * 4},
                                    {"byteStride", 4},
                                    {"extensions",
                                     {{"EXT_meshopt_compression",
                                       {{"buffer", 0},
                                        {"byteOffset", at},
                                        {"byteLength", stream.size()},
                                        {"byteStride", 4},
                                        {"count", g.n.size()},
                                        {"mode", "ATTRIBUTES"},
                                        {"filter", "OCTAHEDRAL"}}}}}});
    b.doc["accessors"].push_back({{"bufferView", 2},
                                  {"componentType", lt::kI8},
                                  {"normalized", true},
                                  {"count", g.n.size()},
                                  {"type", "VEC3"}});
    b.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = 2;
    b.doc["extensionsUsed"] = {"EXT_meshopt_compression", "KHR_mesh_quantization"};
    json d = b.with_buffer("");
    d["buffers"].push_back({{"byteLength", fallback + g.n.size() * 4},
                            {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
    const GltfScene scene = load_bytes(dir, "oct.glb", GltfBuilder::make_glb(d.dump(), b.bin));
    const GltfPrimitive& prim = scene.meshes.at(0).primitives.at(0);
    ASSERT_EQ(prim.normals.size(), g.n.size());
    // 8-bit octahedral: each component within a few 1/127 steps of the source.
    for (std::size_t i = 0; i < g.n.size(); ++i)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(prim.normals[i][c], g.n[i][c], 3.0f / 127.0f) << i;
}

TEST(GltfMeshopt, CorruptStreamsAndBadParametersAreErrorsNamingTheView) {
    ScratchDir dir;
    const MeshoptParts good = encode_meshopt(grid(), false);
    const std::string view0 = "bufferViews[0].extensions.EXT_meshopt_compression";
    const std::string view1 = "bufferViews[1].extensions.EXT_meshopt_compression";
    MeshoptParts cut = good;
    cut.positions.resize(good.positions.size() / 2);
    std::string msg = load_error(dir, "cut.glb", meshopt_glb(cut));
    EXPECT_NE(msg.find(view0 + ": the ATTRIBUTES stream"), std::string::npos) << msg;
    MeshoptParts header = good;
    header.indices[0] = '\x00';  // not an index stream's header byte
    msg = load_error(dir, "header.glb", meshopt_glb(header));
    EXPECT_NE(msg.find(view1 + ": the TRIANGLES stream"), std::string::npos) << msg;
    // Parameters the decoders would assert on.
    GltfBuilder b = meshopt_file(good);
    json d = b.with_buffer("");
    d["buffers"].push_back({{"byteLength", good.vertices * 12 + good.index_count * 4},
                            {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
    json bad = d;
    bad["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteStride"] = 6;
    msg = load_error(dir, "stride.glb", GltfBuilder::make_glb(bad.dump(), b.bin));
    EXPECT_NE(msg.find(view0 + ".byteStride: 6"), std::string::npos) << msg;
    bad = d;
    bad["bufferViews"][1]["extensions"]["EXT_meshopt_compression"]["count"] = 95;
    msg = load_error(dir, "count.glb", GltfBuilder::make_glb(bad.dump(), b.bin));
    EXPECT_NE(msg.find(view1 + ".count: 95"), std::string::npos) << msg;
    bad = d;
    bad["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["mode"] = "POINTS";
    msg = load_error(dir, "mode.glb", GltfBuilder::make_glb(bad.dump(), b.bin));
    EXPECT_NE(msg.find(view0 + ".mode"), std::string::npos) << msg;
    bad = d;
    bad["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = 100000;
    msg = load_error(dir, "outside.glb", GltfBuilder::make_glb(bad.dump(), b.bin));
    EXPECT_NE(msg.find(view0 + ": bytes [0, 100000) lie outside"), std::string::npos) << msg;
    // A huge count: refused by the allowance before anything is allocated; one beyond
    // int range (tinygltf would wrap it) refused as such.
    bad = d;
    bad["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 1u << 30u;
    msg = load_error(dir, "huge.glb", GltfBuilder::make_glb(bad.dump(), b.bin));
    EXPECT_NE(msg.find(view0 + ": decoding needs"), std::string::npos) << msg;
    bad["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["count"] = 1ull << 40u;
    msg = load_error(dir, "wrap.glb", GltfBuilder::make_glb(bad.dump(), b.bin));
    EXPECT_NE(msg.find(view0 + ".count: 1099511627776 is too large"), std::string::npos) << msg;
    // Without the extension's data, the fallback buffer's views hold no bytes.
    bad = d;
    bad["bufferViews"][0].erase("extensions");
    msg = load_error(dir, "nodata.glb", GltfBuilder::make_glb(bad.dump(), b.bin));
    EXPECT_NE(msg.find("bufferViews[0]: lies outside its buffer's data"), std::string::npos) << msg;
    // Random bytes in the streams: an error or a load, never a crash.
    std::mt19937 rng(38);
    for (int trial = 0; trial < 200; ++trial) {
        MeshoptParts r = good;
        for (std::size_t k = 1; k < r.positions.size(); ++k)
            if (rng() % 4 == 0) r.positions[k] = char(rng() & 0xFFu);
        for (std::size_t k = 1; k < r.indices.size(); ++k)
            if (rng() % 4 == 0) r.indices[k] = char(rng() & 0xFFu);
        msg = load_error(dir, "random.glb", meshopt_glb(r));
        if (!msg.empty()) {
            EXPECT_NE(msg.find("random.glb"), std::string::npos) << msg;
        }
    }
}

namespace {

/// A 3 x 2 lossless WebP and its texels (alpha never 0, whose colour WebP may drop).
std::string small_webp(std::vector<std::uint8_t>* texels) {
    *texels = {255, 0,  0,  255, 0,  255, 0,  200, 0,   0,   255, 128,
               10,  20, 30, 255, 40, 50,  60, 1,   250, 240, 230, 77};
    std::uint8_t* out = nullptr;
    const std::size_t size = WebPEncodeLosslessRGBA(texels->data(), 3, 2, 12, &out);
    std::string bytes(reinterpret_cast<const char*>(out), size);
    WebPFree(out);
    return bytes;
}

/// One triangle whose material's base colour uses texture 0 over images stored in buffer
/// views (image i's bytes in `images[i]`, its mimeType in `mimes[i]`).
GltfBuilder textured(const std::vector<std::string>& images, const std::vector<std::string>& mimes,
                     const json& texture) {
    GltfBuilder b = lt::one_triangle();
    for (std::size_t i = 0; i < images.size(); ++i) {
        const int view = b.add_view(images[i].data(), images[i].size());
        b.doc["images"].push_back({{"bufferView", view}, {"mimeType", mimes[i]}});
    }
    b.doc["textures"] = {texture};
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    return b;
}

}  // namespace

TEST(GltfWebp, ExtensionAndPlainWebpImagesDecodeExactly) {
    ScratchDir dir;
    std::vector<std::uint8_t> texels;
    const std::string webp = small_webp(&texels);
    // EXT_texture_webp with a PNG fallback in `source`: the WebP is used.
    GltfBuilder ext =
        textured({lt::tiny_png(), webp}, {"image/png", "image/webp"},
                 {{"source", 0}, {"extensions", {{"EXT_texture_webp", {{"source", 1}}}}}});
    ext.doc["extensionsUsed"] = {"EXT_texture_webp"};
    GltfScene scene = load_bytes(dir, "ext.glb", ext.glb());
    ASSERT_EQ(scene.textures.at(0).image, 1);
    EXPECT_EQ(scene.images[1].width, 3);
    EXPECT_EQ(scene.images[1].height, 2);
    EXPECT_EQ(scene.images[1].rgba, texels);
    EXPECT_TRUE(scene.warnings.empty());
    // Without fallback (the extension required), and a plain image/webp image.
    ext.doc["textures"][0].erase("source");
    ext.doc["extensionsRequired"] = {"EXT_texture_webp"};
    scene = load_bytes(dir, "required.glb", ext.glb());
    EXPECT_EQ(scene.images.at(1).rgba, texels);
    const GltfBuilder plain = textured({webp}, {"image/webp"}, {{"source", 0}});
    scene = load_bytes(dir, "plain.glb", plain.glb());
    ASSERT_EQ(scene.textures.at(0).image, 0);
    EXPECT_EQ(scene.images[0].rgba, texels);
}

TEST(GltfWebp, CorruptWebpIsAWarningNamingTheImage) {
    ScratchDir dir;
    std::vector<std::uint8_t> texels;
    std::string webp = small_webp(&texels);
    webp.resize(webp.size() - 8);  // truncated: its header still parses
    const GltfBuilder b = textured({webp}, {"image/webp"}, {{"source", 0}});
    const GltfScene scene = load_bytes(dir, "cut.glb", b.glb());
    EXPECT_EQ(scene.textures.at(0).image, -1);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("images[0]: "), std::string::npos) << scene.warnings[0];
    EXPECT_NE(scene.warnings[0].find("WebP"), std::string::npos) << scene.warnings[0];
    // A header claiming 16384 x 16384 texels: refused by the texel limit, not decoded.
    const GltfBuilder huge = textured({std::string("RIFF\x20\0\0\0WEBPVP8L\x14\0\0\0\x2f", 21) +
                                       std::string("\xff\xff\xff\x0f", 4) + std::string(16, '\0')},
                                      {"image/webp"}, {{"source", 0}});
    const GltfScene s2 = load_bytes(dir, "huge.glb", huge.glb());
    EXPECT_EQ(s2.textures.at(0).image, -1);
    ASSERT_EQ(s2.warnings.size(), 1u);
    EXPECT_NE(s2.warnings[0].find("images[0]: 16384 x 16384 texels"), std::string::npos)
        << s2.warnings[0];
}

TEST(GltfBasisu, FallbackSourceIsUsedWithAWarningAndNoFallbackIsAnError) {
    ScratchDir dir;
    // KTX2's identifier, then nothing: librt never decodes it.
    const std::string ktx2("\xABKTX 20\xBB\r\n\x1A\n", 12);
    GltfBuilder b =
        textured({lt::tiny_png(), ktx2}, {"image/png", "image/ktx2"},
                 {{"source", 0}, {"extensions", {{"KHR_texture_basisu", {{"source", 1}}}}}});
    b.doc["extensionsUsed"] = {"KHR_texture_basisu"};
    const GltfScene scene = load_bytes(dir, "fallback.glb", b.glb());
    EXPECT_EQ(scene.textures.at(0).image, 0);
    EXPECT_EQ(scene.images[0].width, 2);
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("textures[0]: KHR_texture_basisu"), std::string::npos)
        << scene.warnings[0];
    b.doc["textures"][0].erase("source");
    b.doc["extensionsRequired"] = {"KHR_texture_basisu"};
    const std::string msg = load_error(dir, "ktx2.glb", b.glb());
    EXPECT_NE(msg.find("ktx2.glb: textures[0].extensions.KHR_texture_basisu: KHR_texture_basisu"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("no fallback"), std::string::npos) << msg;
}

TEST(GltfCompression, ARealMeshRoundTripsThroughDracoAndMeshopt) {
    // The largest primitive of a real file (the data's compressed files: none ship with
    // it, so its mesh is compressed here with the reference encoders).
    LIBRT_REQUIRE_DATA_FILE(path, "gltf/dragons_instanced.glb");
    const GltfScene source = load_gltf(path);
    const GltfPrimitive* biggest = nullptr;
    for (const GltfMesh& m : source.meshes)
        for (const GltfPrimitive& p : m.primitives)
            if (biggest == nullptr || p.triangles.size() > biggest->triangles.size()) biggest = &p;
    ASSERT_NE(biggest, nullptr);
    ASSERT_GT(biggest->triangles.size(), 10000u);
    const std::vector<glm::vec3>& p = biggest->positions;
    const std::vector<glm::uvec3>& t = biggest->triangles;
    ScratchDir dir;

    // Draco, sequential (points and triangles stay in order), 16-bit positions.
    draco::Mesh mesh;
    mesh.set_num_points(static_cast<std::uint32_t>(p.size()));
    draco::GeometryAttribute ga;
    ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
    const int att = mesh.AddAttribute(ga, true, static_cast<std::uint32_t>(p.size()));
    for (std::size_t i = 0; i < p.size(); ++i)
        mesh.attribute(att)->SetAttributeValue(draco::AttributeValueIndex(std::uint32_t(i)), &p[i]);
    for (const glm::uvec3& tri : t)
        mesh.AddFace(
            {draco::PointIndex(tri[0]), draco::PointIndex(tri[1]), draco::PointIndex(tri[2])});
    draco::Encoder encoder;
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 16);
    encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
    draco::EncoderBuffer buffer;
    ASSERT_TRUE(encoder.EncodeMeshToBuffer(mesh, &buffer).ok());
    GltfBuilder b;
    const int view = b.add_view(buffer.data(), buffer.size());
    b.doc["accessors"] = {
        {{"componentType", lt::kFloat}, {"count", p.size()}, {"type", "VEC3"}},
        {{"componentType", lt::kU32}, {"count", t.size() * 3}, {"type", "SCALAR"}}};
    b.doc["meshes"] = {
        {{"primitives",
          {{{"attributes", {{"POSITION", 0}}},
            {"indices", 1},
            {"extensions",
             {{"KHR_draco_mesh_compression",
               {{"bufferView", view},
                {"attributes", {{"POSITION", mesh.attribute(att)->unique_id()}}}}}}}}}}}};
    b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    const GltfScene draco_scene = load_bytes(dir, "draco.glb", b.glb());
    const GltfPrimitive& d = draco_scene.meshes.at(0).primitives.at(0);
    ASSERT_EQ(d.positions.size(), p.size());
    ASSERT_EQ(d.triangles, t);
    // 16-bit quantisation over the bounding box's largest side: half a step at most.
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& q : p) {
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
    }
    const glm::vec3 side = hi - lo;
    const float step = std::max({side.x, side.y, side.z}) / 65535.0f;
    float worst = 0.0f;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const glm::vec3 e = glm::abs(d.positions[i] - p[i]);
        worst = std::max({worst, e.x, e.y, e.z});
    }
    EXPECT_LE(worst, step) << "half a quantisation step is " << step / 2;

    // meshopt: exact.
    MeshoptParts m;
    m.vertices = p.size();
    m.index_count = t.size() * 3;
    m.positions.assign(meshopt_encodeVertexBufferBound(m.vertices, 12), '\0');
    m.positions.resize(
        meshopt_encodeVertexBuffer(reinterpret_cast<unsigned char*>(m.positions.data()),
                                   m.positions.size(), p.data(), m.vertices, 12));
    m.indices.assign(meshopt_encodeIndexBufferBound(m.index_count, m.vertices), '\0');
    m.indices.resize(meshopt_encodeIndexBuffer(
        reinterpret_cast<unsigned char*>(m.indices.data()), m.indices.size(),
        reinterpret_cast<const unsigned*>(t.data()), m.index_count));
    const GltfScene meshopt_scene = load_bytes(dir, "meshopt.glb", meshopt_glb(m));
    const GltfPrimitive& o = meshopt_scene.meshes.at(0).primitives.at(0);
    EXPECT_EQ(o.positions, p);
    EXPECT_EQ(triangle_set(o.triangles), triangle_set(t));
    EXPECT_LT(m.positions.size() + m.indices.size(), p.size() * 12 + t.size() * 12);
}
