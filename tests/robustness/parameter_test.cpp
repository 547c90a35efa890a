// Bad parameters at every public entry point: NaN, Inf, zero, negative and absurd values
// throw librt::Error naming the parameter (and its value) before any work or allocation.
// Complements the per-area tests (Camera.InvalidSettingsNameTheParameter,
// Renderer.InvalidSettingsNameTheParameter, Material.ValidationNamesParameterAndValue,
// Procedural.BadParametersNameTheParameter, ...), which cover the ordinary bad values.

#include "robustness/robustness_util.h"

#include <librt/accel/bvh_builder.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/film/camera.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>
#include <librt/io/texture_io.h>
#include <librt/material/texture.h>
#include <librt/obj/obj_materials.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::error_of;
using librt::testing::has;
using librt::testing::ScratchDir;
namespace fs = std::filesystem;

namespace {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

/// Expects `f` to throw a librt::Error whose message contains every one of `parts`.
template <class F>
void expect_error(F&& f, std::initializer_list<const char*> parts) {
    const std::string msg = error_of(f);
    for (const char* part : parts)
        EXPECT_TRUE(has(msg, part)) << "'" << part << "' not in: " << msg;
}

TriangleMesh one_triangle() {
    TriangleMesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}};
    return m;
}

}  // namespace

TEST(BadParameter, CameraNonFiniteAndAbsurdValues) {
    const auto camera = [](auto change) {
        return [change] {
            CameraSettings s;
            change(s);
            (void)Camera(s);
        };
    };
    expect_error(camera([](CameraSettings& s) { s.width = -1; }),
                 {"camera width = -1", "[1, 65536]"});
    expect_error(camera([](CameraSettings& s) { s.height = INT_MAX; }),
                 {"camera height = 2147483647"});
    expect_error(camera([](CameraSettings& s) { s.width = INT_MIN; }), {"width = -2147483648"});
    expect_error(camera([](CameraSettings& s) { s.vertical_fov_degrees = kInf; }),
                 {"vertical_fov_degrees = inf"});
    expect_error(camera([](CameraSettings& s) { s.vertical_fov_degrees = -30.0f; }),
                 {"vertical_fov_degrees = -30"});
    expect_error(camera([](CameraSettings& s) {
                     s.position = {0, kNan, 0};
                 }),
                 {"camera position = (0, nan, 0)"});
    expect_error(camera([](CameraSettings& s) {
                     s.look_at = {kInf, 0, 0};
                 }),
                 {"camera look_at = (inf, 0, 0)"});
    expect_error(camera([](CameraSettings& s) {
                     s.up = {kNan, 1, 0};
                 }),
                 {"camera up = (nan, 1, 0)"});
    // Finite but so far apart that their distance overflows float.
    expect_error(camera([](CameraSettings& s) {
                     s.position = {-3e38f, 0, 0};
                     s.look_at = {3e38f, 0, 0};
                     s.up = {0, 1, 0};
                 }),
                 {"camera look_at", "overflows float"});
    expect_error(camera([](CameraSettings& s) {
                     s.up = {0, 3e38f, 3e38f};
                 }),
                 {"camera up", "overflows float"});
    expect_error(camera([](CameraSettings& s) { s.pixel_sigma = kInf; }), {"pixel_sigma = inf"});
    expect_error(camera([](CameraSettings& s) { s.lens_sigma = kNan; }), {"lens_sigma = nan"});
    expect_error(camera([](CameraSettings& s) { s.lens_radius = -1.0f; }), {"lens_radius = -1"});
    expect_error(camera([](CameraSettings& s) { s.focal_distance = kNan; }),
                 {"focal_distance = nan"});
    expect_error(camera([](CameraSettings& s) { s.focal_distance = -kInf; }),
                 {"focal_distance = -inf"});
}

TEST(BadParameter, RenderSettingsAndFilmSize) {
    Scene scene;
    scene.commit();
    CameraSettings cs;
    cs.width = cs.height = 4;
    const Camera camera(cs);
    PathTracer integrator(PathTracerSettings{5, false});
    const auto render_with = [&](auto change) {
        return [&, change] {
            RenderSettings s;
            s.progress = nullptr;
            change(s);
            (void)render(scene, camera, integrator, s);
        };
    };
    expect_error(render_with([](RenderSettings& s) { s.samples_per_pixel = -7; }),
                 {"samples_per_pixel = -7"});
    expect_error(render_with([](RenderSettings& s) { s.samples_per_pixel = INT_MAX; }),
                 {"samples_per_pixel = 2147483647", "[1, 1048576]"});
    expect_error(render_with([](RenderSettings& s) { s.threads = INT_MIN; }),
                 {"threads = -2147483648"});
    expect_error(render_with([](RenderSettings& s) { s.tile_size = -1; }), {"tile_size = -1"});
    // A tile larger than the image is the whole image (no overflow in the tile arithmetic).
    RenderSettings huge_tile;
    huge_tile.progress = nullptr;
    huge_tile.tile_size = INT_MAX;
    RenderStats stats;
    const Image image = render(scene, camera, integrator, huge_tile, &stats);
    EXPECT_EQ(stats.samples, 16u);
    EXPECT_EQ(image.pixels.size(), 16u);

    // A film that cannot fit in memory is refused before allocating: by the size limit
    // (the message names it); allocated first, it would end in std::bad_alloc, or render.
    for (const auto& [w, h] :
         {std::pair{65536, 65536}, std::pair{65536, 20000}, std::pair{30000, 30000}}) {
        CameraSettings big;
        big.width = w;
        big.height = h;
        const std::string msg =
            error_of([&] { (void)render(scene, Camera(big), integrator, RenderSettings{}); });
        EXPECT_TRUE(has(msg, std::to_string(w) + " x " + std::to_string(h))) << msg;
        EXPECT_TRUE(has(msg, "4 GiB")) << msg;
    }
    expect_error([] { (void)Image(-1, 5); }, {"image size -1 x 5"});
    expect_error([] { (void)Image(INT_MAX, INT_MAX); }, {"image size 2147483647 x 2147483647"});
}

TEST(BadParameter, BounceCounts) {
    for (const int depth : {-1, 1001, INT_MAX, INT_MIN}) {
        const std::string value = "max_depth = " + std::to_string(depth);
        expect_error(
            [&] {
                (void)PathTracer(PathTracerSettings{depth, false});
            },
            {value.c_str(), "[0, 1000]"});
        expect_error(
            [&] {
                (void)BruteForcePathTracer(PathTracerSettings{depth, false});
            },
            {value.c_str()});
        expect_error([&] { (void)DirectLighting(DirectLightingSettings{depth}); }, {value.c_str()});
    }
    expect_error(
        [] {
            (void)PathTracer(PathTracerSettings{5, true, -2});
        },
        {"russian_roulette_depth = -2"});
    // The extremes that are allowed work: no bounce at all, and the maximum.
    EXPECT_NO_THROW((void)PathTracer(PathTracerSettings{0, false}));
    EXPECT_NO_THROW((void)PathTracer(PathTracerSettings{1000, false}));
}

TEST(BadParameter, MaterialNonFiniteAndOutOfRange) {
    expect_error(
        [] {
            (void)Material::diffuse({kNan, 0.5f, 0.5f});
        },
        {"material albedo = (nan, 0.5, 0.5)"});
    expect_error(
        [] {
            (void)Material::diffuse({0.5f, 1.5f, 0.5f});
        },
        {"albedo = (0.5, 1.5, 0.5)", "[0, 1]"});
    expect_error([] { (void)Material::mirror({kInf, 1, 1}); }, {"albedo = (inf, 1, 1)"});
    expect_error([] { (void)Material::dielectric(kInf); }, {"ior = inf"});
    expect_error([] { (void)Material::dielectric(0.0f); }, {"ior = 0"});
    expect_error([] { (void)Material::dielectric(1.5f, true, {1, -0.0001f, 1}); }, {"albedo"});
    expect_error([] { (void)Material::emissive({0, kNan, 0}); }, {"emission = (0, nan, 0)"});
    expect_error([] { (void)Material::emissive({-1, 0, 0}); }, {"emission = (-1, 0, 0)"});
    Material m = Material::diffuse(glm::vec3(0.5f));
    m.albedo_texture = -5;
    expect_error([&] { validate(m); }, {"albedo_texture = -5"});
    // Materials set by hand are validated when added to a scene.
    Scene scene;
    m = Material::diffuse(glm::vec3(0.5f));
    m.ior = kNan;
    expect_error([&] { (void)scene.add_material(m); }, {"ior = nan"});
}

TEST(BadParameter, LightsNonFiniteAndZeroSize) {
    Scene scene;
    expect_error(
        [&] {
            scene.add_point_light({{kNan, 0, 0}, glm::vec3(1.0f)});
        },
        {"point light position = (nan, 0, 0)"});
    expect_error(
        [&] {
            scene.add_point_light({{0, 0, 0}, {kInf, 1, 1}});
        },
        {"point light intensity = (inf, 1, 1)"});
    expect_error(
        [&] {
            scene.add_point_light(PointLight::from_power({0, 0, 0}, -5.0f));
        },
        {"point light intensity"});
    expect_error(
        [&] {
            (void)scene.add_sphere_light({{{0, 0, 0}, 0.0f}, glm::vec3(1.0f)});
        },
        {"sphere light radius = 0"});
    expect_error(
        [&] {
            (void)scene.add_sphere_light({{{0, 0, 0}, kNan}, glm::vec3(1.0f)});
        },
        {"sphere light radius = nan"});
    expect_error(
        [&] {
            (void)scene.add_sphere_light({{{0, kInf, 0}, 1.0f}, glm::vec3(1.0f)});
        },
        {"sphere light center"});
    // A given power on a vanishing radius needs an infinite radiance: refused.
    const glm::vec3 radiance = SphereLight::radiance_for_power(100.0f, 1e-30f);
    expect_error(
        [&] {
            (void)scene.add_sphere_light({{{0, 0, 0}, 1e-30f}, radiance});
        },
        {"sphere light radiance = (inf"});
    EXPECT_EQ(scene.lights().size(), 0u);
}

TEST(BadParameter, SceneGeometryNonFinite) {
    Scene scene;
    const auto grey = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    expect_error([&] { (void)scene.add_sphere({{0, 0, 0}, 0.0f}, grey); }, {"sphere radius = 0"});
    expect_error([&] { (void)scene.add_sphere({{0, 0, 0}, kNan}, grey); }, {"sphere radius = nan"});
    expect_error([&] { (void)scene.add_sphere({{0, 0, 0}, kInf}, grey); }, {"sphere radius = inf"});
    expect_error(
        [&] {
            (void)scene.add_sphere({{0, 0, -kInf}, 1.0f}, grey);
        },
        {"sphere center = (0, 0, -inf)"});
    expect_error([&] { (void)scene.add_sphere({{0, 0, 0}, 1.0f}, 99); }, {"material id 99"});
    expect_error(
        [&] {
            (void)scene.add_triangle({{0, 0, 0}, {kNan, 0, 0}, {0, 1, 0}}, grey);
        },
        {"add_triangle", "finite"});
    TriangleMesh m = one_triangle();
    m.positions[1].y = kInf;
    expect_error([&] { (void)scene.add_mesh(m, grey); }, {"position 1 is not finite"});
    m = one_triangle();
    m.normals = {{0, 0, 1}, {0, 0, kNan}, {0, 0, 1}};
    expect_error([&] { (void)scene.add_mesh(m, grey); }, {"normal 1 is not finite"});
    m = one_triangle();
    m.uvs = {{0, 0}, {1, 0}, {kInf, 1}};
    expect_error([&] { (void)add_mesh_with_mtl(scene, m, grey); }, {"uv 2 is not finite"});
    m = one_triangle();
    m.triangles.push_back({0, 1, 0xFFFFFFFFu});
    expect_error([&] { (void)scene.add_mesh(m, grey); }, {"triangle 1", "out of range"});
    expect_error([&] { (void)scene.add_texture(ImageTexture{}); }, {"add_texture", "empty"});
    EXPECT_EQ(scene.object_count(), 0u);  // nothing half-added
}

TEST(BadParameter, TransformsNonFinite) {
    expect_error(
        [] {
            (void)make_transform({kNan, 1, 1}, {}, {});
        },
        {"make_transform: scale = (nan"});
    expect_error(
        [] {
            (void)make_transform({1, 1, 1}, {0, kInf, 0}, {});
        },
        {"make_transform: rotation_degrees"});
    expect_error(
        [] {
            (void)make_transform({1, 1, 1}, {}, {0, 0, -kInf});
        },
        {"make_transform: translation"});
    TriangleMesh m = one_triangle();
    glm::mat4 bad(1.0f);
    bad[1][2] = kNan;  // column 1, row 2
    expect_error([&] { transform(m, bad); }, {"transform: matrix entry (row 2, column 1) = nan"});
    EXPECT_EQ(m.positions[1], glm::vec3(1, 0, 0));  // untouched
    glm::mat4 projective(1.0f);
    projective[3][3] = kNan;
    expect_error([&] { transform(m, projective); }, {"row 3, column 3"});
    // Finite but overflowing: positions become infinite, which validate() names.
    transform(m, make_transform(glm::vec3(1e38f), {}, {}));
    transform(m, make_transform(glm::vec3(1e38f), {}, {}));
    expect_error([&] { validate(m); }, {"mesh: position 1 is not finite"});
    // A singular matrix is fine for positions, not for normals.
    TriangleMesh with_normals = one_triangle();
    with_normals.normals.assign(3, glm::vec3(0, 0, 1));
    expect_error([&] { transform(with_normals, make_transform({1, 0, 1}, {}, {})); }, {"singular"});
    EXPECT_EQ(with_normals.positions[2], glm::vec3(0, 1, 0));  // untouched
}

TEST(BadParameter, ProceduralCounts) {
    expect_error([] { (void)make_uv_sphere({}, 1, -3, 4); }, {"segments = -3"});
    expect_error([] { (void)make_uv_sphere({}, 1, INT_MAX, 4); }, {"segments = 2147483647"});
    expect_error([] { (void)make_uv_sphere({}, 1, 8, INT_MIN); }, {"rings = -2147483648"});
    // Each count in range, their product absurd: refused by the limit (the message names
    // it) before allocating ~34 GB.
    expect_error([] { (void)make_uv_sphere({}, 1, 1 << 15, 1 << 15); },
                 {"make_uv_sphere", "segments = 32768, rings = 32768", "more than the limit"});
    expect_error([] { (void)make_teapot(4096); },
                 {"make_teapot", "tessellation = 4096", "vertices"});
    expect_error([] { (void)make_teapot(-1); }, {"tessellation = -1"});
    expect_error([] { (void)make_icosphere({}, 1, -1); }, {"subdivisions = -1"});
    expect_error([] { (void)make_icosphere({kNan, 0, 0}, 1, 2); }, {"make_icosphere", "center"});
    expect_error([] { (void)make_uv_sphere({}, kInf, 8, 4); }, {"radius = inf"});
    expect_error([] { (void)make_quad({}, {1, 0, 0}, {2, 0, 0}); }, {"make_quad", "parallel"});
    expect_error([] { (void)make_quad({}, {kNan, 0, 0}, {0, 1, 0}); }, {"make_quad"});
    expect_error([] { (void)make_box({0, 0, 0}, {1, kNan, 1}); }, {"make_box"});
    expect_error([] { (void)make_teapot_with_triangles(std::size_t{1} << 40); }, {"target"});
}

TEST(BadParameter, BvhBuilderInput) {
    const std::vector<BBox> boxes = {BBox{{0, 0, 0}, {1, 1, 1}}, BBox{{0, kNan, 0}, {1, 1, 1}}};
    const std::vector<glm::vec3> centers = {glm::vec3(0.5f), glm::vec3(0.5f)};
    expect_error([&] { (void)build_median_bvh(boxes, centers); },
                 {"BVH build: primitive 1 has a NaN box"});
    expect_error([&] { (void)build_sah_bvh(boxes, centers); }, {"primitive 1 has a NaN box"});
    const std::vector<glm::vec3> inf_centers = {glm::vec3(0.5f), {0, 0, kInf}};
    expect_error([&] { (void)build_bvh(BvhBuilder::Sah, std::vector<BBox>(2), inf_centers); },
                 {"primitive 1 has a non-finite centre"});
    // An empty box (a primitive that covers nothing) is allowed.
    EXPECT_NO_THROW((void)build_sah_bvh(std::vector<BBox>(2), centers));
    // TriangleBvh over a mesh checks the mesh first: a bad index would read out of bounds.
    TriangleMesh m = one_triangle();
    m.triangles.push_back({0, 3, 1});
    expect_error([&] { (void)TriangleBvh(m); }, {"triangle 1 index 3 is out of range"});
    expect_error([&] { (void)TriangleList(m); }, {"out of range"});
    m = one_triangle();
    m.positions[0].x = kNan;
    expect_error([&] { (void)TriangleBvh(m, BvhBuilder::Median); }, {"position 0 is not finite"});
    const std::vector<Triangle> loose = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                                         {{0, 0, 0}, {1, kNan, 0}, {0, 1, 0}}};
    expect_error([&] { (void)TriangleBvh(loose); }, {"triangle 1 has a non-finite corner"});
}

TEST(BadFile, TextureMissingDirectoryEmptyGarbageHuge) {
    ScratchDir dir;
    expect_error([&] { (void)load_texture(dir.path() / "absent.png"); },
                 {"absent.png", "no such file"});
    fs::create_directory(dir.path() / "folder.png");
    expect_error([&] { (void)load_texture(dir.path() / "folder.png"); },
                 {"folder.png", "is a directory"});
    expect_error([&] { (void)load_texture(dir.write("empty.png", "")); },
                 {"cannot load texture", "empty.png"});
    expect_error([&] { (void)load_texture(dir.write("junk.png", "this is not an image")); },
                 {"cannot load texture", "junk.png"});
    // A PNG cut short after its signature.
    expect_error(
        [&] { (void)load_texture(dir.write("cut.png", std::string("\x89PNG\r\n\x1a\n", 8))); },
        {"cut.png"});
    // A header claiming 20000 x 20000 texels: refused from the header, before decoding.
    expect_error([&] { (void)load_texture(dir.write("huge.ppm", "P6\n20000 20000\n255\n")); },
                 {"huge.ppm", "20000 x 20000", "more than the limit"});
    // A binary PPM cut short: stb would hand back uninitialised memory as texels.
    expect_error(
        [&] { (void)load_texture(dir.write("short.ppm", "P6\n64 64\n255\n\x01\x02\x03")); },
        {"short.ppm", "truncated"});
}

TEST(BadFile, TextureUnreadable) {
    ScratchDir dir;
    const fs::path locked = dir.write("locked.ppm", std::string("P6\n1 1\n255\n\xff\xff\xff", 14));
    fs::permissions(locked, fs::perms::none);
    LIBRT_SKIP_IF_PERMISSIONS_BYPASSED(locked);
    expect_error([&] { (void)load_texture(locked); }, {"cannot load texture", "locked.ppm"});
}

TEST(BadFile, ImageOutputPaths) {
    ScratchDir dir;
    const Image image(2, 2);
    // The target is an existing (empty) directory: an error, the directory stays.
    fs::create_directory(dir.path() / "out.png");
    expect_error([&] { write_image(dir.path() / "out.png", image); }, {"out.png"});
    EXPECT_TRUE(fs::is_directory(dir.path() / "out.png"));
    // A directory path with no file name.
    expect_error([&] { write_png(dir.path().string() + "/", image); }, {"no file name"});
    expect_error([&] { write_image(dir.path() / "no_extension", image); },
                 {"no_extension", "unknown image format"});
    EXPECT_EQ(dir.listing(), "out.png");  // no temporary left behind by any of these
    // Reading back: missing, a directory, empty.
    expect_error([&] { (void)read_pfm(dir.path() / "absent.pfm"); }, {"absent.pfm"});
    expect_error([&] { (void)read_pfm(dir.path() / "out.png"); }, {"out.png"});
    expect_error([&] { (void)read_pfm(dir.write("empty.pfm", "")); },
                 {"empty.pfm", "not a valid PFM"});
    // A PFM header claiming an absurd size is refused before allocating.
    expect_error([&] { (void)read_pfm(dir.write("huge.pfm", "PF\n100000 100000\n-1\n")); },
                 {"100000 x 100000", "4 GiB"});
    // Within the limit but without its raster: refused before the 1.2 GB film is made.
    expect_error([&] { (void)read_pfm(dir.write("short.pfm", "PF\n10000 10000\n-1\n")); },
                 {"short.pfm", "truncated raster: 0 bytes for 1200000000"});
}

TEST(BadFile, ImageOutputIntoReadOnlyDirectory) {
    ScratchDir dir;
    const Image image(2, 2);
    const fs::path locked = dir.path() / "locked";
    fs::create_directory(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    const fs::path probe = locked / "probe";
    const bool bypassed = static_cast<bool>(std::ofstream(probe));
    if (bypassed) {
        fs::remove(probe);
        GTEST_SKIP() << "running with permission override (root?): a read-only directory "
                        "is writable here, so that case cannot be tested";
    }
    expect_error([&] { write_image(locked / "x.png", image); }, {"x.png", "Permission denied"});
    EXPECT_TRUE(fs::is_empty(locked));
}
