#include "light/light_bounds.h"
#include "light/light_kind.h"

#include <librt/light/light.h>

#include <concepts>
#include <cstddef>
#include <utility>

namespace librt {
namespace {

/// True, or a compile error naming the kind that does not answer.
template <class Kind>
constexpr bool answers_for_itself() {
    static_assert(LightKind<Kind>,
                  "a LightSource alternative must be a LightKind (light_kind.h): type(), "
                  "surface_normal(p), bounds(), preprocess(scene), sample_li, pdf_li, power");
    return true;
}
template <std::size_t... I>
constexpr bool every_kind_answers(std::index_sequence<I...> /*kinds*/) {
    return (answers_for_itself<std::variant_alternative_t<I, LightSource>>() && ...);
}
static_assert(every_kind_answers(std::make_index_sequence<std::variant_size_v<LightSource>>()));

}  // namespace

glm::vec3 surface_normal(const Light& light, const glm::vec3& p) {
    return std::visit([&](const auto& source) { return source.surface_normal(p); }, light.source);
}

void preprocess(Light& light, const SceneSummary& scene) {
    std::visit([&](auto& source) { source.preprocess(scene); }, light.source);
}

float pdf_li(const Light& light, const glm::vec3& ref, const glm::vec3& wi) {
    return std::visit([&](const auto& source) { return pdf_li(source, ref, wi); }, light.source);
}

glm::vec3 power(const Light& light) {
    return std::visit([](const auto& source) { return power(source); }, light.source);
}

LightLeSample sample_le(const Light& light, const SceneSphere& scene, glm::vec2 u_pos,
                        glm::vec2 u_dir) {
    return std::visit(
        [&](const auto& source) {
            // Lights at infinity start their rays on a disk the size of the scene.
            if constexpr (requires { sample_le(source, scene, u_pos, u_dir); })
                return sample_le(source, scene, u_pos, u_dir);
            else
                return sample_le(source, u_pos, u_dir);
        },
        light.source);
}

LightLePdf pdf_le(const Light& light, const SceneSphere& scene, const glm::vec3& origin,
                  const glm::vec3& normal, const glm::vec3& direction) {
    return std::visit(
        [&](const auto& source) {
            if constexpr (requires { pdf_le(source, scene, origin, normal, direction); })
                return pdf_le(source, scene, origin, normal, direction);
            else
                return pdf_le(source, origin, normal, direction);
        },
        light.source);
}

}  // namespace librt
