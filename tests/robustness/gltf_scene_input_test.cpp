// Bad values in a glTF that only turn bad as librt's floats, transforms, cameras and
// materials: loaded the way rt_render loads a scene (load_scene_file), each error or
// warning names the file and the JSON path of the value, and says what is wrong with it.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"

#include <librt/loader/scene_file.h>

#include <gtest/gtest.h>

#include <string>

using namespace librt;
using librt::testing::error_of;
using librt::testing::GltfBuilder;
using librt::testing::has;
using librt::testing::joined;
using librt::testing::ScratchDir;
using nlohmann::json;
namespace fs = std::filesystem;
namespace lt = librt::testing;

namespace {

/// Writes `b` as `name` in `dir`; returns its path.
fs::path write(const ScratchDir& dir, const std::string& name, const GltfBuilder& b) {
    const fs::path p = dir.path() / name;
    lt::write_file(p, name.ends_with(".glb") ? b.glb() : b.gltf());
    return p;
}

/// The error load_scene_file gives for `b`; checks it is "file: part...".
std::string scene_error(const std::string& name, const GltfBuilder& b, const std::string& part) {
    ScratchDir dir;
    const fs::path p = write(dir, name, b);
    const std::string msg = error_of([&] { (void)load_scene_file(p); });
    EXPECT_TRUE(has(msg, p.string() + ": " + part))
        << "expected '" << p.string() << ": " << part << "' in: " << msg;
    return msg;
}

/// The warnings load_scene_file gives for `b` (which must load); checks one is
/// "file: part...".
std::string scene_warnings(const std::string& name, const GltfBuilder& b, const std::string& part) {
    ScratchDir dir;
    const fs::path p = write(dir, name, b);
    const std::string all = joined(load_scene_file(p).warnings);
    EXPECT_TRUE(has(all, p.string() + ": " + part))
        << "expected '" << p.string() << ": " << part << "' in:\n"
        << all;
    return all;
}

/// One triangle with a perspective camera 0 placed by node 1.
GltfBuilder with_camera(const json& perspective) {
    GltfBuilder b = lt::one_triangle();
    b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", perspective}}};
    b.doc["nodes"].push_back({{"camera", 0}, {"translation", {0, 0, 3}}, {"name", "eye"}});
    b.doc["scenes"][0]["nodes"] = {0, 1};
    return b;
}

}  // namespace

TEST(BadGltfScene, AHugePositionNamesItsAccessor) {
    GltfBuilder b;
    const std::vector<float> p = {0, 0, 0, 1e30f, 0, 0, 0, 1, 0};
    const int pos = b.add_accessor(p, lt::kFloat, "VEC3", 3);
    b.doc["accessors"][pos]["min"] = {0, 0, 0};
    b.doc["accessors"][pos]["max"] = {1e30, 1, 0};
    b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}}};
    b.doc["nodes"] = {{{"mesh", 0}}, {{"mesh", 0}, {"translation", {2, 0, 0}}}};
    b.doc["scenes"] = {{{"nodes", {0, 1}}}};
    const std::string msg =
        scene_error("huge.glb", b, "meshes[0].primitives[0].attributes.POSITION: vertex 1");
    EXPECT_TRUE(has(msg, "coordinate 1e+30 exceeds")) << msg;
}

TEST(BadGltfScene, ANonAffineMatrixNamesTheNode) {
    GltfBuilder b = lt::one_triangle();
    b.doc["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 2};
    scene_error("skew.gltf", b, "nodes[0].matrix: not affine (last row 0 0 1 2");
}

TEST(BadGltfScene, CameraValuesBeyondFloatNameTheCamera) {
    // 1e-300 is a positive double that rounds to a float 0; 1e300 rounds to infinity.
    scene_error("fov.gltf", with_camera({{"yfov", 1e-300}, {"znear", 0.1}}),
                "cameras[0].perspective.yfov: 1e-300: must be > 0 (it rounds to 0");
    scene_error("near.gltf", with_camera({{"yfov", 0.7}, {"znear", 1e300}}),
                "cameras[0].perspective.znear: 1e+300: beyond the float range");
    scene_error("aspect.gltf", with_camera({{"yfov", 0.7}, {"znear", 0.1}, {"aspectRatio", 1e300}}),
                "cameras[0].perspective.aspectRatio: 1e+300: beyond the float range");
}

TEST(BadGltfScene, ACameraNodeScaledToZeroIsRefusedNamingIt) {
    GltfBuilder b = with_camera({{"yfov", 0.7}, {"znear", 0.1}});
    b.doc["nodes"][1]["scale"] = {0, 0, 0};
    scene_error("flat.gltf", b,
                "cameras[0] 'eye' placed by nodes[1]: its world transform is singular "
                "(determinant 0");
}

TEST(BadGltfScene, MeshNodesScaledToZeroOrTooFarAreWarnedAboutNotPlaced) {
    GltfBuilder b = lt::one_triangle();
    b.doc["nodes"] = {{{"mesh", 0}},
                      {{"mesh", 0}, {"scale", {0, 0, 0}}, {"name", "hidden"}},
                      {{"mesh", 0}, {"scale", {1e30, 1e30, 1e30}}, {"name", "huge"}}};
    b.doc["scenes"] = {{{"nodes", {0, 1, 2}}}};
    const std::string all = scene_warnings(
        "scaled.gltf", b,
        "nodes[1] 'hidden': its world transform is singular (determinant 0: scaled to zero");
    // Not called "zero scale": its determinant, 1e90, overflows float.
    EXPECT_TRUE(has(all,
                    ": nodes[2] 'huge': its world transform's determinant 1e+90 overflows "
                    "float (a scale too large to invert): meshes[0] not placed"))
        << all;
}

TEST(BadGltfScene, ALightNodeScaledToZeroIsWarnedAboutNamingIt) {
    GltfBuilder b = lt::one_triangle();
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "spot"}, {"name", "lamp"}, {"spot", json::object()}}};
    b.doc["nodes"].push_back(
        {{"scale", {0, 0, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.doc["scenes"][0]["nodes"] = {0, 1};
    scene_warnings("lamp.gltf", b,
                   "extensions.KHR_lights_punctual.lights[0] 'lamp' placed by nodes[1]: its "
                   "world transform is singular");
}

TEST(BadGltfScene, MaterialValuesBeyondFloatNameTheMaterial) {
    auto with_material = [](const json& material) {
        GltfBuilder b = lt::one_triangle();
        b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_ior"};
        b.doc["materials"] = {{{"name", "plain"}}, material};
        b.doc["meshes"][0]["primitives"][0]["material"] = 1;
        return b;
    };
    scene_error(
        "glow.gltf",
        with_material(
            {{"emissiveFactor", {1, 1, 1}},
             {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1e300}}}}}}),
        "materials[1].extensions.KHR_materials_emissive_strength.emissiveStrength: "
        "1e+300: beyond the float range");
    scene_error("ior.gltf",
                with_material({{"extensions", {{"KHR_materials_ior", {{"ior", 1e300}}}}}}),
                "materials[1].extensions.KHR_materials_ior.ior: 1e+300: beyond the float range");
    // A factor beyond [0, 1] is clamped, as before; the warning shows the value readably.
    scene_warnings("rough.gltf",
                   with_material({{"pbrMetallicRoughness", {{"roughnessFactor", 1e300}}}}),
                   "materials[1].pbrMetallicRoughness.roughnessFactor: 1e+300 outside [0, 1]; "
                   "clamped");
}
