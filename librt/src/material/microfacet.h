#pragma once

// The GGX (Trowbridge-Reitz) microfacet distribution, Smith masking-shadowing, sampling of
// visible normals, and the exact Fresnel equations, shared by the rough BSDFs (conductor,
// dielectric, glTF metallic-roughness). Local shading frame: +z is the macro normal.

#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>

namespace librt::microfacet {

/// Smallest alpha used: below it D's peak (1 / (pi alpha^2)) loses float precision.
inline constexpr float kMinAlpha = 1e-3f;

/// alpha = roughness^2 (the perceptual mapping of glTF and Burley 2012), clamped.
[[nodiscard]] inline float alpha_of(float roughness) {
    return std::max(roughness * roughness, kMinAlpha);
}

/// Smallest alpha a glossy lobe has toward a delta light (point, spot, delta sun) in
/// next-event estimation: path-space regularisation with a fixed radius (Kaplanyan &
/// Dachsbacher 2013). f cos_i <= D(h) / (4 cos_o) <= 1 / (4 pi alpha^2 cos_o), so one light
/// sample of irradiance E adds at most 32 E / cos_o instead of 8e4 E / cos_o at kMinAlpha
/// (docs/materials-and-lights.md, "Delta lights on smooth surfaces").
inline constexpr float kDeltaLightAlpha = 0.05f;

/// The perceptual roughness whose alpha is kDeltaLightAlpha: sqrt(0.05) (alpha = roughness^2).
inline constexpr float kDeltaLightRoughness = 0.22360680f;

/// `roughness` raised so that alpha_of() is at least kDeltaLightAlpha (isotropic and both
/// anisotropic alphas: anisotropic_alphas() only widens alpha along the anisotropy);
/// unchanged, to the bit, at or above it.
[[nodiscard]] inline float delta_light_roughness(float roughness) {
    return std::max(roughness, kDeltaLightRoughness);
}

/// GGX normal distribution D(m) = alpha^2 / (pi (m.z^2 (alpha^2 - 1) + 1)^2) for m.z > 0
/// (Trowbridge & Reitz 1975; Walter et al. 2007, eq. 33, in cosine form).
[[nodiscard]] inline float ggx_d(const glm::vec3& m, float alpha) {
    if (m.z <= 0.0f) return 0.0f;
    // For unit m the denominator is (alpha^2 m.z^2 + m.x^2 + m.y^2)^2: written so, without
    // 1 - m.z^2, it keeps float precision at the peak of a narrow lobe (alpha ~ 1e-3).
    const float a2 = alpha * alpha;
    const float t = a2 * m.z * m.z + (m.x * m.x + m.y * m.y);
    return a2 / (kPi * t * t);
}

/// Smith's Lambda for GGX: (sqrt(1 + alpha^2 tan^2 theta) - 1) / 2 (Heitz 2014, eq. 72).
[[nodiscard]] inline float ggx_lambda(const glm::vec3& w, float alpha) {
    const float c2 = w.z * w.z;
    if (c2 <= 0.0f) return 1e30f;
    const float t2 = (w.x * w.x + w.y * w.y) / c2;  // tan^2, from components (precision)
    return 0.5f * (std::sqrt(1.0f + alpha * alpha * t2) - 1.0f);
}

/// Smith masking G1(w) = 1 / (1 + Lambda(w)) (Heitz 2014, eq. 43).
[[nodiscard]] inline float ggx_g1(const glm::vec3& w, float alpha) {
    return 1.0f / (1.0f + ggx_lambda(w, alpha));
}

/// Height-correlated masking-shadowing G2 = 1 / (1 + Lambda(wo) + Lambda(wi))
/// (Heitz 2014, eq. 99).
[[nodiscard]] inline float ggx_g2(const glm::vec3& wo, const glm::vec3& wi, float alpha) {
    return 1.0f / (1.0f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}

/// A microfacet normal drawn from the distribution of normals visible from wo (wo.z > 0)
/// of a GGX distribution with roughness ax along x and ay along y (Heitz 2018, "Sampling
/// the GGX Distribution of Visible Normals": stretch wo to the hemisphere configuration,
/// sample the projected half disk, unstretch; its listing 1).
[[nodiscard]] inline glm::vec3 sample_visible_normal(const glm::vec3& wo, float ax, float ay,
                                                     glm::vec2 u) {
    const glm::vec3 vh = glm::normalize(glm::vec3(ax * wo.x, ay * wo.y, wo.z));
    const float len2 = vh.x * vh.x + vh.y * vh.y;
    const glm::vec3 t1 =
        len2 > 0.0f ? glm::vec3(-vh.y, vh.x, 0.0f) / std::sqrt(len2) : glm::vec3(1, 0, 0);
    const glm::vec3 t2 = glm::cross(vh, t1);
    // A uniform point on the unit disk, its second coordinate squeezed onto the half of the
    // disk that the projected hemisphere covers as seen from vh.
    const float r = std::sqrt(u.x);
    const float phi = 2.0f * kPi * u.y;
    const float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    const float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
    const glm::vec3 nh =
        p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
    return glm::normalize(glm::vec3(ax * nh.x, ay * nh.y, std::max(1e-7f, nh.z)));
}

/// The isotropic case, density vndf_pdf.
[[nodiscard]] inline glm::vec3 sample_visible_normal(const glm::vec3& wo, float alpha,
                                                     glm::vec2 u) {
    return sample_visible_normal(wo, alpha, alpha, u);
}

/// Density of sample_visible_normal: G1(wo) max(0, wo.m) D(m) / wo.z (Heitz 2018, eq. 3).
[[nodiscard]] inline float vndf_pdf(const glm::vec3& wo, const glm::vec3& m, float alpha) {
    const float om = glm::dot(wo, m);
    if (om <= 0.0f || wo.z <= 0.0f) return 0.0f;
    return ggx_g1(wo, alpha) * om * ggx_d(m, alpha) / wo.z;
}

/// Density of the reflected direction wi = reflect(-wo, h) when h is drawn by
/// sample_visible_normal: vndf_pdf / (4 wo.h) (the Jacobian of reflection, Walter et al.
/// 2007, eq. 14).
[[nodiscard]] inline float reflection_pdf(const glm::vec3& wo, const glm::vec3& h, float alpha) {
    const float om = glm::dot(wo, h);
    return om > 0.0f ? vndf_pdf(wo, h, alpha) / (4.0f * om) : 0.0f;
}

/// Exact unpolarised Fresnel reflectance of a dielectric boundary for light meeting it at
/// cosine cos_i (> 0) from the side of index n_i, eta = n_t / n_i; 1 under total internal
/// reflection (Fresnel equations, e.g. Born & Wolf; Walter et al. 2007, eq. 22 in
/// amplitude form).
[[nodiscard]] inline float fresnel_dielectric(float cos_i, float eta) {
    cos_i = std::clamp(cos_i, 0.0f, 1.0f);
    const float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;
    const float cos_t = std::sqrt(1.0f - sin2_t);
    const float r_par = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    const float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5f * (r_par * r_par + r_perp * r_perp);
}

/// Exact unpolarised Fresnel reflectance of a conductor of complex index eta + i k
/// (relative to the outside) at cosine cos_i, one channel: the s and p reflectances of
/// the Fresnel equations in real arithmetic (Born & Wolf, "Principles of Optics", 14.4).
[[nodiscard]] inline float fresnel_conductor(float cos_i, float eta, float k) {
    cos_i = std::clamp(cos_i, 0.0f, 1.0f);
    const float c2 = cos_i * cos_i, s2 = 1.0f - c2;
    const float t0 = eta * eta - k * k - s2;
    const float a2b2 = std::sqrt(std::max(0.0f, t0 * t0 + 4.0f * eta * eta * k * k));
    const float a = std::sqrt(std::max(0.0f, 0.5f * (a2b2 + t0)));
    const float t1 = a2b2 + c2, t2 = 2.0f * cos_i * a;
    const float rs = (t1 - t2) / std::max(t1 + t2, 1e-30f);
    const float t3 = c2 * a2b2 + s2 * s2, t4 = t2 * s2;
    const float rp = rs * (t3 - t4) / std::max(t3 + t4, 1e-30f);
    return std::clamp(0.5f * (rs + rp), 0.0f, 1.0f);
}

/// fresnel_conductor per RGB channel.
[[nodiscard]] inline glm::vec3 fresnel_conductor(float cos_i, const glm::vec3& eta,
                                                 const glm::vec3& k) {
    return {fresnel_conductor(cos_i, eta.x, k.x), fresnel_conductor(cos_i, eta.y, k.y),
            fresnel_conductor(cos_i, eta.z, k.z)};
}

/// Schlick's approximation F0 + (1 - F0) (1 - cos)^5 (Schlick 1994), the form glTF uses.
[[nodiscard]] inline glm::vec3 schlick(const glm::vec3& f0, float cos) {
    const float m = 1.0f - std::clamp(cos, 0.0f, 1.0f);
    const float m5 = m * m * m * m * m;
    return f0 + (glm::vec3(1.0f) - f0) * m5;
}

}  // namespace librt::microfacet
