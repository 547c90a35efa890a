// Choosing among many lights, measured as RMSE against a long reference at equal render
// time (one thread): the path tracer choosing the light it samples at each vertex by power
// alone (LightChoice::Power, the same table everywhere) against by power times a bound of
// each light's contribution at the point (LightChoice::Bounded; above the light sampler's
// 16 bounded lights, through the light tree of src/light/light_tree.h). The reference is
// rendered by Bounded too (Power's would be far noisier in the same time); that the tree
// is unbiased is the unit tests' business (tests/render/light_bounds_test.cpp: MIS with
// the tree equals brute force).
// Scene, built here and deterministic: a 20 x 20 m diffuse floor (albedo 0.5), a few
// diffuse spheres and boxes, and N small one-sided emissive quads (two triangles each,
// triangle lights) facing down at heights 0.2-2 m, scattered over the floor with random
// colours and radiances spread over two orders of magnitude. Each light lights a pool a
// few metres wide, so most lights are far from most shading points: by power alone almost
// every shadow ray goes to a light that adds next to nothing there, which is what a
// choice by bound (or a tree) should fix. The camera looks down at the floor at 45
// degrees and sees many pools.
// Usage: librt_many_lights [seconds per candidate = 4] [reference seconds = 60]
//                          [lights N = 400 quads: 2N triangle lights] [image side = 64]
//                          [max depth = 4]
// Prints each candidate's samples per pixel, time and RMSE against the reference (Bounded,
// its own seed), and the equal-time RMSE ratio Power / Bounded =
// sqrt(MSE_power * t_power / (MSE_bounded * t_bounded)) (> 1: Bounded is better).

#include <librt/integrator/integrators.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

using namespace librt;
using Clock = std::chrono::steady_clock;

TriangleMesh quad(const glm::vec3& c, const glm::vec3& e0, const glm::vec3& e1) {
    TriangleMesh m;
    m.positions = {c, c + e0, c + e0 + e1, c + e1};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

/// An axis-aligned box standing on the floor: its four sides and top, wound outward.
void add_box(Scene& scene, const glm::vec3& lo, const glm::vec3& hi, std::uint32_t material) {
    const glm::vec3 d = hi - lo;
    const glm::vec3 x{d.x, 0, 0}, y{0, d.y, 0}, z{0, 0, d.z};
    scene.add_mesh(quad({lo.x, hi.y, lo.z}, z, x), material);  // top, up
    scene.add_mesh(quad(lo, z, y), material);                  // -x
    scene.add_mesh(quad({hi.x, lo.y, lo.z}, y, z), material);  // +x
    scene.add_mesh(quad(lo, y, x), material);                  // -z
    scene.add_mesh(quad({lo.x, lo.y, hi.z}, x, y), material);  // +z
}

struct Footprint {
    float x, z, r;  // a disc on the floor no light is placed over
};

/// The floor, the occluders and `n` lights, all from one fixed seed.
void build_scene(Scene& scene, int n) {
    Pcg32 rng(20240611u, 7u);
    const auto floor = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const auto grey = scene.add_material(Material::diffuse(glm::vec3(0.6f)));
    scene.add_mesh(quad({-10, 0, -10}, {0, 0, 20}, {20, 0, 0}), floor);  // up
    std::vector<Footprint> taken;
    for (int i = 0; i < 6; ++i) {  // spheres resting on the floor
        const float r = 0.4f + 0.6f * rng.next_float();
        const float x = -8.0f + 16.0f * rng.next_float(), z = -8.0f + 16.0f * rng.next_float();
        scene.add_sphere({{x, r, z}, r}, grey);
        taken.push_back({x, z, r + 0.2f});
    }
    for (int i = 0; i < 5; ++i) {  // boxes 0.5-1.5 m wide and 0.5-2.5 m tall
        const float w = 0.5f + rng.next_float(), h = 0.5f + 2.0f * rng.next_float();
        const float x = -8.0f + 16.0f * rng.next_float(), z = -8.0f + 16.0f * rng.next_float();
        add_box(scene, {x - w / 2, 0, z - w / 2}, {x + w / 2, h, z + w / 2}, grey);
        taken.push_back({x, z, 0.71f * w + 0.2f});
    }
    const float edge = 0.1f;  // lights of 10 x 10 cm
    for (int i = 0; i < n; ++i) {
        float x = 0, z = 0;
        for (bool clear = false; !clear;) {
            x = -9.8f + 19.6f * rng.next_float();
            z = -9.8f + 19.6f * rng.next_float();
            clear = true;
            for (const Footprint& f : taken)
                clear = clear && (x - f.x) * (x - f.x) + (z - f.z) * (z - f.z) > f.r * f.r;
        }
        const float y = 0.2f + 1.8f * rng.next_float();
        const glm::vec3 colour{0.1f + 0.9f * rng.next_float(), 0.1f + 0.9f * rng.next_float(),
                               0.1f + 0.9f * rng.next_float()};
        const float radiance = 10.0f * std::pow(10.0f, 2.0f * rng.next_float());  // 10-1000
        Material m = Material::emissive(radiance * colour / glm::dot(colour, glm::vec3(1.0f / 3)));
        m.double_sided = false;  // emits only along edge0 x edge1 = -y: down
        scene.add_mesh(quad({x - edge / 2, y, z - edge / 2}, {edge, 0, 0}, {0, 0, edge}),
                       scene.add_material(m));
    }
    scene.commit();
}

struct BenchCamera {
    glm::vec3 eye, forward, up;
    float fov;
    int size;
    [[nodiscard]] Ray ray(int x, int y) const {
        const glm::vec3 right = glm::cross(forward, up);
        const float s = float(size);
        const float depth = s / (2.0f * std::tan(glm::radians(fov) * 0.5f));
        Ray r;
        r.origin = eye;
        r.direction = glm::normalize((float(x) + 0.5f - s / 2.0f) * right +
                                     (s / 2.0f - float(y) - 0.5f) * up + depth * forward);
        return r;
    }
};

/// Renders full passes of one sample per pixel through the pixel centre (as
/// light_targets.cpp: no coverage noise at the occluders' edges, the same for both) until
/// `seconds` pass; the mean image, the passes and the time they took.
std::vector<glm::dvec3> render(const Scene& scene, const Integrator& integrator,
                               const BenchCamera& cam, double seconds, std::uint64_t seed,
                               int* passes, double* spent) {
    const int side = cam.size;
    std::vector<glm::dvec3> sum(std::size_t(side * side), glm::dvec3(0.0));
    const auto start = Clock::now();
    int n = 0;
    do {
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) {
                Sampler s(SamplerKind::Independent, std::uint32_t(x), std::uint32_t(y),
                          std::uint32_t(n), seed);
                sum[std::size_t(y * side + x)] +=
                    glm::dvec3(integrator.li(scene, cam.ray(x, y), s));
            }
        ++n;
    } while (std::chrono::duration<double>(Clock::now() - start).count() < seconds);
    *spent = std::chrono::duration<double>(Clock::now() - start).count();
    for (auto& v : sum) v /= double(n);
    *passes = n;
    return sum;
}

double mse(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const glm::dvec3 d = a[i] - b[i];
        s += glm::dot(d, d) / 3.0;
    }
    return s / double(a.size());
}

double mean(const std::vector<glm::dvec3>& a) {
    double s = 0.0;
    for (const auto& v : a) s += (v.x + v.y + v.z) / 3.0;
    return s / double(a.size());
}

}  // namespace

int main(int argc, char** argv) {
    const double seconds = argc > 1 ? std::atof(argv[1]) : 4.0;
    const double ref_seconds = argc > 2 ? std::atof(argv[2]) : 60.0;
    const int n = argc > 3 ? std::atoi(argv[3]) : 400;
    const int side = argc > 4 ? std::atoi(argv[4]) : 64;
    PathTracerSettings settings;
    settings.max_depth = argc > 5 ? std::atoi(argv[5]) : 4;
    if (n < 1 || side < 1 || settings.max_depth < 1 || !(seconds > 0.0)) {
        std::fprintf(stderr, "usage: %s [seconds] [ref seconds] [lights] [side] [depth]\n",
                     argv[0]);
        return 2;
    }
    settings.light_choice = LightChoice::Power;
    PathTracer power(settings);
    settings.light_choice = LightChoice::Bounded;
    PathTracer bounded(settings);

    Scene scene;
    build_scene(scene, n);
    power.preprocess(scene);
    bounded.preprocess(scene);
    // From 8 m up and 8 m back, looking down at 45 degrees at the floor's middle.
    const BenchCamera cam{{0, 8, 10},
                          glm::normalize(glm::vec3(0, -1, -1)),
                          glm::normalize(glm::vec3(0, 1, -1)),
                          60.0f,
                          side};
    std::printf("%zu triangle lights (%d quads), %d x %d pixels, max depth %d, one thread\n",
                scene.lights().size(), n, side, side, settings.max_depth);

    int nr = 0, np = 0, nb = 0;
    double tr = 0, tp = 0, tb = 0;
    const auto ref = render(scene, bounded, cam, ref_seconds, 1000, &nr, &tr);
    std::printf("reference (bounded): %d spp in %.1f s, mean %.5f\n", nr, tr, mean(ref));
    const auto p = render(scene, power, cam, seconds, 1, &np, &tp);
    const auto b = render(scene, bounded, cam, seconds, 2, &nb, &tb);
    const double mp = mse(p, ref), mb = mse(b, ref);
    std::printf("power:   %d spp in %.2f s, RMSE %.5f\n", np, tp, std::sqrt(mp));
    std::printf("bounded: %d spp in %.2f s, RMSE %.5f\n", nb, tb, std::sqrt(mb));
    std::printf("equal-time RMSE ratio power / bounded: %.2fx\n", std::sqrt(mp * tp / (mb * tb)));
    return 0;
}
