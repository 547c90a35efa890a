// load_gltf feature by feature, on files the tests write: primitive modes, index types,
// sparse accessors, normalised attributes, external and embedded buffers and images,
// cameras, lights, materials with their extensions.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"

#include <librt/gltf/gltf.h>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::GltfBuilder;
using librt::testing::ScratchDir;
using nlohmann::json;
namespace fs = std::filesystem;
namespace lt = librt::testing;

namespace {

/// Five vertices of a zig-zag (for strips and fans) plus the primitive using them.
GltfBuilder five_vertices(int mode, int index_type) {
    GltfBuilder b;
    const std::vector<float> p = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0};
    const int pos = b.add_accessor(p, lt::kFloat, "VEC3", 5);
    json prim = {{"attributes", {{"POSITION", pos}}}, {"mode", mode}};
    if (index_type == lt::kU8) {
        prim["indices"] =
            b.add_accessor(std::vector<std::uint8_t>{0, 1, 2, 3, 4}, lt::kU8, "SCALAR", 5);
    } else if (index_type == lt::kU16) {
        prim["indices"] =
            b.add_accessor(std::vector<std::uint16_t>{0, 1, 2, 3, 4}, lt::kU16, "SCALAR", 5);
    } else if (index_type == lt::kU32) {
        prim["indices"] =
            b.add_accessor(std::vector<std::uint32_t>{0, 1, 2, 3, 4}, lt::kU32, "SCALAR", 5);
    }
    b.doc["meshes"] = {{{"primitives", {prim}}}};
    b.doc["nodes"] = {{{"mesh", 0}}};
    b.doc["scenes"] = {{{"nodes", {0}}}};
    return b;
}

GltfScene load_text(const ScratchDir& dir, const std::string& name, const std::string& bytes) {
    const fs::path p = dir.path() / name;
    lt::write_file(p, bytes);
    return load_gltf(p);
}

}  // namespace

TEST(GltfMeshes, StripsFansAndTrianglesWithEveryIndexType) {
    ScratchDir dir;
    for (const int type : {0, lt::kU8, lt::kU16, lt::kU32}) {
        SCOPED_TRACE(type);
        // Strip (spec 3.7.2.1, {v_i, v_(i+1+i%2), v_(i+2-i%2)}): {0 1 2}, {1 3 2}, {2 3 4},
        // every triangle wound alike.
        GltfScene s = load_text(dir, "strip.glb", five_vertices(5, type).glb());
        ASSERT_EQ(s.meshes[0].primitives[0].triangles.size(), 3u);
        EXPECT_EQ(s.meshes[0].primitives[0].triangles[0], glm::uvec3(0, 1, 2));
        EXPECT_EQ(s.meshes[0].primitives[0].triangles[1], glm::uvec3(1, 3, 2));
        EXPECT_EQ(s.meshes[0].primitives[0].triangles[2], glm::uvec3(2, 3, 4));
        // Fan: {1 2 0}, {2 3 0}, {3 4 0}.
        s = load_text(dir, "fan.glb", five_vertices(6, type).glb());
        ASSERT_EQ(s.meshes[0].primitives[0].triangles.size(), 3u);
        EXPECT_EQ(s.meshes[0].primitives[0].triangles[2], glm::uvec3(3, 4, 0));
        // Triangles: 5 vertices make one triangle and a warning about the 2 left over.
        s = load_text(dir, "tri.glb", five_vertices(4, type).glb());
        EXPECT_EQ(s.meshes[0].primitives[0].triangles.size(), 1u);
        EXPECT_TRUE(lt::has(lt::joined(s.warnings), "meshes[0].primitives[0]"))
            << lt::joined(s.warnings);
    }
}

TEST(GltfMeshes, PointsAndLinesAreSkippedWithAWarning) {
    ScratchDir dir;
    for (const int mode : {0, 1, 2, 3}) {
        const GltfScene s = load_text(dir, "lines.gltf", five_vertices(mode, 0).gltf());
        EXPECT_TRUE(s.meshes[0].primitives.empty());
        EXPECT_TRUE(lt::has(lt::joined(s.warnings),
                            "lines.gltf: meshes[0].primitives[0]: points and lines"))
            << lt::joined(s.warnings);
    }
}

TEST(GltfMeshes, NormalisedAttributesAndColours) {
    GltfBuilder b = lt::one_triangle();
    const int uv = b.add_accessor(std::vector<std::uint8_t>{0, 255, 51, 0, 255, 255, 0, 0}, lt::kU8,
                                  "VEC2", 3, true);
    // i16 normalised: -32768 and -32767 both map to -1 (spec: max(c / 32767, -1)).
    const int n = b.add_accessor(std::vector<std::int16_t>{0, 0, 32767, 0, -32768, 0, -32767, 0, 0},
                                 lt::kI16, "VEC3", 3, true);
    const int col =
        b.add_accessor(std::vector<std::uint16_t>{65535, 0, 0, 0, 65535, 0, 0, 0, 65535}, lt::kU16,
                       "VEC3", 3, true);
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
    b.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = n;
    // Normals as normalised i16 need KHR_mesh_quantization (glTF 2.0, section 3.7.2.1).
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    b.doc["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = col;
    ScratchDir dir;
    const GltfScene s = load_text(dir, "norm.gltf", b.gltf());
    const GltfPrimitive& p = s.meshes[0].primitives[0];
    ASSERT_EQ(p.uv0.size(), 3u);
    EXPECT_FLOAT_EQ(p.uv0[0].y, 1.0f);
    EXPECT_FLOAT_EQ(p.uv0[1].x, 0.2f);
    ASSERT_EQ(p.normals.size(), 3u);
    EXPECT_FLOAT_EQ(p.normals[0].z, 1.0f);
    EXPECT_FLOAT_EQ(p.normals[1].y, -1.0f);
    EXPECT_FLOAT_EQ(p.normals[2].x, -1.0f);
    ASSERT_EQ(p.colors.size(), 3u);
    EXPECT_EQ(p.colors[1], glm::vec4(0, 1, 0, 1));  // RGB gets alpha 1
}

TEST(GltfMeshes, SparseAccessorsReplaceValues) {
    GltfBuilder b = lt::one_triangle();
    // Sparse over the positions: vertex 2 becomes (0, 5, 0).
    const int idx = b.add_view(std::vector<std::uint16_t>{2, 0}.data(), 2);
    const std::vector<float> val = {0, 5, 0};
    const int vals = b.add_view(val.data(), 12);
    b.doc["accessors"][0]["sparse"] = {
        {"count", 1},
        {"indices", {{"bufferView", idx}, {"componentType", lt::kU16}}},
        {"values", {{"bufferView", vals}}}};
    // A sparse accessor without a buffer view: zeros except the listed TEXCOORD_0 values.
    const std::vector<float> uvval = {0.5f, 0.25f};
    const int uvv = b.add_view(uvval.data(), 8);
    b.doc["accessors"].push_back({{"componentType", lt::kFloat},
                                  {"count", 3},
                                  {"type", "VEC2"},
                                  {"sparse",
                                   {{"count", 1},
                                    {"indices", {{"bufferView", idx}, {"componentType", lt::kU16}}},
                                    {"values", {{"bufferView", uvv}}}}}});
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = b.doc["accessors"].size() - 1;
    ScratchDir dir;
    const GltfScene s = load_text(dir, "sparse.glb", b.glb());
    const GltfPrimitive& p = s.meshes[0].primitives[0];
    EXPECT_EQ(p.positions[1], glm::vec3(1, 0, 0));
    EXPECT_EQ(p.positions[2], glm::vec3(0, 5, 0));
    EXPECT_EQ(p.uv0[0], glm::vec2(0, 0));
    EXPECT_EQ(p.uv0[2], glm::vec2(0.5f, 0.25f));
}

TEST(GltfFiles, ExternalBinAndImagesDataUriImagesAndAMissingImage) {
    GltfBuilder b = lt::one_triangle();
    const std::string png = lt::tiny_png();
    ScratchDir dir;
    fs::create_directories(dir.path() / "sub dir");
    lt::write_file(dir.path() / "sub dir" / "tex.png", png);
    b.doc["images"] = {{{"uri", "sub%20dir/tex.png"}},
                       {{"uri", "data:image/png;base64," + lt::base64(png)}},
                       {{"uri", "missing.png"}}};
    b.doc["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}, {"magFilter", 9728}}};
    b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 1}}, {{"source", 2}}};
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}},
                          {{"emissiveTexture", {{"index", 2}}}, {"emissiveFactor", {1, 1, 1}}}};
    lt::write_file(dir.path() / "scene.bin", b.bin);
    const fs::path p = dir.path() / "scene.gltf";
    lt::write_file(p, b.with_buffer("scene.bin").dump());
    const GltfScene s = load_gltf(p);
    ASSERT_EQ(s.textures.size(), 3u);
    for (int t = 0; t < 2; ++t) {
        ASSERT_EQ(s.textures[t].image, t);
        const GltfImage& img = s.images[std::size_t(t)];
        ASSERT_EQ(img.width, 2);
        ASSERT_EQ(img.height, 1);
        EXPECT_EQ(img.rgba[0], 255);  // red texel
        EXPECT_EQ(img.rgba[6], 255);  // blue texel's blue
        EXPECT_EQ(img.rgba[7], 128);  // its alpha
    }
    EXPECT_EQ(s.images[0].uri, "sub%20dir/tex.png");
    EXPECT_EQ(s.textures[0].wrap_s, GltfWrap::ClampToEdge);
    EXPECT_EQ(s.textures[0].wrap_t, GltfWrap::MirroredRepeat);
    EXPECT_EQ(s.textures[0].mag_filter, GltfFilter::Nearest);
    EXPECT_EQ(s.textures[0].min_filter, GltfFilter::Unset);
    // The missing image: a warning naming it; the texture is unusable, the material kept.
    EXPECT_EQ(s.textures[2].image, -1);
    EXPECT_TRUE(lt::has(lt::joined(s.warnings), p.string() + ": images[2]"))
        << lt::joined(s.warnings);
    EXPECT_EQ(s.materials[1].emissive_factor, glm::vec3(1.0f));
}

TEST(GltfScene, CamerasLightsAndTheirTransforms) {
    GltfBuilder b = lt::one_triangle();
    b.doc["cameras"] = {{{"type", "perspective"},
                         {"name", "persp"},
                         {"perspective", {{"yfov", 0.5}, {"aspectRatio", 1.5}, {"znear", 0.1}}}},
                        {{"type", "orthographic"},
                         {"orthographic", {{"xmag", 2}, {"ymag", 1}, {"znear", 0}, {"zfar", 10}}}}};
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "spot"},
         {"color", {1, 0.5, 0.25}},
         {"intensity", 100},
         {"range", 20},
         {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.4}}}},
        {{"type", "directional"}, {"name", "sun"}, {"intensity", 3}}};
    b.doc["nodes"] = {
        {{"mesh", 0}},
        {{"camera", 0}, {"translation", {0, 0, 5}}},
        {{"camera", 1}, {"name", "ortho node"}},
        {{"translation", {1, 2, 3}}, {"children", {4}}},
        {{"translation", {0, 1, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}},
        {{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}}};
    b.doc["scenes"] = {{{"nodes", {0, 1, 2, 3, 5}}}};
    ScratchDir dir;
    const GltfScene s = load_text(dir, "cams.gltf", b.gltf());
    ASSERT_EQ(s.cameras.size(), 2u);
    EXPECT_EQ(s.cameras[0].type, GltfCamera::Type::Perspective);
    EXPECT_EQ(s.cameras[0].name, "persp");
    EXPECT_FLOAT_EQ(s.cameras[0].yfov, 0.5f);
    EXPECT_FLOAT_EQ(s.cameras[0].aspect_ratio, 1.5f);
    EXPECT_FLOAT_EQ(s.cameras[0].zfar, 0.0f);  // infinite
    EXPECT_FLOAT_EQ(s.cameras[0].world[3][2], 5.0f);
    EXPECT_EQ(s.cameras[1].type, GltfCamera::Type::Orthographic);
    EXPECT_EQ(s.cameras[1].name, "ortho node");  // the node's name when the camera has none
    EXPECT_FLOAT_EQ(s.cameras[1].xmag, 2.0f);
    ASSERT_EQ(s.lights.size(), 2u);
    const GltfLight& spot = s.lights[0];
    EXPECT_EQ(spot.type, GltfLight::Type::Spot);
    EXPECT_EQ(spot.color, glm::vec3(1, 0.5f, 0.25f));
    EXPECT_FLOAT_EQ(spot.range, 20.0f);
    EXPECT_FLOAT_EQ(spot.outer_cone_angle, 0.4f);
    EXPECT_EQ(glm::vec3(spot.world[3]), glm::vec3(1, 3, 3));  // composed through its parent
    EXPECT_EQ(s.lights[1].name, "sun");
    EXPECT_EQ(s.lights[1].type, GltfLight::Type::Directional);
}

TEST(GltfScene, MaterialsWithTheirExtensions) {
    GltfBuilder b = lt::one_triangle();
    b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_transmission",
                               "KHR_materials_ior", "KHR_texture_transform", "EXT_unknown_thing"};
    b.doc["images"] = {{{"uri", "data:image/png;base64," + lt::base64(lt::tiny_png())}}};
    b.doc["textures"] = {{{"source", 0}}};
    b.doc["materials"] = {
        {{"name", "all"},
         {"pbrMetallicRoughness",
          {{"baseColorFactor", {0.5, 0.25, 1, 0.75}},
           {"metallicFactor", 0.3},
           {"roughnessFactor", 0.6},
           {"baseColorTexture",
            {{"index", 0},
             {"texCoord", 1},
             {"extensions",
              {{"KHR_texture_transform",
                {{"offset", {0.5, 0}},
                 {"rotation", 1.5707963},
                 {"scale", {2, 2}},
                 {"texCoord", 0}}}}}}}}},
         {"normalTexture", {{"index", 0}, {"scale", 0.5}}},
         {"emissiveFactor", {1, 0.5, 0}},
         {"alphaMode", "MASK"},
         {"alphaCutoff", 0.3},
         {"doubleSided", true},
         {"extensions",
          {{"KHR_materials_emissive_strength", {{"emissiveStrength", 15}}},
           {"KHR_materials_transmission",
            {{"transmissionFactor", 0.9}, {"transmissionTexture", {{"index", 0}}}}},
           {"KHR_materials_ior", {{"ior", 1.33}}}}}}};
    ScratchDir dir;
    const GltfScene s = load_text(dir, "mat.gltf", b.gltf());
    ASSERT_EQ(s.materials.size(), 1u);
    const GltfMaterial& m = s.materials[0];
    EXPECT_EQ(m.base_color_factor, glm::vec4(0.5f, 0.25f, 1, 0.75f));
    EXPECT_FLOAT_EQ(m.metallic_factor, 0.3f);
    EXPECT_FLOAT_EQ(m.roughness_factor, 0.6f);
    EXPECT_EQ(m.base_color_texture.texture, 0);
    EXPECT_EQ(m.base_color_texture.tex_coord, 0);  // KHR_texture_transform's override
    ASSERT_TRUE(m.base_color_texture.has_transform);
    // (1, 0) scaled to (2, 0), rotated by 90 degrees as the extension's matrix says
    // ([cos sin; -sin cos] applied to (u, v): (2, 0) -> (0, -2)), then offset by (0.5, 0).
    const glm::vec3 uv = m.base_color_texture.transform.matrix() * glm::vec3(1, 0, 1);
    EXPECT_NEAR(uv.x, 0.5f, 1e-5f);
    EXPECT_NEAR(uv.y, -2.0f, 1e-5f);
    EXPECT_FLOAT_EQ(m.normal_texture.scale, 0.5f);
    EXPECT_EQ(m.emissive_factor, glm::vec3(1, 0.5f, 0));
    EXPECT_FLOAT_EQ(m.emissive_strength, 15.0f);
    EXPECT_FLOAT_EQ(m.transmission_factor, 0.9f);
    EXPECT_EQ(m.transmission_texture.texture, 0);
    EXPECT_FLOAT_EQ(m.ior, 1.33f);
    EXPECT_EQ(m.alpha_mode, GltfAlphaMode::Mask);
    EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
    EXPECT_TRUE(m.double_sided);
    // Only the unknown optional extension is a warning.
    ASSERT_EQ(s.warnings.size(), 1u) << lt::joined(s.warnings);
    EXPECT_TRUE(lt::has(s.warnings[0], "extensionsUsed[4]: extension 'EXT_unknown_thing'"));
}

// The glTF fuzzer's seeds (tests/fuzz/corpus/gltf, written by hand) are valid files that
// reach every stage: the fuzzer mutates from there.
TEST(GltfFuzzSeeds, EverySeedLoads) {
    const fs::path dir = fs::path(LIBRT_FUZZ_CORPUS_DIR) / "gltf";
    GltfScene s = load_gltf(dir / "quad_indexed.glb");
    EXPECT_EQ(s.triangles_placed(), 2u);
    EXPECT_TRUE(s.warnings.empty()) << lt::joined(s.warnings);
    s = load_gltf(dir / "strip_sparse.gltf");
    EXPECT_EQ(s.triangles_placed(), 3u);  // the strip; the lines skipped
    EXPECT_EQ(s.meshes[0].primitives[0].positions[3], glm::vec3(2, 2, 0));  // sparse
    EXPECT_EQ(s.warnings.size(), 1u) << lt::joined(s.warnings);
    s = load_gltf(dir / "scene_features.gltf");
    EXPECT_EQ(s.cameras.size(), 2u);
    EXPECT_EQ(s.lights.size(), 3u);
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.textures[0].image, 0);
    EXPECT_TRUE(s.warnings.empty()) << lt::joined(s.warnings);
    s = load_gltf(dir / "fan_quantized.glb");
    EXPECT_EQ(s.triangles_placed(), 2u);
    EXPECT_EQ(s.meshes[0].primitives[0].positions[2], glm::vec3(100, 100, 0));
    EXPECT_NEAR(s.meshes[0].primitives[0].colors[2].w, 128.0f / 255.0f, 1e-6f);
    ASSERT_EQ(s.warnings.size(), 1u);  // it has no scenes: its root nodes are placed
    EXPECT_TRUE(lt::has(s.warnings[0], "fan_quantized.glb: scenes: none in the file"));
    // scene_features.gltf's material as a brushed metal (KHR_materials_anisotropy).
    s = load_gltf(dir / "anisotropy.gltf");
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_FLOAT_EQ(s.materials[0].anisotropy_strength, 0.6f);
    EXPECT_FLOAT_EQ(s.materials[0].anisotropy_rotation, 0.4f);
    EXPECT_EQ(s.materials[0].anisotropy_texture.texture, 0);
    EXPECT_TRUE(s.warnings.empty()) << lt::joined(s.warnings);
    // Compressed glTF (written by the reference encoders): a Draco quad, and a meshopt quad
    // with a WebP texture over a fallback buffer.
    s = load_gltf(dir / "draco_quad.glb");
    EXPECT_EQ(s.triangles_placed(), 2u);
    EXPECT_TRUE(s.warnings.empty()) << lt::joined(s.warnings);
    s = load_gltf(dir / "meshopt_webp_quad.glb");
    EXPECT_EQ(s.triangles_placed(), 2u);
    EXPECT_EQ(s.meshes[0].primitives[0].positions[3], glm::vec3(1, 1, 0));
    ASSERT_EQ(s.textures.size(), 1u);
    EXPECT_EQ(s.images.at(0).width, 2);
    EXPECT_TRUE(s.warnings.empty()) << lt::joined(s.warnings);
}
