// KHR_materials_clearcoat, _sheen, _specular, _unlit and _iridescence in glTF files the
// test writes: factors and texture references read into GltfMaterial and mapped to
// Material; the extensions accepted when required; malformed values refused naming the
// JSON path; textures librt does not apply, and iridescence, warned naming the material;
// an unlit wall seen by the camera is exactly its base colour, whatever light is near.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/integrator/integrators.h>
#include <librt/loader/scene_file.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <variant>
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

/// One triangle with material 0 named "paint" carrying `extensions`, all listed as used.
GltfBuilder triangle_with(const json& extensions) {
    GltfBuilder b = lt::one_triangle();
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    json used = json::array();
    for (const auto& [name, value] : extensions.items()) used.push_back(name);
    b.doc["extensionsUsed"] = used;
    b.doc["materials"] = {{{"name", "paint"},
                           {"pbrMetallicRoughness", {{"metallicFactor", 0}}},
                           {"extensions", extensions}}};
    return b;
}

fs::path write(const ScratchDir& dir, const std::string& name, const GltfBuilder& b) {
    const fs::path p = dir.path() / name;
    lt::write_file(p, b.gltf());
    return p;
}

const json kLayers = {
    {"KHR_materials_clearcoat",
     {{"clearcoatFactor", 0.7},
      {"clearcoatRoughnessFactor", 0.2},
      {"clearcoatTexture", {{"index", 0}}},
      {"clearcoatRoughnessTexture", {{"index", 0}}}}},
    {"KHR_materials_sheen", {{"sheenColorFactor", {0.9, 0.5, 0.1}}, {"sheenRoughnessFactor", 0.4}}},
    {"KHR_materials_specular",
     {{"specularFactor", 0.3}, {"specularColorFactor", {2.0, 1.0, 0.5}}}}};

}  // namespace

TEST(GltfMaterialExtensions, ClearcoatSheenAndSpecularAreReadAndMapped) {
    GltfBuilder b = triangle_with(kLayers);
    b.doc["extensionsRequired"] = b.doc["extensionsUsed"];
    b.doc["textures"] = {json::object()};  // no image: only the reference is read here
    ScratchDir dir;
    const GltfScene s = load_gltf(write(dir, "layers.gltf", b));
    ASSERT_EQ(s.materials.size(), 1u);
    const GltfMaterial& g = s.materials[0];
    EXPECT_FLOAT_EQ(g.clearcoat_factor, 0.7f);
    EXPECT_FLOAT_EQ(g.clearcoat_roughness_factor, 0.2f);
    EXPECT_EQ(g.clearcoat_texture.texture, 0);
    EXPECT_EQ(g.clearcoat_roughness_texture.texture, 0);
    EXPECT_EQ(g.sheen_color_factor, glm::vec3(0.9f, 0.5f, 0.1f));
    EXPECT_FLOAT_EQ(g.sheen_roughness_factor, 0.4f);
    EXPECT_FLOAT_EQ(g.specular_factor, 0.3f);
    EXPECT_EQ(g.specular_color_factor, glm::vec3(2.0f, 1.0f, 0.5f));
    GltfMaterialTextures ids;
    ids.clearcoat = 2;
    ids.clearcoat_roughness = 3;
    const Material m = material_from_gltf(g, ids);
    EXPECT_EQ(m.kind, MaterialKind::MetallicRoughness);
    EXPECT_FLOAT_EQ(m.clearcoat, 0.7f);
    EXPECT_FLOAT_EQ(m.clearcoat_roughness, 0.2f);
    EXPECT_EQ(m.clearcoat_texture.texture, 2);
    EXPECT_EQ(m.clearcoat_roughness_texture.texture, 3);
    EXPECT_EQ(m.sheen_color, glm::vec3(0.9f, 0.5f, 0.1f));
    EXPECT_FLOAT_EQ(m.sheen_roughness, 0.4f);
    EXPECT_FLOAT_EQ(m.specular, 0.3f);
    EXPECT_EQ(m.specular_color, glm::vec3(2.0f, 1.0f, 0.5f));
    // Without the extensions: their inert defaults.
    const Material plain = material_from_gltf(GltfMaterial{});
    EXPECT_EQ(plain.clearcoat, 0.0f);
    EXPECT_EQ(plain.sheen_color, glm::vec3(0.0f));
    EXPECT_EQ(plain.specular, 1.0f);
    EXPECT_EQ(plain.specular_color, glm::vec3(1.0f));
    // And in the scene: the material as mapped (the texture without an image is dropped).
    const LoadedScene loaded = load_scene_file(write(dir, "layers2.gltf", b));
    bool found = false;
    for (std::uint32_t i = 0; i < loaded.scene.material_count(); ++i) {
        const Material& sm = loaded.scene.material(i);
        if (sm.kind != MaterialKind::MetallicRoughness) continue;
        found = true;
        EXPECT_FLOAT_EQ(sm.clearcoat, 0.7f);
        EXPECT_EQ(sm.sheen_color, glm::vec3(0.9f, 0.5f, 0.1f));
        EXPECT_FLOAT_EQ(sm.specular, 0.3f);
    }
    EXPECT_TRUE(found);
}

TEST(GltfMaterialExtensions, MalformedValuesNameTheJsonPath) {
    ScratchDir dir;
    const auto error = [&](const json& ext) {
        const fs::path p = write(dir, "bad.gltf", triangle_with(ext));
        return error_of([&] { (void)load_gltf(p); });
    };
    std::string e = error({{"KHR_materials_clearcoat", {{"clearcoatFactor", "shiny"}}}});
    EXPECT_TRUE(has(e, "materials[0].extensions.KHR_materials_clearcoat.clearcoatFactor")) << e;
    e = error({{"KHR_materials_sheen", {{"sheenColorFactor", {1, 0}}}}});
    EXPECT_TRUE(has(e, "materials[0].extensions.KHR_materials_sheen.sheenColorFactor")) << e;
    e = error({{"KHR_materials_specular", {{"specularColorFactor", {1, "x", 0}}}}});
    EXPECT_TRUE(has(e, "KHR_materials_specular.specularColorFactor[1]")) << e;
    e = error({{"KHR_materials_clearcoat", {{"clearcoatTexture", {{"index", 5}}}}}});
    EXPECT_TRUE(has(e, "KHR_materials_clearcoat.clearcoatTexture.index")) << e;
    e = error({{"KHR_materials_unlit", 3}});
    EXPECT_TRUE(has(e, "materials[0].extensions.KHR_materials_unlit")) << e;
    // Out of range: clamped with a warning naming the path.
    const GltfScene s =
        load_gltf(write(dir, "clamped.gltf",
                        triangle_with({{"KHR_materials_clearcoat", {{"clearcoatFactor", 2}}}})));
    EXPECT_FLOAT_EQ(s.materials[0].clearcoat_factor, 1.0f);
    EXPECT_TRUE(has(lt::joined(s.warnings), "KHR_materials_clearcoat.clearcoatFactor"))
        << lt::joined(s.warnings);
}

TEST(GltfMaterialExtensions, UnappliedTexturesAndIridescenceAreWarnedByMaterial) {
    json ext = {{"KHR_materials_sheen",
                 {{"sheenColorFactor", {1, 1, 1}}, {"sheenColorTexture", {{"index", 0}}}}},
                {"KHR_materials_specular", {{"specularTexture", {{"index", 0}}}}},
                {"KHR_materials_clearcoat",
                 {{"clearcoatFactor", 1}, {"clearcoatNormalTexture", {{"index", 0}}}}},
                {"KHR_materials_iridescence", {{"iridescenceFactor", 1}}}};
    GltfBuilder b = triangle_with(ext);
    b.doc["textures"] = {json::object()};
    ScratchDir dir;
    const LoadedScene loaded = load_scene_file(write(dir, "irid.gltf", b));
    const std::string w = lt::joined(loaded.warnings);
    EXPECT_TRUE(has(w, "materials[0] 'paint': KHR_materials_iridescence is not supported")) << w;
    EXPECT_FALSE(has(w, "clearcoat normal")) << w;  // applied (the test below)
    // The sheen and specular textures are applied (the test below), so not warned.
    EXPECT_FALSE(has(w, "sheen colour texture")) << w;
    EXPECT_FALSE(has(w, "specular texture")) << w;
    // Required, the file still loads (drawn without it), with the same warning.
    b.doc["extensionsRequired"] = {"KHR_materials_iridescence"};
    const LoadedScene required = load_scene_file(write(dir, "irid_required.gltf", b));
    EXPECT_TRUE(has(lt::joined(required.warnings), "KHR_materials_iridescence is not supported"))
        << lt::joined(required.warnings);
}

// The sheen, specular and transmission textures multiply their factors at each hit, each
// from the channel and colour space the extensions give: sheenColorTexture and
// specularColorTexture RGB in sRGB, sheenRoughnessTexture and specularTexture alpha, and
// transmissionTexture red, linear. One texel (128, 128, 128, 64) read by all five.
TEST(GltfMaterialExtensions, SheenSpecularAndTransmissionTexturesMultiplyTheirFactors) {
    const json tex = {{"index", 0}};
    json ext = {{"KHR_materials_sheen",
                 {{"sheenColorFactor", {0.9, 0.5, 0.25}},
                  {"sheenColorTexture", tex},
                  {"sheenRoughnessFactor", 0.8},
                  {"sheenRoughnessTexture", tex}}},
                {"KHR_materials_specular",
                 {{"specularFactor", 0.6},
                  {"specularTexture", tex},
                  {"specularColorFactor", {2.0, 1.0, 0.5}},
                  {"specularColorTexture", tex}}},
                {"KHR_materials_transmission",
                 {{"transmissionFactor", 0.7}, {"transmissionTexture", tex}}}};
    GltfBuilder b = triangle_with(ext);
    b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    b.doc["samplers"] = {{{"magFilter", 9728}}};  // NEAREST
    const unsigned char texel[4] = {128, 128, 128, 64};
    b.doc["images"] = {{{"uri", "data:image/png;base64," + lt::base64(lt::rgba_png(1, 1, texel))}}};
    ScratchDir dir;
    LoadedScene loaded = load_scene_file(write(dir, "textured_layers.gltf", b));
    const std::string w = lt::joined(loaded.warnings);
    EXPECT_FALSE(has(w, "texture ignored")) << w;
    Scene& scene = loaded.scene;
    scene.commit();
    const std::uint32_t mat = [&] {
        for (std::uint32_t i = 0; i < scene.material_count(); ++i)
            if (scene.material(i).kind == MaterialKind::MetallicRoughness) return i;
        return kInvalidId;
    }();
    ASSERT_NE(mat, kInvalidId);
    const Material& stored = scene.material(mat);
    for (const TextureSlot* slot :
         {&stored.sheen_color_texture, &stored.sheen_roughness_texture, &stored.specular_texture,
          &stored.specular_color_texture, &stored.transmission_texture})
        EXPECT_TRUE(slot->bound());
    // The image read twice, once per colour space.
    EXPECT_EQ(stored.sheen_color_texture.texture, stored.specular_color_texture.texture);
    EXPECT_EQ(stored.specular_texture.texture, stored.transmission_texture.texture);
    EXPECT_NE(stored.sheen_color_texture.texture, stored.specular_texture.texture);

    // glTF's sRGB transfer function (KHR_texture... / the spec's Appendix), in double.
    const double c = 128.0 / 255.0;
    const auto srgb = float(std::pow((c + 0.055) / 1.055, 2.4));
    const auto linear = float(c), alpha = 64.0f / 255.0f;
    Hit hit;
    const Ray ray({0.25f, 0.25f, 1.0f}, {0.0f, 0.0f, -1.0f});
    ASSERT_TRUE(scene.intersect_for_shading(ray, hit));
    ShadedMaterial scratch;
    const Material& m = scene.shade(hit, ray.direction, scratch);
    const float tol = 1e-6f;
    EXPECT_NEAR(m.sheen_color.x, 0.9f * srgb, tol);
    EXPECT_NEAR(m.sheen_color.z, 0.25f * srgb, tol);
    EXPECT_NEAR(m.sheen_roughness, 0.8f * alpha, tol);
    EXPECT_NEAR(m.specular, 0.6f * alpha, tol);
    EXPECT_NEAR(m.specular_color.x, 2.0f * srgb, tol);
    EXPECT_NEAR(m.specular_color.y, 1.0f * srgb, tol);
    EXPECT_NEAR(m.transmission, 0.7f * linear, tol);
    // The stored material keeps its factors.
    EXPECT_FLOAT_EQ(stored.sheen_roughness, 0.8f);
    EXPECT_FLOAT_EQ(stored.transmission, 0.7f);
}

// clearcoatNormalTexture bends the coat's own normal, read with its scale, while the base
// keeps normalTexture's: a triangle facing +z (tangent +x from its uvs) with a base normal
// texel (128, 200, 255) and a coat normal texel (255, 128, 200) at scale 0.5.
TEST(GltfMaterialExtensions, ClearcoatNormalTextureBendsOnlyTheCoat) {
    GltfBuilder b = triangle_with(
        {{"KHR_materials_clearcoat",
          {{"clearcoatFactor", 1}, {"clearcoatNormalTexture", {{"index", 1}, {"scale", 0.5}}}}}});
    const int uv = b.add_accessor(std::vector<float>{0, 0, 1, 0, 0, 1}, lt::kFloat, "VEC2", 3);
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = uv;
    b.doc["materials"][0]["normalTexture"] = {{"index", 0}};
    b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}, {{"source", 1}, {"sampler", 0}}};
    b.doc["samplers"] = {{{"magFilter", 9728}}};  // NEAREST
    const unsigned char base_texel[4] = {128, 200, 255, 255}, coat_texel[4] = {255, 128, 200, 255};
    b.doc["images"] = {
        {{"uri", "data:image/png;base64," + lt::base64(lt::rgba_png(1, 1, base_texel))}},
        {{"uri", "data:image/png;base64," + lt::base64(lt::rgba_png(1, 1, coat_texel))}}};
    ScratchDir dir;
    const fs::path file = write(dir, "coat_normal.gltf", b);
    const GltfScene g = load_gltf(file);
    EXPECT_EQ(g.materials[0].clearcoat_normal_texture.texture, 1);
    EXPECT_FLOAT_EQ(g.materials[0].clearcoat_normal_texture.scale, 0.5f);
    LoadedScene loaded = load_scene_file(file);
    const std::string w = lt::joined(loaded.warnings);
    EXPECT_FALSE(has(w, "clearcoat")) << w;
    Scene& scene = loaded.scene;
    scene.commit();
    std::uint32_t mat = kInvalidId;
    for (std::uint32_t i = 0; i < scene.material_count(); ++i)
        if (scene.material(i).kind == MaterialKind::MetallicRoughness) mat = i;
    ASSERT_NE(mat, kInvalidId);
    const Material& stored = scene.material(mat);
    ASSERT_TRUE(stored.clearcoat_normal_texture.bound());
    EXPECT_NE(stored.clearcoat_normal_texture.texture, stored.normal_texture.texture);
    EXPECT_FLOAT_EQ(stored.clearcoat_normal_scale, 0.5f);
    EXPECT_EQ(stored.clearcoat_normal, glm::vec3(0.0f));  // set per hit only

    Hit hit;
    const Ray ray({0.25f, 0.25f, 1.0f}, {0.0f, 0.0f, -1.0f});
    ASSERT_TRUE(scene.intersect_for_shading(ray, hit));
    ShadedMaterial scratch;
    const Material& m = scene.shade(hit, ray.direction, scratch);
    // glTF 2.0 sec. 3.9.3: n = normalize((2 texel - 1) * (scale, scale, 1)) in (T, B, N),
    // with T = +x (u), N = +z; B = +-y, so only its sign rests on the uv convention.
    const auto decode = [](int v) { return 2.0 * v / 255.0 - 1.0; };
    const glm::dvec3 coat(decode(255) * 0.5, decode(128) * 0.5, decode(200));
    const glm::dvec3 coat_n = glm::normalize(coat);
    EXPECT_NEAR(m.clearcoat_normal.x, coat_n.x, 1e-5);
    EXPECT_NEAR(std::fabs(m.clearcoat_normal.y), std::fabs(coat_n.y), 1e-5);
    EXPECT_NEAR(m.clearcoat_normal.z, coat_n.z, 1e-5);
    // The base's shading normal is normalTexture's (scale 1), the coat's texel not involved.
    const glm::dvec3 base_n = glm::normalize(glm::dvec3(decode(128), decode(200), 1.0));
    EXPECT_NEAR(hit.shading_normal.x, base_n.x, 1e-5);
    EXPECT_NEAR(std::fabs(hit.shading_normal.y), std::fabs(base_n.y), 1e-5);
    EXPECT_NEAR(hit.shading_normal.z, base_n.z, 1e-5);
    // The stored material keeps no per-hit normal.
    EXPECT_EQ(scene.material(mat).clearcoat_normal, glm::vec3(0.0f));
}

TEST(GltfMaterialExtensions, UnlitIsAnEmitterOfItsBaseColourNotALight) {
    GltfBuilder b = triangle_with({{"KHR_materials_unlit", json::object()}});
    b.doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"] = {0.2, 0.5, 0.7, 1.0};
    b.doc["extensionsRequired"] = {"KHR_materials_unlit"};
    ScratchDir dir;
    const GltfScene s = load_gltf(write(dir, "unlit.gltf", b));
    ASSERT_TRUE(s.materials[0].unlit);
    const Material m = material_from_gltf(s.materials[0]);
    EXPECT_EQ(m.kind, MaterialKind::Emissive);
    EXPECT_TRUE(m.unlit);
    EXPECT_EQ(m.emission, glm::vec3(0.2f, 0.5f, 0.7f));
    LoadedScene loaded = load_scene_file(write(dir, "unlit2.gltf", b));
    loaded.scene.commit();
    // Not light-sampled: the scene's lights are only what scene_from_gltf adds (if any),
    // none of them on the triangle.
    for (const Light& light : loaded.scene.lights())
        EXPECT_FALSE(std::holds_alternative<TriangleLight>(light.source));
    EXPECT_TRUE(loaded.scene.has_unsampled_emitters());
}

// Camera rays see an unlit wall as exactly its base colour, a point light next to it
// notwithstanding: it reflects nothing, and its emission is the colour.
TEST(GltfMaterialExtensions, CameraSeesExactlyTheUnlitBaseColour) {
    GltfBuilder b;
    const std::vector<float> p = {-4, -100, -100, -4, -100, 300, -4, 300, -100};
    const int pos = b.add_accessor(p, lt::kFloat, "VEC3", 3);
    b.doc["accessors"][pos]["min"] = {-4, -100, -100};
    b.doc["accessors"][pos]["max"] = {-4, 300, 300};
    b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"material", 0}}}}}};
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.5, 0.7, 1}}}},
                           {"doubleSided", true},
                           {"extensions", {{"KHR_materials_unlit", json::object()}}}}};
    b.doc["cameras"] = {{{"type", "perspective"},
                         {"perspective", {{"yfov", 0.8}, {"aspectRatio", 1.0}, {"znear", 0.1}}}}};
    b.doc["extensionsUsed"] = {"KHR_materials_unlit", "KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"intensity", 5000}}};
    const double h = std::sqrt(0.5);  // looking down -x at the wall
    b.doc["nodes"] = {
        {{"mesh", 0}},
        {{"camera", 0}, {"translation", {1, 2, 3}}, {"rotation", {0, h, 0, h}}},
        {{"translation", {-3, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}};
    b.doc["scenes"] = {{{"nodes", {0, 1, 2}}}};
    b.doc["scene"] = 0;
    ScratchDir dir;
    const fs::path path = dir.path() / "unlit_wall.glb";
    lt::write_file(path, b.glb());
    SceneFileOptions options;
    options.width = 16;
    options.height = 16;
    LoadedScene loaded = load_scene_file(path, options);
    loaded.scene.commit();
    PathTracerSettings pts;
    pts.max_depth = 5;
    PathTracer integrator(pts);
    RenderSettings settings;
    settings.samples_per_pixel = 4;
    settings.seed = 3;
    const Image image = render(loaded.scene, Camera(loaded.camera), integrator, settings);
    ASSERT_EQ(image.pixels.size(), 256u);
    for (const glm::vec3& px : image.pixels) {
        ASSERT_NEAR(px.x, 0.2f, 1e-5f);
        ASSERT_NEAR(px.y, 0.5f, 1e-5f);
        ASSERT_NEAR(px.z, 0.7f, 1e-5f);
    }
}

namespace {

/// One triangle facing +z with TEXCOORD_0 everywhere (0.25, 0.5) (tiny_png's red texel)
/// and TEXCOORD_1 everywhere (0.75, 0.5) (its blue one), and the PNG as texture 0 with
/// NEAREST magnification; material 0 as `material` says.
GltfBuilder two_uv_sets(const json& material) {
    GltfBuilder b = lt::one_triangle();
    const int uv0 =
        b.add_accessor(std::vector<float>{0.25, 0.5, 0.25, 0.5, 0.25, 0.5}, lt::kFloat, "VEC2", 3);
    const int uv1 =
        b.add_accessor(std::vector<float>{0.75, 0.5, 0.75, 0.5, 0.75, 0.5}, lt::kFloat, "VEC2", 3);
    auto& attributes = b.doc["meshes"][0]["primitives"][0]["attributes"];
    attributes["TEXCOORD_0"] = uv0;
    attributes["TEXCOORD_1"] = uv1;
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    b.doc["images"] = {{{"uri", "data:image/png;base64," + lt::base64(lt::tiny_png())}}};
    b.doc["samplers"] = {{{"magFilter", 9728}}};
    b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    b.doc["materials"] = {material};
    return b;
}

/// The loaded scene's material at the triangle's centre, per-hit inputs applied.
struct Shaded {
    LoadedScene loaded;
    Hit hit;
    ShadedMaterial scratch;
    const Material* m = nullptr;
};
void shade_centre(const fs::path& p, Shaded& out) {
    out.loaded = load_scene_file(p);
    out.loaded.scene.commit();
    const Ray ray({0.25f, 0.25f, 2.0f}, {0.0f, 0.0f, -1.0f});
    ASSERT_TRUE(out.loaded.scene.intersect(ray, out.hit));
    out.m = &out.loaded.scene.shade(out.hit, ray.direction, out.scratch);
}

}  // namespace

// A texture info with texCoord 1 reads TEXCOORD_1: alone (the mesh's uvs are then set 1)
// and next to a texture on set 0 (the second set stored as uvs1, read by that slot only);
// a material on one set stores no second one.
TEST(GltfUvSets, ATextureOnTexcoord1ReadsTexcoord1) {
    ScratchDir dir;
    const auto material = [](int base_set, int mr_set) {
        json pbr = {{"baseColorTexture", {{"index", 0}, {"texCoord", base_set}}},
                    {"metallicFactor", 1.0}};
        if (mr_set >= 0) pbr["metallicRoughnessTexture"] = {{"index", 0}, {"texCoord", mr_set}};
        return json{{"pbrMetallicRoughness", pbr}};
    };
    {
        Shaded s;
        const fs::path p = dir.path() / "set1.gltf";
        lt::write_file(p, two_uv_sets(material(1, -1)).gltf());
        ASSERT_NO_FATAL_FAILURE(shade_centre(p, s));
        EXPECT_NEAR(s.m->base_color.x, 0.0f, 1e-6f);  // blue, not red
        EXPECT_NEAR(s.m->base_color.z, 1.0f, 1e-6f);
        EXPECT_TRUE(s.loaded.scene.top_level().prototype_mesh(0).uvs1.empty());
    }
    {
        Shaded s;
        const fs::path p = dir.path() / "set0.gltf";
        lt::write_file(p, two_uv_sets(material(0, -1)).gltf());
        ASSERT_NO_FATAL_FAILURE(shade_centre(p, s));
        EXPECT_NEAR(s.m->base_color.x, 1.0f, 1e-6f);  // red
        EXPECT_NEAR(s.m->base_color.z, 0.0f, 1e-6f);
    }
    {
        // Base colour on set 1, metallic-roughness on set 0: red's B (metallic) is 0, and
        // blue's G (roughness) is 0; set 0 read for both would leave metallic 0 and
        // roughness 0, set 1 for both metallic 1.
        Shaded s;
        const fs::path p = dir.path() / "mixed.gltf";
        lt::write_file(p, two_uv_sets(material(1, 0)).gltf());
        ASSERT_NO_FATAL_FAILURE(shade_centre(p, s));
        EXPECT_NEAR(s.m->base_color.z, 1.0f, 1e-6f);  // set 1: blue
        EXPECT_NEAR(s.m->metallic, 0.0f, 1e-6f);      // set 0: red's B = 0
        EXPECT_EQ(s.loaded.scene.top_level().prototype_mesh(0).uvs1.size(), 3u);
        // The first texture's set (base colour: TEXCOORD_1) is the mesh's uvs; the other
        // (TEXCOORD_0) its uvs1, read by the metallic-roughness slot.
        EXPECT_EQ(s.m->base_color_texture.uv_set, 0);
        EXPECT_EQ(s.m->metallic_roughness_texture.uv_set, 1);
        EXPECT_FALSE(has(lt::joined(s.loaded.warnings), "TEXCOORD"))
            << lt::joined(s.loaded.warnings);
    }
}

// occlusionTexture reaches the albedo AOV's factor (Scene::occlusion) with its strength,
// on its own uv set, and never the shaded material.
TEST(GltfUvSets, OcclusionScalesTheAlbedoGuideOnly) {
    ScratchDir dir;
    // tiny_png's red texel has R = 1 (no occlusion), its blue one R = 0 (full).
    json m = {{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}},
              {"occlusionTexture", {{"index", 0}, {"texCoord", 1}, {"strength", 0.6}}}};
    Shaded s;
    const fs::path p = dir.path() / "ao.gltf";
    lt::write_file(p, two_uv_sets(m).gltf());
    ASSERT_NO_FATAL_FAILURE(shade_centre(p, s));
    EXPECT_TRUE(s.m->occlusion_texture.bound());
    EXPECT_FLOAT_EQ(s.m->occlusion_strength, 0.6f);
    // Set 1 is blue: R = 0, so 1 + 0.6 (0 - 1) = 0.4.
    const glm::vec3 ao = s.loaded.scene.occlusion(s.hit);
    EXPECT_NEAR(ao.x, 0.4f, 1e-6f);
    EXPECT_EQ(s.m->base_color, glm::vec3(1.0f));  // shading untouched
    EXPECT_FALSE(has(lt::joined(s.loaded.warnings), "occlusion")) << lt::joined(s.loaded.warnings);
}
