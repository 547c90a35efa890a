#pragma once

// The one dispatch point from MaterialKind to its BSDF: each kind's type (in its own
// bsdf_<kind>.h) provides kLobes and static sample / eval / pdf; a new kind adds its header
// and one case in dispatch(). Private, and inline so that the integrators' path loop
// calls the BSDFs without a call through the public, out-of-line functions of bsdf.h.
// The microfacet kinds (Conductor, RoughDielectric, MetallicRoughness) mark their own
// sample / eval / pdf gnu::noinline: their bodies (isotropic and anisotropic) inlined into
// the path loop made g++ stop inlining the loop's helpers (microfacet_anisotropic.h).

#include "material/bsdf_conductor.h"
#include "material/bsdf_dielectric.h"
#include "material/bsdf_diffuse.h"
#include "material/bsdf_metallic_roughness.h"
#include "material/bsdf_mirror.h"
#include "material/bsdf_rough_dielectric.h"

#include <librt/material/bsdf.h>

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

/// The one dispatch point from MaterialKind to its BSDF type: each type provides kLobes
/// and static sample / eval / pdf. A new kind adds its header and one case here.
template <class Fn>
inline decltype(auto) dispatch(MaterialKind kind, Fn&& fn) {
    switch (kind) {
        case MaterialKind::Diffuse:
            return fn(bsdfs::Diffuse{});
        case MaterialKind::Mirror:
            return fn(bsdfs::Mirror{});
        case MaterialKind::Dielectric:
            return fn(bsdfs::Dielectric{});
        case MaterialKind::Conductor:
            return fn(bsdfs::Conductor{});
        case MaterialKind::RoughDielectric:
            return fn(bsdfs::RoughDielectric{});
        case MaterialKind::MetallicRoughness:
            return fn(bsdfs::MetallicRoughness{});
        case MaterialKind::Emissive:
            break;
    }
    return fn(bsdfs::Black{});
}

/// lobes() of bsdf.h, inline: a type whose lobes depend on its parameters (a rough kind
/// at roughness 0 is specular) provides static lobes(m); the others their kLobes.
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
