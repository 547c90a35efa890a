#include <librt/core/error.h>
#include <librt/material/bsdf.h>
#include <librt/material/material.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

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

// A scalar in [0, 1] (NaN fails).
void check_unit(const char* name, float v) {
    if (!(v >= 0.0f && v <= 1.0f)) {
        std::ostringstream msg;
        msg << "material " << name << " = " << v << ": must be in [0, 1]";
        throw Error(msg.str());
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

Material Material::conductor(const glm::vec3& eta, const glm::vec3& k, float roughness) {
    Material m;
    m.kind = MaterialKind::Conductor;
    m.albedo = glm::vec3(1.0f);
    m.eta = eta;
    m.k = k;
    m.roughness = roughness;
    validate(m);
    return m;
}

Material Material::conductor(Metal metal, float roughness) {
    // (n, k) at 650, 550 and 450 nm (R, G, B: 1.907, 2.254 and 2.755 eV).
    // Au, Ag, Cu: Johnson & Christy, Phys. Rev. B 6, 4370 (1972), Table 1, interpolated
    // linearly in photon energy between its rows (1.88/2.01, 2.13/2.26, 2.75/2.88 eV).
    // Al: the Lorentz-Drude model of Rakic et al., Appl. Opt. 37, 5271 (1998), Table 1
    // (fitted to Rakic, Appl. Opt. 34, 4755 (1995)), evaluated at those energies.
    // tests/render/metal_table_test.cpp recomputes every value from those sources. (Before,
    // gold's red k was 3.15, J&C's value near 610 nm, and silver's red and green n 0.14
    // and 0.12 where J&C give 0.05 and 0.06.)
    switch (metal) {
        case Metal::Gold:
            return conductor({0.155f, 0.424f, 1.383f}, {3.607f, 2.473f, 1.915f}, roughness);
        case Metal::Silver:
            return conductor({0.052f, 0.060f, 0.040f}, {4.413f, 3.598f, 2.649f}, roughness);
        case Metal::Copper:
            return conductor({0.237f, 1.006f, 1.240f}, {3.633f, 2.583f, 2.393f}, roughness);
        case Metal::Aluminium:
            return conductor({1.420f, 0.966f, 0.590f}, {7.467f, 6.458f, 5.311f}, roughness);
    }
    throw Error("material metal: unknown Metal value " + std::to_string(int(metal)));
}

Material Material::conductor_artist(const glm::vec3& reflectance, const glm::vec3& edge_tint,
                                    float roughness) {
    check_colour("reflectance", reflectance, true);
    check_colour("edge_tint", edge_tint, true);
    glm::vec3 eta, k;
    for (int c = 0; c < 3; ++c) {
        // Gulbrandsen 2014, eqs. for n(r, g) and k(r, n): n interpolates by g between the
        // n that gives r with k = 0 and the one that gives r with k -> its limit.
        const float r = std::min(reflectance[c], 0.999f), g = edge_tint[c];
        const float sr = std::sqrt(r);
        const float n_min = (1.0f - r) / (1.0f + r);
        const float n_max = (1.0f + sr) / (1.0f - sr);
        const float n = g * n_min + (1.0f - g) * n_max;
        const float k2 = ((n + 1.0f) * (n + 1.0f) * r - (n - 1.0f) * (n - 1.0f)) / (1.0f - r);
        eta[c] = n;
        k[c] = std::sqrt(std::max(0.0f, k2));
    }
    return conductor(eta, k, roughness);
}

Material Material::rough_dielectric(float ior, float roughness, const glm::vec3& tint) {
    Material m = dielectric(ior, true, tint);
    m.kind = MaterialKind::RoughDielectric;
    m.roughness = roughness;
    validate(m);
    return m;
}

Material Material::metallic_roughness(const glm::vec3& base_color, float metallic, float roughness,
                                      float ior, float transmission) {
    Material m;
    m.kind = MaterialKind::MetallicRoughness;
    m.albedo = glm::vec3(1.0f);  // colours are the material's own (bsdf.h's albedo contract)
    m.base_color = base_color;
    m.metallic = metallic;
    m.roughness = roughness;
    m.ior = ior;
    m.transmission = transmission;
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

glm::vec3 Material::interior_transmittance(float length) const {
    if (!absorbs_inside() || !(length > 0.0f)) return glm::vec3(1.0f);
    // c^(L / d) = exp(ln(c) L / d): sigma = -ln(c) / d per unit length (KHR_materials_volume).
    const float x = length / attenuation_distance;
    return {std::pow(attenuation_color.x, x), std::pow(attenuation_color.y, x),
            std::pow(attenuation_color.z, x)};
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
    check_colour("base_color", material.base_color, true);
    check_colour("eta", material.eta, false);
    check_colour("k", material.k, false);
    check_unit("roughness", material.roughness);
    check_unit("metallic", material.metallic);
    check_unit("transmission", material.transmission);
    check_unit("alpha", material.alpha);
    check_unit("alpha_cutoff", material.alpha_cutoff);
    check_unit("anisotropy", material.anisotropy);
    if (material.unlit && material.kind != MaterialKind::Emissive)
        throw Error("material unlit = true: only an Emissive material is unlit");
    check_unit("clearcoat", material.clearcoat);
    check_unit("clearcoat_roughness", material.clearcoat_roughness);
    check_unit("specular", material.specular);
    check_colour("specular_color", material.specular_color, false);
    check_colour("sheen_color", material.sheen_color, true);
    check_unit("sheen_roughness", material.sheen_roughness);
    check_unit("occlusion_strength", material.occlusion_strength);
    if (!std::isfinite(material.anisotropy_rotation)) {
        std::ostringstream msg;
        msg << "material anisotropy_rotation = " << material.anisotropy_rotation
            << ": must be finite";
        throw Error(msg.str());
    }
    const glm::vec3& d = material.anisotropy_direction;
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) {
        std::ostringstream msg;
        msg << "material anisotropy_direction = (" << d.x << ", " << d.y << ", " << d.z
            << "): must be finite";
        throw Error(msg.str());
    }
    if (!std::isfinite(material.normal_scale)) {
        std::ostringstream msg;
        msg << "material normal_scale = " << material.normal_scale << ": must be finite";
        throw Error(msg.str());
    }
    if (!std::isfinite(material.clearcoat_normal_scale)) {
        std::ostringstream msg;
        msg << "material clearcoat_normal_scale = " << material.clearcoat_normal_scale
            << ": must be finite";
        throw Error(msg.str());
    }
    const glm::vec3& cn = material.clearcoat_normal;
    if (!std::isfinite(cn.x) || !std::isfinite(cn.y) || !std::isfinite(cn.z)) {
        std::ostringstream msg;
        msg << "material clearcoat_normal = (" << cn.x << ", " << cn.y << ", " << cn.z
            << "): must be finite";
        throw Error(msg.str());
    }
    const std::pair<const char*, const TextureSlot*> slots[] = {
        {"base_color_texture", &material.base_color_texture},
        {"metallic_roughness_texture", &material.metallic_roughness_texture},
        {"emission_texture", &material.emission_texture},
        {"normal_texture", &material.normal_texture},
        {"anisotropy_texture", &material.anisotropy_texture},
        {"clearcoat_texture", &material.clearcoat_texture},
        {"clearcoat_roughness_texture", &material.clearcoat_roughness_texture},
        {"clearcoat_normal_texture", &material.clearcoat_normal_texture},
        {"sheen_color_texture", &material.sheen_color_texture},
        {"sheen_roughness_texture", &material.sheen_roughness_texture},
        {"specular_texture", &material.specular_texture},
        {"specular_color_texture", &material.specular_color_texture},
        {"transmission_texture", &material.transmission_texture},
        {"occlusion_texture", &material.occlusion_texture}};
    for (const auto& [name, slot] : slots) {
        bool finite_map = true;
        for (int c = 0; c < 3; ++c)
            finite_map = finite_map && std::isfinite(slot->transform[c].x) &&
                         std::isfinite(slot->transform[c].y);
        if (slot->uv_set > 1) {
            std::ostringstream msg;
            msg << "material " << name << ".uv_set = " << int(slot->uv_set) << ": must be 0 or 1";
            throw Error(msg.str());
        }
        if (slot->texture < -1 || !finite_map) {
            std::ostringstream msg;
            msg << "material " << name << " = texture " << slot->texture
                << (finite_map ? ": must be a texture id or -1" : ": its transform is not finite");
            throw Error(msg.str());
        }
    }
    if (material.albedo_texture < -1) {
        std::ostringstream msg;
        msg << "material albedo_texture = " << material.albedo_texture
            << ": must be a texture id or -1";
        throw Error(msg.str());
    }
    if (material.diffuse_model != DiffuseModel::Lambert &&
        material.diffuse_model != DiffuseModel::Burley) {
        std::ostringstream msg;
        msg << "material diffuse_model = " << int(material.diffuse_model)
            << ": must be Lambert or Burley";
        throw Error(msg.str());
    }
    // A component of 0 would absorb everything after any distance: log(0) has no rate.
    const glm::vec3& c = material.attenuation_color;
    if (!(c.x > 0.0f && c.x <= 1.0f && c.y > 0.0f && c.y <= 1.0f && c.z > 0.0f && c.z <= 1.0f)) {
        std::ostringstream msg;
        msg << "material attenuation_color = (" << c.x << ", " << c.y << ", " << c.z
            << "): each component must be in (0, 1]";
        throw Error(msg.str());
    }
    if (!(material.attenuation_distance > 0.0f)) {
        std::ostringstream msg;
        msg << "material attenuation_distance = " << material.attenuation_distance
            << ": must be > 0 (infinity: no absorption)";
        throw Error(msg.str());
    }
}

}  // namespace librt
