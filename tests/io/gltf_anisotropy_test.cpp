// KHR_materials_anisotropy in glTF files the test writes: strength, rotation and texture
// read into GltfMaterial and mapped to Material by material_from_gltf; a required
// extension is accepted; the scene's mesh gets tangents (from its uvs), so Scene::shade
// turns the tangent by the rotation; bad values throw librt::Error naming the JSON path.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::error_of;
using librt::testing::GltfBuilder;
using librt::testing::has;
using librt::testing::ScratchDir;
using nlohmann::json;
namespace fs = std::filesystem;
namespace lt = librt::testing;

namespace {

/// One triangle (0,0,0), (1,0,0), (0,1,0) facing +z with TEXCOORD_0 u along +x and glTF's
/// v (down the image) along +y, and material 0 with KHR_materials_anisotropy `ext`.
GltfBuilder anisotropic_triangle(const json& ext) {
    GltfBuilder b = lt::one_triangle();
    const int uv = b.add_accessor(std::vector<float>{0, 0, 1, 0, 0, 1}, lt::kFloat, "VEC2", 3);
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    b.doc["extensionsUsed"] = {"KHR_materials_anisotropy"};
    b.doc["materials"] = {
        {{"pbrMetallicRoughness", {{"metallicFactor", 1}, {"roughnessFactor", 0.4}}},
         {"extensions", {{"KHR_materials_anisotropy", ext}}}}};
    return b;
}

fs::path write(const ScratchDir& dir, const std::string& name, const GltfBuilder& b) {
    const fs::path p = dir.path() / name;
    lt::write_file(p, b.gltf());
    return p;
}

}  // namespace

TEST(GltfAnisotropy, StrengthRotationAndTextureAreReadAndMapped) {
    GltfBuilder b = anisotropic_triangle({{"anisotropyStrength", 0.6},
                                          {"anisotropyRotation", 0.5},
                                          {"anisotropyTexture", {{"index", 0}}}});
    b.doc["extensionsRequired"] = {"KHR_materials_anisotropy"};
    b.doc["textures"] = {json::object()};  // no image: only the reference is read here
    ScratchDir dir;
    const GltfScene s = load_gltf(write(dir, "a.gltf", b));
    ASSERT_EQ(s.materials.size(), 1u);
    const GltfMaterial& g = s.materials[0];
    EXPECT_FLOAT_EQ(g.anisotropy_strength, 0.6f);
    EXPECT_FLOAT_EQ(g.anisotropy_rotation, 0.5f);
    EXPECT_EQ(g.anisotropy_texture.texture, 0);
    // The one warning is the texture's missing image (only the reference matters here).
    ASSERT_EQ(s.warnings.size(), 1u) << lt::joined(s.warnings);
    EXPECT_TRUE(has(s.warnings[0], "textures[0]: no source image")) << s.warnings[0];
    GltfMaterialTextures ids;
    ids.anisotropy = 3;
    const Material m = material_from_gltf(g, ids);
    EXPECT_FLOAT_EQ(m.anisotropy, 0.6f);
    EXPECT_FLOAT_EQ(m.anisotropy_rotation, 0.5f);
    EXPECT_EQ(m.anisotropy_texture.texture, 3);
    // Without the extension: isotropic.
    EXPECT_EQ(material_from_gltf(GltfMaterial{}).anisotropy, 0.0f);
}

TEST(GltfAnisotropy, TheSceneTurnsTheUvTangentByTheRotation) {
    ScratchDir dir;
    for (const double rotation : {0.0, 1.5707963267948966, 0.5}) {
        LoadedScene loaded = scene_from_gltf(
            load_gltf(write(dir, "r.gltf",
                            anisotropic_triangle(
                                {{"anisotropyStrength", 0.7}, {"anisotropyRotation", rotation}}))));
        EXPECT_TRUE(loaded.warnings.empty() || !has(lt::joined(loaded.warnings), "TEXCOORD"))
            << lt::joined(loaded.warnings);
        loaded.scene.commit();
        Hit hit;
        const Ray ray({0.2f, 0.3f, 1.0f}, {0, 0, -1});
        ASSERT_TRUE(loaded.scene.intersect_for_shading(ray, hit));
        ShadedMaterial scratch;
        const Material& m = loaded.scene.shade(hit, ray.direction, scratch);
        EXPECT_FLOAT_EQ(m.anisotropy, 0.7f);
        // Tangent +x (increasing u); the bitangent points up the image, i.e. toward
        // decreasing glTF v: -y (the convention of glTF normal maps, generate_tangents).
        const glm::vec3 want(std::cos(rotation), -std::sin(rotation), 0.0);
        EXPECT_NEAR(glm::distance(m.anisotropy_direction, want), 0.0f, 1e-4f)
            << "rotation " << rotation;
    }
}

TEST(GltfAnisotropy, BadValuesNameTheJsonPath) {
    ScratchDir dir;
    const std::string at = "materials[0].extensions.KHR_materials_anisotropy";
    const auto error = [&](const json& ext) {
        const fs::path p = write(dir, "bad.gltf", anisotropic_triangle(ext));
        return error_of([&] { (void)load_gltf(p); });
    };
    std::string msg = error({{"anisotropyStrength", "strong"}});
    EXPECT_TRUE(has(msg, at + ".anisotropyStrength: must be a number")) << msg;
    msg = error({{"anisotropyRotation", json::array({1})}});
    EXPECT_TRUE(has(msg, at + ".anisotropyRotation: must be a number")) << msg;
    msg = error({{"anisotropyTexture", {{"index", 7}}}});
    EXPECT_TRUE(has(msg, at + ".anisotropyTexture.index")) << msg;
    msg = error({{"anisotropyTexture", {{"texCoord", 0}}}});
    EXPECT_TRUE(has(msg, at + ".anisotropyTexture.index: missing")) << msg;
    // Not an object: tinygltf would drop it without a word; the pre-pass names it.
    for (const json& not_object : {json(5), json::array({1, 2}), json("strong")}) {
        msg = error(not_object);
        EXPECT_TRUE(has(msg, at + ": must be a JSON object, found")) << msg;
    }
    GltfBuilder b = anisotropic_triangle({{"anisotropyStrength", 0.5}});
    b.doc["materials"][0]["extensions"] = 3;
    msg = error_of([&] { (void)load_gltf(write(dir, "ext.gltf", b)); });
    EXPECT_TRUE(has(msg, "materials[0].extensions: must be a JSON object, found number")) << msg;
    // Free-form data may hold anything, and an extension librt does not read is left alone.
    b.doc["materials"][0]["extensions"] = {{"EXT_unknown", 7}};
    b.doc["materials"][0]["extras"] = {{"extensions", 1}};
    EXPECT_NO_THROW((void)load_gltf(write(dir, "free.gltf", b)));
    // Out of [0, 1]: clamped with a warning, as every glTF factor is.
    const GltfScene s =
        load_gltf(write(dir, "clamp.gltf", anisotropic_triangle({{"anisotropyStrength", 1.5}})));
    EXPECT_FLOAT_EQ(s.materials[0].anisotropy_strength, 1.0f);
    EXPECT_TRUE(has(lt::joined(s.warnings), at + ".anisotropyStrength")) << lt::joined(s.warnings);
}
