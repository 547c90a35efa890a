#include "planar_light.h"

#include <librt/render/triangle_light.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>

namespace librt {
namespace {

// The texture coordinate at barycentrics b, interpolated as a hit on the triangle
// interpolates it (the slot's affine transform commutes with the interpolation).
glm::vec2 uv_at(const TriangleLight& light, glm::vec2 b) {
    return (1.0f - b.x - b.y) * light.uv0 + b.x * light.uv1 + b.y * light.uv2;
}

}  // namespace

glm::vec3 radiance_at(const TriangleLight& light, glm::vec2 b) {
    if (!light.texture) return light.radiance;
    return light.radiance * light.texture->lookup(uv_at(light, b));
}

glm::vec3 mean_texture_estimate(const TriangleLight& light) {
    if (!light.texture) return glm::vec3(1.0f);
    constexpr int n = 4;
    glm::vec3 sum(0.0f);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const glm::vec2 u{(float(i) + 0.5f) / n, (float(j) + 0.5f) / n};
            sum += light.texture->lookup(uv_at(light, sample_uniform_triangle(u)));
        }
    return sum / float(n * n);
}

LightLiSample sample_li(const TriangleLight& light, const glm::vec3& ref, glm::vec2 u) {
    const glm::vec3 e1 = light.p1 - light.p0, e2 = light.p2 - light.p0;
    const glm::vec3 c = glm::cross(e1, e2);
    const float len = glm::length(c);
    if (!(len > 0.0f)) return {};
    const glm::vec2 b = sample_uniform_triangle(u);
    const glm::vec3 p = light.p0 + b.x * e1 + b.y * e2;
    LightLiSample s = planar::toward(ref, p, c / len, 0.5f * len, light.radiance, light.two_sided);
    if (light.texture && s.valid()) s.radiance = radiance_at(light, b);
    return s;
}

float pdf_li(const TriangleLight& light, const glm::vec3& ref, const glm::vec3& wi) {
    const glm::vec3 e1 = light.p1 - light.p0, e2 = light.p2 - light.p0;
    const glm::vec3 c = glm::cross(e1, e2);
    const float len = glm::length(c);
    if (!(len > 0.0f)) return 0.0f;
    const glm::vec3 n = c / len;
    const planar::PlaneHit h = planar::hit_plane(light.p0, n, ref, wi, light.two_sided);
    if (!(h.t > 0.0f)) return 0.0f;
    // Barycentrics of the plane point (sub-triangle areas over the whole, signed along n).
    const glm::vec3 q = h.point - light.p0;
    const float u = glm::dot(glm::cross(q, e2), n) / len;
    const float v = glm::dot(glm::cross(e1, q), n) / len;
    if (u < 0.0f || v < 0.0f || u + v > 1.0f) return 0.0f;
    return planar::pdf_of(h, 0.5f * len);
}

glm::vec3 power(const TriangleLight& light) {
    // Lambertian emitter: L pi per unit area and side (pbrt 4th ed. 12.5), the texture by
    // its estimated mean.
    const float area = 0.5f * glm::length(glm::cross(light.p1 - light.p0, light.p2 - light.p0));
    const float sides = light.two_sided ? 2.0f : 1.0f;
    return light.radiance * light.mean_texture * (sides * k_pi * area);
}

}  // namespace librt
