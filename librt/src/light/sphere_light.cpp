#include "light/emission.h"
#include "light/light_bounds.h"
#include "light/light_validation.h"
#include "light/sphere_light_cuts.h"

#include <librt/core/constants.h>
#include <librt/core/error.h>
#include <librt/light/sphere_light.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <sstream>

namespace librt {
void validate(const SphereLight& light) {
    detail::require_finite("sphere light center", light.sphere.center);
    if (!std::isfinite(light.sphere.radius) || !(light.sphere.radius > 0.0f)) {
        std::ostringstream msg;
        msg << "sphere light radius = " << light.sphere.radius << ": must be finite and > 0";
        throw Error(msg.str());
    }
    detail::require_finite_non_negative("sphere light radiance", light.radiance);
}

namespace {

/// 2 pi r^2 (z1 - z0): the area of the zone z0 <= n . a <= z1 of a sphere of radius r
/// (Archimedes' hat-box theorem).
double cap_area(double radius, const VisibleCap& cap) {
    return 2.0 * kPiDouble * radius * radius * (cap.z1 - cap.z0);
}

/// The solid-angle density of a point uniform in area on the cap, seen from ref at
/// distance^2 d2 with cosine cos_light at the light: d^2 / (A cos) (pbrt-v4, 4.2.3, the
/// area-to-solid-angle Jacobian); 0 when not finite and positive.
float cap_pdf(double d2, double area, double cos_light) {
    const double pdf = d2 / (area * cos_light);
    return pdf > 0.0 && pdf < double(std::numeric_limits<float>::max()) ? float(pdf) : 0.0f;
}

}  // namespace

LightLiSample sample_li_cut(const SphereLight& light, const glm::vec3& ref, glm::vec2 u) {
    const VisibleCap cap = visible_cap(light, ref);
    if (cap.kind == CapKind::Whole) return sample_li_cone(light, ref, u);
    if (cap.kind == CapKind::Hidden) return {};
    const SphereCut& c = *cap.cut;
    // Uniform in area on the zone: z = n . a uniform in [z0, z1], phi uniform (Archimedes).
    const double z = std::min(cap.z1, cap.z0 + double(u.x) * (cap.z1 - cap.z0));
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 2.0 * kPiDouble * double(u.y);
    const glm::dvec3 n = z * c.axis + s * (std::cos(phi) * c.tangent + std::sin(phi) * c.bitangent);
    const double r = double(light.sphere.radius);
    const glm::dvec3 q = glm::dvec3(light.sphere.center) + r * n;
    const glm::dvec3 v = q - glm::dvec3(ref);
    const double d2 = glm::dot(v, v);
    if (!(d2 > 0.0)) return {};
    const double d = std::sqrt(d2);
    const glm::dvec3 wi = v / d;
    // Facing away from ref: hidden behind the light's own front (a sphere's visible part
    // from outside is exactly its front-facing part).
    const double cos_light = -glm::dot(n, wi);
    if (!(cos_light > 0.0)) return {};
    const float pdf = cap_pdf(d2, cap_area(r, cap), cos_light);
    if (!(pdf > 0.0f)) return {};
    return {glm::vec3(wi), light.radiance, pdf, float(d), false};
}

float pdf_li(const SphereLight& light, const glm::vec3& ref, const glm::vec3& wi) {
    if (light.cuts != nullptr) {
        const VisibleCap cap = visible_cap(light, ref);
        if (cap.kind == CapKind::Hidden) return 0.0f;
        if (cap.kind == CapKind::Cap) {
            // The near root of the ray with the light (ref is outside it: visible_cap is
            // Whole inside), as t = c / (-b + sqrt(disc)) for a unit direction: the
            // quadratic t^2 + 2 b t + c with b = oc . w, c = |oc|^2 - r^2, the
            // discriminant r^2 - |oc - b w|^2 without cancellation (Numerical Recipes 5.6).
            const glm::dvec3 w = glm::normalize(glm::dvec3(wi));
            const glm::dvec3 cl(light.sphere.center);
            const double r = double(light.sphere.radius);
            const glm::dvec3 oc = glm::dvec3(ref) - cl;
            const double b = glm::dot(oc, w);
            const glm::dvec3 perp = oc - b * w;
            const double disc = r * r - glm::dot(perp, perp);
            if (!(b < 0.0) || !(disc >= 0.0)) return 0.0f;
            const double c = glm::dot(oc, oc) - r * r;
            const double t = c / (-b + std::sqrt(disc));
            if (!(t > 0.0)) return 0.0f;
            const glm::dvec3 n = (oc + t * w) / r;
            const double z = glm::dot(n, cap.cut->axis);
            if (!(z >= cap.z0 && z <= cap.z1)) return 0.0f;
            const double cos_light = -glm::dot(n, w);
            if (!(cos_light > 0.0)) return 0.0f;
            return cap_pdf(t * t, cap_area(r, cap), cos_light);
        }
    }
    const float p = sphere_visible_pdf(light.sphere.center, light.sphere.radius, ref, wi);
    return std::isfinite(p) ? p : 0.0f;
}

namespace {

/// 1 / (4 pi r^2), in double so that a tiny radius does not underflow; 0 for a radius not
/// > 0 or when the result is not a finite float.
float sphere_area_pdf(float radius) {
    if (!(radius > 0.0f)) return 0.0f;
    const double pdf = 1.0 / (4.0 * kPiDouble * double(radius) * double(radius));
    return pdf > 0.0 && pdf < double(std::numeric_limits<float>::max()) ? float(pdf) : 0.0f;
}

}  // namespace

LightLeSample sample_le(const SphereLight& light, glm::vec2 u_pos, glm::vec2 u_dir) {
    const float pdf_pos = sphere_area_pdf(light.sphere.radius);
    if (!(pdf_pos > 0.0f) || !finite(light.sphere.center)) return {};
    // Uniform by area, then cosine-weighted: the weight L cos / (pdf_pos pdf_dir) is the
    // power L pi 4 pi r^2 for every ray.
    const glm::vec3 n = sample_uniform_sphere(u_pos);
    const glm::vec3 p = light.sphere.center + light.sphere.radius * n;
    return emission::leave_surface(p, n, pdf_pos, light.radiance, false, u_dir);
}

LightLePdf pdf_le(const SphereLight& light, const glm::vec3& /*origin*/, const glm::vec3& normal,
                  const glm::vec3& direction) {
    return {sphere_area_pdf(light.sphere.radius),
            emission::direction_pdf(normal, false, direction)};
}

glm::vec3 power(const SphereLight& light) {
    // Uniform emitter: power = L * pi (cosine-weighted hemisphere) * 4 pi r^2 (area), in
    // double so that a tiny radius does not underflow before the product is formed.
    const double r = light.sphere.radius;
    const double k = 4.0 * double(kPi) * double(kPi) * r * r;
    return glm::vec3(glm::dvec3(light.radiance) * k);
}

LightBounds SphereLight::bounds() const {
    return detail::finite_light_bounds(sphere.center, sphere.radius, power(*this));
}

}  // namespace librt
