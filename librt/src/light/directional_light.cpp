#include "light/emission.h"
#include "light/light_bounds.h"

#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/light/directional_light.h>
#include <librt/light/scene_summary.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <limits>
#include <sstream>

namespace librt {
namespace {

/// 1 - cos(theta) without cancellation for tiny cones: 2 sin^2(theta / 2).
using emission::one_minus_cos;

/// Radiance of the cone that gives irradiance E at normal incidence: E / (pi sin^2 theta).
glm::vec3 cone_radiance(const DirectionalLight& light) {
    const float s = std::sin(light.angular_radius);
    return light.irradiance / (kPi * s * s);
}

}  // namespace

void validate(const DirectionalLight& light) {
    if (!finite(light.to_light) || !(glm::length(light.to_light) > 0.0f)) {
        std::ostringstream msg;
        msg << "directional light to_light = (" << light.to_light.x << ", " << light.to_light.y
            << ", " << light.to_light.z << "): must be finite and non-zero";
        throw Error(msg.str());
    }
    if (!finite(light.irradiance) || light.irradiance.x < 0.0f || light.irradiance.y < 0.0f ||
        light.irradiance.z < 0.0f) {
        std::ostringstream msg;
        msg << "directional light irradiance = (" << light.irradiance.x << ", "
            << light.irradiance.y << ", " << light.irradiance.z << "): must be finite and >= 0";
        throw Error(msg.str());
    }
    if (!(light.angular_radius >= 0.0f) || !(light.angular_radius < 0.5f * kPi)) {
        std::ostringstream msg;
        msg << "directional light angular_radius = " << light.angular_radius
            << ": must be in [0, pi/2)";
        throw Error(msg.str());
    }
}

LightLiSample sample_li(const DirectionalLight& light, const glm::vec3& /*ref*/, glm::vec2 u) {
    const glm::vec3 axis = glm::normalize(light.to_light);
    constexpr float inf = std::numeric_limits<float>::infinity();
    if (!(light.angular_radius > 0.0f)) return {axis, light.irradiance, 1.0f, inf, true};
    // Uniform in the cone: cos(theta) uniform in [cos(theta_max), 1] (pbrt 4th ed. A.5.4).
    const float omc = one_minus_cos(light.angular_radius);
    const float cos_t = 1.0f - u.x * omc;
    const float sin_t = std::sqrt(std::max(0.0f, 1.0f - cos_t * cos_t));
    const float phi = 2.0f * kPi * u.y;
    const glm::vec3 a = std::fabs(axis.x) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 t = glm::normalize(glm::cross(a, axis));
    const glm::vec3 b = glm::cross(axis, t);
    const glm::vec3 wi = sin_t * std::cos(phi) * t + sin_t * std::sin(phi) * b + cos_t * axis;
    return {glm::normalize(wi), cone_radiance(light), 1.0f / (2.0f * kPi * omc), inf, false};
}

float pdf_li(const DirectionalLight& light, const glm::vec3& /*ref*/, const glm::vec3& wi) {
    if (!(light.angular_radius > 0.0f)) return 0.0f;
    if (glm::dot(wi, glm::normalize(light.to_light)) < std::cos(light.angular_radius)) return 0.0f;
    return 1.0f / (2.0f * kPi * one_minus_cos(light.angular_radius));
}

glm::vec3 escaped_radiance(const DirectionalLight& light, const glm::vec3& dir) {
    if (!(light.angular_radius > 0.0f)) return glm::vec3(0.0f);
    if (glm::dot(dir, glm::normalize(light.to_light)) < std::cos(light.angular_radius))
        return glm::vec3(0.0f);
    return cone_radiance(light);
}

LightLeSample sample_le(const DirectionalLight& light, const SceneSphere& scene, glm::vec2 u_pos,
                        glm::vec2 u_dir) {
    const float len = glm::length(light.to_light);
    if (!(len > 0.0f) || !std::isfinite(len)) return {};
    const glm::vec3 axis = light.to_light / len;
    if (!(light.angular_radius > 0.0f)) {
        // A delta direction: the irradiance stands for the radiance, pdf_dir 1, so the
        // weight E / pdf_pos = E pi R^2 is the power crossing the disk.
        LightLeSample s = emission::from_disk(scene, axis, light.irradiance, 1.0f, u_pos);
        s.delta_direction = true;
        return s;
    }
    // Uniform in the cone, as sample_li, but from 1 - cos kept exact (sample_li rounds cos
    // near 1 to 6e-8, 0.5% of the real sun's 1 - cos = 1.1e-5), so that pdf_le's cone test
    // finds the sampled directions inside.
    const float omc = one_minus_cos(light.angular_radius);
    const glm::vec3 wi = emission::sample_cone(axis, omc, u_dir);
    return emission::from_disk(scene, wi, cone_radiance(light), emission::cone_pdf(omc), u_pos);
}

LightLePdf pdf_le(const DirectionalLight& light, const SceneSphere& scene,
                  const glm::vec3& /*origin*/, const glm::vec3& /*normal*/,
                  const glm::vec3& direction) {
    const float pos = emission::disk_pdf(scene);
    if (!(light.angular_radius > 0.0f)) return {pos, 1.0f};
    const float len = glm::length(light.to_light);
    if (!(len > 0.0f) || !std::isfinite(len)) return {pos, 0.0f};
    const float omc = one_minus_cos(light.angular_radius);
    // The direction travels away from the sun: -direction is in the cone around to_light.
    if (!emission::in_cone(-direction, light.to_light / len, omc)) return {pos, 0.0f};
    return {pos, emission::cone_pdf(omc)};
}

glm::vec3 power(const DirectionalLight& light) {
    // What crosses the disk of the scene's bounding sphere (pbrt 4th ed. 12.4).
    const float r = light.scene_radius > 0.0f ? light.scene_radius : 1.0f;
    return light.irradiance * (kPi * r * r);
}

LightBounds DirectionalLight::bounds() const {
    LightBounds b = detail::infinite_light_bounds(power(*this));
    b.cone = true;
    b.axis = glm::normalize(to_light);
    // The cone of directions toward the sun's disk, widened by 1e-4 rad against rounding.
    b.cos_cone = std::cos(std::min(angular_radius + 1e-4f, kPi));
    return b;
}

void DirectionalLight::preprocess(const SceneSummary& scene) { scene_radius = scene.sphere.radius; }

}  // namespace librt
