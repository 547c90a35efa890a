#include <librt/core/error.h>
#include <librt/render/bsdf.h>
#include <librt/render/material.h>

#include <cmath>
#include <sstream>

namespace librt {
namespace {

// Every component finite and >= 0, and <= 1 when `at_most_one` (a reflectance).
void check_colour(const char* name, const glm::vec3& c, bool at_most_one) {
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(c[i]) || c[i] < 0.0f || (at_most_one && c[i] > 1.0f)) {
            std::ostringstream msg;
            msg << "material " << name << " = (" << c.x << ", " << c.y << ", " << c.z
                << "): every component must be " << (at_most_one ? "in [0, 1]" : "finite and >= 0");
            throw Error(msg.str());
        }
    }
}

}  // namespace

Material Material::diffuse(const glm::vec3& albedo) {
    Material m;
    m.kind = MaterialKind::Diffuse;
    m.albedo = albedo;
    validate(m);
    return m;
}

Material Material::mirror(const glm::vec3& tint) {
    Material m;
    m.kind = MaterialKind::Mirror;
    m.albedo = tint;
    validate(m);
    return m;
}

Material Material::dielectric(float ior, bool fresnel, const glm::vec3& tint) {
    Material m;
    m.kind = MaterialKind::Dielectric;
    m.albedo = tint;
    m.ior = ior;
    m.fresnel = fresnel;
    validate(m);
    return m;
}

Material Material::emissive(const glm::vec3& radiance) {
    Material m;
    m.kind = MaterialKind::Emissive;
    m.albedo = glm::vec3(0.0f);
    m.emission = radiance;
    validate(m);
    return m;
}

bool Material::is_specular() const {
    const BsdfLobe l = lobes(*this);
    return l != BsdfLobe::None && !has_non_specular(l);
}

void validate(const Material& material) {
    // A reflectance above 1 creates energy: throughput would grow without bound.
    check_colour("albedo", material.albedo, true);
    check_colour("emission", material.emission, false);
    if (!std::isfinite(material.ior) || !(material.ior > 0.0f)) {
        std::ostringstream msg;
        msg << "material ior = " << material.ior << ": must be finite and > 0";
        throw Error(msg.str());
    }
    if (material.albedo_texture < -1) {
        std::ostringstream msg;
        msg << "material albedo_texture = " << material.albedo_texture
            << ": must be a texture id or -1";
        throw Error(msg.str());
    }
}

}  // namespace librt
