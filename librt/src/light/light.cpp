#include <librt/light/light.h>

namespace librt {

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
