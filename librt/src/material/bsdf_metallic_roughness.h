#pragma once

// The glTF 2.0 metallic-roughness material (MaterialKind::MetallicRoughness) as the glTF
// 2.0 specification, Appendix B, defines it (with KHR_materials_ior and a thin-walled
// KHR_materials_transmission):
//   material   = mix(dielectric, metal, metallic)
//   metal      = specular_brdf(alpha) * (c + (1 - c) (1 - |V.H|)^5)        (conductor_fresnel)
//   dielectric = mix(base, specular_brdf(alpha), Fr)                       (fresnel_mix)
//   Fr         = f0 + (1 - f0) (1 - |V.H|)^5,  f0 = ((ior - 1) / (ior + 1))^2 (0.04 at 1.5)
//   base       = mix(c / pi, specular_btdf(alpha), transmission)
//   specular_brdf = D V with GGX D and the height-correlated Smith V = G2 / (4 |N.L| |N.V|)
// with c the base colour and alpha = roughness^2. The transmission lobe is thin-walled
// (the extension's default without KHR_materials_volume): c D V evaluated at wi mirrored
// through the surface plane, i.e. the light leaves undeviated by refraction.
//
// Sampling: one lobe (GGX reflection by visible normals, cosine diffuse, or the mirrored
// GGX transmission) chosen with probability proportional to an estimate of its directional
// albedo at wo (Schlick Fresnel at cos_o times the lobe's colour), and the pdf is the whole
// mixture's, so MIS sees one density. Estimating per lobe what it contributes keeps the
// one-sample mixture's variance low without tables; the specular lobe keeps at least a
// small share because its Fresnel at wo.h can exceed the estimate at cos_o.
// Smooth transmission (roughness at GGX's alpha floor, no anisotropy) is a Null lobe: a
// thin wall of roughness 0 lets light through undeviated, so it is exactly a transparent
// surface of colour (1 - metallic) (1 - Fr(cos_o)) transmission c. The integrators cross
// it without a bounce and shadow rays see lights through it (pass_through); sample / eval /
// pdf keep the reflection lobes. As a GGX lobe of alpha 10^-3 it was a spike that next-event
// estimation could not light through: only a BSDF ray that happened to reach a light did.
// Anisotropic GGX when Material::anisotropy > 0 (microfacet_anisotropic.h), as
// KHR_materials_anisotropy extends this material. Material::albedo scales every lobe (1 by
// default); base colour is its own field, because a black base colour still reflects the
// dielectric specular (bsdf.h's albedo contract).
//
// Material::diffuse_model = DiffuseModel::Burley replaces Lambert x (1 - Fr) by Burley's diffuse
// (2012, "Physically Based Shading at Disney", sec. 5.3), Blender's Principled BSDF's:
//   base = (1 - transmission) c / pi (1 + (F_D90 - 1)(1 - cos_i)^5)(1 + (F_D90 - 1)(1 -
//   cos_o)^5),  F_D90 = 0.5 + 2 roughness (wi.h)^2
// (reciprocal; not energy conserving: above roughness 0.25, F_D90 can exceed 1 and a white
// base reflects more than it receives at grazing angles, as in Cycles).
//
// The glTF extensions layered on it (docs/materials-and-lights.md, "glTF material
// extensions"), each inert at its default:
//   KHR_materials_specular: Fr = specular (F0' + (1 - F0') (1 - |V.H|)^5), F0' = min(f0
//     specular_color, 1), and the base under it weighs 1 - max(Fr) (the extension's
//     fresnel_mix);
//   KHR_materials_sheen: f = sheen_color D_charlie V_neubelt (sheen.h) + Ts base, Ts =
//     min(1 - max(sheen_color) E(cos_o), 1 - max(sheen_color) E(cos_i)) (the extension's
//     albedo scaling, reciprocal as written);
//   KHR_materials_clearcoat: f = clearcoat Fc(|V.H|) D_c V_c + Tc (sheen + base), a GGX
//     coat of IOR 1.5 (Fc: Schlick, F0 0.04) and alpha = clearcoat_roughness^2, with Tc =
//     (1 - clearcoat Fc(cos_o)) (1 - clearcoat Fc(cos_i)). The extension writes the view's
//     factor alone, (1 - clearcoat Fc(N.V)); light crosses the coat on the way in and out,
//     and the product of both crossings is reciprocal and conserves energy, which the
//     view's factor alone (or the larger cosine's, on both sides) does not: a grazing view
//     would see the coat's reflection plus a base barely dimmed for near-normal light.
// The coat and sheen are sampled as two more lobes of the one-sample mixture (the coat's
// GGX by visible normals, the sheen by the cosine), chosen with probabilities from their
// albedo estimates at wo (clearcoat Fc(cos_o); max(sheen_color) E(cos_o)).
// clearcoatNormalTexture gives the coat a normal n_c of its own (Material::clearcoat_normal):
// the coat lobe is the same GGX lobe in the frame of n_c, its cosines (in Fc, D, V and Tc)
// taken against n_c, and it carries its own cosine as every lobe does: what the integrator
// multiplies by |wi.z| (the base's shading normal) is f_c (wi.n_c) / wi.z, so f cos over
// wi is f_c (wi.n_c), the coat's reflection about its normal (as Cycles' closures each
// bring their own N). Like any shading normal this is reciprocal only in the coat's frame
// (f_c is; the cosine ratio is not), and the coat reflects only where wo and wi are above
// both n_c and the base's side of the surface.

#include "material/microfacet.h"
#include "material/microfacet_anisotropic.h"
#include "material/sheen.h"
#include "material/specular.h"

#include <librt/material/bsdf.h>
#include <librt/sampling/warp.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace librt::bsdfs {

struct MetallicRoughness {
    static constexpr MaterialKind kKind = MaterialKind::MetallicRoughness;
    static constexpr BsdfLobe kLobes = BsdfLobe::Diffuse | BsdfLobe::Glossy | BsdfLobe::Reflection |
                                       BsdfLobe::Transmission | BsdfLobe::Null;

    /// Any transmission factor: the metallic texture may lower metallic at a point.
    static bool transmits(const Material& m) { return m.transmission > 0.0f; }
    /// Wholly metal only: its one GGX reflection. (A wholly transmissive one has no Lambert
    /// layer either but stays guided, as it was when this rule lived in the path loop.)
    static bool near_specular(const Material& m, float limit) {
        return m.roughness < limit && m.metallic >= 1.0f && !has_sheen(m) &&
               !(m.clearcoat > 0.0f && m.clearcoat_roughness >= limit);
    }
    /// Its Lambert layer weighs (1 - metallic)(1 - transmission): a caster only without it.
    static bool casts_caustics(const Material& m, float max_roughness) {
        return m.roughness <= max_roughness && (m.metallic >= 1.0f || m.transmission >= 1.0f) &&
               !has_sheen(m) && !(m.clearcoat > 0.0f && m.clearcoat_roughness > max_roughness);
    }

    /// The coat's frame: its own normal (clearcoatNormalTexture) in the shading frame, or
    /// none (bent = false), when the coat's cosines are the base's own z.
    struct CoatFrame {
        bool bent = false;
        Frame frame;  ///< local shading frame -> the coat's frame (bent only)
        /// w (local) in the coat's frame.
        [[nodiscard]] glm::vec3 to_coat(const glm::vec3& w) const {
            return bent ? frame.to_local(w) : w;
        }
        /// The cosine of w (local) against the coat's normal.
        [[nodiscard]] float cos(const glm::vec3& w) const {
            return bent ? glm::dot(w, frame.n) : w.z;
        }
    };
    /// m.clearcoat_normal in p's local frame, turned to the side of the geometric normal
    /// facing wo (as the frame turns the shading normal).
    static CoatFrame coat_frame(const Material& m, const ShadingPoint& p) {
        CoatFrame c;
        if (!(m.clearcoat > 0.0f) || m.clearcoat_normal == glm::vec3(0.0f)) [[likely]]
            return c;
        glm::vec3 n = p.frame.to_local(m.clearcoat_normal);
        if (glm::dot(n, p.frame.geometric) < 0.0f) n = -n;
        const float len = glm::length(n);
        if (!(len > 0.0f) || !std::isfinite(len)) return c;
        c.bent = true;
        c.frame = Frame::from_normal(n / len);
        return c;
    }

    /// Colours of the lobes' Fresnel etc. as the extensions' factors set them.
    static float max3(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
    static bool has_sheen(const Material& m) { return max3(m.sheen_color) > 0.0f; }
    /// A clear coat or a sheen: the layers eval / pdf / sample add (inert otherwise).
    static bool has_layers(const Material& m) { return m.clearcoat > 0.0f || has_sheen(m); }
    /// The coat's F0: IOR 1.5 (KHR_materials_clearcoat).
    static constexpr float kCoatF0 = 0.04f;
    static float coat_fresnel(float cos) { return microfacet::schlick(glm::vec3(kCoatF0), cos).x; }
    /// The dielectric's Fresnel at cos, KHR_materials_specular's: specular (F0' + (1 - F0')
    /// (1 - cos)^5), F0' = min(f0 specular_color, 1); the base under it weighs 1 - its max.
    static glm::vec3 dielectric_fresnel(const Material& m, float cos) {
        const glm::vec3 f0 =
            glm::min(glm::vec3(f0_dielectric(m.ior)) * m.specular_color, glm::vec3(1.0f));
        return m.specular * microfacet::schlick(f0, cos);
    }
    /// What the coat and the sheen let through to the material under them, for the
    /// cosines of wo and wi (both >= 0) against the shading normal and (cco, cci) against
    /// the coat's: Tc Ts of the header's comment.
    static float under_layers(const Material& m, float co, float ci, float cco, float cci) {
        float t = 1.0f;
        if (m.clearcoat > 0.0f)
            t = (1.0f - m.clearcoat * coat_fresnel(std::max(cco, 0.0f))) *
                (1.0f - m.clearcoat * coat_fresnel(std::max(cci, 0.0f)));
        const float s = max3(m.sheen_color);
        if (s > 0.0f) {
            const float eo = microfacet::sheen_albedo(co, m.sheen_roughness);
            const float ei = microfacet::sheen_albedo(ci, m.sheen_roughness);
            t *= std::max(0.0f, std::min(1.0f - s * eo, 1.0f - s * ei));
        }
        return t;
    }
    /// The layers over f_base (wr above the surface: wi, mirrored when transmitted).
    static glm::vec3 layered(const Material& m, const CoatFrame& cf, const glm::vec3& f_base,
                             const glm::vec3& wo, const glm::vec3& wr, bool transmitted) {
        const float cco = cf.cos(wo), cci = cf.cos(wr);
        glm::vec3 f = under_layers(m, wo.z, wr.z, cco, cci) * f_base;
        if (transmitted) return f;  // the coat and the sheen only reflect
        const glm::vec3 h = glm::normalize(wo + wr);
        float tc = 1.0f;
        if (m.clearcoat > 0.0f) {
            if (cco > 0.0f && cci > 0.0f) {
                const microfacet::IsotropicGgx coat{microfacet::alpha_of(m.clearcoat_roughness)};
                const glm::vec3 wo_c = cf.to_coat(wo), wr_c = cf.to_coat(wr);
                float dv = coat.d(cf.to_coat(h)) * coat.g2(wo_c, wr_c) / (4.0f * wo_c.z * wr_c.z);
                if (cf.bent) dv *= wr_c.z / wr.z;  // the coat's cosine, not the base's
                f += glm::vec3(m.clearcoat * coat_fresnel(std::fabs(glm::dot(wo, h))) * dv);
            }
            tc = (1.0f - m.clearcoat * coat_fresnel(std::max(cco, 0.0f))) *
                 (1.0f - m.clearcoat * coat_fresnel(std::max(cci, 0.0f)));
        }
        if (has_sheen(m)) {
            const float alpha = m.sheen_roughness * m.sheen_roughness;
            f += tc * m.sheen_color * microfacet::sheen_f(wo.z, wr.z, h.z, alpha);
        }
        return f;
    }
    /// glTF: COLOR_0 multiplies the base colour (albedo scales every lobe, the dielectric
    /// specular too, which the vertex colour does not tint).
    static void multiply_color(Material& m, const glm::vec3& c) { m.base_color *= c; }
    /// The lobes' colours at normal incidence (Fresnel at cos = 1: f0 for the dielectric,
    /// c for the metal): (1 - metallic) [(1 - f0) c ((1 - transmission) + transmission) +
    /// f0] + metallic c, tinted by albedo. The diffuse and the transmitted light share the
    /// colour c; a pane of transmission 1 keeps its colour rather than 0.04, which a
    /// denoiser dividing by the albedo could not use.
    /// With layers: the base under them at normal incidence, plus the coat's F0 and the
    /// sheen colour times its albedo there.
    static glm::vec3 denoising_albedo(const Material& m, const ShadingPoint& p) {
        const glm::vec3 f0 = dielectric_fresnel(m, 1.0f);
        const float under = 1.0f - max3(f0);
        const glm::vec3& c = m.base_color;
        // Burley's diffuse at normal incidence is c (both factors 1), with no (1 - F).
        const float diffuse_under = m.diffuse_model == DiffuseModel::Burley ? 1.0f : under;
        const glm::vec3 diffuse = (1.0f - m.metallic) * (1.0f - m.transmission) * diffuse_under * c;
        const glm::vec3 transmitted = (1.0f - m.metallic) * m.transmission * under * c;
        const glm::vec3 specular = (1.0f - m.metallic) * f0 + m.metallic * c;
        glm::vec3 a = diffuse + transmitted + specular;
        if (has_layers(m)) [[unlikely]] {
            const float tc = (1.0f - m.clearcoat * kCoatF0) * (1.0f - m.clearcoat * kCoatF0);
            a = under_layers(m, 1.0f, 1.0f, 1.0f, 1.0f) * a + glm::vec3(m.clearcoat * kCoatF0) +
                tc * m.sheen_color * microfacet::sheen_albedo(1.0f, m.sheen_roughness);
        }
        return p.albedo * a;
    }

    static BsdfLobe lobes(const Material& m) {
        const BsdfLobe refl = BsdfLobe::Diffuse | BsdfLobe::Glossy | BsdfLobe::Reflection;
        if (!(m.transmission > 0.0f && m.metallic < 1.0f)) return refl;
        return smooth_transmission(m) ? refl | BsdfLobe::Null : refl | BsdfLobe::Transmission;
    }

    /// True when the transmission is a Null lobe: the surface transmits (transmission > 0,
    /// not wholly metal), isotropic, with roughness^2 at or below GGX's alpha floor.
    static bool smooth_transmission(const Material& m) {
        return m.transmission > 0.0f && m.metallic < 1.0f && !(m.anisotropy > 0.0f) &&
               m.roughness * m.roughness <= microfacet::kMinAlpha;
    }

    /// Any point may be smooth and transmit: the textures scale roughness and metallic.
    static bool may_pass_through(const Material& m) { return m.transmission > 0.0f; }

    /// The Null lobe's colour for wo: the dielectric base layer's transmitted share with
    /// the half vector at the normal, (1 - metallic) (1 - Fr(cos_o)) transmission c.
    static glm::vec3 pass_through(const Material& m, const ShadingPoint& p, const glm::vec3& wo) {
        if (!smooth_transmission(m)) return glm::vec3(0.0f);
        const float co = std::fabs(wo.z);
        const float under = 1.0f - max3(dielectric_fresnel(m, co));
        const glm::vec3 t =
            p.albedo * ((1.0f - m.metallic) * under * m.transmission) * m.base_color;
        if (!has_layers(m)) return t;
        const CoatFrame cf = coat_frame(m, p);
        const float cco = cf.bent ? std::fabs(cf.cos(wo)) : co;
        return under_layers(m, co, co, cco, cco) * t;
    }

    static float f0_dielectric(float ior) {
        const float r = (ior - 1.0f) / (ior + 1.0f);  // glTF KHR_materials_ior
        return r * r;
    }

    /// Burley's diffuse over Lambert's c / pi for cosines co, ci of wo and wi and cd = wi.h
    /// (the header's comment): (1 + (F_D90 - 1)(1 - ci)^5)(1 + (F_D90 - 1)(1 - co)^5).
    static float burley_factor(float roughness, float co, float ci, float cd) {
        const float fd90 = 0.5f + 2.0f * roughness * cd * cd;
        const auto schlick_weight = [](float c) {
            const float x = std::clamp(1.0f - c, 0.0f, 1.0f);
            const float x2 = x * x;
            return x2 * x2 * x;
        };
        return (1.0f + (fd90 - 1.0f) * schlick_weight(ci)) *
               (1.0f + (fd90 - 1.0f) * schlick_weight(co));
    }

    /// Probabilities of the specular, diffuse, transmission, coat and sheen lobes at wo.
    static std::array<float, 5> lobe_probabilities(const Material& m, const ShadingPoint& p,
                                                   const glm::vec3& wo) {
        const glm::vec3& c = m.base_color;
        const glm::vec3 fr = dielectric_fresnel(m, wo.z);
        const float fd = (fr.x + fr.y + fr.z) / 3.0f;
        const glm::vec3 fmc = microfacet::schlick(c, wo.z);
        const float fm = (fmc.x + fmc.y + fmc.z) / 3.0f;
        const float mean_c = (c.x + c.y + c.z) / 3.0f;
        const float dielectric = (1.0f - m.metallic) * (1.0f - max3(fr)) * mean_c;
        float w_spec = (1.0f - m.metallic) * fd + m.metallic * fm;
        float w_diff = dielectric * (1.0f - m.transmission);
        // A Null lobe is no lobe of sample(): the integrator crosses it (pass_through).
        float w_trans = smooth_transmission(m) ? 0.0f : dielectric * m.transmission;
        w_spec = std::max(w_spec, 0.1f * (w_spec + w_diff + w_trans) + 1e-4f);
        if (!has_layers(m)) [[likely]] {
            const float total = w_spec + w_diff + w_trans;
            return {w_spec / total, w_diff / total, w_trans / total, 0.0f, 0.0f};
        }
        return layered_probabilities(m, p, wo, w_spec, w_diff, w_trans);
    }
    /// lobe_probabilities with layers, out of line: the common material without them keeps
    /// its inlined fast path.
    [[gnu::noinline]] static std::array<float, 5> layered_probabilities(const Material& m,
                                                                        const ShadingPoint& p,
                                                                        const glm::vec3& wo,
                                                                        float w_spec, float w_diff,
                                                                        float w_trans) {
        // Layers: the coat's and the sheen's albedo estimates at wo, the base's under them.
        const float cco = coat_frame(m, p).cos(wo);  // wo's cosine against the coat's normal
        const float under = under_layers(m, wo.z, wo.z, cco, cco);
        const float base = w_spec + w_diff + w_trans;
        // No coat sample where wo is below the coat's normal (its lobe is zero there).
        float w_coat = cco > 0.0f ? m.clearcoat * coat_fresnel(cco) : 0.0f;
        const float tc = 1.0f - w_coat;
        const float w_sheen =
            tc * max3(m.sheen_color) * microfacet::sheen_albedo(wo.z, m.sheen_roughness);
        w_spec *= under;
        w_diff *= under;
        w_trans *= under;
        // The coat's Fresnel at wo.h can exceed its estimate at cos_o, as the base's can.
        if (m.clearcoat > 0.0f && cco > 0.0f)
            w_coat = std::max(w_coat, 0.1f * m.clearcoat * (under * base + w_sheen) + 1e-4f);
        const float total = w_spec + w_diff + w_trans + w_coat + w_sheen;
        return {w_spec / total, w_diff / total, w_trans / total, w_coat / total, w_sheen / total};
    }

    /// Where wi may go: reflection above both normals, (thin) transmission below both.
    static bool reaches(const ShadingPoint& p, const glm::vec3& wo, const glm::vec3& wi) {
        if (wo.z <= 0.0f || wi.z == 0.0f) return false;
        return wi.z > 0.0f ? p.frame.above_geometry(wi) : !p.frame.above_geometry(wi);
    }

    [[gnu::noinline]] static BsdfSample sample(const Material& m, const ShadingPoint& p,
                                               const glm::vec3& wo, float uc, glm::vec2 u) {
        if (m.anisotropy > 0.0f) [[unlikely]]
            return microfacet::sample_anisotropic<MetallicRoughness>(m, p, wo, uc, u);
        if (wo.z <= 0.0f) return {};
        return sample_with(microfacet::IsotropicGgx{microfacet::alpha_of(m.roughness)}, m, p, wo,
                           uc, u);
    }

    [[gnu::noinline]] static glm::vec3 eval(const Material& m, const ShadingPoint& p,
                                            const glm::vec3& wo, const glm::vec3& wi) {
        if (m.anisotropy > 0.0f) [[unlikely]]
            return microfacet::eval_anisotropic<MetallicRoughness>(m, p, wo, wi);
        if (!reaches(p, wo, wi)) return glm::vec3(0.0f);
        return eval_with(microfacet::IsotropicGgx{microfacet::alpha_of(m.roughness)}, m, p, wo, wi);
    }

    /// GGX lobes narrower than kDeltaLightAlpha (delta_light_material), unless the
    /// transmission is the Null lobe: a raised roughness would turn it into a glossy
    /// transmission that counts the light pass_through already lets across.
    static bool widens_for_delta_light(const Material& m) {
        return !smooth_transmission(m) &&
               (m.roughness < microfacet::kDeltaLightRoughness ||
                (m.clearcoat > 0.0f && m.clearcoat_roughness < microfacet::kDeltaLightRoughness));
    }
    [[gnu::noinline]] static float pdf(const Material& m, const ShadingPoint& p,
                                       const glm::vec3& wo, const glm::vec3& wi) {
        if (m.anisotropy > 0.0f) [[unlikely]]
            return microfacet::pdf_anisotropic<MetallicRoughness>(m, p, wo, wi);
        if (!reaches(p, wo, wi)) return 0.0f;
        return pdf_with(microfacet::IsotropicGgx{microfacet::alpha_of(m.roughness)}, m, p, wo, wi);
    }

    /// The sample for wo.z > 0, given the GGX lobe.
    template <class Ggx>
    static BsdfSample sample_with(const Ggx& ggx, const Material& m, const ShadingPoint& p,
                                  const glm::vec3& wo, float uc, glm::vec2 u) {
        const auto prob = lobe_probabilities(m, p, wo);
        // The lobe uc falls in; rounding past the last lobe of nonzero probability gives it.
        int last = 0;
        for (int i = 1; i < 5; ++i)
            if (prob[std::size_t(i)] > 0.0f) last = i;
        int chosen = 0;
        float acc = 0.0f;
        for (; chosen < last; ++chosen) {
            acc += prob[std::size_t(chosen)];
            if (uc < acc && prob[std::size_t(chosen)] > 0.0f) break;
        }
        glm::vec3 wi;
        BsdfLobe lobe = BsdfLobe::Glossy | BsdfLobe::Reflection;
        switch (chosen) {
            case 0:
                wi = reflect(-wo, ggx.sample_visible_normal(wo, u));
                break;
            case 1:
                wi = sample_cosine_hemisphere(u);
                lobe = BsdfLobe::DiffuseReflection;
                break;
            case 2:
                wi = reflect(-wo, ggx.sample_visible_normal(wo, u));
                wi.z = -wi.z;  // thin-walled: the reflection mirrored through the surface
                lobe = BsdfLobe::Glossy | BsdfLobe::Transmission;
                break;
            case 3: {
                // In the coat's frame (its probability is 0 unless wo is above its normal).
                const microfacet::IsotropicGgx coat{microfacet::alpha_of(m.clearcoat_roughness)};
                const CoatFrame cf = coat_frame(m, p);
                const glm::vec3 wo_c = cf.to_coat(wo);
                wi = reflect(-wo_c, coat.sample_visible_normal(wo_c, u));
                if (cf.bent) {
                    // A reflection under the coat's own normal is no sample of the coat
                    // (its density there is 0), as one under the surface is none below.
                    if (!(wi.z > 0.0f)) return {};
                    wi = cf.frame.to_world(wi);
                }
                break;
            }
            default:
                // The sheen: a broad lobe, sampled by the cosine.
                wi = sample_cosine_hemisphere(u);
                break;
        }
        // A reflection that went under the surface is no sample of its lobe (nor of the
        // other side's): without this check it would be counted with the wrong density.
        const bool wants_transmission = has(lobe, BsdfLobe::Transmission);
        if ((wi.z < 0.0f) != wants_transmission || !reaches(p, wo, wi)) return {};
        const float density = pdf_with(ggx, m, p, wo, wi);
        if (!(density > 0.0f)) return {};
        return {wi, eval_with(ggx, m, p, wo, wi) * std::fabs(wi.z) / density, density, lobe};
    }

    /// eval() on a valid side, given the GGX lobe.
    template <class Ggx>
    static glm::vec3 eval_with(const Ggx& ggx, const Material& m, const ShadingPoint& p,
                               const glm::vec3& wo, const glm::vec3& wi) {
        const bool transmitted = wi.z < 0.0f;
        const glm::vec3 wr(wi.x, wi.y, std::fabs(wi.z));  // thin transmission: mirrored wi
        const glm::vec3 h = glm::normalize(wo + wr);
        const float vh = std::fabs(glm::dot(wo, h));
        // specular_brdf = D V, V = G2 / (4 |N.L| |N.V|) (glTF 2.0 Appendix B).
        const float dv = ggx.d(h) * ggx.g2(wo, wr) / (4.0f * wo.z * wr.z);
        const glm::vec3 fr = dielectric_fresnel(m, vh);
        const float under = 1.0f - max3(fr);
        const glm::vec3& c = m.base_color;
        glm::vec3 f;
        if (transmitted) {
            if (smooth_transmission(m)) return glm::vec3(0.0f);  // the Null lobe's, not f's
            // Only the dielectric's base layer transmits: (1 - Fr) transmission c D V.
            f = (1.0f - m.metallic) * under * m.transmission * c * dv;
        } else {
            const float base = m.diffuse_model == DiffuseModel::Burley
                                   ? burley_factor(m.roughness, wo.z, wr.z, glm::dot(wr, h))
                                   : under;
            const glm::vec3 dielectric = base * (1.0f - m.transmission) * c * kInvPi + fr * dv;
            const glm::vec3 metal = microfacet::schlick(c, vh) * dv;
            f = (1.0f - m.metallic) * dielectric + m.metallic * metal;
        }
        if (has_layers(m)) [[unlikely]]
            f = layered(m, coat_frame(m, p), f, wo, wr, transmitted);
        return p.albedo * f;
    }

    /// pdf() on a valid side, given the GGX lobe.
    template <class Ggx>
    static float pdf_with(const Ggx& ggx, const Material& m, const ShadingPoint& p,
                          const glm::vec3& wo, const glm::vec3& wi) {
        const auto prob = lobe_probabilities(m, p, wo);
        const glm::vec3 wr(wi.x, wi.y, std::fabs(wi.z));
        const glm::vec3 h = glm::normalize(wo + wr);
        const float glossy = ggx.reflection_pdf(wo, h);
        if (wi.z < 0.0f) return prob[2] * glossy;
        float density = prob[0] * glossy + prob[1] * cosine_hemisphere_pdf(wi.z);
        if (has_layers(m)) [[unlikely]]
            density += layers_pdf(m, p, prob, wo, wr, h);
        return density;
    }

    /// The coat's and the sheen's share of pdf_with for a reflection wr (half vector h),
    /// out of line as layered_probabilities is.
    [[gnu::noinline]] static float layers_pdf(const Material& m, const ShadingPoint& p,
                                              const std::array<float, 5>& prob, const glm::vec3& wo,
                                              const glm::vec3& wr, const glm::vec3& h) {
        float density = prob[4] * cosine_hemisphere_pdf(wr.z);
        const CoatFrame cf = coat_frame(m, p);
        if (prob[3] > 0.0f && cf.cos(wr) > 0.0f) {
            const microfacet::IsotropicGgx coat{microfacet::alpha_of(m.clearcoat_roughness)};
            density += prob[3] * coat.reflection_pdf(cf.to_coat(wo), cf.to_coat(h));
        }
        return density;
    }
};

}  // namespace librt::bsdfs
