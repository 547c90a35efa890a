#include "light/emission.h"
#include "light/light_bounds.h"
#include "light/light_validation.h"
#include "light/planar_light.h"

#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/geometry/ray_offset.h>
#include <librt/light/disk_light.h>
#include <librt/sampling/warp.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace librt {

using detail::fail_light_parameter;

namespace {

/// An orthonormal frame (t, b, n) of the disk, n its unit front normal.
struct DiskFrame {
    glm::vec3 t, b, n;
};
DiskFrame frame_of(const DiskLight& light) {
    const glm::vec3 n = glm::normalize(light.normal);
    // Any axis not parallel to n gives a tangent.
    const glm::vec3 a = std::fabs(n.x) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 t = glm::normalize(glm::cross(a, n));
    return {t, glm::cross(n, t), n};
}

constexpr float kSector = 2.0f * kPi / float(kDiskLightSides);

/// Area of the regular N-gon of circumradius r: N/2 r^2 sin(2 pi / N).
float polygon_area(float r) { return 0.5f * float(kDiskLightSides) * r * r * std::sin(kSector); }

/// A point uniform by area on the polygon (frame f), from u in [0, 1)^2.
glm::vec3 polygon_point(const DiskLight& light, const DiskFrame& f, glm::vec2 u) {
    // All sectors have the same area: pick one with u.x, reuse its fraction for the point.
    const float x = u.x * float(kDiskLightSides);
    const int k = std::min(int(x), kDiskLightSides - 1);
    const glm::vec2 b = sample_uniform_triangle({x - float(k), u.y});
    const float a0 = kSector * float(k), a1 = kSector * float(k + 1);
    const glm::vec3 c0 = std::cos(a0) * f.t + std::sin(a0) * f.b;
    const glm::vec3 c1 = std::cos(a1) * f.t + std::sin(a1) * f.b;
    return light.center + light.radius * (b.x * c0 + b.y * c1);
}

}  // namespace

void validate(const DiskLight& light) {
    if (!finite(light.center))
        fail_light_parameter("disk light center", light.center, "must be finite");
    if (!finite(light.normal) || !(glm::length(light.normal) > 0.0f))
        fail_light_parameter("disk light normal", light.normal, "must be finite and non-zero");
    if (!std::isfinite(light.radius) || !(light.radius > 0.0f)) {
        std::ostringstream msg;
        msg << "disk light radius = " << light.radius << ": must be finite and > 0";
        throw Error(msg.str());
    }
    if (!finite(light.radiance) || light.radiance.x < 0.0f || light.radiance.y < 0.0f ||
        light.radiance.z < 0.0f)
        fail_light_parameter("disk light radiance", light.radiance, "must be finite and >= 0");
}

glm::vec3 disk_light_corner(const DiskLight& light, int i) {
    const DiskFrame f = frame_of(light);
    const float a = kSector * float(i % kDiskLightSides);
    return light.center + light.radius * (std::cos(a) * f.t + std::sin(a) * f.b);
}

LightLiSample sample_li(const DiskLight& light, const glm::vec3& ref, glm::vec2 u) {
    const DiskFrame f = frame_of(light);
    const glm::vec3 p = polygon_point(light, f, u);
    return planar::toward(ref, p, f.n, polygon_area(light.radius), light.radiance, light.two_sided);
}

float pdf_li(const DiskLight& light, const glm::vec3& ref, const glm::vec3& wi) {
    const DiskFrame f = frame_of(light);
    const planar::PlaneHit h = planar::hit_plane(light.center, f.n, ref, wi, light.two_sided);
    if (!(h.t > 0.0f)) return 0.0f;
    const glm::vec3 q = h.point - light.center;
    const float x = glm::dot(q, f.t), y = glm::dot(q, f.b);
    // Inside the polygon: the projection on the sector's bisector is within the apothem.
    float a = std::atan2(y, x);
    if (a < 0.0f) a += 2.0f * kPi;
    const float k = std::floor(a / kSector);
    const float mid = (k + 0.5f) * kSector;
    const float apothem = light.radius * std::cos(0.5f * kSector);
    if (x * std::cos(mid) + y * std::sin(mid) > apothem) return 0.0f;
    return planar::pdf_of(h, polygon_area(light.radius));
}

LightLeSample sample_le(const DiskLight& light, glm::vec2 u_pos, glm::vec2 u_dir) {
    const float area = polygon_area(light.radius);
    if (!(area > 0.0f) || !std::isfinite(area) || !finite(light.normal)) return {};
    const DiskFrame f = frame_of(light);  // a zero normal gives NaNs: leave_surface's check
    LightLeSample s = emission::leave_surface(polygon_point(light, f, u_pos), f.n, 1.0f / area,
                                              light.radiance, light.two_sided, u_dir);
    // Its fan's test rounds at the corners' magnitude (LightLeSample::offset).
    s.offset = ray_offset_scale(glm::abs(light.center) + glm::vec3(light.radius));
    return s;
}

LightLePdf pdf_le(const DiskLight& light, const glm::vec3& /*origin*/, const glm::vec3& /*normal*/,
                  const glm::vec3& direction) {
    const float area = polygon_area(light.radius);
    const float len = glm::length(light.normal);
    if (!(area > 0.0f) || !std::isfinite(area) || !(len > 0.0f) || !std::isfinite(len)) return {};
    // The unit normal as frame_of makes it, so that sample_le's density is this one.
    const glm::vec3 n = glm::normalize(light.normal);
    return {1.0f / area, emission::direction_pdf(n, light.two_sided, direction)};
}

glm::vec3 power(const DiskLight& light) {
    // Lambertian emitter: L pi per unit area and emitting side.
    return light.radiance * (kPi * polygon_area(light.radius) * (light.two_sided ? 2.0f : 1.0f));
}

LightBounds DiskLight::bounds() const {
    LightBounds b = detail::finite_light_bounds(center, radius, power(*this));
    detail::bound_planar(b, normal, !two_sided);
    return b;
}

}  // namespace librt
