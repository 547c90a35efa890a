#pragma once

// Helpers of the anisotropic GGX tests: the distribution and Smith Lambda in double,
// written from Heitz 2014, a quadrature over microfacet normals dense where an
// anisotropic lobe is, and a white (F = 1) reflector's directional albedo by it.

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <functional>
#include <numbers>

namespace librt::testing {

/// Anisotropic GGX D in double, slope form (Heitz 2014, eq. 85):
/// 1 / (pi ax ay cos^4 (1 + tan^2 (cos^2 phi / ax^2 + sin^2 phi / ay^2))^2).
inline double ref_d(const glm::dvec3& m, double ax, double ay) {
    if (m.z <= 0.0) return 0.0;
    const double sx = m.x / m.z, sy = m.y / m.z, c2 = m.z * m.z;
    const double q = 1.0 + sx * sx / (ax * ax) + sy * sy / (ay * ay);
    return 1.0 / (std::numbers::pi * ax * ay * c2 * c2 * q * q);
}

/// Smith Lambda in double (Heitz 2014, eq. 86, with alpha_o of eq. 80).
inline double ref_lambda(const glm::dvec3& w, double ax, double ay) {
    const double s2 = w.x * w.x + w.y * w.y;
    if (s2 <= 0.0) return 0.0;
    const double ao = std::sqrt((w.x * w.x * ax * ax + w.y * w.y * ay * ay) / s2);
    const double a = w.z / (ao * std::sqrt(s2));  // 1 / (alpha_o tan theta)
    return 0.5 * (std::sqrt(1.0 + 1.0 / (a * a)) - 1.0);
}

/// Calls visit(m, d omega) for a quadrature over microfacet normals m (upper hemisphere),
/// dense where an (ax, ay) GGX lobe is, rotated by phi0 about +z: slopes
/// (ax tan psi cos phi, ay tan psi sin phi) on a midpoint grid in (psi, phi), each normal
/// weighted by d omega = cos^3 theta d(slope area) = cos^3 ax ay tan psi sec^2 psi dpsi dphi.
inline void for_each_normal(double ax, double ay, double phi0,
                            const std::function<void(const glm::dvec3&, double)>& visit, int n_psi,
                            int n_phi) {
    const double dpsi = 0.5 * std::numbers::pi / n_psi, dphi = 2.0 * std::numbers::pi / n_phi;
    const double c0 = std::cos(phi0), s0 = std::sin(phi0);
    for (int i = 0; i < n_psi; ++i) {
        const double psi = (i + 0.5) * dpsi, r = std::tan(psi), sec = 1.0 / std::cos(psi);
        for (int j = 0; j < n_phi; ++j) {
            const double phi = (j + 0.5) * dphi;
            const double x = ax * r * std::cos(phi), y = ay * r * std::sin(phi);
            const double inv = 1.0 / std::sqrt(1.0 + x * x + y * y);  // cos theta
            const glm::dvec3 m(inv * (c0 * x - s0 * y), inv * (s0 * x + c0 * y), inv);
            visit(m, inv * inv * inv * ax * ay * r * sec * sec * dpsi * dphi);
        }
    }
}

/// Directional albedo of a white (F = 1) anisotropic GGX reflector at wo (in the lobe's
/// frame: ax along x): the integral of D G2 (wo.h) / cos_o over normals h (reflection's
/// d omega_i = 4 (wo.h) d omega_h times f cos_i = D G2 / (4 cos_o)), double formulas.
inline double ref_anisotropic_albedo(const glm::dvec3& wo, double ax, double ay) {
    double e = 0.0;
    for_each_normal(
        ax, ay, 0.0,
        [&](const glm::dvec3& h, double w) {
            const double oh = glm::dot(wo, h);
            if (oh <= 0.0) return;
            const glm::dvec3 wi = 2.0 * oh * h - wo;
            if (wi.z <= 0.0) return;
            const double g2 = 1.0 / (1.0 + ref_lambda(wo, ax, ay) + ref_lambda(wi, ax, ay));
            e += ref_d(h, ax, ay) * g2 * oh / wo.z * w;
        },
        1200, 480);
    return e;
}

}  // namespace librt::testing
