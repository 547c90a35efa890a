#include "bsdf_dielectric.h"
#include "bsdf_diffuse.h"
#include "bsdf_mirror.h"

#include <librt/render/bsdf.h>

namespace librt {
namespace bsdfs {

/// A surface that scatters nothing (MaterialKind::Emissive: a light's own surface).
struct Black {
    static constexpr BsdfLobe kLobes = BsdfLobe::None;
    static BsdfSample sample(const Material&, const ShadingPoint&, const glm::vec3&, float,
                             glm::vec2) {
        return {};
    }
    static glm::vec3 eval(const Material&, const ShadingPoint&, const glm::vec3&,
                          const glm::vec3&) {
        return glm::vec3(0.0f);
    }
    static float pdf(const Material&, const ShadingPoint&, const glm::vec3&, const glm::vec3&) {
        return 0.0f;
    }
};

}  // namespace bsdfs
namespace {

/// The one dispatch point from MaterialKind to its BSDF type: each type provides kLobes
/// and static sample / eval / pdf. A new kind adds its header and one case here.
template <class Fn>
decltype(auto) dispatch(MaterialKind kind, Fn&& fn) {
    switch (kind) {
        case MaterialKind::Diffuse:
            return fn(bsdfs::Diffuse{});
        case MaterialKind::Mirror:
            return fn(bsdfs::Mirror{});
        case MaterialKind::Dielectric:
            return fn(bsdfs::Dielectric{});
        case MaterialKind::Emissive:
            break;
    }
    return fn(bsdfs::Black{});
}

}  // namespace

BsdfLobe lobes(const Material& material) {
    return dispatch(material.kind, [](auto bsdf) { return decltype(bsdf)::kLobes; });
}

BsdfSample sample(const Material& material, const ShadingPoint& point, const glm::vec3& wo,
                  float uc, glm::vec2 u) {
    return dispatch(material.kind,
                    [&](auto bsdf) { return decltype(bsdf)::sample(material, point, wo, uc, u); });
}

glm::vec3 eval(const Material& material, const ShadingPoint& point, const glm::vec3& wo,
               const glm::vec3& wi) {
    return dispatch(material.kind,
                    [&](auto bsdf) { return decltype(bsdf)::eval(material, point, wo, wi); });
}

float pdf(const Material& material, const ShadingPoint& point, const glm::vec3& wo,
          const glm::vec3& wi) {
    return dispatch(material.kind,
                    [&](auto bsdf) { return decltype(bsdf)::pdf(material, point, wo, wi); });
}

}  // namespace librt
