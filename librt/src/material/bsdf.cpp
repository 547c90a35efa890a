#include "material/bsdf_dispatch.h"

#include <librt/material/bsdf.h>

namespace librt {

BsdfLobe lobes(const Material& material) { return bsdfs::lobes_of(material); }

glm::vec3 pass_through(const Material& material, const ShadingPoint& point, const glm::vec3& wo) {
    return bsdfs::pass_through_of(material, point, wo);
}

bool may_pass_through(const Material& material) { return bsdfs::may_pass_through_of(material); }

glm::vec3 denoising_albedo(const Material& material, const ShadingPoint& point) {
    return bsdfs::denoising_albedo_of(material, point);
}

BsdfSample sample(const Material& material, const ShadingPoint& point, const glm::vec3& wo,
                  float uc, glm::vec2 u) {
    return bsdfs::sample_bsdf(material, point, wo, uc, u);
}

glm::vec3 eval(const Material& material, const ShadingPoint& point, const glm::vec3& wo,
               const glm::vec3& wi) {
    return bsdfs::eval_bsdf(material, point, wo, wi);
}

float pdf(const Material& material, const ShadingPoint& point, const glm::vec3& wo,
          const glm::vec3& wi) {
    return bsdfs::pdf_bsdf(material, point, wo, wi);
}

}  // namespace librt
