#pragma once

// A minimal local pixel loop for the integrator tests (independent of the renderer):
// a pinhole ray through each pixel centre, Sampler(x, y, s, seed), and per-pixel running
// sums of the samples and their squares, so tests can derive their tolerances from the
// sample variance.

#include <librt/geometry/ray.h>
#include <librt/integrator/integrator.h>
#include <librt/material/material.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace librt::testing {

/// A pinhole camera looking down -z (+y up) like the report's, or along any forward axis.
struct Pinhole {
    glm::vec3 eye{0.0f};
    glm::vec3 forward{0.0f, 0.0f, -1.0f};  ///< unit
    glm::vec3 up{0.0f, 1.0f, 0.0f};        ///< unit, orthogonal to forward
    float fov_degrees = 60.0f;             ///< vertical
    int width = 16;
    int height = 16;

    /// The ray through the centre of pixel (x, y), rows top to bottom: the report's
    /// (j - W/2 + 0.5, -i + H/2 - 0.5, -H / (2 tan(fov/2))) in the camera frame.
    [[nodiscard]] Ray ray(int x, int y) const {
        const glm::vec3 right = glm::cross(forward, up);
        const float depth = float(height) / (2.0f * std::tan(glm::radians(fov_degrees) * 0.5f));
        const float px = float(x) - float(width) / 2.0f + 0.5f;
        const float py = -float(y) + float(height) / 2.0f - 0.5f;
        Ray r;
        r.origin = eye;
        r.direction = glm::normalize(px * right + py * up + depth * forward);
        return r;
    }
};

/// Running statistics of one pixel's samples, in double.
struct PixelStats {
    glm::dvec3 sum{0.0};
    glm::dvec3 sum2{0.0};
    int n = 0;

    void add(const glm::vec3& v) {
        const glm::dvec3 d(v);
        sum += d;
        sum2 += d * d;
        ++n;
    }
    [[nodiscard]] glm::dvec3 mean() const { return sum / double(n); }
    /// Unbiased sample variance of one sample.
    [[nodiscard]] glm::dvec3 variance() const {
        const glm::dvec3 m = mean();
        return glm::max(glm::dvec3(0.0), (sum2 - double(n) * m * m) / double(n - 1));
    }
};

/// Per-pixel statistics of a whole image.
struct StatImage {
    int width = 0;
    int height = 0;
    std::vector<PixelStats> pixels;

    [[nodiscard]] const PixelStats& at(int x, int y) const {
        return pixels[std::size_t(y) * std::size_t(width) + std::size_t(x)];
    }
};

/// Renders spp samples per pixel with the integrator (pixel-centre rays, no jitter).
inline StatImage render_stats(const Scene& scene, Integrator& integrator, const Pinhole& camera,
                              int spp, std::uint64_t seed) {
    integrator.preprocess(scene);
    StatImage img{camera.width, camera.height,
                  std::vector<PixelStats>(std::size_t(camera.width) * std::size_t(camera.height))};
    for (int y = 0; y < camera.height; ++y)
        for (int x = 0; x < camera.width; ++x) {
            const Ray ray = camera.ray(x, y);
            PixelStats& p = img.pixels[std::size_t(y) * std::size_t(camera.width) + std::size_t(x)];
            for (int s = 0; s < spp; ++s) {
                Sampler sampler(std::uint32_t(x), std::uint32_t(y), std::uint32_t(s), seed);
                p.add(integrator.li(scene, ray, sampler));
            }
        }
    return img;
}

/// The mean over a rectangle of pixels [x0, x1) x [y0, y1) and the squared standard error
/// of that mean: pixels are estimated independently, so se^2 = sum_p var_p / n_p / P^2.
struct RegionEstimate {
    glm::dvec3 mean{0.0};
    glm::dvec3 se2{0.0};
};

inline RegionEstimate region(const StatImage& img, int x0, int y0, int x1, int y1) {
    RegionEstimate r;
    double count = 0.0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const PixelStats& p = img.at(x, y);
            r.mean += p.mean();
            r.se2 += p.variance() / double(p.n);
            count += 1.0;
        }
    r.mean /= count;
    r.se2 /= count * count;
    return r;
}

/// The report's room (scenes.md): six wall spheres and four spheres (add the light yourself).
inline void add_room(Scene& scene) {
    auto diffuse = [&](glm::vec3 a) { return scene.add_material(Material::diffuse(a)); };
    scene.add_sphere({{0, -1000, 0}, 990}, diffuse({0, 0, 1}));
    scene.add_sphere({{0, 0, -1050}, 940}, diffuse({1, 0, 1}));
    scene.add_sphere({{0, 0, 1000}, 940}, diffuse({1, 1, 0}));
    scene.add_sphere({{1000, 0, 0}, 940}, diffuse({1, 0, 0}));
    scene.add_sphere({{-1000, 0, 0}, 940}, diffuse({0, 1, 0}));
    scene.add_sphere({{0, 1000, 0}, 940}, diffuse({1, 1, 1}));
    scene.add_sphere({{-15, -2, 0}, 8}, diffuse({1, 1, 1}));
    scene.add_sphere({{25, 0, -50}, 8}, diffuse({0, 1, 0}));
    scene.add_sphere({{-15, 20, 0}, 7}, scene.add_material(Material::mirror()));
    scene.add_sphere({{15, 20, 0}, 7}, scene.add_material(Material::dielectric(1.4f)));
}

/// The report's camera on the room: at (0, 0, 55) looking down -z, size x size pixels.
inline Pinhole room_camera(int size) {
    Pinhole cam;
    cam.eye = {0, 0, 55};
    cam.width = cam.height = size;
    return cam;
}

}  // namespace librt::testing
