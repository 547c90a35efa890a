// A glTF file's orthographic camera (cameras[i].orthographic: xmag, ymag, znear, zfar),
// written here by hand, is the camera load_scene_file renders through: two emissive
// rectangles at different depths light exactly the pixels whose centres glTF's projection
// puts inside them (no perspective: depth changes nothing), the image aspect follows
// xmag / ymag, and bad values are errors naming the file and JSON path.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/integrator/integrators.h>
#include <librt/loader/scene_file.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

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

/// An axis-aligned rectangle [x0, x1] x [y0, y1] in the plane z.
struct Rect {
    float x0, x1, y0, y1, z;
};

// Edges chosen off the pixel centres of the 64 x 32 image below (centres at
// -2 + (j + 0.5) / 16 across, 1 - (i + 0.5) / 16 down).
const Rect kNear{0.3f, 1.3f, 0.1f, 0.7f, 0.0f};
const Rect kFar{-1.7f, -0.45f, -0.8f, 0.15f, -20.0f};

/// Two emissive rectangles (one mesh each) and an orthographic camera at (0, 0, 5) looking
/// down -z with the given xmag and ymag.
GltfBuilder rectangles_and_camera(double xmag, double ymag) {
    GltfBuilder b;
    json meshes = json::array(), nodes = json::array();
    for (const Rect& r : {kNear, kFar}) {
        const std::vector<float> p = {r.x0, r.y0, r.z, r.x1, r.y0, r.z,
                                      r.x1, r.y1, r.z, r.x0, r.y1, r.z};
        const int pos = b.add_accessor(p, lt::kFloat, "VEC3", 4);
        b.doc["accessors"][pos]["min"] = {r.x0, r.y0, r.z};
        b.doc["accessors"][pos]["max"] = {r.x1, r.y1, r.z};
        const int idx =
            b.add_accessor(std::vector<std::uint16_t>{0, 1, 2, 0, 2, 3}, lt::kU16, "SCALAR", 6);
        meshes.push_back(
            {{"primitives",
              {{{"attributes", {{"POSITION", pos}}}, {"indices", idx}, {"material", 0}}}}});
        nodes.push_back({{"mesh", int(meshes.size()) - 1}});
    }
    b.doc["meshes"] = meshes;
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}},
                           {"emissiveFactor", {1, 1, 1}}}};
    b.doc["cameras"] = {
        {{"type", "orthographic"},
         {"name", "top"},
         {"orthographic", {{"xmag", xmag}, {"ymag", ymag}, {"znear", 0.5}, {"zfar", 100}}}}};
    nodes.push_back({{"camera", 0}, {"translation", {0, 0, 5}}});
    b.doc["nodes"] = nodes;
    b.doc["scenes"] = {{{"nodes", {0, 1, 2}}}};
    b.doc["scene"] = 0;
    return b;
}

std::string load_error(const fs::path& p) {
    try {
        (void)load_scene_file(p);
    } catch (const Error& e) {
        return e.what();
    }
    return "loaded";
}

}  // namespace

TEST(GltfOrthographic, RendersThroughTheFilesOrthographicCamera) {
    ScratchDir dir;
    const fs::path p = dir.path() / "ortho.glb";
    lt::write_file(p, rectangles_and_camera(2.0, 1.0).glb());
    SceneFileOptions options;
    options.default_long_side = 64;  // the size follows xmag / ymag = 2: 64 x 32
    // The emissive rectangles alone, on black: no studio sky behind them.
    options.default_lighting = false;
    LoadedScene loaded = load_scene_file(p, options);
    EXPECT_EQ(loaded.camera_name, "top");  // the first camera, although orthographic
    ASSERT_EQ(loaded.camera.projection, Projection::Orthographic);
    ASSERT_EQ(loaded.camera.width, 64);
    ASSERT_EQ(loaded.camera.height, 32);
    EXPECT_FLOAT_EQ(loaded.camera.near_clip, 0.5f);
    EXPECT_FLOAT_EQ(loaded.camera.far_clip, 100.0f);
    EXPECT_TRUE(lt::joined(loaded.warnings).empty()) << lt::joined(loaded.warnings);
    loaded.scene.commit();

    PathTracerSettings pts;
    pts.max_depth = 1;
    PathTracer integrator(pts);
    RenderSettings settings;
    settings.samples_per_pixel = 1;
    const Image image = render(loaded.scene, Camera(loaded.camera), integrator, settings);
    int lit_near = 0, lit_far = 0;
    for (int i = 0; i < 32; ++i) {
        for (int j = 0; j < 64; ++j) {
            // glTF's projection: x = xmag * ndc_x, y = ymag * ndc_y at the pixel centre.
            const float x = 2.0f * ((float(j) + 0.5f) / 32.0f - 1.0f);
            const float y = 1.0f * (1.0f - (float(i) + 0.5f) / 16.0f);
            const auto inside = [&](const Rect& r) {
                return x > r.x0 && x < r.x1 && y > r.y0 && y < r.y1;
            };
            const bool want = inside(kNear) || inside(kFar);
            lit_near += inside(kNear) ? 1 : 0;
            lit_far += inside(kFar) ? 1 : 0;
            const glm::vec3 px = image.at(j, i);
            EXPECT_EQ(px.x > 0.5f, want) << "pixel " << j << "," << i << " = " << px.x;
            if (!want) {
                EXPECT_EQ(px, glm::vec3(0.0f)) << "pixel " << j << "," << i;
            }
        }
    }
    // 16 x 9 and 20 x 15 pixels: the far rectangle is not shrunk by its distance.
    EXPECT_EQ(lit_near, 16 * 9);
    EXPECT_EQ(lit_far, 20 * 15);
}

TEST(GltfOrthographic, ASizeOfAnotherAspectStretchesWithAWarning) {
    ScratchDir dir;
    const fs::path p = dir.path() / "ortho.gltf";
    lt::write_file(p, rectangles_and_camera(2.0, 1.0).gltf());
    SceneFileOptions options;
    options.width = options.height = 32;
    const LoadedScene loaded = load_scene_file(p, options);
    EXPECT_FLOAT_EQ(loaded.camera.xmag, 2.0f);
    EXPECT_FLOAT_EQ(loaded.camera.ymag, 1.0f);
    EXPECT_TRUE(lt::has(lt::joined(loaded.warnings), "the image is stretched"))
        << lt::joined(loaded.warnings);
}

TEST(GltfOrthographic, BadMagnificationsAndClipsNameTheJsonPath) {
    ScratchDir dir;
    const auto error_of = [&](double xmag, double ymag, double znear, double zfar) {
        GltfBuilder b = rectangles_and_camera(xmag, ymag);
        b.doc["cameras"][0]["orthographic"]["znear"] = znear;
        b.doc["cameras"][0]["orthographic"]["zfar"] = zfar;
        const fs::path p = dir.path() / "bad.gltf";
        lt::write_file(p, b.gltf());
        return std::pair{p.string(), load_error(p)};
    };
    for (const auto& [args, part] : std::vector<std::pair<std::vector<double>, std::string>>{
             {{0.0, 1.0, 0.0, 10.0}, "cameras[0].orthographic.xmag: 0: must be finite and not 0"},
             {{1.0, 0.0, 0.0, 10.0}, "cameras[0].orthographic.ymag: 0:"},
             {{1e300, 1.0, 0.0, 10.0}, "cameras[0].orthographic.xmag"},
             {{1.0, 1.0, -1.0, 10.0}, "cameras[0].orthographic: znear = -1, zfar = 10"},
             {{1.0, 1.0, 5.0, 5.0}, "needs 0 <= znear < zfar"}}) {
        const auto [file, message] = error_of(args[0], args[1], args[2], args[3]);
        EXPECT_TRUE(lt::has(message, file)) << message;
        EXPECT_TRUE(lt::has(message, part)) << message;
    }
    // A negative magnitude is allowed by the spec (SHOULD NOT): a warning, its magnitude used.
    GltfBuilder b = rectangles_and_camera(-2.0, 1.0);
    const fs::path p = dir.path() / "negative.gltf";
    lt::write_file(p, b.gltf());
    const LoadedScene loaded = load_scene_file(p);
    EXPECT_FLOAT_EQ(loaded.camera.xmag, 2.0f);
    EXPECT_TRUE(lt::has(lt::joined(loaded.warnings), "cameras[0].orthographic.xmag: -2"))
        << lt::joined(loaded.warnings);
}
