#pragma once

// Shared by the light tests: a small scene (a diffuse floor with a sphere on it), the
// MIS path tracer against the brute-force one on it, and a light's irradiance estimated
// through its own sample_li.

#include "integrator_test_util.h"

#include <librt/integrator/integrators.h>
#include <librt/light/light.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace librt::testing {

// Irradiance at p (normal n) from a Lambertian polygon of radiance L (Lambert 1760; e.g.
// Arvo 1995 "Applications of irradiance tensors", eq. 1): E = L/2 sum_i Theta_i
// (n . g_i), Theta_i the angle between r_i = v_i - p and r_{i+1}, g_i the unit normal of
// the plane through p and that edge (r_i x r_{i+1} normalised).
inline double lambert_polygon_irradiance(const std::vector<glm::dvec3>& v, const glm::dvec3& p,
                                         const glm::dvec3& n, double radiance) {
    double sum = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const glm::dvec3 a = glm::normalize(v[i] - p);
        const glm::dvec3 b = glm::normalize(v[(i + 1) % v.size()] - p);
        const double theta = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
        sum += theta * glm::dot(n, glm::normalize(glm::cross(a, b)));
    }
    return std::fabs(0.5 * radiance * sum);
}

/// A 4 x 4 diffuse floor at y = 0 (albedo 0.7, facing up) with a sphere of radius 0.5 on
/// it (albedo 0.5): what the light tests light.
inline void add_floor_and_ball(Scene& scene) {
    const auto floor = scene.add_material(Material::diffuse(glm::vec3(0.7f)));
    TriangleMesh mesh;
    mesh.positions = {{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(mesh, floor);
    scene.add_sphere({{0.3f, 0.5f, 0.2f}, 0.5f},
                     scene.add_material(Material::diffuse(glm::vec3(0.5f, 0.6f, 0.4f))));
}

/// A 12 x 12 camera above the floor looking straight down.
inline Pinhole top_camera() {
    Pinhole cam;
    cam.eye = {0.0f, 1.8f, 0.0f};
    cam.forward = {0.0f, -1.0f, 0.0f};
    cam.up = {0.0f, 0.0f, -1.0f};
    cam.fov_degrees = 80.0f;
    cam.width = cam.height = 12;
    return cam;
}

/// A 12 x 12 camera at the side, seeing floor, ball and what is above the horizon.
inline Pinhole side_camera() {
    Pinhole cam;
    cam.eye = {0.0f, 1.0f, 3.5f};
    cam.width = cam.height = 12;
    cam.fov_degrees = 70.0f;
    return cam;
}

/// |a - b| <= k sqrt(se_a^2 + se_b^2) per channel for the whole image and its 2 x 2 blocks.
inline void expect_images_agree(const StatImage& a, const StatImage& b, const std::string& what,
                                double k = 5.0) {
    const int w = a.width, h = a.height;
    for (int by = -1; by < 2; ++by)
        for (int bx = 0; bx < 2; ++bx) {
            const bool whole = by < 0;
            const int x0 = whole ? 0 : bx * w / 2, x1 = whole ? w : (bx + 1) * w / 2;
            const int y0 = whole ? 0 : by * h / 2, y1 = whole ? h : (by + 1) * h / 2;
            if (whole && bx > 0) continue;
            const RegionEstimate ra = region(a, x0, y0, x1, y1), rb = region(b, x0, y0, x1, y1);
            for (int c = 0; c < 3; ++c) {
                const double tol = k * std::sqrt(ra.se2[c] + rb.se2[c]);
                EXPECT_LE(std::fabs(ra.mean[c] - rb.mean[c]), tol)
                    << what << (whole ? " whole image" : " block") << " (" << x0 << ", " << y0
                    << ") channel " << c << ": " << ra.mean[c] << " vs " << rb.mean[c];
            }
        }
}

/// Renders the scene with the MIS path tracer and the brute-force one (which finds
/// emitters only by BSDF sampling or escaping) and expects the same image; also that the
/// image is not black, so the test says something.
inline void expect_mis_equals_brute(const Scene& scene, const Pinhole& cam, int spp_mis,
                                    int spp_brute, const std::string& what) {
    PathTracerSettings s;
    s.max_depth = 3;
    PathTracer mis(s);
    BruteForcePathTracer brute(s);
    const StatImage a = render_stats(scene, mis, cam, spp_mis, 11);
    const StatImage b = render_stats(scene, brute, cam, spp_brute, 12);
    const RegionEstimate whole = region(a, 0, 0, a.width, a.height);
    EXPECT_GT(whole.mean.x + whole.mean.y + whole.mean.z, 1e-3) << what << ": black image";
    expect_images_agree(a, b, what);
}

/// Irradiance at p (unit normal n) from one light, estimated with n samples of its
/// sample_li (no occlusion): mean and standard error of L cos / pdf. Also checks that
/// pdf_li agrees with the samples' pdf (all but 1 in 10^4: float rounding can put a
/// sample that lies on the emitter's edge, or a pixel's, just across it).
struct Estimate {
    glm::dvec3 mean{0.0};
    glm::dvec3 se{0.0};
};
inline Estimate irradiance_by_sampling(const Light& light, const glm::vec3& p, const glm::vec3& n,
                                       int count, std::uint64_t seed) {
    Pcg32 rng(seed, 7);
    glm::dvec3 sum(0.0), sum2(0.0);
    int mismatches = 0;
    for (int i = 0; i < count; ++i) {
        const glm::vec2 u{rng.next_float(), rng.next_float()};
        const LightLiSample s = sample_li(light, p, u);
        if (!s.valid()) continue;
        if (!s.is_delta) {
            const float q = pdf_li(light, p, s.wi);
            if (!(std::fabs(q - s.pdf) <= 2e-3f * s.pdf)) ++mismatches;
        }
        const float c = std::max(0.0f, glm::dot(n, s.wi));
        const glm::dvec3 v = glm::dvec3(s.radiance) * double(c / s.pdf);
        sum += v;
        sum2 += v * v;
    }
    EXPECT_LE(mismatches, count / 10000) << "pdf_li disagrees with sample_li";
    Estimate e;
    e.mean = sum / double(count);
    const glm::dvec3 var = glm::max(glm::dvec3(0.0), sum2 / double(count) - e.mean * e.mean);
    e.se = glm::sqrt(var / double(count));
    return e;
}

}  // namespace librt::testing
