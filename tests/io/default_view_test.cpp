// What a file without a camera or a light gets (issue 38 item 5, issue 42 item 1): the
// framing camera (film/framing.h) sees the whole model and fills the frame, checked with
// librt's own Camera; the studio lighting (scene/default_lighting.h) is decided by punctual
// lights alone, so a camera-less, light-less glTF box renders lit inside the frame and an
// emissive-only file is lit too, unless the option turns it off; an environment turned by
// rotation_about_up moves its one bright region by the angle; .exr environments load.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/film/framing.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrators.h>
#include <librt/io/exr.h>
#include <librt/io/hdr_image.h>
#include <librt/light/environment_light.h>
#include <librt/loader/scene_file.h>
#include <librt/render/renderer.h>
#include <librt/scene/default_lighting.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::GltfBuilder;
using librt::testing::ScratchDir;
namespace lt = librt::testing;

namespace {

/// The pixels whose camera ray (through the pixel's centre) hits the scene: their bounding
/// rectangle, in pixels, inclusive; x0 > x1 when none.
struct Covered {
    int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
    int count = 0;
};

Covered covered(const Scene& scene, const CameraSettings& settings) {
    const Camera camera(settings);  // no pixel jitter: the ray through the pixel's centre
    Covered c;
    for (int y = 0; y < camera.height(); ++y) {
        for (int x = 0; x < camera.width(); ++x) {
            Sampler sampler(std::uint32_t(x), std::uint32_t(y), 0, 1);
            Hit hit;
            if (!scene.intersect(camera.generate_ray(x, y, sampler), hit)) continue;
            c.x0 = std::min(c.x0, x);
            c.x1 = std::max(c.x1, x);
            c.y0 = std::min(c.y0, y);
            c.y1 = std::max(c.y1, y);
            ++c.count;
        }
    }
    return c;
}

/// `c` lies inside the image, off every edge (the framing's 5 % margin leaves at least a
/// pixel free at these sizes), and spans at least `fill` of the width or of the height.
void expect_inside_and_filling(const Covered& c, int width, int height, double fill,
                               const std::string& what) {
    ASSERT_GT(c.count, 0) << what;
    EXPECT_GT(c.x0, 0) << what;
    EXPECT_GT(c.y0, 0) << what;
    EXPECT_LT(c.x1, width - 1) << what;
    EXPECT_LT(c.y1, height - 1) << what;
    const double fx = double(c.x1 - c.x0 + 1) / width, fy = double(c.y1 - c.y0 + 1) / height;
    EXPECT_GE(std::max(fx, fy), fill) << what << ": spans " << fx << " x " << fy;
}

/// A box as a glTF mesh (8 corners, 12 triangles, positions and indices only, no material:
/// glTF's default, white-ish diffuse), placed by node 0 of scene 0; no camera, no light.
GltfBuilder box_gltf(const glm::vec3& lo, const glm::vec3& hi) {
    GltfBuilder b;
    std::vector<float> p;
    for (int i = 0; i < 8; ++i) {
        p.push_back((i & 1) != 0 ? hi.x : lo.x);
        p.push_back((i & 2) != 0 ? hi.y : lo.y);
        p.push_back((i & 4) != 0 ? hi.z : lo.z);
    }
    // Each face as two triangles, wound outward (counter-clockwise seen from outside).
    const std::vector<std::uint16_t> idx = {0, 2, 3, 0, 3, 1,   // -z
                                            4, 5, 7, 4, 7, 6,   // +z
                                            0, 4, 6, 0, 6, 2,   // -x
                                            1, 3, 7, 1, 7, 5,   // +x
                                            0, 1, 5, 0, 5, 4,   // -y
                                            2, 6, 7, 2, 7, 3};  // +y
    const int pos = b.add_accessor(p, lt::kFloat, "VEC3", 8);
    b.doc["accessors"][pos]["min"] = {lo.x, lo.y, lo.z};
    b.doc["accessors"][pos]["max"] = {hi.x, hi.y, hi.z};
    const int ind = b.add_accessor(idx, lt::kU16, "SCALAR", idx.size());
    b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", ind}}}}}};
    b.doc["nodes"] = {{{"mesh", 0}}};
    b.doc["scenes"] = {{{"nodes", {0}}}};
    b.doc["scene"] = 0;
    return b;
}

/// The scene's image through its camera: `spp` samples, 2 threads, the path tracer.
Image render_loaded(LoadedScene& loaded, int spp) {
    loaded.scene.commit();
    const Camera camera(loaded.camera);
    PathTracer pt;
    RenderSettings rs;
    rs.samples_per_pixel = spp;
    rs.threads = 2;
    rs.seed = 7;
    return render(loaded.scene, camera, pt, rs);
}

/// Mean of the image's channels over the pixels whose rays hit the scene.
double mean_on_model(const Scene& scene, const CameraSettings& settings, const Image& image) {
    const Camera camera(settings);
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < camera.height(); ++y) {
        for (int x = 0; x < camera.width(); ++x) {
            Sampler sampler(std::uint32_t(x), std::uint32_t(y), 0, 1);
            Hit hit;
            if (!scene.intersect(camera.generate_ray(x, y, sampler), hit)) continue;
            const glm::vec3 v = image.at(x, y);
            sum += (double(v.x) + double(v.y) + double(v.z)) / 3.0;
            ++n;
        }
    }
    return n > 0 ? sum / n : 0.0;
}

}  // namespace

// Boxes of every shape (a cube, a wide slab, a tall pole, one far from the origin), image
// shapes (square, wide, tall) and view directions (the default, the side, nearly straight
// down): every corner inside the frame, the box spanning >= 0.85 of it in one axis (the
// margin is 5 % a side: the limiting axis spans about 0.9).
TEST(Framing, TheWholeBoxIsInsideAndFillsTheFrame) {
    const std::vector<std::pair<glm::vec3, glm::vec3>> boxes = {
        {{-1, -1, -1}, {1, 1, 1}},
        {{-4, -0.2f, -1}, {4, 0.2f, 1}},
        {{-0.1f, 0, -0.1f}, {0.1f, 6, 0.1f}},
        {{1000, 50, -300}, {1003, 52, -299}},
    };
    const std::vector<std::pair<int, int>> sizes = {{120, 120}, {192, 108}, {90, 160}};
    const std::vector<glm::vec3> views = {default_view_direction(), {1, 0.2f, 0}, {0.1f, 1, 0.05f}};
    for (const auto& [lo, hi] : boxes) {
        Scene scene;
        const std::uint32_t m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
        (void)scene.add_mesh(make_box(lo, hi), m);
        scene.commit();
        for (const auto& [w, h] : sizes) {
            for (const glm::vec3& view : views) {
                FramingOptions o;
                o.view_from = view;
                const CameraSettings c = frame_bounds(BBox(lo, hi), w, h, o);
                const std::string what = "box " + std::to_string(lo.x) + ".." +
                                         std::to_string(hi.x) + ", " + std::to_string(w) + "x" +
                                         std::to_string(h) + ", view " + std::to_string(view.x) +
                                         "," + std::to_string(view.y);
                expect_inside_and_filling(covered(scene, c), w, h, 0.85, what);
            }
        }
    }
}

TEST(Framing, TheDefaultDirectionIsTheFrontFifteenDegreesAbove) {
    const glm::vec3 d = default_view_direction();
    EXPECT_NEAR(glm::length(d), 1.0f, 1e-6f);
    EXPECT_NEAR(d.x, 0.0f, 1e-7f);
    EXPECT_NEAR(std::asin(d.y), 15.0f * 3.14159265f / 180.0f, 1e-6f);
    EXPECT_GT(d.z, 0.0f);
    // default_camera is that framing: the camera in front of a cube (+z) and above it.
    const CameraSettings c = default_camera(BBox({-1, -1, -1}, {1, 1, 1}), 64, 48);
    EXPECT_GT(c.position.z, 1.0f);
    EXPECT_GT(c.position.y, 0.0f);
    EXPECT_NEAR(c.position.x, 0.0f, 1e-4f);
}

TEST(Framing, BadInputIsAnErrorNamingIt) {
    const BBox box({0, 0, 0}, {1, 1, 1});
    const auto message = [](auto f) {
        try {
            f();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    EXPECT_NE(message([&] { (void)frame_bounds(BBox(), 10, 10); }).find("bounds empty"),
              std::string::npos);
    EXPECT_NE(message([&] { (void)frame_bounds(box, 0, 10); }).find("size = 0x10"),
              std::string::npos);
    FramingOptions o;
    o.vertical_fov_degrees = 180.0f;
    EXPECT_NE(message([&] { (void)frame_bounds(box, 10, 10, o); }).find("vertical_fov_degrees"),
              std::string::npos);
    o = {};
    o.margin = 0.5f;
    EXPECT_NE(message([&] { (void)frame_bounds(box, 10, 10, o); }).find("margin"),
              std::string::npos);
    o = {};
    o.view_from = glm::vec3(0.0f);
    EXPECT_NE(message([&] { (void)frame_bounds(box, 10, 10, o); }).find("view_from"),
              std::string::npos);
}

// The file as a new user brings it: a box, no camera, no light. The loader frames it and
// lights it; the render is finite, the box is inside the frame and spans most of it, and
// its pixels are lit (the studio lighting gives a white-ish diffuse box about 0.3-0.8).
TEST(DefaultLighting, ACameraLessLightLessGltfRendersLitInsideTheFrame) {
    ScratchDir dir;
    const auto p = dir.path() / "box.glb";
    lt::write_file(p, box_gltf({-2, 0, -1}, {2, 1.5f, 1}).glb());
    SceneFileOptions options;
    options.width = 96;
    options.height = 72;
    LoadedScene loaded = load_scene_file(p, options);
    EXPECT_EQ(loaded.camera_name, "default");
    EXPECT_FALSE(loaded.lighting_note.empty());
    ASSERT_EQ(loaded.scene.lights().size(), 2u);  // the sky and the key light
    const Image image = render_loaded(loaded, 16);
    for (const glm::vec3& v : image.pixels)
        ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z));
    expect_inside_and_filling(covered(loaded.scene, loaded.camera), 96, 72, 0.85, "box.glb");
    EXPECT_GT(mean_on_model(loaded.scene, loaded.camera, image), 0.2);
}

// Emission does not decide: a file whose only light is an emissive surface gets the studio
// lighting too (its diffuse box lit well above what the small emitter gives it), and with
// default_lighting off it keeps its own light alone, as before (no light added, the box
// only lit by the emitter).
TEST(DefaultLighting, AnEmissiveOnlyFileIsLitUnlessTurnedOff) {
    GltfBuilder b = box_gltf({-1, -1, -1}, {1, 1, 1});
    // A second primitive, a small emissive triangle beside the box.
    const std::vector<float> tri = {1.5f, -1, 0, 1.7f, -1, 0, 1.5f, -0.8f, 0};
    const int pos = b.add_accessor(tri, lt::kFloat, "VEC3", 3);
    b.doc["accessors"][pos]["min"] = {1.5, -1, 0};
    b.doc["accessors"][pos]["max"] = {1.7, -0.8, 0};
    b.doc["materials"] = {{{"emissiveFactor", {1, 1, 1}}}};
    b.doc["meshes"][0]["primitives"].push_back(
        {{"attributes", {{"POSITION", pos}}}, {"material", 0}});
    ScratchDir dir;
    const auto p = dir.path() / "label.gltf";
    lt::write_file(p, b.gltf());
    SceneFileOptions options;
    options.width = 48;
    options.height = 36;
    LoadedScene lit = load_scene_file(p, options);
    EXPECT_FALSE(lit.lighting_note.empty());
    EXPECT_EQ(lit.scene.lights().size(), 2u);  // before commit: the emitter is not yet a light
    options.default_lighting = false;
    LoadedScene own = load_scene_file(p, options);
    EXPECT_TRUE(own.lighting_note.empty());
    EXPECT_EQ(own.scene.lights().size(), 0u);
    const Image with = render_loaded(lit, 8);
    const Image without = render_loaded(own, 8);
    const double a = mean_on_model(lit.scene, lit.camera, with);
    const double b0 = mean_on_model(own.scene, own.camera, without);
    EXPECT_GT(a, 0.2);
    EXPECT_GT(a, 3.0 * b0) << "studio " << a << ", own light " << b0;
}

// A file with a punctual light keeps its light alone; "auto" frames it even though it has a
// camera.
TEST(DefaultLighting, APunctualLightKeepsTheFileAloneAndAutoFramesIt) {
    GltfBuilder b = box_gltf({-1, -1, -1}, {1, 1, 1});
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"intensity", 683}}};
    b.doc["cameras"] = {
        {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    b.doc["nodes"].push_back({{"camera", 0}, {"translation", {0, 0, 10}}});
    b.doc["nodes"].push_back(
        {{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}, {"translation", {0, 5, 0}}});
    b.doc["scenes"][0]["nodes"] = {0, 1, 2};
    ScratchDir dir;
    const auto p = dir.path() / "lit.gltf";
    lt::write_file(p, b.gltf());
    SceneFileOptions options;
    options.width = options.height = 32;
    LoadedScene own = load_scene_file(p, options);
    EXPECT_TRUE(own.lighting_note.empty());
    EXPECT_EQ(own.scene.lights().size(), 1u);
    EXPECT_NE(own.camera_name, "default");
    options.camera = "auto";
    LoadedScene framed = load_scene_file(p, options);
    EXPECT_EQ(framed.camera_name, "default");
    const CameraSettings want = default_camera(framed.bounds, 32, 32);
    EXPECT_EQ(framed.camera.position, want.position);
    EXPECT_EQ(framed.camera.look_at, want.look_at);
}

// The key light follows the camera: above, left of and behind it, whichever way it looks.
TEST(DefaultLighting, TheKeyLightIsAboveLeftBehindTheCamera) {
    for (const glm::vec3& look :
         {glm::vec3(0, 0, -1), glm::vec3(1, 0, 0), glm::vec3(-1, -0.5f, 1)}) {
        CameraSettings c;
        c.position = {3, 2, 1};
        c.look_at = c.position + look;
        const DirectionalLight key = studio_key_light(c);
        const glm::vec3 forward = glm::normalize(look);
        const glm::vec3 right = glm::normalize(glm::cross(forward, c.up));
        const glm::vec3 up = glm::cross(right, forward);
        const glm::vec3 l = glm::normalize(key.to_light);
        EXPECT_LT(glm::dot(l, right), -0.3f);
        EXPECT_GT(glm::dot(l, up), 0.6f);
        EXPECT_LT(glm::dot(l, forward), -0.4f);
    }
    // The sky: grey, brighter above than below, continuous at the horizon: the rows either
    // side of it are centred half a row (pi / (2 h) rad) above and below, where the curves
    // give 0.35 + 0.25 sin(e) and 0.12 + 0.23 exp(-e / 0.15), within 0.003 of each other for
    // rows of a tenth of a degree (no visible step).
    const EnvironmentImage sky = studio_sky();
    ASSERT_EQ(sky.pixels.size(), std::size_t(sky.width * sky.height));
    const glm::vec3 top = sky.pixels.front(), bottom = sky.pixels.back();
    EXPECT_EQ(top.x, top.y);
    EXPECT_EQ(top.y, top.z);
    EXPECT_GT(top.x, 2.0f * bottom.x);
    const float above = sky.pixels[std::size_t(sky.height / 2 - 1) * std::size_t(sky.width)].x;
    const float below = sky.pixels[std::size_t(sky.height / 2) * std::size_t(sky.width)].x;
    const double e = 0.5 * 3.14159265358979323846 / sky.height;
    EXPECT_NEAR(above, 0.35 + 0.25 * std::sin(e), 1e-5);
    EXPECT_NEAR(below, 0.12 + 0.23 * std::exp(-e / 0.15), 1e-5);
    EXPECT_LT(above - below, 0.003f);
    EXPECT_LE(3.14159265358979323846 / sky.height, 0.1 * 3.14159265358979323846 / 180.0);
}

// An environment whose only bright pixels are one column at the equator, 5 degrees wide
// (column 3: azimuths [15, 20) degrees), turned by a: seen along azimuth psi (direction
// (cos psi, 0, -sin psi), EnvironmentLight's phi) it is bright exactly when psi - a falls in
// that column. Checked at every column centre, for turns that are multiples of 5 degrees.
TEST(EnvironmentRotation, TheBrightRegionMovesByTheAngle) {
    EnvironmentImage image;
    image.width = 72;
    image.height = 2;
    image.pixels.assign(144, glm::vec3(0.0f));
    image.pixels[3] = image.pixels[72 + 3] = glm::vec3(10.0f);
    for (const float a : {0.0f, 90.0f, -45.0f, 200.0f, 360.0f}) {
        const EnvironmentLight light = EnvironmentLight::from_image(image, rotation_about_up(a));
        for (int j = 0; j < 72; ++j) {
            const double psi = (j + 0.5) * 5.0 * 3.14159265358979323846 / 180.0;
            const glm::vec3 dir(float(std::cos(psi)), 0.0f, float(-std::sin(psi)));
            const bool bright = escaped_radiance(light, dir).x > 1.0f;
            const int want = ((3 + int(a) / 5) % 72 + 72) % 72;
            EXPECT_EQ(bright, j == want) << "turn " << a << ", column " << j;
        }
    }
}

// An .exr environment loads with its pixels as written; a negative pixel and an unknown
// extension are errors naming the file.
TEST(EnvironmentFile, ExrLoadsAndBadOnesNameTheFile) {
    ScratchDir dir;
    ImageLayers layers;
    layers.beauty = Image(8, 4);
    for (int i = 0; i < 32; ++i)
        layers.beauty.pixels[std::size_t(i)] = glm::vec3(0.25f * float(i), 1.0f, 0.5f);
    const auto good = dir.path() / "sky.exr";
    (void)write_exr(good, layers);
    const EnvironmentImage env = load_environment_image(good);
    ASSERT_EQ(env.width, 8);
    ASSERT_EQ(env.height, 4);
    for (int i = 0; i < 32; ++i)
        EXPECT_EQ(env.pixels[std::size_t(i)], layers.beauty.pixels[std::size_t(i)]);
    (void)EnvironmentLight::from_image(env);  // a valid environment

    layers.beauty.pixels[9] = glm::vec3(-1.0f, 0.0f, 0.0f);
    const auto negative = dir.path() / "negative.EXR";
    (void)write_exr(negative, layers);
    try {
        (void)load_environment_image(negative);
        ADD_FAILURE() << "a negative pixel loaded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("negative.EXR: pixel (1, 1)"), std::string::npos)
            << e.what();
    }
    try {
        (void)load_environment_image(dir.path() / "sky.png");
        ADD_FAILURE() << "a .png loaded as an environment";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("sky.png: unknown environment format"),
                  std::string::npos)
            << e.what();
    }
}

// --orbit (issue 42 item 6): the framing camera turned about +y. At 90 degrees it stands on
// the +x side of the box's centre, at the default elevation (15 degrees), and still sees the
// whole box filling the frame; the key light of the default lighting follows it.
TEST(ViewOptions, AnOrbitFramesTheBoxFromTheTurnedDirection) {
    ScratchDir dir;
    const auto p = dir.path() / "box.glb";
    lt::write_file(p, box_gltf({-2, 0, -1}, {2, 1.5f, 1}).glb());
    SceneFileOptions options;
    options.width = 96;
    options.height = 64;
    options.view.orbit_degrees = 90.0f;
    LoadedScene loaded = load_scene_file(p, options);
    const glm::vec3 centre(0.0f, 0.75f, 0.0f);
    const glm::vec3 back = glm::normalize(loaded.camera.position - loaded.camera.look_at);
    EXPECT_NEAR(back.x, std::cos(glm::radians(15.0f)), 1e-4f);
    EXPECT_NEAR(back.y, std::sin(glm::radians(15.0f)), 1e-4f);
    EXPECT_NEAR(back.z, 0.0f, 1e-4f);
    EXPECT_GT(loaded.camera.position.x, centre.x + 2.0f);  // outside the box, on its +x side
    loaded.scene.commit();
    expect_inside_and_filling(covered(loaded.scene, loaded.camera), 96, 64, 0.85, "orbit 90");
    // The key light comes from behind the new camera: from +x, not from +z.
    const DirectionalLight key = studio_key_light(loaded.camera);
    EXPECT_GT(key.to_light.x, 0.0f);
}

// --look-from alone aims at the bounds' centre; with --look-at, at that point; straight down,
// the image's up becomes -z. A file's camera keeps its projection and gets the new field of
// view; the framing camera with a new field of view alone is reframed (same direction, still
// filling the frame) rather than zoomed.
TEST(ViewOptions, LookFromLookAtAndFieldOfView) {
    ScratchDir dir;
    const auto p = dir.path() / "box.glb";
    lt::write_file(p, box_gltf({-2, 0, -1}, {2, 1.5f, 1}).glb());
    SceneFileOptions options;
    options.width = 64;
    options.height = 64;
    options.view.look_from = glm::vec3(0.0f, 10.0f, 10.0f);
    LoadedScene from = load_scene_file(p, options);
    EXPECT_EQ(from.camera.position, glm::vec3(0.0f, 10.0f, 10.0f));
    EXPECT_EQ(from.camera.look_at, glm::vec3(0.0f, 0.75f, 0.0f));
    EXPECT_EQ(from.camera.up, glm::vec3(0.0f, 1.0f, 0.0f));

    options.view.look_at = glm::vec3(1.0f, 0.0f, 0.0f);
    options.view.look_from = glm::vec3(1.0f, 10.0f, 0.0f);
    LoadedScene down = load_scene_file(p, options);
    EXPECT_EQ(down.camera.look_at, glm::vec3(1.0f, 0.0f, 0.0f));
    EXPECT_EQ(down.camera.up, glm::vec3(0.0f, 0.0f, -1.0f));
    down.scene.commit();
    // The centre pixel's ray goes straight down onto the box's top at x = 1.
    const Camera camera(down.camera);
    Sampler sampler(32, 32, 0, 1);
    const Ray ray = camera.generate_ray(32, 32, sampler);
    Hit hit;
    ASSERT_TRUE(down.scene.intersect(ray, hit));
    EXPECT_NEAR(ray.origin.y + hit.t * ray.direction.y, 1.5f, 1e-3f);

    SceneFileOptions fov;
    fov.width = 64;
    fov.height = 64;
    fov.view.vertical_fov_degrees = 20.0f;
    LoadedScene narrow = load_scene_file(p, fov);
    SceneFileOptions plain;
    plain.width = 64;
    plain.height = 64;
    const LoadedScene wide = load_scene_file(p, plain);
    EXPECT_FLOAT_EQ(narrow.camera.vertical_fov_degrees, 20.0f);
    // Same direction, farther away: the model still fills the frame.
    EXPECT_NEAR(glm::dot(glm::normalize(narrow.camera.position - narrow.camera.look_at),
                         glm::normalize(wide.camera.position - wide.camera.look_at)),
                1.0f, 1e-5f);
    EXPECT_GT(glm::length(narrow.camera.position - narrow.camera.look_at),
              1.5f * glm::length(wide.camera.position - wide.camera.look_at));
    narrow.scene.commit();
    expect_inside_and_filling(covered(narrow.scene, narrow.camera), 64, 64, 0.85, "fov 20");
}

TEST(ViewOptions, BadViewsAreErrorsNamingTheField) {
    ScratchDir dir;
    const auto p = dir.path() / "box.glb";
    lt::write_file(p, box_gltf({-2, 0, -1}, {2, 1.5f, 1}).glb());
    const auto message = [&](const ViewOptions& view) {
        SceneFileOptions options;
        options.view = view;
        try {
            (void)load_scene_file(p, options);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    ViewOptions same;
    same.look_from = same.look_at = glm::vec3(1.0f);
    EXPECT_NE(message(same).find("view: look_from = 1.000000,1.000000,1.000000, look_at ="),
              std::string::npos)
        << message(same);
    ViewOptions nan;
    nan.look_at = glm::vec3(0.0f, std::nanf(""), 0.0f);
    EXPECT_NE(message(nan).find("view: look_at = "), std::string::npos) << message(nan);
    ViewOptions fov;
    fov.vertical_fov_degrees = 180.0f;
    EXPECT_NE(message(fov).find("view: vertical_fov_degrees = 180"), std::string::npos)
        << message(fov);
    ViewOptions orbit;
    orbit.orbit_degrees = 400.0f;
    EXPECT_NE(message(orbit).find("view: orbit_degrees = 400"), std::string::npos)
        << message(orbit);
    orbit.orbit_degrees = 10.0f;
    orbit.look_at = glm::vec3(0.0f);
    EXPECT_NE(message(orbit).find("not with look_from or look_at"), std::string::npos)
        << message(orbit);
    // An orthographic camera has no field of view.
    CameraSettings ortho;
    ortho.projection = Projection::Orthographic;
    ViewOptions narrow;
    narrow.vertical_fov_degrees = 30.0f;
    EXPECT_THROW((void)apply_view(ortho, false, BBox{}, narrow), Error);
}
