#pragma once

// What a BSDF kind must answer, as a concept: the checklist for a new MaterialKind in code.
// Each kind is a stateless type in its own bsdf_<kind>.h; the dispatch (bsdf_dispatch.h)
// accepts only types that satisfy BsdfKind, so a kind that forgets a fact does not
// compile, and the integrators and the scene ask these facts instead of naming kinds
// (after Mitsuba's BSDFFlags, which its integrators query the same way).

#include <librt/material/bsdf.h>
#include <librt/material/material.h>

#include <concepts>

namespace librt::bsdfs {

/// A BSDF kind: the MaterialKind it implements, its lobes, its three BSDF functions and the
/// facts about it that the path loops and the scene need.
template <class T>
concept BsdfKind = requires(const Material& m, Material& shaded, const ShadingPoint& p,
                            const glm::vec3& w, float x, glm::vec2 u) {
    /// The enumerator this type implements (dispatch()'s case label).
    { T::kKind } -> std::convertible_to<MaterialKind>;
    /// Every lobe a material of the kind may have, over all its parameters; a kind whose
    /// lobes depend on them also provides static lobes(m), one material's (lobes_of).
    { T::kLobes } -> std::convertible_to<BsdfLobe>;
    /// sample / eval / pdf of bsdf.h.
    { T::sample(m, p, w, x, u) } -> std::same_as<BsdfSample>;
    { T::eval(m, p, w, w) } -> std::same_as<glm::vec3>;
    { T::pdf(m, p, w, w) } -> std::same_as<float>;
    /// True when some ray may pass the surface at some point of it (refraction, a
    /// transmission lobe, a Null lobe), whatever its per-hit inputs give there; false
    /// promises that no sample() ever crosses it: the scene's occluders rely on it.
    { T::transmits(m) } -> std::same_as<bool>;
    /// True when every non-specular lobe is a microfacet lobe of perceptual roughness below
    /// `limit` and there is no diffuse part: too narrow for path guiding's cells.
    { T::near_specular(m, x) } -> std::same_as<bool>;
    /// True when the surface is a caustic caster (caustic_paths.h): every part of its BSDF
    /// is specular or a microfacet lobe of perceptual roughness <= max_roughness, with no
    /// diffuse part.
    { T::casts_caustics(m, x) } -> std::same_as<bool>;
    /// Multiplies the material's colour by a per-vertex colour (glTF COLOR_0): albedo, or
    /// the kind's own colour where albedo is not its colour.
    { T::multiply_color(shaded, w) } -> std::same_as<void>;
    /// The colour the surface reflects or transmits at p (per-hit inputs applied), for the
    /// albedo AOV a denoiser divides by (bsdf.h, denoising_albedo): each lobe's colour
    /// weighted by its Fresnel share at normal incidence.
    { T::denoising_albedo(m, p) } -> std::same_as<glm::vec3>;
};

}  // namespace librt::bsdfs
