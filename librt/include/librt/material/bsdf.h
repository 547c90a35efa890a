#pragma once

#include <librt/export.h>
#include <librt/material/material.h>
#include <librt/sampling/warp.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>

// The BSDF seam: what a surface does to light, as three free functions over the plain,
// tagged Material (sample, eval, pdf, after Nori's BSDF interface) and lobe flags that
// tell the integrator what kind of scattering a material has (after Mitsuba's BSDFFlags),
// so that it asks "is this vertex specular?" instead of switching on the material kind.
// Each kind's formulas live in their own private header (librt/src/material/bsdf_*.h); the
// one switch over MaterialKind is src/material/bsdf_dispatch.h. Directions are unit vectors
// in the local shading frame, both pointing away from the surface: wo toward where the
// light goes (the previous path vertex), wi toward where it comes from.

namespace librt {

/// What kind of scattering a lobe does, as bit flags (a material may have several lobes).
enum class BsdfLobe : std::uint8_t {
    None = 0,               ///< no scattering at all (a pure emitter)
    Reflection = 1 << 0,    ///< leaves on the side it arrived from
    Transmission = 1 << 1,  ///< crosses the surface
    Diffuse = 1 << 2,       ///< spread over the hemisphere (Lambert)
    Glossy = 1 << 3,        ///< spread around a preferred direction (rough metal, rough glass)
    Specular = 1 << 4,      ///< a delta distribution: one direction, no density
    /// Light passes straight through, direction unchanged (a smooth thin-walled layer; after
    /// Mitsuba's null lobe). Not part of sample / eval / pdf: pass_through() gives its
    /// colour, and the integrators cross it as they would a transparent surface, neither a
    /// bounce nor a vertex, so shadow rays can see a light through it.
    Null = 1 << 5,
    DiffuseReflection = Diffuse | Reflection,       ///< Lambertian reflection
    SpecularReflection = Specular | Reflection,     ///< mirror reflection
    SpecularTransmission = Specular | Transmission  ///< refraction through smooth glass
};

/// Union of lobe flags.
[[nodiscard]] constexpr BsdfLobe operator|(BsdfLobe a, BsdfLobe b) {
    return BsdfLobe(std::uint8_t(a) | std::uint8_t(b));
}
/// Intersection of lobe flags.
[[nodiscard]] constexpr BsdfLobe operator&(BsdfLobe a, BsdfLobe b) {
    return BsdfLobe(std::uint8_t(a) & std::uint8_t(b));
}
/// True when `flags` has any of the bits of `any`.
[[nodiscard]] constexpr bool has(BsdfLobe flags, BsdfLobe any) {
    return (std::uint8_t(flags) & std::uint8_t(any)) != 0;
}
/// True when some lobe has a density (diffuse or glossy): light sampling and MIS apply.
[[nodiscard]] constexpr bool has_non_specular(BsdfLobe flags) {
    return has(flags, BsdfLobe::Diffuse | BsdfLobe::Glossy);
}

/// The local frame of a surface point: +z is the shading normal turned to the side wo
/// arrives from (decided by the geometric normal, which is what a ray can cross).
struct ShadingFrame {
    Frame shading;  ///< world <-> local; shading.n is the shading normal on wo's side
    /// The geometric normal on wo's side, in local coordinates: a direction below it is
    /// on the other side of the real surface, whatever the (interpolated) shading normal says.
    glm::vec3 geometric{0.0f, 0.0f, 1.0f};
    /// True when wo is on the side the primitive faces (outside a closed, outward-wound
    /// dielectric, so a refracted ray enters it).
    bool front = true;

    /// The frame at a hit with unit normals ns (shading) and ng (geometric, the side the
    /// primitive faces, with ns on its side) for a ray arriving along `incoming` (toward
    /// the surface, need not be unit).
    [[nodiscard]] static ShadingFrame at(const glm::vec3& ns, const glm::vec3& ng,
                                         const glm::vec3& incoming) {
        const bool front = glm::dot(incoming, ng) < 0.0f;
        return facing(front ? ns : -ns, front ? ng : -ng, front);
    }
    /// The frame from unit normals already turned to wo's side (n shading, g geometric) and
    /// the side they were turned to: at()'s second half, for a caller that has used the
    /// world-space normals before deciding it needs the frame (the path loop).
    [[nodiscard]] static ShadingFrame facing(const glm::vec3& n, const glm::vec3& g, bool front) {
        ShadingFrame f;
        f.front = front;
        f.shading = Frame::from_normal(n);
        f.geometric = f.shading.to_local(g);
        return f;
    }
    /// World direction to local.
    [[nodiscard]] glm::vec3 to_local(const glm::vec3& v) const { return shading.to_local(v); }
    /// Local direction to world.
    [[nodiscard]] glm::vec3 to_world(const glm::vec3& v) const { return shading.to_world(v); }
    /// True when local direction w leaves on wo's side of the real (geometric) surface.
    [[nodiscard]] bool above_geometry(const glm::vec3& w) const {
        return glm::dot(w, geometric) > 0.0f;
    }
};

/// What a BSDF needs at one point besides its material: the frame and the material's
/// parameters with its textures looked up there.
struct ShadingPoint {
    ShadingFrame frame;  ///< local frame, facing wo
    /// Material::albedo, or its texture's value at the point: the colour that scales every
    /// lobe of the material (Lambert's reflectance, the tint of mirrors and glass). A zero
    /// channel scatters nothing in that channel, which the integrators use to skip a vertex
    /// whose throughput times albedo is 0; a kind whose lobes share no such scale must
    /// leave it at 1 and apply its colours itself.
    glm::vec3 albedo{0.0f};
};

/// One direction drawn by sample().
struct BsdfSample {
    glm::vec3 wi{0.0f};  ///< sampled direction, local, unit
    /// f cos(theta_i) / pdf, the factor a path's throughput is multiplied by; for a
    /// specular lobe the whole scattering weight (e.g. the tint of glass).
    glm::vec3 weight{0.0f};
    /// Solid-angle density of wi (what pdf() returns) for a non-specular lobe; for a
    /// specular lobe the discrete probability of having chosen it (1, or F for Fresnel).
    float pdf = 0.0f;
    BsdfLobe lobe = BsdfLobe::None;  ///< the one lobe sampled (None: no direction)

    /// True when a direction was drawn; false ends the path (absorbed, or below the surface).
    [[nodiscard]] bool valid() const { return lobe != BsdfLobe::None && pdf > 0.0f; }
};

/// True when sample() needs its uc to choose among several lobes (reflection and
/// transmission, or lobes of different kinds); with one lobe uc is unused, and a caller
/// may pass anything and save drawing it.
[[nodiscard]] constexpr bool chooses_lobe(BsdfLobe flags) {
    const int kinds = int(has(flags, BsdfLobe::Diffuse)) + int(has(flags, BsdfLobe::Glossy)) +
                      int(has(flags, BsdfLobe::Specular));
    return kinds > 1 || (has(flags, BsdfLobe::Reflection) && has(flags, BsdfLobe::Transmission));
}

/// The lobes a material has.
[[nodiscard]] LIBRT_API BsdfLobe lobes(const Material& material);

/// The fraction of light (per channel) that passes the surface straight through for the
/// outgoing wo (local): the weight of the Null lobe, 0 for a material without one. A ray
/// along -wo continues along -wo with this factor; sample / eval / pdf describe the rest
/// of the BSDF, so the whole BSDF is theirs plus pass_through(wo) delta(wi = -wo).
[[nodiscard]] LIBRT_API glm::vec3 pass_through(const Material& material, const ShadingPoint& point,
                                               const glm::vec3& wo);

/// True when some point of a surface with this material may have a Null lobe (whatever its
/// textures give there): what tells a Scene its shadow rays must look for such surfaces.
[[nodiscard]] LIBRT_API bool may_pass_through(const Material& material);

/// The colour the surface reflects or transmits at `point` (the material's per-hit inputs
/// already applied, as Scene::shade gives them): the albedo AOV, the guide a denoiser
/// divides the image by. Each lobe contributes its colour weighted by its Fresnel share at
/// normal incidence, ignoring the microfacets' shadowing: Lambert its reflectance; a mirror,
/// glass (smooth or rough) their tint; a conductor its exact Fresnel reflectance at normal
/// incidence times its tint; the glTF metallic-roughness material
/// (1 - metallic) [(1 - f0) base_color + f0] + metallic base_color with f0 from its ior
/// (0.04 at 1.5), its diffuse and transmitted parts sharing base_color; an emitter 0. This
/// is what Open Image Denoise's documentation asks of its albedo input (the ratio of
/// reflected or transmitted to incident light; for metals the reflectivity at normal
/// incidence; for glass 1 or the tint), as Cycles' Denoising Albedo pass also sums its
/// closures' colours.
/// Independent of the view direction, so a flat material gives a flat AOV.
[[nodiscard]] LIBRT_API glm::vec3 denoising_albedo(const Material& material,
                                                   const ShadingPoint& point);

/// Draws wi for the outgoing wo (local) from uc (to choose a lobe) and u (the direction),
/// both uniform in [0, 1). An invalid sample means the path ends there.
[[nodiscard]] LIBRT_API BsdfSample sample(const Material& material, const ShadingPoint& point,
                                          const glm::vec3& wo, float uc, glm::vec2 u);

/// The BSDF value f(wo, wi) (per steradian, without the cosine) of the non-specular lobes;
/// 0 for specular lobes and for directions they cannot reach (e.g. below the surface).
[[nodiscard]] LIBRT_API glm::vec3 eval(const Material& material, const ShadingPoint& point,
                                       const glm::vec3& wo, const glm::vec3& wi);

/// The solid-angle density with which sample() draws wi given wo (non-specular lobes
/// only; 0 for specular ones). Where sample() may fail (a bent shading normal), this is a
/// sub-density: it integrates to the probability of a valid sample.
[[nodiscard]] LIBRT_API float pdf(const Material& material, const ShadingPoint& point,
                                  const glm::vec3& wo, const glm::vec3& wi);

}  // namespace librt
