// KHR_materials_volume and solid transmission, in glTF files the test writes (a closed cube
// of side 2, outward winding, material "glass" with KHR_materials_transmission 1):
// the volume's values read and mapped (solid glass with Beer-Lambert inside), malformed
// ones refused naming the JSON path; transmission without a volume loads thin-walled with
// one hint naming the material, and as solid glass with solid_transmission. Then light
// followed through the cube with the scene's own intersect / shade and the BSDF's sample():
// along a straight path of length L inside, the weight is attenuationColor^(L / distance)
// (Beer-Lambert, KHR_materials_volume's definition); a slanted ray entering solid glass
// refracts by Snell's law, and the thin wall lets it through undeviated.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/geometry/ray_offset.h>
#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/loader/scene_file.h>
#include <librt/material/bsdf.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
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

/// A cube [-1, 1]^3, wound counter-clockwise seen from outside, material 0 "glass":
/// transmission 1, metallic 0, roughness 0, KHR_materials_ior `ior`, and `volume` (an
/// object, or null for none), placed by `nodes` nodes.
GltfBuilder glass_cube(const json& volume, double ior = 1.5, int nodes = 1) {
    GltfBuilder b;
    const std::vector<float> p = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                  -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
    const std::vector<std::uint16_t> idx = {0, 3, 2, 0, 2, 1, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                            3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    const int pos = b.add_accessor(p, lt::kFloat, "VEC3", 8);
    b.doc["accessors"][pos]["min"] = {-1, -1, -1};
    b.doc["accessors"][pos]["max"] = {1, 1, 1};
    const int ind = b.add_accessor(idx, lt::kU16, "SCALAR", 36);
    b.doc["meshes"] = {
        {{"primitives",
          {{{"attributes", {{"POSITION", pos}}}, {"indices", ind}, {"material", 0}}}}}};
    json ext = {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                {"KHR_materials_ior", {{"ior", ior}}}};
    json used = {"KHR_materials_transmission", "KHR_materials_ior"};
    if (!volume.is_null()) {
        ext["KHR_materials_volume"] = volume;
        used.push_back("KHR_materials_volume");
    }
    b.doc["extensionsUsed"] = used;
    b.doc["materials"] = {
        {{"name", "glass"},
         {"pbrMetallicRoughness", {{"metallicFactor", 0}, {"roughnessFactor", 0}}},
         {"extensions", ext}}};
    json scene_nodes = json::array();
    for (int i = 0; i < nodes; ++i) {
        b.doc["nodes"].push_back({{"mesh", 0}, {"translation", {4.0 * i, 0, 0}}});
        scene_nodes.push_back(i);
    }
    b.doc["scenes"] = {{{"nodes", scene_nodes}}};
    b.doc["scene"] = 0;
    return b;
}

fs::path write(const ScratchDir& dir, const std::string& name, const GltfBuilder& b) {
    const fs::path p = dir.path() / name;
    lt::write_file(p, b.gltf());
    return p;
}

const json kVolume = {
    {"thicknessFactor", 2.0}, {"attenuationDistance", 1.0}, {"attenuationColor", {0.5, 0.25, 0.8}}};

int count(const std::vector<std::string>& lines, std::string_view part) {
    int n = 0;
    for (const std::string& l : lines) n += has(l, part) ? 1 : 0;
    return n;
}

/// One step of a path: the closest hit along `ray`, its material as the scene shades it,
/// and a BSDF sample there with numbers (uc, u).
struct Step {
    bool hit = false;
    bool front = false;  ///< the ray met the surface's outside
    float t = 0.0f;
    Material material;
    glm::vec3 weight{0.0f};
    glm::vec3 wi{0.0f};  ///< world direction sampled
    Ray next;
};

Step step(const Scene& scene, const Ray& ray, float uc) {
    Step s;
    Hit hit;
    if (!scene.intersect(ray, hit)) return s;
    s.hit = true;
    s.t = hit.t;
    ShadedMaterial scratch;
    s.material = scene.shade(hit, ray.direction, scratch);
    const ShadingPoint p{ShadingFrame::at(hit.shading_normal, hit.geometric_normal, ray.direction),
                         s.material.albedo};
    s.front = p.frame.front;
    const BsdfSample b =
        sample(s.material, p, p.frame.to_local(-ray.direction), uc, glm::vec2(0.3f, 0.6f));
    if (!b.valid()) return s;
    s.weight = b.weight;
    s.wi = p.frame.to_world(b.wi);
    s.next = spawn_ray(hit, s.wi);
    return s;
}

}  // namespace

TEST(GltfVolume, ValuesAreReadAndMappedToSolidGlass) {
    ScratchDir dir;
    GltfBuilder b = glass_cube(kVolume);
    b.doc["extensionsRequired"] = {"KHR_materials_volume"};
    const GltfScene s = load_gltf(write(dir, "volume.gltf", b));
    ASSERT_EQ(s.materials.size(), 1u);
    const GltfMaterial& g = s.materials[0];
    EXPECT_FLOAT_EQ(g.thickness_factor, 2.0f);
    EXPECT_FLOAT_EQ(g.attenuation_distance, 1.0f);
    EXPECT_EQ(g.attenuation_color, glm::vec3(0.5f, 0.25f, 0.8f));
    EXPECT_TRUE(gltf_solid_glass(g));
    const Material m = material_from_gltf(g);
    EXPECT_EQ(m.kind, MaterialKind::RoughDielectric);
    EXPECT_FLOAT_EQ(m.ior, 1.5f);
    EXPECT_EQ(m.roughness, 0.0f);
    EXPECT_EQ(m.albedo, glm::vec3(1.0f));
    EXPECT_TRUE(m.double_sided);
    EXPECT_EQ(m.attenuation_color, glm::vec3(0.5f, 0.25f, 0.8f));
    EXPECT_FLOAT_EQ(m.attenuation_distance, 1.0f);
    EXPECT_TRUE(m.absorbs_inside());
    // c^(L / d), Beer-Lambert.
    const glm::vec3 t = m.interior_transmittance(3.0f);
    EXPECT_NEAR(t.x, 0.125f, 1e-6f);
    EXPECT_NEAR(t.y, 0.015625f, 1e-7f);
    EXPECT_NEAR(t.z, 0.512f, 1e-6f);
    // The extension's defaults: no volume, thin-walled; a volume without attenuation
    // absorbs nothing.
    const GltfMaterial plain{};
    EXPECT_EQ(plain.thickness_factor, 0.0f);
    EXPECT_TRUE(std::isinf(plain.attenuation_distance));
    EXPECT_EQ(plain.attenuation_color, glm::vec3(1.0f));
    GltfMaterial clear = g;
    clear.attenuation_distance = std::numeric_limits<float>::infinity();
    EXPECT_FALSE(material_from_gltf(clear).absorbs_inside());
    // No hint for a material that says it is solid.
    const LoadedScene loaded = load_scene_file(write(dir, "volume2.gltf", b));
    EXPECT_EQ(count(loaded.warnings, "thin-walled"), 0) << lt::joined(loaded.warnings);
}

TEST(GltfVolume, MalformedValuesNameTheJsonPath) {
    ScratchDir dir;
    const auto error = [&](const json& volume) {
        const fs::path p = write(dir, "bad.gltf", glass_cube(volume));
        return error_of([&] { (void)load_gltf(p); });
    };
    std::string e = error({{"attenuationDistance", 0}});
    EXPECT_TRUE(has(e, "materials[0].extensions.KHR_materials_volume.attenuationDistance")) << e;
    e = error({{"thicknessFactor", -1}});
    EXPECT_TRUE(has(e, "KHR_materials_volume.thicknessFactor")) << e;
    e = error({{"attenuationColor", {1, 1}}});
    EXPECT_TRUE(has(e, "KHR_materials_volume.attenuationColor")) << e;
    e = error({{"thicknessFactor", "thick"}});
    EXPECT_TRUE(has(e, "KHR_materials_volume.thicknessFactor")) << e;
    // Out of range colour: clamped with a warning naming the path; 0 absorbs all but
    // 1e-4 per distance (log 0 has no rate).
    const GltfScene s =
        load_gltf(write(dir, "clamped.gltf",
                        glass_cube({{"thicknessFactor", 1}, {"attenuationColor", {2, 0, 0.5}}})));
    EXPECT_EQ(s.materials[0].attenuation_color, glm::vec3(1.0f, 0.0f, 0.5f));
    EXPECT_TRUE(has(lt::joined(s.warnings), "KHR_materials_volume.attenuationColor[0]"))
        << lt::joined(s.warnings);
    EXPECT_EQ(material_from_gltf(s.materials[0]).attenuation_color, glm::vec3(1.0f, 1e-4f, 0.5f));
    Material bad = material_from_gltf(s.materials[0]);
    bad.attenuation_distance = 0.0f;
    EXPECT_THROW(validate(bad), Error);
    bad.attenuation_distance = 1.0f;
    bad.attenuation_color.y = 0.0f;
    EXPECT_THROW(validate(bad), Error);
}

// Along the cube's axis through its centre, at normal incidence (no bending): the entry
// passes the light unchanged, and the exit, reached after L = 2 inside, weighs
// attenuationColor^(L / attenuationDistance). The numbers pick refraction (uc above F).
TEST(GltfVolume, BeerLambertAlongAStraightPath) {
    ScratchDir dir;
    for (const double distance : {1.0, 0.5}) {
        json volume = kVolume;
        volume["attenuationDistance"] = distance;
        LoadedScene loaded = load_scene_file(write(dir, "cube.gltf", glass_cube(volume)));
        loaded.scene.commit();
        const Ray ray{glm::vec3(0.1f, -0.2f, 5.0f), glm::vec3(0.0f, 0.0f, -1.0f)};
        const Step in = step(loaded.scene, ray, 0.999f);
        ASSERT_TRUE(in.hit);
        EXPECT_TRUE(in.front);
        EXPECT_NEAR(in.t, 4.0f, 1e-5f);
        EXPECT_EQ(in.weight, glm::vec3(1.0f)) << "entering: nothing absorbed yet";
        EXPECT_NEAR(in.wi.z, -1.0f, 1e-6f);
        const Step out = step(loaded.scene, in.next, 0.999f);
        ASSERT_TRUE(out.hit);
        EXPECT_FALSE(out.front);
        EXPECT_NEAR(out.t, 2.0f, 1e-4f);
        // c^(t / d) for the length travelled (float rounding: 1e-5 relative), and the
        // cube's 2 within what the rays' offsets from the faces (1e-4 above) allow.
        const glm::vec3 c(0.5f, 0.25f, 0.8f);
        for (int k = 0; k < 3; ++k) {
            const double exact = std::pow(double(c[k]), double(out.t) / distance);
            EXPECT_NEAR(out.weight[k], exact, 1e-5 * exact) << "distance " << distance;
            const double ideal = std::pow(double(c[k]), 2.0 / distance);
            EXPECT_NEAR(out.weight[k], ideal, 1e-3 * ideal) << "distance " << distance;
        }
        EXPECT_NEAR(out.wi.z, -1.0f, 1e-6f);
    }
}

// Transmission without KHR_materials_volume: thin-walled by default, with one hint naming
// the material however many nodes place it; the thin wall lets a slanted ray through
// undeviated. With solid_transmission: solid glass, no hint, no absorption (no volume),
// and the slanted ray refracts by Snell's law, sin(theta_t) = sin(theta_i) / ior.
TEST(GltfVolume, TransmissionWithoutVolumeIsThinUnlessSolidIsAsked) {
    ScratchDir dir;
    const fs::path p = write(dir, "blender_glass.gltf", glass_cube(nullptr, 1.45, 2));
    LoadedScene thin = load_scene_file(p);
    EXPECT_EQ(count(thin.warnings, "thin-walled"), 1) << lt::joined(thin.warnings);
    EXPECT_EQ(count(thin.warnings, "materials[0] 'glass'"), 1) << lt::joined(thin.warnings);
    EXPECT_TRUE(has(lt::joined(thin.warnings), "--solid-transmission"));

    SceneFileOptions options;
    options.solid_transmission = true;
    LoadedScene solid = load_scene_file(p, options);
    EXPECT_EQ(count(solid.warnings, "thin-walled"), 0) << lt::joined(solid.warnings);

    // A ray at 40 degrees from the +z face's normal, in the xz plane.
    const double theta = 40.0 * 3.14159265358979 / 180.0;
    const glm::vec3 d(float(std::sin(theta)), 0.0f, float(-std::cos(theta)));
    const Ray ray{glm::vec3(0.0f, 0.0f, 1.0f) - 3.0f * d, d};

    thin.scene.commit();
    Hit hit;
    ASSERT_TRUE(thin.scene.intersect(ray, hit));
    const Material& tm = thin.scene.material(hit);
    EXPECT_EQ(tm.kind, MaterialKind::MetallicRoughness);
    EXPECT_FLOAT_EQ(tm.transmission, 1.0f);
    EXPECT_TRUE(has(lobes(tm), BsdfLobe::Null)) << "a smooth thin wall is crossed undeviated";

    solid.scene.commit();
    ASSERT_TRUE(solid.scene.intersect(ray, hit));
    const Material& sm = solid.scene.material(hit);
    EXPECT_EQ(sm.kind, MaterialKind::RoughDielectric);
    EXPECT_FLOAT_EQ(sm.ior, 1.45f);
    EXPECT_FALSE(sm.absorbs_inside());
    const Step in = step(solid.scene, ray, 0.999f);
    ASSERT_TRUE(in.hit);
    EXPECT_TRUE(in.front);
    const double sin_t = std::sin(theta) / 1.45;
    EXPECT_NEAR(in.wi.x, sin_t, 1e-5);
    EXPECT_NEAR(in.wi.y, 0.0, 1e-6);
    EXPECT_NEAR(in.wi.z, -std::sqrt(1.0 - sin_t * sin_t), 1e-5);
    EXPECT_NEAR(in.weight.x, 1.0f, 1e-6f);
    // Out through the bottom face (parallel to the top): the original direction again.
    const Step out = step(solid.scene, in.next, 0.999f);
    ASSERT_TRUE(out.hit);
    EXPECT_FALSE(out.front);
    EXPECT_NEAR(out.wi.x, d.x, 1e-5f);
    EXPECT_NEAR(out.wi.z, d.z, 1e-5f);
    EXPECT_NEAR(out.weight.x, 1.0f, 1e-6f) << "no volume: nothing absorbed";
}

// Solid glass is only glass: transmission below 1 stays thin-walled, with a warning.
TEST(GltfVolume, PartialTransmissionStaysThinWithAWarning) {
    ScratchDir dir;
    GltfBuilder b = glass_cube(kVolume);
    b.doc["materials"][0]["extensions"]["KHR_materials_transmission"]["transmissionFactor"] = 0.5;
    const LoadedScene loaded = load_scene_file(write(dir, "half.gltf", b));
    EXPECT_EQ(count(loaded.warnings, "drawn thin-walled"), 1) << lt::joined(loaded.warnings);
    GltfMaterial g;
    g.transmission_factor = 0.5f;
    g.thickness_factor = 1.0f;
    g.metallic_factor = 0.0f;
    EXPECT_FALSE(gltf_solid_glass(g));
    EXPECT_EQ(material_from_gltf(g).kind, MaterialKind::MetallicRoughness);
}

// SceneFileOptions::diffuse_model reaches every glTF material.
TEST(GltfVolume, DiffuseModelOptionReachesTheMaterials) {
    ScratchDir dir;
    const fs::path p = write(dir, "plain.gltf", glass_cube(nullptr));
    SceneFileOptions options;
    options.diffuse_model = DiffuseModel::Burley;
    LoadedScene loaded = load_scene_file(p, options);
    loaded.scene.commit();
    Hit hit;
    ASSERT_TRUE(loaded.scene.intersect(Ray{glm::vec3(0, 0, 5), glm::vec3(0, 0, -1)}, hit));
    EXPECT_EQ(loaded.scene.material(hit).diffuse_model, DiffuseModel::Burley);
    LoadedScene lambert = load_scene_file(p);
    lambert.scene.commit();
    ASSERT_TRUE(lambert.scene.intersect(Ray{glm::vec3(0, 0, 5), glm::vec3(0, 0, -1)}, hit));
    EXPECT_EQ(lambert.scene.material(hit).diffuse_model, DiffuseModel::Lambert);
}
