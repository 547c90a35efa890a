#pragma once

// What the lights' sample_le and pdf_le share (private): the cosine-weighted directions
// leaving an area light, the uniform cone of a spot or a soft sun, and the disk from which
// the rays of a light at infinity start.

#include <librt/core/finite.h>
#include <librt/light/light_sample.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace librt::emission {

// ---- Area lights: a point on the surface, then a direction leaving it ----

/// The density of a direction leaving a Lambertian emitter of unit front normal n: one-
/// sided, cosine-weighted about n (cos / pi, 0 behind); two-sided, a side with
/// probability 1/2 then cosine-weighted about its normal (|cos| / (2 pi)).
[[nodiscard]] inline float direction_pdf(const glm::vec3& n, bool two_sided,
                                         const glm::vec3& direction) {
    const float c = glm::dot(direction, n);
    if (!two_sided) return cosine_hemisphere_pdf(c);
    return 0.5f * cosine_hemisphere_pdf(std::fabs(c));
}

/// The ray leaving point p of a Lambertian emitter (unit front normal n, emitting
/// `radiance` there) whose points are drawn uniformly by area (pdf_pos = 1 / A). The
/// direction is cosine-weighted about the normal of the side it leaves, which is the front
/// for a one-sided emitter, and for a two-sided one the front when u.x < 1/2 (u.x then
/// rescaled to [0, 1) for the direction). Cosine weighting makes the weight L |cos| /
/// (pdf_pos pdf_dir) = L A pi (twice that two-sided): constant, the light's power.
/// Invalid when pdf_pos is not finite and > 0, the point or normal is degenerate or the
/// direction grazes the surface.
[[nodiscard]] inline LightLeSample leave_surface(const glm::vec3& p, const glm::vec3& n,
                                                 float pdf_pos, const glm::vec3& radiance,
                                                 bool two_sided, glm::vec2 u) {
    if (!(pdf_pos > 0.0f) || !(pdf_pos < std::numeric_limits<float>::infinity())) return {};
    if (!finite(p) || !finite(n) || !(glm::dot(n, n) > 0.5f)) return {};
    glm::vec3 side = n;
    if (two_sided) {
        // u.x < 1/2: the front, u.x in [0, 1/2) stretched to [0, 1); else the back. Both
        // halves map to [0, 1) exactly (a product or difference by powers of two).
        if (u.x < 0.5f) {
            u.x *= 2.0f;
        } else {
            u.x = 2.0f * u.x - 1.0f;
            side = -n;
        }
    }
    const glm::vec3 d = glm::normalize(sample_cosine_hemisphere(side, u));
    // The density from the direction itself, as pdf_le computes it, so the two agree.
    const float pdf_dir = direction_pdf(n, two_sided, d);
    if (!(pdf_dir > 0.0f)) return {};
    LightLeSample s;
    s.origin = p;
    s.direction = d;
    s.normal = side;
    s.radiance = radiance;
    s.pdf_pos = pdf_pos;
    s.pdf_dir = pdf_dir;
    return s;
}

// ---- Cones: a spot light's directions, a soft sun's ----

/// 1 - cos(theta) as 2 sin^2(theta / 2): without the cancellation that loses a small
/// angle's digits.
[[nodiscard]] inline float one_minus_cos(float theta) {
    const float s = std::sin(0.5f * theta);
    return 2.0f * s * s;
}

/// A direction uniform in the cone of directions within angle theta of unit `axis`, given
/// omc = 1 - cos(theta): 1 - cos uniform in [0, omc) (uniform in solid angle, pbrt 4th ed.
/// A.5.4), sin from (1 - cos)(1 + cos) so that small cones keep their digits.
[[nodiscard]] inline glm::vec3 sample_cone(const glm::vec3& axis, float omc, glm::vec2 u) {
    const float w = u.x * omc;
    const float sin_t = std::sqrt(std::max(0.0f, w * (2.0f - w)));
    const float phi = 2.0f * kPi * u.y;
    const glm::vec3 local(sin_t * std::cos(phi), sin_t * std::sin(phi), 1.0f - w);
    return glm::normalize(Frame::from_normal(axis).to_world(local));
}

/// Whether unit direction d is in that cone: |d - axis|^2 = 2 (1 - cos) for unit vectors,
/// which, unlike a comparison of cosines near 1, keeps the digits of small angles.
[[nodiscard]] inline bool in_cone(const glm::vec3& d, const glm::vec3& axis, float omc) {
    const glm::vec3 chord = d - axis;
    return glm::dot(chord, chord) <= 2.0f * omc;
}

/// Density per solid angle of sample_cone: 1 / (2 pi omc), the cone's solid angle
/// inverted; 0 when that is not finite.
[[nodiscard]] inline float cone_pdf(float omc) {
    const float pdf = 1.0f / (2.0f * kPi * omc);
    return pdf > 0.0f && pdf < std::numeric_limits<float>::infinity() ? pdf : 0.0f;
}

// ---- Lights at infinity: rays from a disk facing the scene ----

/// The density of a ray origin on the disk of radius R: 1 / (pi R^2); 0 for a scene sphere
/// that is not finite with R > 0.
[[nodiscard]] inline float disk_pdf(const SceneSphere& scene) {
    if (!finite(scene.center) || !std::isfinite(scene.radius)) return 0.0f;
    const float pdf = uniform_disk_pdf() / (scene.radius * scene.radius);
    return pdf > 0.0f && pdf < std::numeric_limits<float>::infinity() ? pdf : 0.0f;
}

/// The ray of a light at infinity arriving along unit `wi` (pointing toward the light):
/// direction -wi, origin uniform on the disk of radius R perpendicular to wi centred at
/// center + R wi (tangent to the scene sphere on the light's side, pbrt 4th ed. 12.4's
/// choice), so it covers every line along wi that meets the sphere. The normal is the
/// direction: the disk faces the way its rays go, |cos| = 1. Invalid for a degenerate
/// scene sphere or direction.
[[nodiscard]] inline LightLeSample from_disk(const SceneSphere& scene, const glm::vec3& wi,
                                             const glm::vec3& radiance, float pdf_dir,
                                             glm::vec2 u) {
    const float pdf_pos = disk_pdf(scene);
    if (!(pdf_pos > 0.0f) || !(pdf_dir > 0.0f) || !finite(wi)) return {};
    const Frame f = Frame::from_normal(wi);
    const glm::vec2 d = sample_uniform_disk_concentric(u);
    LightLeSample s;
    s.origin = scene.center + scene.radius * (wi + d.x * f.t + d.y * f.b);
    s.direction = -wi;
    s.normal = -wi;
    s.radiance = radiance;
    s.pdf_pos = pdf_pos;
    s.pdf_dir = pdf_dir;
    return s;
}

}  // namespace librt::emission
