#include "light/emission.h"
#include "light/light_bounds.h"
#include "light/light_validation.h"

#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/light/spot_light.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace librt {

using detail::fail_light_parameter;

void validate(const SpotLight& light) {
    if (!finite(light.position))
        fail_light_parameter("spot light position", light.position, "must be finite");
    if (!finite(light.direction) || !(glm::length(light.direction) > 0.0f))
        fail_light_parameter("spot light direction", light.direction,
                             "must be finite and non-zero");
    if (!finite(light.intensity) || light.intensity.x < 0.0f || light.intensity.y < 0.0f ||
        light.intensity.z < 0.0f)
        fail_light_parameter("spot light intensity", light.intensity, "must be finite and >= 0");
    if (!(light.inner_angle >= 0.0f) || !(light.inner_angle < light.outer_angle) ||
        !(light.outer_angle <= 0.5f * kPi)) {
        std::ostringstream msg;
        msg << "spot light angles inner = " << light.inner_angle
            << ", outer = " << light.outer_angle << ": need 0 <= inner < outer <= pi/2";
        throw Error(msg.str());
    }
}

float spot_falloff(const SpotLight& light, float cos_theta) {
    // KHR_lights_punctual's "Inner and Outer Cone Angles" implementation note.
    const float cos_outer = std::cos(light.outer_angle);
    const float scale = 1.0f / std::max(0.001f, std::cos(light.inner_angle) - cos_outer);
    const float a = std::clamp((cos_theta - cos_outer) * scale, 0.0f, 1.0f);
    return a * a;
}

LightLiSample sample_li(const SpotLight& light, const glm::vec3& ref, glm::vec2 /*u*/) {
    const glm::vec3 to_light = light.position - ref;
    const float d2 = glm::dot(to_light, to_light);
    if (!(d2 > 0.0f) || !std::isfinite(d2)) return {};
    const float d = std::sqrt(d2);
    const glm::vec3 wi = to_light / d;
    const float f = spot_falloff(light, glm::dot(-wi, glm::normalize(light.direction)));
    if (!(f > 0.0f)) return {};
    // Inverse-square law with the cone's falloff: E = I f cos(theta) / d^2.
    return {wi, light.intensity * (f / d2), 1.0f, d, true};
}

namespace {

/// The spot's unit axis and its outer cone's 1 - cos, or omc 0 when either is degenerate.
struct SpotCone {
    glm::vec3 axis{0.0f};
    float omc = 0.0f;
};
SpotCone cone_of(const SpotLight& light) {
    const float len = glm::length(light.direction);
    if (!(len > 0.0f) || !std::isfinite(len)) return {};
    const float omc = emission::one_minus_cos(light.outer_angle);
    return {light.direction / len, std::isfinite(omc) ? omc : 0.0f};
}

}  // namespace

LightLeSample sample_le(const SpotLight& light, glm::vec2 /*u_pos*/, glm::vec2 u_dir) {
    const SpotCone c = cone_of(light);
    // Uniform in the outer cone, outside which the falloff is 0: I f / pdf_dir integrates
    // to the power. (Sampling by the falloff itself would weigh rays more evenly; the
    // uniform cone is exact and what pdf_le can invert cheaply.)
    const float pdf_dir = emission::cone_pdf(c.omc);
    if (!(pdf_dir > 0.0f) || !finite(light.position)) return {};
    const glm::vec3 d = emission::sample_cone(c.axis, c.omc, u_dir);
    LightLeSample s;
    s.origin = light.position;
    s.direction = d;
    s.radiance = light.intensity * spot_falloff(light, glm::dot(d, c.axis));
    s.pdf_pos = 1.0f;
    s.pdf_dir = pdf_dir;
    s.delta_position = true;
    return s;
}

LightLePdf pdf_le(const SpotLight& light, const glm::vec3& /*origin*/, const glm::vec3& /*normal*/,
                  const glm::vec3& direction) {
    const SpotCone c = cone_of(light);
    if (!emission::in_cone(direction, c.axis, c.omc)) return {1.0f, 0.0f};
    return {1.0f, emission::cone_pdf(c.omc)};
}

glm::vec3 power(const SpotLight& light) {
    // 2 pi I times the integral of the falloff over cos(theta): 1 - cos(inner) at full
    // strength, plus the quadratic ramp's (cos(inner) - cos(outer)) / 3.
    const float ci = std::cos(light.inner_angle), co = std::cos(light.outer_angle);
    return light.intensity * (2.0f * kPi * ((1.0f - ci) + (ci - co) / 3.0f));
}

LightBounds SpotLight::bounds() const {
    LightBounds b = detail::finite_light_bounds(position, 0.0f, power(*this));
    b.cone = true;
    b.axis = glm::normalize(direction);
    // spot_falloff is 0 from the outer angle on; a 1e-4 slack keeps rounding conservative.
    b.cos_cone = std::cos(outer_angle) - 1e-4f;
    return b;
}

}  // namespace librt
