#include <librt/sampling/warp.h>

namespace librt {

namespace {

// Direction at polar angle theta around +z, given w = 1 - cos(theta) (which keeps the
// digits of small angles that cos(theta) itself loses) and the azimuth sample u_phi.
glm::vec3 cone_direction(float one_minus_cos, float u_phi) {
    const float cos_theta = 1.0f - one_minus_cos;
    // sin^2 = (1 - cos)(1 + cos): no cancellation, unlike 1 - cos^2.
    const float sin_theta = std::sqrt(std::max(0.0f, one_minus_cos * (2.0f - one_minus_cos)));
    const float phi = 2.0f * kPi * u_phi;
    return {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta};
}

// The cone a sphere subtends at a point outside it, from sin^2(theta_max) = r^2 / d^2.
struct SubtendedCone {
    float cos_max;
    float one_minus_cos_max;
};

SubtendedCone subtended_cone(float sin2_max) {
    const float cos_max = std::sqrt(std::max(0.0f, 1.0f - sin2_max));
    // 1 - cos(theta_max) = sin^2 / (1 + cos): exact, and for tiny cones it is the Taylor
    // form sin^2 / 2 instead of collapsing to 1 - 1 = 0.
    return {cos_max, sin2_max / (1.0f + cos_max)};
}

// Uniform in the cone: 1 / solid angle = 1 / (2 pi (1 - cos(theta_max))); 0 if degenerate.
float cone_pdf(float one_minus_cos_max) {
    return one_minus_cos_max > 0.0f ? 1.0f / (2.0f * kPi * one_minus_cos_max) : 0.0f;
}

}  // namespace

glm::vec3 sample_uniform_cone(glm::vec2 u, float cos_theta_max) {
    // 1 - cos(theta) uniform in [0, 1 - cos_theta_max): uniform in solid angle.
    return cone_direction(u.x * (1.0f - cos_theta_max), u.y);
}

glm::vec2 sample_uniform_disk_concentric(glm::vec2 u) {
    const float a = 2.0f * u.x - 1.0f;
    const float b = 2.0f * u.y - 1.0f;
    if (a == 0.0f && b == 0.0f) return {0.0f, 0.0f};
    // The square's ring at "radius" max(|a|, |b|) maps to the circle of that radius; the
    // position along the ring maps linearly to the angle, keeping areas equal.
    float r, phi;
    if (std::abs(a) > std::abs(b)) {
        r = a;
        phi = 0.25f * kPi * (b / a);
    } else {
        r = b;
        phi = 0.5f * kPi - 0.25f * kPi * (a / b);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}

SphereSample sample_sphere_area(const glm::vec3& center, float radius, glm::vec2 u) {
    const glm::vec3 n = sample_uniform_sphere(u);
    // Uniform on the surface: 1 / area = 1 / (4 pi r^2).
    return {center + radius * n, n, 1.0f / (4.0f * kPi * radius * radius)};
}

SphereSample sample_sphere_visible(const glm::vec3& center, float radius, const glm::vec3& ref,
                                   glm::vec2 u) {
    const glm::vec3 to_center = center - ref;
    const float dist2 = glm::dot(to_center, to_center);
    const float r2 = radius * radius;
    if (!(dist2 > r2)) {
        // Inside or on the sphere: every direction sees it once. Sample the area and
        // convert: pdf_solid_angle = pdf_area * dist^2 / |cos at the light|.
        SphereSample s = sample_sphere_area(center, radius, u);
        const glm::vec3 to_point = s.point - ref;
        const float d2 = glm::dot(to_point, to_point);
        const float cos_light = std::abs(glm::dot(s.normal, to_point)) / std::sqrt(d2);
        s.pdf = (d2 > 0.0f && cos_light > 0.0f) ? s.pdf * d2 / cos_light : 0.0f;
        return s;
    }
    const float sin2_max = r2 / dist2;
    const auto [cos_max, one_minus_cos_max] = subtended_cone(sin2_max);
    const float sin_max = std::sqrt(sin2_max);

    // Direction at (theta, phi) around the axis ref -> center: 1 - cos(theta) uniform in
    // [0, 1 - cos(theta_max)), as in sample_uniform_cone.
    const float one_minus_cos = u.x * one_minus_cos_max;
    const float cos_theta = 1.0f - one_minus_cos;
    const float sin2_theta = one_minus_cos * (2.0f - one_minus_cos);
    const float sin_theta = std::sqrt(sin2_theta);
    const float phi = 2.0f * kPi * u.y;

    // Where that ray first meets the sphere, as the angle alpha at the centre between
    // the axis back to ref and the normal. q = (d sin(theta) / r)^2 <= 1.
    const float q = std::min(1.0f, sin2_theta / sin2_max);
    const float root = std::sqrt(std::max(0.0f, 1.0f - q));
    // cos(alpha) = (d / r) sin^2(theta) + cos(theta) sqrt(1 - q): a sum of non-negatives.
    const float cos_alpha = sin_theta * std::sqrt(q) + cos_theta * root;
    // sin(alpha) = t sin(theta) / r with the near hit distance t = (d^2 - r^2) /
    // (d cos(theta) + sqrt(r^2 - d^2 sin^2(theta))), free of the cancellation in
    // d cos(theta) - sqrt(...) and accurate where sqrt(1 - cos^2(alpha)) is not.
    const float sin_alpha =
        sin_theta * (cos_max * cos_max) / (sin_max * (cos_theta + sin_max * root));

    const Frame frame = Frame::from_normal(to_center / std::sqrt(dist2));
    const glm::vec3 n_local(sin_alpha * std::cos(phi), sin_alpha * std::sin(phi), -cos_alpha);
    const glm::vec3 normal = glm::normalize(frame.to_world(n_local));
    return {center + radius * normal, normal, cone_pdf(one_minus_cos_max)};
}

SphereDirectionSample sample_sphere_direction(const glm::vec3& center, float radius,
                                              const glm::vec3& ref, glm::vec2 u) {
    const glm::vec3 to_center = center - ref;
    const float dist2 = glm::dot(to_center, to_center);
    const float r2 = radius * radius;
    if (!(dist2 > r2)) {
        const SphereSample s = sample_sphere_visible(center, radius, ref, u);
        const glm::vec3 to_point = s.point - ref;
        const float distance = glm::length(to_point);
        if (!(distance > 0.0f) || !(s.pdf > 0.0f)) return {};
        return {to_point / distance, distance, s.pdf};
    }
    const float one_minus_cos_max = subtended_cone(r2 / dist2).one_minus_cos_max;
    const float one_minus_cos = u.x * one_minus_cos_max;
    // The local direction first: its sincos call then comes before the frame exists, so
    // fewer values are saved and restored around it (the same values).
    const glm::vec3 local = cone_direction(one_minus_cos, u.y);
    const float cos_theta = 1.0f - one_minus_cos;
    const float sin2_theta = one_minus_cos * (2.0f - one_minus_cos);
    const float dist = std::sqrt(dist2);
    const Frame frame = Frame::from_normal(to_center * (1.0f / dist));
    const glm::vec3 direction = frame.to_world(local);
    // Near root of the ray-sphere quadratic at angle theta off the axis:
    // t = d cos(theta) - sqrt(r^2 - d^2 sin^2(theta)), written as (d^2 - r^2) /
    // (d cos(theta) + sqrt(...)) to avoid the cancellation, with d^2 - r^2 = (d - r)(d + r).
    const float half_chord = std::sqrt(std::max(0.0f, r2 - dist2 * sin2_theta));
    const float distance = (dist - radius) * (dist + radius) / (dist * cos_theta + half_chord);
    return {direction, distance, cone_pdf(one_minus_cos_max)};
}

float sphere_visible_pdf(const glm::vec3& center, float radius, const glm::vec3& ref,
                         const glm::vec3& wi) {
    const glm::vec3 to_center = center - ref;
    const float dist2 = glm::dot(to_center, to_center);
    const float r2 = radius * radius;
    const float along = glm::dot(wi, to_center);  // b of the ray-sphere quadratic, negated
    // Squared distance from the centre to the line ref + t wi, without cancellation.
    const glm::vec3 perp = glm::cross(wi, to_center);
    const float miss2 = glm::dot(perp, perp);
    if (!(dist2 > r2)) {
        // Inside: the ray exits at t = along + sqrt(r^2 - miss^2), where |cos| at the
        // light is sqrt(r^2 - miss^2) / r; pdf = t^2 / (|cos| 4 pi r^2).
        const float half_chord = std::sqrt(std::max(0.0f, r2 - miss2));
        const float t = along + half_chord;
        if (!(t > 0.0f) || !(half_chord > 0.0f)) return 0.0f;
        return t * t / (4.0f * kPi * radius * half_chord);
    }
    if (along <= 0.0f || miss2 > r2) return 0.0f;  // outside the cone
    return cone_pdf(subtended_cone(r2 / dist2).one_minus_cos_max);
}

}  // namespace librt
