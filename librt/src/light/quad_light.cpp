#include "light/emission.h"
#include "light/light_bounds.h"
#include "light/light_validation.h"
#include "light/planar_light.h"

#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/geometry/ray_offset.h>
#include <librt/light/quad_light.h>
#include <librt/sampling/warp.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>

namespace librt {

using detail::fail_light_parameter;

void validate(const QuadLight& light) {
    if (!finite(light.corner))
        fail_light_parameter("quad light corner", light.corner, "must be finite");
    if (!finite(light.edge0))
        fail_light_parameter("quad light edge0", light.edge0, "must be finite");
    if (!finite(light.edge1))
        fail_light_parameter("quad light edge1", light.edge1, "must be finite");
    const float area = glm::length(glm::cross(light.edge0, light.edge1));
    if (!(area > 0.0f) || !std::isfinite(area))
        fail_light_parameter("quad light edge1", light.edge1, "spans no area with edge0");
    if (!finite(light.radiance) || light.radiance.x < 0.0f || light.radiance.y < 0.0f ||
        light.radiance.z < 0.0f)
        fail_light_parameter("quad light radiance", light.radiance, "must be finite and >= 0");
}

LightLiSample sample_li(const QuadLight& light, const glm::vec3& ref, glm::vec2 u) {
    const glm::vec3 c = glm::cross(light.edge0, light.edge1);
    const float area = glm::length(c);
    if (!(area > 0.0f)) return {};
    const glm::vec3 p = light.corner + u.x * light.edge0 + u.y * light.edge1;
    return planar::toward(ref, p, c / area, area, light.radiance, light.two_sided);
}

float pdf_li(const QuadLight& light, const glm::vec3& ref, const glm::vec3& wi) {
    const glm::vec3 c = glm::cross(light.edge0, light.edge1);
    const float area = glm::length(c);
    if (!(area > 0.0f)) return 0.0f;
    const glm::vec3 n = c / area;
    const planar::PlaneHit h = planar::hit_plane(light.corner, n, ref, wi, light.two_sided);
    if (!(h.t > 0.0f)) return 0.0f;
    // Parallelogram coordinates of the plane point: q = s e0 + t e1 solved with cross
    // products (Cramer's rule in the plane).
    const glm::vec3 q = h.point - light.corner;
    const float s = glm::dot(glm::cross(q, light.edge1), n) / area;
    const float t = glm::dot(glm::cross(light.edge0, q), n) / area;
    if (s < 0.0f || s > 1.0f || t < 0.0f || t > 1.0f) return 0.0f;
    return planar::pdf_of(h, area);
}

LightLeSample sample_le(const QuadLight& light, glm::vec2 u_pos, glm::vec2 u_dir) {
    const glm::vec3 c = glm::cross(light.edge0, light.edge1);
    const float area = glm::length(c);
    if (!(area > 0.0f) || !std::isfinite(area)) return {};
    const glm::vec3 p = light.corner + u_pos.x * light.edge0 + u_pos.y * light.edge1;
    LightLeSample s =
        emission::leave_surface(p, c / area, 1.0f / area, light.radiance, light.two_sided, u_dir);
    // Its two triangles' test rounds at the corners' magnitude (LightLeSample::offset).
    const glm::vec3 far = light.corner + light.edge0 + light.edge1;
    s.offset = ray_offset_scale(glm::max(
        glm::max(glm::abs(light.corner), glm::abs(far)),
        glm::max(glm::abs(light.corner + light.edge0), glm::abs(light.corner + light.edge1))));
    return s;
}

LightLePdf pdf_le(const QuadLight& light, const glm::vec3& /*origin*/, const glm::vec3& /*normal*/,
                  const glm::vec3& direction) {
    const glm::vec3 c = glm::cross(light.edge0, light.edge1);
    const float area = glm::length(c);
    if (!(area > 0.0f) || !std::isfinite(area)) return {};
    return {1.0f / area, emission::direction_pdf(c / area, light.two_sided, direction)};
}

glm::vec3 power(const QuadLight& light) {
    // Lambertian emitter: L pi per unit area and emitting side.
    const float area = glm::length(glm::cross(light.edge0, light.edge1));
    return light.radiance * (kPi * area * (light.two_sided ? 2.0f : 1.0f));
}

LightBounds QuadLight::bounds() const {
    const glm::vec3 c = corner + 0.5f * (edge0 + edge1);
    // Half the longer diagonal reaches every corner from the centre.
    const float r = 0.5f * std::max(glm::length(edge0 + edge1), glm::length(edge0 - edge1));
    LightBounds b = detail::finite_light_bounds(c, r, power(*this));
    detail::bound_planar(b, glm::cross(edge0, edge1), !two_sided);
    return b;
}

}  // namespace librt
