#pragma once

// Helpers of the microfacet BSDF tests: a flat shading point, the materials under test,
// and an independent double-precision GGX (D, Smith Lambda) written from the papers for
// the quadratures the library is checked against.

#include <librt/material/bsdf.h>
#include <librt/material/material.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

namespace librt::testing {

/// A shading point whose shading and geometric normals are the local +z; `front`: wo is
/// on the side the surface faces (outside glass).
inline ShadingPoint flat_point(bool front = true, const glm::vec3& albedo = glm::vec3(1.0f)) {
    ShadingPoint p;
    p.frame.shading = Frame::from_normal({0.0f, 0.0f, 1.0f});
    p.frame.geometric = {0.0f, 0.0f, 1.0f};
    p.frame.front = front;
    p.albedo = albedo;
    return p;
}

/// A local direction at polar cosine c and azimuth phi.
inline glm::vec3 local_dir(double c, double phi) {
    const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    return glm::vec3(glm::dvec3(s * std::cos(phi), s * std::sin(phi), c));
}

/// A material under test with a name for messages and the side it is seen from.
struct Case {
    std::string name;
    Material material;
    bool front = true;
};

/// Every non-delta kind at the given roughness.
inline std::vector<Case> rough_cases(float roughness) {
    const std::string r = " r=" + std::to_string(roughness);
    return {{"gold" + r, Material::conductor(Metal::Gold, roughness)},
            {"artist copper" + r,
             Material::conductor_artist({0.95f, 0.64f, 0.54f}, {1.0f, 0.9f, 0.6f}, roughness)},
            {"glass outside" + r, Material::rough_dielectric(1.5f, roughness), true},
            {"glass inside" + r, Material::rough_dielectric(1.5f, roughness), false},
            {"gltf plastic" + r, Material::metallic_roughness({0.8f, 0.3f, 0.1f}, 0.0f, roughness)},
            {"gltf half metal" + r,
             Material::metallic_roughness({0.9f, 0.7f, 0.2f}, 0.5f, roughness, 1.45f)},
            {"gltf transmissive" + r,
             Material::metallic_roughness({0.9f, 0.9f, 0.8f}, 0.2f, roughness, 1.5f, 0.7f)}};
}

/// GGX D(h) in double (Walter et al. 2007, eq. 33): alpha^2 / (pi (cos^4) (alpha^2 + tan^2)^2).
inline double ref_ggx_d(const glm::dvec3& h, double alpha) {
    if (h.z <= 0.0) return 0.0;
    const double c2 = h.z * h.z, t2 = (1.0 - c2) / c2, a2 = alpha * alpha;
    return a2 / (std::numbers::pi * c2 * c2 * (a2 + t2) * (a2 + t2));
}

/// Smith Lambda for GGX in double (Heitz 2014, eq. 72).
inline double ref_lambda(const glm::dvec3& w, double alpha) {
    const double c2 = w.z * w.z, t2 = (1.0 - c2) / c2;
    return 0.5 * (std::sqrt(1.0 + alpha * alpha * t2) - 1.0);
}

/// Calls visit(h, w) for the nodes of a quadrature over microfacet normals h (upper
/// hemisphere, weights w in steradians): the midpoint rule in (psi, phi) with
/// theta_h = atan(alpha tan psi), which spreads GGX's peak (width ~alpha) over the whole
/// psi range, so one grid serves every roughness.
inline void for_each_normal(double alpha,
                            const std::function<void(const glm::dvec3&, double)>& visit,
                            int n_psi = 1200, int n_phi = 480) {
    const double half_pi = 0.5 * std::numbers::pi, two_pi = 2.0 * std::numbers::pi;
    const double cell = (half_pi / n_psi) * (two_pi / n_phi);
    for (int i = 0; i < n_psi; ++i) {
        const double psi = (i + 0.5) * half_pi / n_psi;
        const double tp = std::tan(psi);
        const double theta = std::atan(alpha * tp);
        // d theta / d psi = alpha sec^2 psi / (1 + alpha^2 tan^2 psi).
        const double jac =
            alpha / (std::cos(psi) * std::cos(psi) * (1.0 + alpha * alpha * tp * tp));
        const double st = std::sin(theta), ct = std::cos(theta);
        for (int j = 0; j < n_phi; ++j) {
            const double phi = (j + 0.5) * two_pi / n_phi;
            visit(glm::dvec3(st * std::cos(phi), st * std::sin(phi), ct), st * jac * cell);
        }
    }
}

/// Integral over microfacet normals of g(h) d omega_h (for_each_normal's quadrature).
inline double integrate_over_normals(double alpha,
                                     const std::function<double(const glm::dvec3&)>& g,
                                     int n_psi = 1200, int n_phi = 480) {
    double sum = 0.0;
    for_each_normal(
        alpha, [&](const glm::dvec3& h, double w) { sum += g(h) * w; }, n_psi, n_phi);
    return sum;
}

/// Directional albedo of a white (F = 1) GGX reflector, integral of D G2 / (4 cos_o)
/// over wi, written over h (d omega_i = 4 (wo.h) d omega_h) with independent formulas.
inline double ref_ggx_albedo(const glm::dvec3& wo, double alpha) {
    return integrate_over_normals(alpha, [&](const glm::dvec3& h) {
        const double oh = glm::dot(wo, h);
        if (oh <= 0.0) return 0.0;
        const glm::dvec3 wi = 2.0 * oh * h - wo;
        if (wi.z <= 0.0) return 0.0;
        const double g2 = 1.0 / (1.0 + ref_lambda(wo, alpha) + ref_lambda(wi, alpha));
        return ref_ggx_d(h, alpha) * g2 / (4.0 * wo.z) * 4.0 * oh;
    });
}

}  // namespace librt::testing
