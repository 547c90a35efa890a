#pragma once

// The one dispatch point from MaterialKind to its BSDF: each kind is a type in its own
// bsdf_<kind>.h that satisfies BsdfKind (bsdf_kind.h: its kKind, kLobes, sample / eval /
// pdf and the facts the integrators and the scene ask: transmits, near_specular,
// casts_caustics, multiply_color); a new kind adds its header and one case in dispatch().
// A MaterialKind without a case, or a type that misses a fact, does not compile.
// Private, and inline so that the integrators' path loop calls the BSDFs without a call
// through the public, out-of-line functions of bsdf.h.
// The microfacet kinds (Conductor, RoughDielectric, MetallicRoughness) mark their own
// sample / eval / pdf gnu::noinline: their bodies (isotropic and anisotropic) inlined into
// the path loop made g++ stop inlining the loop's helpers (microfacet_anisotropic.h).

#include "material/bsdf_conductor.h"
#include "material/bsdf_dielectric.h"
#include "material/bsdf_diffuse.h"
#include "material/bsdf_emissive.h"
#include "material/bsdf_kind.h"
#include "material/bsdf_metallic_roughness.h"
#include "material/bsdf_mirror.h"
#include "material/bsdf_rough_dielectric.h"

#include <librt/material/bsdf.h>

namespace librt {
namespace bsdfs {

/// The value dispatch() hands its function for kind T: a T, once checked to answer every
/// fact of BsdfKind.
template <BsdfKind T>
[[gnu::always_inline]] constexpr T bsdf_of() {
    return T{};
}

// A MaterialKind without a case in dispatch() is an error, not a warning (-Wswitch).
#pragma GCC diagnostic push
#pragma GCC diagnostic error "-Wswitch"
/// The one dispatch point from MaterialKind to its BSDF type: fn(bsdf) with bsdf an
/// object of the kind's type (bsdf_of<T>()). A new kind adds its header and one case here;
/// the case label is the type's own kKind, so a type cannot sit under another's enumerator.
template <class Fn>
constexpr decltype(auto) dispatch(MaterialKind kind, Fn&& fn) {
    switch (kind) {
        case Diffuse::kKind:
            return fn(bsdf_of<Diffuse>());
        case Mirror::kKind:
            return fn(bsdf_of<Mirror>());
        case Dielectric::kKind:
            return fn(bsdf_of<Dielectric>());
        case Conductor::kKind:
            return fn(bsdf_of<Conductor>());
        case RoughDielectric::kKind:
            return fn(bsdf_of<RoughDielectric>());
        case MetallicRoughness::kKind:
            return fn(bsdf_of<MetallicRoughness>());
        case Emissive::kKind:
            break;
    }
    // Emissive, and a value outside the enumerators (only a cast makes one): it scatters
    // nothing.
    return fn(bsdf_of<Emissive>());
}
#pragma GCC diagnostic pop

/// True when `kind` has its own case in dispatch() (false for a value outside the
/// enumerators): what a test walks to visit every kind.
[[nodiscard]] constexpr bool has_bsdf(MaterialKind kind) {
    return dispatch(kind, [](auto bsdf) { return decltype(bsdf)::kKind; }) == kind;
}

/// True when m is Lambertian (bsdfs::Diffuse): the one kind the path loop handles inline,
/// in world space, without the dispatch (integrators.cpp's fast paths).
[[nodiscard]] constexpr bool is_lambertian(const Material& m) { return m.kind == Diffuse::kKind; }

/// Whether some ray may pass a surface of material m (BsdfKind::transmits): false for an
/// occluder that no sample() crosses.
[[nodiscard]] inline bool transmits(const Material& m) {
    return dispatch(m.kind, [&](auto bsdf) { return decltype(bsdf)::transmits(m); });
}

/// Whether m's lobes are all narrower than perceptual roughness `limit`, without a diffuse
/// part (BsdfKind::near_specular).
[[nodiscard]] inline bool near_specular(const Material& m, float limit) {
    return dispatch(m.kind, [&](auto bsdf) { return decltype(bsdf)::near_specular(m, limit); });
}

/// Whether m (per-hit inputs applied) is a caustic caster at max_roughness
/// (BsdfKind::casts_caustics; caustic_paths.h).
[[nodiscard]] inline bool casts_caustics(const Material& m, float max_roughness) {
    return dispatch(m.kind,
                    [&](auto bsdf) { return decltype(bsdf)::casts_caustics(m, max_roughness); });
}

/// Multiplies m's colour by c, a per-vertex colour (BsdfKind::multiply_color).
inline void multiply_color(Material& m, const glm::vec3& c) {
    dispatch(m.kind, [&](auto bsdf) { decltype(bsdf)::multiply_color(m, c); });
}

/// denoising_albedo() of bsdf.h (BsdfKind::denoising_albedo).
[[nodiscard]] inline glm::vec3 denoising_albedo_of(const Material& m, const ShadingPoint& p) {
    return dispatch(m.kind, [&](auto bsdf) { return decltype(bsdf)::denoising_albedo(m, p); });
}

/// lobes() of bsdf.h, inline: a type whose lobes depend on its parameters (a rough kind
/// at roughness 0 is specular) provides static lobes(m), a subset of its kLobes; the
/// others have their kLobes.
[[nodiscard]] inline BsdfLobe lobes_of(const Material& m) {
    return dispatch(m.kind, [&](auto bsdf) {
        using T = decltype(bsdf);
        if constexpr (requires { T::lobes(m); })
            return T::lobes(m);
        else
            return T::kLobes;
    });
}
/// pass_through() of bsdf.h: a type with a Null lobe provides static pass_through(m, p, wo).
[[nodiscard]] inline glm::vec3 pass_through_of(const Material& m, const ShadingPoint& p,
                                               const glm::vec3& wo) {
    return dispatch(m.kind, [&](auto bsdf) {
        using T = decltype(bsdf);
        if constexpr (requires { T::pass_through(m, p, wo); })
            return T::pass_through(m, p, wo);
        else
            return glm::vec3(0.0f);
    });
}
/// may_pass_through() of bsdf.h: a type with a Null lobe provides static may_pass_through(m).
[[nodiscard]] inline bool may_pass_through_of(const Material& m) {
    return dispatch(m.kind, [&](auto bsdf) {
        using T = decltype(bsdf);
        if constexpr (requires { T::may_pass_through(m); })
            return T::may_pass_through(m);
        else
            return false;
    });
}
/// sample() of bsdf.h, inline (forced: g++ keeps the call in the path loop otherwise).
[[nodiscard, gnu::always_inline]] inline BsdfSample sample_bsdf(const Material& m,
                                                                const ShadingPoint& p,
                                                                const glm::vec3& wo, float uc,
                                                                glm::vec2 u) {
    return dispatch(m.kind, [&](auto bsdf) { return decltype(bsdf)::sample(m, p, wo, uc, u); });
}
/// eval() of bsdf.h, inline.
[[nodiscard]] inline glm::vec3 eval_bsdf(const Material& m, const ShadingPoint& p,
                                         const glm::vec3& wo, const glm::vec3& wi) {
    return dispatch(m.kind, [&](auto bsdf) { return decltype(bsdf)::eval(m, p, wo, wi); });
}
/// The material a vertex next to a delta light (point, spot, delta sun) scatters with:
/// path-space regularisation (docs/materials-and-lights.md). m with its roughness raised
/// to microfacet::kDeltaLightRoughness, in `out`, when the kind provides static
/// widens_for_delta_light(m) and it is true; false, `out` untouched, otherwise (the
/// material is used as it is). PathTracer's light sample evaluates it; BDPT also samples
/// it and takes its densities, so that every strategy sees the same integrand.
[[nodiscard]] inline bool delta_light_material(const Material& m, Material& out) {
    return dispatch(m.kind, [&](auto bsdf) {
        using T = decltype(bsdf);
        if constexpr (requires { T::widens_for_delta_light(m); }) {
            if (!T::widens_for_delta_light(m)) return false;
            out = m;
            out.roughness = microfacet::delta_light_roughness(m.roughness);
            // A clear coat's own lobe (MetallicRoughness; 0 and unused by the others).
            out.clearcoat_roughness = microfacet::delta_light_roughness(m.clearcoat_roughness);
            return true;
        } else {
            return false;
        }
    });
}
/// eval() and pdf() of bsdf.h at once (one dispatch; what next-event estimation with MIS
/// needs), as f and the density.
struct EvalPdf {
    glm::vec3 f;
    float pdf;
};
[[nodiscard]] inline EvalPdf eval_pdf_bsdf(const Material& m, const ShadingPoint& p,
                                           const glm::vec3& wo, const glm::vec3& wi) {
    return dispatch(m.kind, [&](auto bsdf) {
        using T = decltype(bsdf);
        return EvalPdf{T::eval(m, p, wo, wi), T::pdf(m, p, wo, wi)};
    });
}
/// pdf() of bsdf.h, inline.
[[nodiscard]] inline float pdf_bsdf(const Material& m, const ShadingPoint& p, const glm::vec3& wo,
                                    const glm::vec3& wi) {
    return dispatch(m.kind, [&](auto bsdf) { return decltype(bsdf)::pdf(m, p, wo, wi); });
}

}  // namespace bsdfs
}  // namespace librt
