#pragma once

#include <librt/core/constants.h>
#include <librt/export.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

// Stateless warps from a uniform sample u in [0,1)^2 to a distribution, each with its
// pdf. Local directions are in a frame whose +z is the normal (or the cone axis).

namespace librt {

/// An orthonormal, right-handed frame (t, b, n) with t x b = n.
struct Frame {
    glm::vec3 t{1.0f, 0.0f, 0.0f};  ///< tangent, local +x
    glm::vec3 b{0.0f, 1.0f, 0.0f};  ///< bitangent, local +y
    glm::vec3 n{0.0f, 0.0f, 1.0f};  ///< normal, local +z

    /// Local coordinates (x along t, y along b, z along n) to world.
    [[nodiscard]] glm::vec3 to_world(const glm::vec3& v) const {
        return v.x * t + v.y * b + v.z * n;
    }

    /// World vector to local coordinates.
    [[nodiscard]] glm::vec3 to_local(const glm::vec3& v) const {
        return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)};
    }

    /// A frame around a unit normal, branchless and continuous except at n.z = 0's
    /// sign flip (Duff et al. 2017, "Building an orthonormal basis, revisited"):
    /// exact at n = (0, 0, -1), where Frisvad's original divides by zero.
    [[nodiscard]] static Frame from_normal(const glm::vec3& normal) {
        const float sign = std::copysign(1.0f, normal.z);
        const float a = -1.0f / (sign + normal.z);
        const float c = normal.x * normal.y * a;
        return {{1.0f + sign * normal.x * normal.x * a, sign * c, -sign * normal.x},
                {c, sign + normal.y * normal.y * a, -normal.y},
                normal};
    }
};

/// Cosine-weighted hemisphere around +z, the report's formula: with (r1, r2) = u,
/// (cos(2 pi r1) sqrt(1 - r2), sin(2 pi r1) sqrt(1 - r2), sqrt(r2)). pdf: cosine_hemisphere_pdf.
[[nodiscard]] inline glm::vec3 sample_cosine_hemisphere(glm::vec2 u) {
    const float phi = 2.0f * kPi * u.x;
    const float r = std::sqrt(1.0f - u.y);  // sin(theta), as cos^2(theta) = r2
    return {std::cos(phi) * r, std::sin(phi) * r, std::sqrt(u.y)};
}

/// Density per solid angle of sample_cosine_hemisphere: cos(theta) / pi, 0 below the horizon.
[[nodiscard]] inline float cosine_hemisphere_pdf(float cos_theta) {
    return cos_theta > 0.0f ? cos_theta * kInvPi : 0.0f;
}

/// Cosine-weighted world direction around a unit normal; pdf: cosine_hemisphere_pdf(dot(n, w)).
[[nodiscard]] inline glm::vec3 sample_cosine_hemisphere(const glm::vec3& normal, glm::vec2 u) {
    return Frame::from_normal(normal).to_world(sample_cosine_hemisphere(u));
}

/// Uniform direction on the unit sphere (z uniform in [-1, 1], Archimedes).
[[nodiscard]] inline glm::vec3 sample_uniform_sphere(glm::vec2 u) {
    const float z = 1.0f - 2.0f * u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));  // sin(theta)
    const float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Density per solid angle of sample_uniform_sphere: 1 / (4 pi).
[[nodiscard]] constexpr float uniform_sphere_pdf() { return 0.25f * kInvPi; }

/// Uniform direction on the hemisphere z >= 0.
[[nodiscard]] inline glm::vec3 sample_uniform_hemisphere(glm::vec2 u) {
    const float z = u.x;
    const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));  // sin(theta)
    const float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

/// Density per solid angle of sample_uniform_hemisphere: 1 / (2 pi).
[[nodiscard]] constexpr float uniform_hemisphere_pdf() { return 0.5f * kInvPi; }

/// Uniform direction in the cone of half-angle theta_max around +z (cos theta uniform in
/// [cos_theta_max, 1]). For a cone known by its sin^2, sample_sphere_visible keeps more
/// digits; here 1 - cos_theta_max is taken as given.
[[nodiscard]] LIBRT_API glm::vec3 sample_uniform_cone(glm::vec2 u, float cos_theta_max);

/// Density per solid angle of sample_uniform_cone: 1 / (2 pi (1 - cos_theta_max)), the
/// inverse of the cone's solid angle.
[[nodiscard]] inline float uniform_cone_pdf(float cos_theta_max) {
    return 1.0f / (2.0f * kPi * (1.0f - cos_theta_max));
}

/// Uniform point on the unit disk by Shirley and Chiu's concentric map: squares of
/// [-1,1]^2 become rings, so strata stay compact and adjacent (unlike sqrt(u1), 2 pi u2).
[[nodiscard]] LIBRT_API glm::vec2 sample_uniform_disk_concentric(glm::vec2 u);

/// Density per unit area of sample_uniform_disk_concentric: 1 / pi.
[[nodiscard]] constexpr float uniform_disk_pdf() { return kInvPi; }

/// Uniform barycentrics (u, v) on a triangle, in Triangle's convention
/// point = (1 - u - v) p0 + u p1 + v p2; pdf 1 / area.
[[nodiscard]] inline glm::vec2 sample_uniform_triangle(glm::vec2 u) {
    const float s = std::sqrt(u.x);
    // Pick a distance 1 - s from p0 with density ~ s (edge lengths grow linearly), then a
    // uniform point along that segment.
    return {s * (1.0f - u.y), s * u.y};
}

/// A sampled point on a sphere light.
struct SphereSample {
    glm::vec3 point{0.0f};   ///< on the sphere surface
    glm::vec3 normal{0.0f};  ///< outward unit normal at point
    float pdf = 0.0f;        ///< per unit area or per unit solid angle, as the sampler says
};

/// Uniform point on the whole sphere surface; pdf per unit AREA = 1 / (4 pi r^2).
[[nodiscard]] LIBRT_API SphereSample sample_sphere_area(const glm::vec3& center, float radius,
                                                        glm::vec2 u);

/// A point on the part of a sphere visible from ref, found by sampling the cone of
/// directions the sphere subtends at ref uniformly; pdf per unit SOLID ANGLE at ref,
/// 1 / (2 pi (1 - cos theta_max)). Stays accurate for tiny cones (far or small lights).
/// When ref is inside (or on) the sphere there is no cone: the point is sampled uniformly
/// over the area and the pdf converted to solid angle (dist^2 / (|cos| 4 pi r^2)), 0 if
/// degenerate. The normal is outward, so from inside it faces away from ref.
[[nodiscard]] LIBRT_API SphereSample sample_sphere_visible(const glm::vec3& center, float radius,
                                                           const glm::vec3& ref, glm::vec2 u);

/// A direction from a point toward a sphere, and how far the sphere is along it.
struct SphereDirectionSample {
    glm::vec3 direction{0.0f};  ///< unit, from ref toward the sphere
    float distance = 0.0f;      ///< from ref to the first point of the sphere along direction
    float pdf = 0.0f;           ///< per unit solid angle at ref; 0 when degenerate
};

/// sample_sphere_visible for light sampling, where only the direction to the sphere and
/// its distance are needed: the same cone, sampled with the same u, but neither the
/// point nor its normal is built (from outside, 4 square roots and 3 divisions instead
/// of the 10 and 10 that the point, its normal and the shadow ray toward it cost). From
/// inside (or on) the sphere it falls back to sample_sphere_visible.
[[nodiscard]] LIBRT_API SphereDirectionSample sample_sphere_direction(const glm::vec3& center,
                                                                      float radius,
                                                                      const glm::vec3& ref,
                                                                      glm::vec2 u);

/// The density per solid angle at ref with which sample_sphere_visible picks direction
/// wi (unit length), for weighting lights against BSDF samples; 0 if wi misses the sphere.
[[nodiscard]] LIBRT_API float sphere_visible_pdf(const glm::vec3& center, float radius,
                                                 const glm::vec3& ref, const glm::vec3& wi);

}  // namespace librt
