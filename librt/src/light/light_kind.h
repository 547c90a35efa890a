#pragma once

#include "light/light_bounds.h"

#include <librt/light/light.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <concepts>

// The members and functions a light kind must give (docs/architecture.md, "Adding a light
// kind"): light.cpp asserts it of every LightSource alternative, and the light-kinds test
// of a dummy kind and of kinds each missing one answer.

namespace librt {

/// What every light kind answers for itself (light.h): the members the dispatch
/// (light.cpp) and the light sampler call, with the types they must return.
template <class Kind>
concept LightKind = requires(const Kind& light, Kind& mutable_light, const glm::vec3& p,
                             const SceneSummary& scene, const glm::vec3& ref, glm::vec2 u) {
    { light.type() } -> std::same_as<LightType>;
    { light.surface_normal(p) } -> std::same_as<glm::vec3>;
    { light.bounds() } -> std::same_as<LightBounds>;
    mutable_light.preprocess(scene);
    { sample_li(light, ref, u) } -> std::same_as<LightLiSample>;
    { pdf_li(light, ref, p) } -> std::same_as<float>;
    { power(light) } -> std::same_as<glm::vec3>;
};

}  // namespace librt
