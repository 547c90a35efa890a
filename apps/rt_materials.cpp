// rt_materials: the material gallery (docs/gallery.md). Spheres on a checkered ground
// plane, lit only by an environment: three rows of the glTF metallic-roughness material
// (metallic 0, 0.5, 1) and a row of rough glass, each over roughness 0 .. 1 in seven
// columns, and a row of the four tabulated metals (gold, silver, copper, aluminium) with
// brushed (anisotropic) aluminium between them, turned by 0, 45 and 90 degrees. The
// environment is a built-in sky (a gradient and a sun), so the app needs no data files, or
// an equirectangular .hdr given by --env. Output as rt_render's: PNG sRGB-encoded after a
// clamp, .hdr / .pfm / .exr linear; Ctrl-C or --time-limit writes the finished passes.
#include "common/cli.h"
#include "common/scene_app.h"

#include <librt/core/constants.h>
#include <librt/core/error.h>
#include <librt/core/image.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/sphere.h>
#include <librt/integrator/integrators.h>
#include <librt/io/hdr_image.h>
#include <librt/io/image_io.h>
#include <librt/light/environment_light.h>
#include <librt/material/texture.h>
#include <librt/render/renderer.h>

#include <CLI/CLI.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace librt;

namespace {

constexpr int kColumns = 7;                 // roughness 0, 1/6, ..., 1
constexpr float kSpacing = 2.5f;            // between sphere centres, in both directions
constexpr float kRadius = 1.0f;             // every sphere
constexpr float kMetalRoughness = 0.25f;    // the named metals' row
constexpr float kBrushedAnisotropy = 0.9f;  // the brushed aluminium spheres of that row
constexpr float kAspect = 16.0f / 9.0f;     // of the default image and the framing
/// The base colour of the metallic-roughness rows: a red that reads as plastic at
/// metallic 0 and as a coloured metal at metallic 1 (linear RGB).
const glm::vec3 kBaseColor{0.8f, 0.12f, 0.06f};

struct Options {
    std::string output = "materials.png";
    std::string size = "960";  // "WxH" or a width (height from the 16:9 framing)
    int spp = 64;
    int threads = 0;
    std::uint64_t seed = 0;
    int max_depth = 8;  // glass needs several bounces through two surfaces
    std::string env;    // equirectangular .hdr; empty = the built-in sky
    float env_strength = 1.0f;
    float env_rotate = 0.0f;  // degrees about +y
    float exposure_ev = 0.0f;
    double time_limit = 0.0;
    bool orthographic = false;
    bool quiet = false;
};

[[noreturn]] void bad(const std::string& option, const std::string& value, const char* rule) {
    throw Error(option + " = " + value + ": " + rule);
}

/// A value as the user typed it (shortest round-trip form).
template <class T>
std::string typed(T v) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
    return std::string(buffer, result.ptr);
}

/// The built-in sky's radiance along unit direction d (y up): a zenith-to-horizon gradient
/// with a sun of angular radius 2.5 degrees and its glow above, a dim ground below. Not a
/// physical sky model; chosen so that the sun casts shadows and makes highlights.
glm::vec3 built_in_sky(const glm::vec3& d) {
    const glm::vec3 sun_dir = glm::normalize(glm::vec3(-0.6f, 0.7f, 0.5f));
    const float cos_sun = glm::dot(d, sun_dir);
    if (cos_sun > std::cos(glm::radians(2.5f))) return {380.0f, 350.0f, 300.0f};
    if (d.y < 0.0f) return glm::vec3(0.12f, 0.11f, 0.10f);
    const glm::vec3 zenith(0.15f, 0.3f, 0.75f), horizon(0.75f, 0.82f, 0.95f);
    // Brighter towards the horizon (1 - y)^4, plus a glow exp(40 (cos - 1)) around the sun.
    const glm::vec3 sky = glm::mix(zenith, horizon, std::pow(1.0f - d.y, 4.0f));
    return sky + 2.0f * std::exp(40.0f * (cos_sun - 1.0f)) * glm::vec3(1.0f, 0.85f, 0.6f);
}

/// The built-in sky as an equirectangular image in EnvironmentImage's layout: pixel
/// (x, y) centred at theta = pi v from +y, phi = 2 pi u, direction
/// (sin theta cos phi, cos theta, -sin theta sin phi).
EnvironmentImage built_in_sky_image() {
    EnvironmentImage image;
    image.width = 1024;
    image.height = 512;
    image.pixels.resize(std::size_t(image.width) * std::size_t(image.height));
    for (int y = 0; y < image.height; ++y) {
        const float theta = kPi * (float(y) + 0.5f) / float(image.height);
        for (int x = 0; x < image.width; ++x) {
            const float phi = 2.0f * kPi * (float(x) + 0.5f) / float(image.width);
            const glm::vec3 d(std::sin(theta) * std::cos(phi), std::cos(theta),
                              -std::sin(theta) * std::sin(phi));
            image.pixels[std::size_t(y) * std::size_t(image.width) + std::size_t(x)] =
                built_in_sky(d);
        }
    }
    return image;
}

/// Rotation by `degrees` about +y (light frame to world).
glm::mat3 rotation_y(float degrees) {
    const float c = std::cos(glm::radians(degrees)), s = std::sin(glm::radians(degrees));
    return glm::mat3(glm::vec3(c, 0.0f, -s), glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(s, 0.0f, c));
}

/// A grey checkerboard texture, two squares per side (each square one sphere spacing).
ImageTexture checker_texture() {
    constexpr int kTexels = 64;
    std::vector<glm::vec3> texels(std::size_t(kTexels) * kTexels);
    for (int y = 0; y < kTexels; ++y) {
        for (int x = 0; x < kTexels; ++x) {
            const bool light = ((x / (kTexels / 2)) + (y / (kTexels / 2))) % 2 == 0;
            texels[std::size_t(y) * kTexels + std::size_t(x)] = glm::vec3(light ? 0.4f : 0.22f);
        }
    }
    return ImageTexture(kTexels, kTexels, std::move(texels));
}

/// The ground: a square of side 400 at y = 0, its checker squares centred under the
/// spheres (uv 0.5 per spacing, offset by a quarter so a sphere sits mid-square).
TriangleMesh ground_mesh() {
    constexpr float kHalf = 200.0f;
    TriangleMesh mesh;
    mesh.positions = {
        {-kHalf, 0.0f, -kHalf}, {-kHalf, 0.0f, kHalf}, {kHalf, 0.0f, kHalf}, {kHalf, 0.0f, -kHalf}};
    mesh.normals.assign(4, glm::vec3(0.0f, 1.0f, 0.0f));
    for (const glm::vec3& p : mesh.positions) {
        mesh.uvs.emplace_back(p.x / (2.0f * kSpacing) + 0.25f, -p.z / (2.0f * kSpacing) + 0.25f);
    }
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};  // counter-clockwise seen from above (+y)
    return mesh;
}

/// Centre of the sphere in row `row` (0 = back) and column `col` (0 = left), on the ground.
glm::vec3 sphere_centre(int row, float col) {
    return {(col - 0.5f * float(kColumns - 1)) * kSpacing, kRadius, (float(row) - 2.0f) * kSpacing};
}

/// The gallery's spheres and ground (rows back to front: metallic 0, 0.5, 1, rough
/// glass, named metals).
void build_gallery(Scene& scene) {
    Material ground = Material::diffuse(glm::vec3(1.0f));
    ground.albedo_texture = scene.add_texture(checker_texture());
    scene.add_mesh(ground_mesh(), scene.add_material(ground));
    for (int col = 0; col < kColumns; ++col) {
        const float roughness = float(col) / float(kColumns - 1);
        const float metallic[] = {0.0f, 0.5f, 1.0f};
        for (int row = 0; row < 3; ++row) {
            const Material m = Material::metallic_roughness(kBaseColor, metallic[row], roughness);
            scene.add_sphere(Sphere{sphere_centre(row, float(col)), kRadius},
                             scene.add_material(m));
        }
        scene.add_sphere(Sphere{sphere_centre(3, float(col)), kRadius},
                         scene.add_material(Material::rough_dielectric(1.5f, roughness)));
    }
    // The metals under columns 0, 2, 4 and 6.
    const Metal metals[] = {Metal::Gold, Metal::Silver, Metal::Copper, Metal::Aluminium};
    for (int i = 0; i < 4; ++i) {
        scene.add_sphere(Sphere{sphere_centre(4, float(2 * i)), kRadius},
                         scene.add_material(Material::conductor(metals[i], kMetalRoughness)));
    }
    // Brushed aluminium between them (columns 1, 3, 5): anisotropy 0.9 along the sphere's
    // tangent (east about +y), turned by 0, 45 and 90 degrees toward its bitangent.
    for (int i = 0; i < 3; ++i) {
        Material brushed = Material::conductor(Metal::Aluminium, kMetalRoughness);
        brushed.anisotropy = kBrushedAnisotropy;
        brushed.anisotropy_rotation = float(i) * 0.25f * kPi;
        scene.add_sphere(Sphere{sphere_centre(4, float(2 * i + 1)), kRadius},
                         scene.add_material(brushed));
    }
}

/// A camera 35 degrees above the ground, in front of the grid (+z), framing it at 16:9:
/// perspective from 40 units with a 17 degree vertical field, or orthographic along the
/// same direction with the same half width at the grid's centre.
CameraSettings gallery_camera(int width, int height, bool orthographic) {
    CameraSettings c;
    const float elevation = glm::radians(35.0f);
    const glm::vec3 target(0.0f, 0.6f, 0.3f);
    c.look_at = target;
    c.position = target + 40.0f * glm::vec3(0.0f, std::sin(elevation), std::cos(elevation));
    c.width = width;
    c.height = height;
    c.vertical_fov_degrees = 17.0f;
    c.pixel_jitter = PixelJitter::Gaussian;  // anti-aliasing
    if (orthographic) {
        c.projection = Projection::Orthographic;
        // The perspective view's half height at the target: 40 tan(8.5 degrees).
        c.ymag = 40.0f * std::tan(glm::radians(8.5f));
        c.xmag = c.ymag * kAspect;
    }
    return c;
}

int render_gallery(const Options& o) {
    const auto started = std::chrono::steady_clock::now();
    // Everything the user typed is checked before anything is built or loaded.
    check_image_path(o.output);
    int width = 0, height = 0;
    apps::parse_size(o.size, kAspect, width, height);
    check_image_size(width, height);
    // The render's films, copies and output buffers must fit, before any is allocated.
    RenderMemoryOptions memory;
    memory.noise_estimate = !o.quiet;  // the progress bar's noise estimate
    apps::check_render_memory("--size", o.size, width, height,
                              apps::progressive_output_bytes_per_pixel(o.output, memory));
    RenderSettings check;
    check.samples_per_pixel = o.spp;
    check.threads = o.threads;
    validate(check);
    if (o.max_depth < 0 || o.max_depth > 1000)
        bad("--max-depth", std::to_string(o.max_depth), "must be in [0, 1000]");
    if (!std::isfinite(o.time_limit) || o.time_limit < 0.0)
        bad("--time-limit", typed(o.time_limit), "must be finite and >= 0 (0 = none)");
    if (!std::isfinite(o.exposure_ev) || std::abs(o.exposure_ev) > 64.0f)
        bad("--exposure", typed(o.exposure_ev), "must be in [-64, 64] (EV stops)");
    if (!std::isfinite(o.env_strength) || o.env_strength < 0.0f)
        bad("--env-strength", typed(o.env_strength), "must be finite and >= 0");
    if (!std::isfinite(o.env_rotate))
        bad("--env-rotate", typed(o.env_rotate), "must be finite (degrees)");
    const Camera camera(gallery_camera(width, height, o.orthographic));

    Scene scene;
    EnvironmentImage sky = o.env.empty() ? built_in_sky_image() : load_hdr_image(o.env);
    scene.add_environment_light(
        EnvironmentLight::from_image(std::move(sky), rotation_y(o.env_rotate), o.env_strength));
    build_gallery(scene);
    scene.commit();

    PathTracerSettings pt;
    pt.max_depth = o.max_depth;
    PathTracer integrator(pt);
    apps::ProgressiveOutput out;
    out.output = o.output;
    out.spp = o.spp;
    out.threads = o.threads;
    out.seed = o.seed;
    out.time_limit = o.time_limit;
    out.scale = std::exp2(o.exposure_ev);
    out.quiet = o.quiet;
    out.started = started;
    return apps::render_progressively_and_write(scene, camera, integrator, out);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "The material gallery: spheres over roughness (columns) x metallic, rough glass, "
        "named and brushed metals, on a ground plane lit by a sky",
        "rt_materials"};
    Options o;
    app.add_option("-o,--output", o.output,
                   "Output image: .png (exposure, clamp, sRGB), .hdr, .pfm (linear) or .exr "
                   "(linear, with AOV layers)")
        ->capture_default_str();
    app.add_option("--size", o.size, "Image size WIDTHxHEIGHT, or WIDTH (16:9)")
        ->capture_default_str();
    app.add_option("--spp", o.spp, "Samples per pixel")->capture_default_str();
    app.add_option("--threads", o.threads, "Worker threads, 0 = all cores")->capture_default_str();
    app.add_option("--seed", o.seed, "Random seed")->capture_default_str();
    app.add_option("--max-depth", o.max_depth, "Scattering events per path")->capture_default_str();
    app.add_option("--env", o.env,
                   "Equirectangular Radiance .hdr lighting the scene (default: a built-in sky "
                   "with a sun)");
    app.add_option("--env-strength", o.env_strength, "Scale of the environment's radiance")
        ->capture_default_str();
    app.add_option("--env-rotate", o.env_rotate, "Turn the environment about +y, in degrees")
        ->capture_default_str();
    app.add_option("--exposure", o.exposure_ev, "Exposure in stops: the image is scaled by 2^EV")
        ->capture_default_str();
    app.add_option("--time-limit", o.time_limit,
                   "Stop after this many seconds and write the finished passes (0 = none)")
        ->capture_default_str();
    app.add_flag("--orthographic", o.orthographic,
                 "View the grid through an orthographic camera (every sphere the same size)");
    app.add_flag("-q,--quiet", o.quiet, "No progress bar and no summary");
    return apps::run(app, argc, argv, [&] { return render_gallery(o); });
}
