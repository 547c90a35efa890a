// Issue 12's light targets, measured as RMSE against a high-sample reference at equal
// render time (one thread):
//   panel: a box lit by an emissive ceiling panel, the panel sampled as triangle lights
//          (PathTracer) against the same panel unsampled (BruteForcePathTracer: with the
//          panel the only emitter, the same estimator as the path tracer before triangle
//          lights, which sampled no light there and counted the panel when hit);
//   sky:   a floor, a ball and a block lit only by sky.hdr, environment importance
//          sampling with MIS (PathTracer) against cosine sampling of the sky
//          (BruteForcePathTracer: the diffuse BSDF samples the cosine).
// Environment, for the panel's diagnosis: LIBRT_PANEL_Y (its height, default 1.99 under a
// ceiling at 2), LIBRT_PANEL_ONE_SIDED (=1: the panel's triangles get the material a glTF
// file's single-sided emissive material maps to, through material_from_gltf, so they are
// one-sided triangle lights; =quad: a one-sided quad light instead); LIBRT_BLOCK_RMSE (set:
// also print each candidate's RMSE per 8 x 8 pixel block, to see where the error is);
// LIBRT_WORST (set: print the 10 pixels where the sampled candidate is furthest from the
// reference, with all three images' values: fireflies); LIBRT_BENCH_SIZE (image side,
// default 32); LIBRT_GUIDING_PASSES (training passes of the guided candidate).
// Usage: librt_light_targets [seconds per candidate = 2] [reference seconds = 40]
//                            [panel edge = 0.5 (its power is kept: radiance / edge^2)]
//                            [max depth = 5] [sampler of the sampled candidate and the
//                            reference = independent | sobol] [roulette = 1 | 0]
//                            [scene = both | panel | sky | glb] [guided = 0 | 1]
// glb: ../shared/data/gltf/cornell_pbr.glb as rt_render loads it (its two-sided emissive
// panel 1 cm under the ceiling, gold, thin glass and plastic), seen from the file's own
// camera (the same eye, direction and 40 degree field of view as the panel box's).

#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/integrator/bdpt.h>
#include <librt/integrator/integrators.h>
#include <librt/io/hdr_image.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace librt;
using Clock = std::chrono::steady_clock;

/// Image side in pixels: 32, or LIBRT_BENCH_SIZE (a multiple of 4) for experiments.
const int kSize = [] {
    const char* v = std::getenv("LIBRT_BENCH_SIZE");
    const int n = v != nullptr ? std::atoi(v) : 32;
    return n >= 4 && n % 4 == 0 ? n : 32;
}();

TriangleMesh quad(const glm::vec3& c, const glm::vec3& e0, const glm::vec3& e1) {
    TriangleMesh m;
    m.positions = {c, c + e0, c + e0 + e1, c + e1};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

/// Height of the panel: 1.99 (0.01 under the ceiling), or LIBRT_PANEL_Y for experiments.
float panel_y() {
    const char* y = std::getenv("LIBRT_PANEL_Y");
    return y != nullptr ? float(std::atof(y)) : 1.99f;
}

/// A 2 x 2 x 2 box open at +z, two blocks in it, and a 0.5 x 0.5 emissive ceiling panel
/// just below the ceiling.
void build_panel_box(Scene& scene, float edge) {
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.73f)));
    const auto red = scene.add_material(Material::diffuse({0.65f, 0.05f, 0.05f}));
    const auto green = scene.add_material(Material::diffuse({0.12f, 0.45f, 0.15f}));
    scene.add_mesh(quad({-1, 0, -1}, {0, 0, 2}, {2, 0, 0}), white);  // floor, up
    scene.add_mesh(quad({-1, 2, -1}, {2, 0, 0}, {0, 0, 2}), white);  // ceiling, down
    scene.add_mesh(quad({-1, 0, -1}, {2, 0, 0}, {0, 2, 0}), white);  // back
    scene.add_mesh(quad({-1, 0, -1}, {0, 2, 0}, {0, 0, 2}), red);    // left
    scene.add_mesh(quad({1, 0, -1}, {0, 0, 2}, {0, 2, 0}), green);   // right
    scene.add_sphere({{-0.4f, 0.4f, -0.3f}, 0.4f}, white);
    scene.add_sphere({{0.45f, 0.3f, 0.3f}, 0.3f}, white);
    const float k = 0.25f / (edge * edge);  // the same power as the 0.5 x 0.5 panel
    const auto lamp = scene.add_material(Material::emissive(k * glm::vec3(17.0f, 12.0f, 4.0f)));
    const glm::vec3 corner{-0.5f * edge, panel_y(), -0.5f * edge};
    const char* one_sided = std::getenv("LIBRT_PANEL_ONE_SIDED");
    if (one_sided != nullptr && std::string(one_sided) == "quad") {
        // The panel as a one-sided quad light facing down (edge0 x edge1 = -y): no light
        // into the gap between it and the ceiling (docs/light-targets.md).
        (void)scene.add_quad_light(QuadLight{
            corner, {edge, 0, 0}, {0, 0, edge}, k * glm::vec3(17.0f, 12.0f, 4.0f), false});
    } else if (one_sided != nullptr) {
        // What a glTF emissive material that is not doubleSided becomes (black base, the
        // emission as emissiveFactor x KHR_materials_emissive_strength), on triangles wound
        // to face down: one-sided triangle lights.
        GltfMaterial g;
        g.base_color_factor = {0.0f, 0.0f, 0.0f, 1.0f};
        g.metallic_factor = 0.0f;
        g.emissive_factor = glm::vec3(17.0f, 12.0f, 4.0f) / 17.0f;
        g.emissive_strength = 17.0f * k;
        g.double_sided = false;
        scene.add_mesh(quad(corner, {edge, 0, 0}, {0, 0, edge}),
                       scene.add_material(material_from_gltf(g, {})));
    } else {
        scene.add_mesh(quad(corner, {edge, 0, 0}, {0, 0, edge}), lamp);  // two-sided triangles
    }
    scene.commit();
}

void build_sky(Scene& scene, const EnvironmentImage& sky) {
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.7f)));
    scene.add_mesh(quad({-3, 0, -3}, {0, 0, 6}, {6, 0, 0}), white);
    scene.add_sphere({{-0.5f, 0.5f, -0.3f}, 0.5f}, white);
    scene.add_mesh(quad({0.2f, 0, -1}, {0, 1.2f, 0}, {0.8f, 0, 0}), white);
    scene.add_environment_light(EnvironmentLight::from_image(sky));
    scene.commit();
}

struct BenchCamera {
    glm::vec3 eye, forward, up;
    float fov;
    [[nodiscard]] Ray ray(int x, int y, float jx, float jy) const {
        const glm::vec3 right = glm::cross(forward, up);
        const float depth = float(kSize) / (2.0f * std::tan(glm::radians(fov) * 0.5f));
        Ray r;
        r.origin = eye;
        r.direction = glm::normalize((float(x) + jx - float(kSize) / 2.0f) * right +
                                     (float(kSize) / 2.0f - float(y) - jy) * up + depth * forward);
        return r;
    }
};

/// Renders passes of one sample per pixel, through the pixel centre (no anti-aliasing:
/// the panel seen directly would otherwise add the same coverage noise to both
/// estimators and hide the lighting's), until `seconds` pass; the mean image.
std::vector<glm::dvec3> render(const Scene& scene, const Integrator& integrator,
                               const BenchCamera& cam, double seconds, std::uint64_t seed,
                               int* passes, SamplerKind kind = SamplerKind::Independent,
                               int max_passes = 0) {
    std::vector<glm::dvec3> sum(std::size_t(kSize * kSize), glm::dvec3(0.0));
    const auto start = Clock::now();
    int n = 0;
    do {
        if (max_passes > 0 && n == max_passes) break;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                Sampler s(kind, std::uint32_t(x), std::uint32_t(y), std::uint32_t(n), seed);
                sum[std::size_t(y * kSize + x)] +=
                    glm::dvec3(integrator.li(scene, cam.ray(x, y, 0.5f, 0.5f), s));
            }
        ++n;
    } while (max_passes > 0 ||
             std::chrono::duration<double>(Clock::now() - start).count() < seconds);
    for (auto& v : sum) v /= double(n);
    *passes = n;
    return sum;
}

double rmse(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const glm::dvec3 d = a[i] - b[i];
        s += glm::dot(d, d) / 3.0;
    }
    return std::sqrt(s / double(a.size()));
}

/// The RMSE of a against b in each of 4 x 4 blocks (8 x 8 pixels at the default size),
/// top row first.
void print_block_rmse(const char* what, const std::vector<glm::dvec3>& a,
                      const std::vector<glm::dvec3>& b) {
    const int blocks = 4, side = kSize / blocks;
    std::printf("  %s, RMSE per %d x %d block:\n", what, side, side);
    for (int by = 0; by < blocks; ++by) {
        std::printf("   ");
        for (int bx = 0; bx < blocks; ++bx) {
            double s = 0.0;
            for (int y = by * side; y < (by + 1) * side; ++y)
                for (int x = bx * side; x < (bx + 1) * side; ++x) {
                    const glm::dvec3 d =
                        a[std::size_t(y * kSize + x)] - b[std::size_t(y * kSize + x)];
                    s += glm::dot(d, d) / 3.0;
                }
            std::printf(" %8.5f", std::sqrt(s / double(side * side)));
        }
        std::printf("\n");
    }
}

void compare(const char* name, const Scene& sampled, const Integrator& good, const Scene& plain,
             const Integrator& base, const BenchCamera& cam, double seconds, double ref_seconds,
             SamplerKind kind, PathTracer* guided, const Integrator* candidate = nullptr) {
    int nr = 0, ng = 0, nb = 0;
    const auto ref = render(sampled, good, cam, ref_seconds, 1000, &nr, kind);
    std::vector<glm::dvec3> g;
    if (guided != nullptr) {
        // The guided candidate's training passes count in its time (their samples are
        // discarded), as render() without keep_training_samples does.
        const auto start = Clock::now();
        guided->preprocess(sampled);
        int trained = 0;
        for (int pass = 0;; ++pass) {
            const std::uint32_t spp = guided->begin_training_pass(pass);
            if (spp == 0) break;
            int done = 0;
            (void)render(sampled, *guided, cam, 0.0, 5000 + std::uint64_t(pass), &done, kind,
                         int(spp));
            guided->end_training_pass(pass);
            trained += done;
        }
        const double spent = std::chrono::duration<double>(Clock::now() - start).count();
        std::printf("guided: %d training spp in %.2f s, %zu spatial leaves\n", trained, spent,
                    guided->guiding_leaf_count());
        g = render(sampled, *guided, cam, seconds - spent, 1, &ng, kind);
    } else {
        g = render(sampled, candidate != nullptr ? *candidate : good, cam, seconds, 1, &ng, kind);
    }
    const auto b = render(plain, base, cam, seconds, 2, &nb);
    const double rg = rmse(g, ref), rb = rmse(b, ref);
    std::printf(
        "%s: reference %d spp; sampled %d spp RMSE %.5f; baseline %d spp RMSE %.5f; "
        "ratio %.1fx\n",
        name, nr, ng, rg, nb, rb, rb / rg);
    if (std::getenv("LIBRT_WORST") != nullptr) {
        std::vector<std::size_t> idx(g.size());
        for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
        std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t c) {
            return glm::length(g[a] - ref[a]) > glm::length(g[c] - ref[c]);
        });
        for (int k = 0; k < 10; ++k) {
            const std::size_t i = idx[std::size_t(k)];
            std::printf(
                "  pixel (%zu, %zu): sampled %.4f %.4f %.4f ref %.4f %.4f %.4f base %.4f %.4f "
                "%.4f\n",
                i % std::size_t(kSize), i / std::size_t(kSize), g[i].x, g[i].y, g[i].z, ref[i].x,
                ref[i].y, ref[i].z, b[i].x, b[i].y, b[i].z);
        }
    }
    // LIBRT_BLOCK_RMSE=1: where the error is (diagnosis of the panel's noise).
    if (std::getenv("LIBRT_BLOCK_RMSE") != nullptr) {
        print_block_rmse("sampled", g, ref);
        print_block_rmse("baseline", b, ref);
    }
}

}  // namespace

int main(int argc, char** argv) {
    const double seconds = argc > 1 ? std::atof(argv[1]) : 2.0;
    const double ref_seconds = argc > 2 ? std::atof(argv[2]) : 40.0;
    const float edge = argc > 3 ? float(std::atof(argv[3])) : 0.5f;
    PathTracerSettings settings;
    settings.max_depth = argc > 4 ? std::atoi(argv[4]) : 5;
    const SamplerKind kind =
        argc > 5 && std::string(argv[5]) == "sobol" ? SamplerKind::Sobol : SamplerKind::Independent;
    settings.russian_roulette = argc > 6 ? std::atoi(argv[6]) != 0 : true;
    settings.light_choice = LightChoice::Power;  // the figures' (measured before Auto)
    const std::string which = argc > 7 ? argv[7] : "both";
    const PathTracer pt(settings);
    const BruteForcePathTracer brute(settings);
    // [guided = 0 | 1]: the sampled candidate also guides its paths (path guiding, its
    // training passes in its time; LIBRT_GUIDING_PASSES sets their number).
    PathTracerSettings guided_settings = settings;
    guided_settings.guiding.enabled = true;
    if (const char* p = std::getenv("LIBRT_GUIDING_PASSES"))
        guided_settings.guiding.training_passes = std::atoi(p);
    PathTracer guided_pt(guided_settings);
    PathTracer* guided = argc > 8 && std::atoi(argv[8]) != 0 ? &guided_pt : nullptr;
    // LIBRT_BDPT set: the sampled candidate is the bidirectional path tracer (its t >= 2
    // strategies: this bench's pixel-centre camera has no splat film), the reference
    // still the path tracer.
    BidirectionalSettings bd;
    bd.max_depth = settings.max_depth;
    BidirectionalPathTracer bdpt(bd);
    const Integrator* candidate = std::getenv("LIBRT_BDPT") != nullptr ? &bdpt : nullptr;

    const char* dir = std::getenv("LIBRT_DATA_DIR");
    const std::filesystem::path data(dir ? dir : LIBRT_DEFAULT_DATA_DIR);
    const BenchCamera box_cam{{0, 1, 3.4f}, {0, 0, -1}, {0, 1, 0}, 40.0f};
    if (which == "glb") {
        // Its own emitter alone, as docs/light-targets.md measured it (no studio lighting).
        SceneFileOptions own_light;
        own_light.default_lighting = false;
        LoadedScene loaded =
            scene_from_gltf(load_gltf(data / "gltf" / "cornell_pbr.glb"), own_light);
        loaded.scene.commit();
        bdpt.preprocess(loaded.scene);
        compare("cornell_pbr.glb (triangle lights vs the panel unsampled)", loaded.scene, pt,
                loaded.scene, brute, box_cam, seconds, ref_seconds, kind, guided, candidate);
        return 0;
    }
    if (which != "sky") {
        Scene lit;
        build_panel_box(lit, edge);
        bdpt.preprocess(lit);
        compare("panel (triangle lights vs the panel unsampled)", lit, pt, lit, brute, box_cam,
                seconds, ref_seconds, kind, guided, candidate);
    }
    if (which == "panel") return 0;

    const std::filesystem::path path = data / "sky.hdr";
    const EnvironmentImage sky = load_hdr_image(path);
    Scene sky_scene;
    build_sky(sky_scene, sky);
    const BenchCamera sky_cam{{0, 1.2f, 3.5f},
                              glm::normalize(glm::vec3(0, -0.25f, -1)),
                              glm::normalize(glm::vec3(0, 1, -0.25f)),
                              50.0f};
    compare("sky.hdr (environment sampling + MIS vs cosine sampling)", sky_scene, pt, sky_scene,
            brute, sky_cam, seconds, ref_seconds, kind, guided);
    return 0;
}
