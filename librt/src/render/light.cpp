#include <librt/render/light.h>

namespace librt {

float pdf_li(const Light& light, const glm::vec3& ref, const glm::vec3& wi) {
    return std::visit([&](const auto& source) { return pdf_li(source, ref, wi); }, light.source);
}

glm::vec3 power(const Light& light) {
    return std::visit([](const auto& source) { return power(source); }, light.source);
}

}  // namespace librt
