// The integrators' one path loop (trace) and the pieces it forces inline. Over 400 lines
// because those pieces share the loop's private types (Vertex, Bounce) and must inline
// into it for speed; guiding's own code is in guiding/.

#include "geometry/ray_copy.h"
#include "integrator/caustic_paths.h"
#include "integrator/guiding/path_recorder.h"
#include "integrator/guiding/sd_tree.h"
#include "integrator/mis.h"
#include "integrator/transmittance.h"
#include "material/bsdf_dispatch.h"
#include "scene/shadow_ray.h"

#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/integrator/integrators.h>
#include <librt/light/light.h>
#include <librt/material/bsdf.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <new>
#include <string>
#include <variant>

namespace librt {
namespace {

constexpr int kMaxDepthLimit = 1000;

void check_depth(const char* name, int value, int lo, int hi) {
    if (value < lo || value > hi)
        throw Error(std::string(name) + " = " + std::to_string(value) + ": must be in [" +
                    std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

void check(const PathTracerSettings& s) {
    check_depth("max_depth", s.max_depth, 0, kMaxDepthLimit);
    check_depth("russian_roulette_depth", s.russian_roulette_depth, 0, kMaxDepthLimit);
    guiding::validate(s.guiding);
    const float r = s.caustic_paths.max_roughness;
    if (!(r >= 0.0f && r <= 1.0f))
        throw Error("caustic_paths.max_roughness = " + std::to_string(r) + ": must be in [0, 1]");
    if (s.caustic_paths.enabled && s.guiding.enabled)
        throw Error(
            "caustic_paths.enabled and guiding.enabled: choose one (a guided path "
            "cannot leave the caustics out)");
}

/// Which strategies a path uses at its non-specular vertices.
enum class Strategy {
    Direct,  ///< light sampling at the first non-specular hit, then stop
    Path,    ///< light sampling and BSDF sampling, MIS-weighted (or light sampling only)
    Brute,   ///< BSDF sampling only; emitters found by chance
};

/// How the emission of a light's surface hit by the ray just traced counts.
enum class EmitterWeight : std::uint8_t {
    Full,  ///< camera ray, after a specular bounce, or no light strategy in the estimator
    Mis,   ///< after a non-specular bounce that also sampled a light: power heuristic
    Zero,  ///< after a non-specular bounce whose light sample took the whole weight
};

/// What the emitter weight of the next hit needs to know about the bounce that led to it.
struct Bounce {
    EmitterWeight weight = EmitterWeight::Full;
    float pdf = 0.0f;       ///< solid-angle density of the BSDF sample (for Mis)
    glm::vec3 point{0.0f};  ///< where it was taken: the light's reference point
};

/// The weight of the emission of light `light` (kInvalidId: an emitter no light samples)
/// found along unit direction `dir` after `bounce`; `chosen_at` set when the light there
/// was chosen per point (LightChoice::Bounded): that choice's pmf depends on it.
float light_weight(const Scene& scene, std::uint32_t light, const glm::vec3& dir,
                   const Bounce& bounce, const LightChoicePoint* chosen_at) {
    if (bounce.weight == EmitterWeight::Full) return 1.0f;
    if (light == kInvalidId) return 1.0f;  // no light strategy could have found it
    if (bounce.weight == EmitterWeight::Zero) return 0.0f;
    // Density with which the light strategy at the previous vertex picks this direction.
    // The light choice's pmf as it was at that vertex: per point when chosen by bounds.
    const float pmf = chosen_at != nullptr ? scene.light_sampler().pmf(light, *chosen_at)
                                           : scene.light_sampler().pmf(light);
    const float light_pdf = pmf * pdf_li(scene.lights()[light], bounce.point, dir);
    return power_heuristic(bounce.pdf, light_pdf);
}

/// A scattering vertex: the normals turned to the incoming ray's side, in world space, and
/// the local frame built from them only when a BSDF needs local directions. Why lazy: a
/// Lambertian light sample needs only two cosines, and the last vertex of a path samples
/// no direction, so there the frame (and the conversions into and out of it) would be
/// pure cost (callgrind on the synthesis: ~9% of the path loop's instructions).
struct Vertex {
    const Material& m;
    glm::vec3 incoming;  ///< unit direction of the ray that arrived (toward the surface)
    glm::vec3 n;         ///< unit shading normal on the incoming side
    glm::vec3 g;         ///< unit geometric normal on the incoming side
    glm::vec3 albedo;    ///< the BSDF's albedo here (Scene::albedo)
    bool front;          ///< the incoming side is the one the primitive faces
    bool framed = false;
    // Constructed only by point(): a member ShadingPoint would have its defaulted frame
    // written at every vertex, and Lambertian vertices never read it.
    union {
        ShadingPoint sp;  ///< valid once `framed`
    };

    Vertex(const Material& material, const Hit& hit, const glm::vec3& dir,
           const glm::vec3& albedo_at_hit)
        : m(material),
          incoming(dir),
          albedo(albedo_at_hit),
          front(glm::dot(dir, hit.geometric_normal) < 0.0f) {
        n = front ? hit.shading_normal : -hit.shading_normal;
        g = front ? hit.geometric_normal : -hit.geometric_normal;
    }
    /// The ShadingPoint with its frame (ShadingFrame::at's, built on first use).
    const ShadingPoint& point() {
        if (!framed) {
            new (&sp) ShadingPoint{ShadingFrame::facing(n, g, front), albedo};
            framed = true;
        }
        return sp;
    }
    /// wo in the local frame.
    glm::vec3 wo() { return point().frame.to_local(-incoming); }
};

/// The BSDF's f and pdf toward world direction wi, with |cos(theta_i)| in `cos_i`: from
/// world-space cosines for a kind that depends on nothing else (it provides pdf_cos, e.g.
/// Lambert), else through the local frame. The same values as eval_pdf_bsdf() up to the
/// rounding of the geometric-side test.
[[gnu::always_inline]] inline bsdfs::EvalPdf light_eval(Vertex& v, const glm::vec3& wi,
                                                        float& cos_i) {
    // Lambert first, outside dispatch(): g++ keeps dispatch() with this lambda out of line
    // (a call and an EvalPdf through memory per light sample: callgrind on the synthesis,
    // 46M instructions); the same expressions as its Diffuse case below.
    if (bsdfs::is_lambertian(v.m)) [[likely]] {
        const float cos_s = glm::dot(v.n, wi), cos_g = glm::dot(v.g, wi);
        cos_i = std::fabs(cos_s);
        // Diffuse::eval_cos, from the albedo alone (no ShadingPoint built).
        return bsdfs::EvalPdf{
            bsdfs::Diffuse::reaches_cos(cos_s, cos_g) ? v.albedo * kInvPi : glm::vec3(0.0f),
            bsdfs::Diffuse::pdf_cos(cos_s, cos_g)};
    }
    return bsdfs::dispatch(v.m.kind, [&](auto bsdf) {
        using T = decltype(bsdf);
        if constexpr (requires { T::pdf_cos(0.0f, 0.0f); }) {
            // wi.z in the local frame is exactly dot(n, wi): to_local's third component.
            const float cos_s = glm::dot(v.n, wi), cos_g = glm::dot(v.g, wi);
            cos_i = std::fabs(cos_s);
            return bsdfs::EvalPdf{T::eval_cos(v.point(), cos_s, cos_g), T::pdf_cos(cos_s, cos_g)};
        } else {
            const ShadingPoint& p = v.point();
            const glm::vec3 wo = v.wo(), wl = p.frame.to_local(wi);
            cos_i = std::fabs(wl.z);
            return bsdfs::EvalPdf{T::eval(v.m, p, wo, wl), T::pdf(v.m, p, wo, wl)};
        }
    });
}

/// light_eval() toward a delta light (point, spot, delta sun): a material whose kind widens
/// narrow lobes for it (bsdfs::delta_light_material) is evaluated widened, the others as
/// light_eval(). Its pdf is 0: unused, a delta light's sample gets no MIS weight.
// Out of line: delta lights are the rare case next to the report scenes' sphere lights.
[[gnu::noinline]] bsdfs::EvalPdf delta_light_eval(Vertex& v, const glm::vec3& wi, float& cos_i) {
    Material widened;
    if (!bsdfs::delta_light_material(v.m, widened)) return light_eval(v, wi, cos_i);
    const ShadingPoint& p = v.point();
    const glm::vec3 wo = v.wo(), wl = p.frame.to_local(wi);
    cos_i = std::fabs(wl.z);
    return bsdfs::EvalPdf{bsdfs::eval_bsdf(widened, p, wo, wl), 0.0f};
}

/// The weight of the emission of the object hit along unit direction `dir` after `bounce`:
/// 0 from the back of a one-sided light.
// Out of line, as escaped() below: rare next to scattering, so the path loop's hot blocks
// stay contiguous (perf on the synthesis, docs/benchmarks.md).
[[gnu::noinline]] float emitter_weight(const Scene& scene, const Hit& hit, const glm::vec3& dir,
                                       const Bounce& bounce, const LightChoicePoint* chosen_at) {
    const std::uint32_t light = scene.light_of_hit(hit);
    if (light != kInvalidId && scene.lights()[light].one_sided &&
        !(glm::dot(dir, hit.geometric_normal) < 0.0f))
        return 0.0f;
    return light_weight(scene, light, dir, bounce, chosen_at);
}

/// What a ray leaving the scene along unit direction `dir` after `bounce` receives from
/// the lights at infinity, each with its MIS weight (all of them fully when `brute`).
[[gnu::noinline]] glm::vec3 escaped(const Scene& scene, const glm::vec3& dir, const Bounce& bounce,
                                    bool brute, bool camera_ray,
                                    const LightChoicePoint* chosen_at) {
    glm::vec3 sum(0.0f);
    for (const std::uint32_t i : scene.infinite_lights()) {
        const Light& light = scene.lights()[i];
        if (camera_ray && !light.camera_visible) continue;
        const glm::vec3 le = escaped_radiance(light, dir);
        if (!(max_component(le) > 0.0f)) continue;
        sum += le * (brute ? 1.0f : light_weight(scene, i, dir, bounce, chosen_at));
    }
    return sum;
}

/// sample_li of a light that is not a sphere light, out of line: std::visit over every
/// light type inline put a jump table and its calls between the path loop's hot blocks.
[[gnu::noinline]] LightLiSample sample_other_li(const Light& light, const glm::vec3& p,
                                                glm::vec2 u) {
    return sample_li(light, p, u);
}

/// Next-event estimation at a non-specular hit: the light sampler chooses a light, a
/// direction toward it is drawn, and its contribution f L |cos| / pdf is returned if a
/// shadow ray finds it unoccluded, times the power heuristic against BSDF sampling when
/// `mis` (delta lights: weight 1, no BSDF sample can find them). `beta` is the path's
/// throughput: no shadow ray is spent on a contribution it zeroes. `at` set: the light is
/// chosen by its bound there (LightChoice::Bounded), else by power.
// Forced inline: called once per non-specular vertex, and g++ otherwise keeps the call
// (callgrind on the synthesis: -1.6% instructions in the path loop).
// With Guided, `leaf` is the vertex's SD-tree leaf and `alpha` the BSDF's share of the
// mixture the BSDF-side direction is drawn from: that mixture's density weighs the light
// sample (nullptr: the vertex is not guided). With SplitCaustics, `infinite_only` keeps
// only lights at infinity (a template parameter: the other loops see none of it).
template <bool Guided = false, bool SplitCaustics = false>
[[gnu::always_inline]] inline glm::vec3 sample_direct(const Scene& scene, const Hit& hit, Vertex& v,
                                                      const glm::vec3& beta, Sampler& sampler,
                                                      bool mis, const LightChoicePoint* at,
                                                      const guiding::DirLeaf* leaf = nullptr,
                                                      float alpha = 1.0f,
                                                      bool infinite_only = false) {
    const LightSampler& lights = scene.light_sampler();
    // Drawn even when unused, so later decisions of the path keep their numbers; no
    // number chooses among a single light. The caller's start_bounce put the sampler on
    // the light choice's dimension; the light's 2D keeps its own (SampleDimensions).
    const std::uint32_t first = sampler.dimension();
    const float u_light = lights.size() > 1 ? sampler.next_1d() : 0.0f;
    sampler.set_dimension(first + SampleDimensions::kBounceLight);
    const glm::vec2 u = sampler.next_2d();
    const SampledLight chosen =
        at != nullptr ? lights.sample(u_light, *at) : lights.sample(u_light);
    if (!chosen.valid()) return glm::vec3(0.0f);
    const Light& light = scene.lights()[chosen.light];
    if constexpr (SplitCaustics) {
        if (infinite_only && !is_infinite(light)) return glm::vec3(0.0f);
    }
    // Sphere lights (the report scenes' kind) called directly: std::visit over all the
    // light types costs a dispatch per sample; the same sample_li either way.
    const SphereLight* sphere = as_sphere_light(light);
    const LightLiSample s =
        sphere != nullptr ? sample_li(*sphere, hit.point, u) : sample_other_li(light, hit.point, u);
    if (!s.valid()) return glm::vec3(0.0f);
    // The unshadowed integrand f L |cos(theta_i)|; no shadow ray when it is 0.
    float cos_i = 0.0f;
    // A delta light meets a near-specular lobe with a regularised one (microfacet.h's
    // kDeltaLightAlpha): without it roughness 0 (alpha 1e-3) gave fireflies of 1e4 x E.
    const bsdfs::EvalPdf bsdf = s.is_delta && !bsdfs::is_lambertian(v.m)
                                    ? delta_light_eval(v, s.wi, cos_i)
                                    : light_eval(v, s.wi, cos_i);
    glm::vec3 fl = bsdf.f * s.radiance * cos_i;
    if (!(max_component(beta * fl) > 0.0f)) return glm::vec3(0.0f);
    // The light's own surface is skipped: the segment ends on it.
    if (scene.has_pass_through_surfaces()) {
        // Null lobes may be in the way: look through them (the light path a BSDF ray
        // crossing them finds, so MIS below weighs the two alike). transmittance() alone:
        // its first closest hit answers what unoccluded() would, so asking that first
        // only repeated the query for every blocked ray.
        fl *= transmittance(scene,
                            spawn_ray_to(hit.point, hit.geometric_normal, hit.offset, s.wi,
                                         s.distance, s.end_slope),
                            light.object);
        if (!(max_component(beta * fl) > 0.0f)) return glm::vec3(0.0f);
    } else if (!unoccluded(scene,
                           spawn_ray_to(hit.point, hit.geometric_normal, hit.offset, s.wi,
                                        s.distance, s.end_slope),
                           light.object)) {
        return glm::vec3(0.0f);
    }
    // Monte Carlo estimate f L |cos| / p_light, times the MIS weight when asked.
    const float a = chosen.pmf * s.pdf;
    if (!mis || s.is_delta) return fl / a;
    float b = bsdf.pdf;
    if constexpr (Guided) {
        if (leaf != nullptr && alpha < 1.0f)
            b = alpha * b + (1.0f - alpha) * leaf->sampling.pdf(s.wi);
    }
    // Power heuristic folded into the estimate: (a^2 / (a^2 + b^2)) / a = a / (a^2 + b^2),
    // one division; the general form when the squares overflow (tiny lights).
    const float denom = a * a + b * b;
    if (denom < std::numeric_limits<float>::infinity()) return fl * (a / denom);
    return fl * (power_heuristic(a, b) / a);
}

/// What a guided path needs: the learned field, the recorder of a training path (nullptr
/// when not training) and the BSDF's share of the sampling mixture.
struct GuideContext {
    const guiding::SdTree* tree = nullptr;
    guiding::PathRecorder* recorder = nullptr;
    float bsdf_fraction = 0.5f;
};

/// A lobe too narrow for the guide's cells (GGX alpha = roughness^2 below 0.01, i.e.
/// roughness < 0.1, on a kind with no diffuse part): the BSDF samples it far better than
/// any mixture would, and its vertices are left unguided.
bool near_specular(const Material& m) {
    constexpr float kRoughness = 0.1f;
    return bsdfs::near_specular(m, kRoughness);
}

/// Lambert's sampling: a cosine-weighted direction about the unit normal n, in world space,
/// and in `local` in the frame about n (its z the cosine). The local direction first: the
/// frame built after its sincos call is not saved and restored around it.
[[gnu::always_inline]] inline glm::vec3 lambert_direction(const glm::vec3& n, glm::vec2 u,
                                                          glm::vec3& local) {
    local = sample_cosine_hemisphere(u);
    const Frame frame = Frame::from_normal(n);
    return frame.to_world(local);
}

/// A direction drawn at a guided vertex: wi (world), f |cos| / pdf and the mixture's pdf.
struct GuidedSample {
    glm::vec3 wi{0.0f};
    glm::vec3 weight{0.0f};
    float pdf = 0.0f;
};

/// One-sample MIS over BSDF and guide sampling (Müller et al. 2017, section 4; Veach 1997,
/// the balance heuristic as one sample of a mixture): with probability alpha the BSDF's
/// sample(), else the leaf's quadtree; either way the weight is f |cos| divided by the
/// mixture density alpha pdf_bsdf + (1 - alpha) pdf_guide, which is unbiased for any
/// learned distribution while alpha > 0. The BSDF's lobe choice keeps the lobe dimension
/// (the sampler keeps 7 dimensions per bounce). A
/// weight of 0 (no valid direction) ends the path, as an invalid BSDF sample does.
GuidedSample sample_guided(Vertex& v, const guiding::DirLeaf& leaf, float alpha, Sampler& sampler,
                           std::uint32_t dim) {
    sampler.set_dimension(dim + SampleDimensions::kBounceLobe);
    const float uc = sampler.next_1d();
    sampler.set_dimension(dim + SampleDimensions::kBounceBsdf);
    glm::vec2 u = sampler.next_2d();
    GuidedSample g;
    float guide_pdf = -1.0f;  // known from the guide's own descent when it drew wi
    // The strategy is chosen by u.x, rescaled into [0, 1) for the chosen one: each then
    // gets a stratified subset of the 2D points (choosing by another dimension would hand
    // each a random subset, and Sobol' would lose its 2D stratification at guided bounces).
    if (u.x < alpha) {
        u.x = std::min(u.x / alpha, 0x1.fffffep-1f);
        if (bsdfs::is_lambertian(v.m)) {
            glm::vec3 local;
            g.wi = lambert_direction(v.n, u, local);
        } else {
            const ShadingPoint& sp = v.point();
            const BsdfSample bs = bsdfs::dispatch(v.m.kind, [&](auto bsdf) {
                return decltype(bsdf)::sample(v.m, sp, v.wo(), uc, u);
            });
            if (!bs.valid()) return g;
            g.wi = sp.frame.to_world(bs.wi);
        }
    } else {
        u.x = std::min((u.x - alpha) / (1.0f - alpha), 0x1.fffffep-1f);
        float square_pdf = 0.0f;
        g.wi = guiding::square_to_direction(leaf.sampling.sample_square(u, &square_pdf));
        guide_pdf = square_pdf * (0.25f * kInvPi);  // the equal-area map: 4 pi
    }
    float cos_i = 0.0f;
    const bsdfs::EvalPdf e = light_eval(v, g.wi, cos_i);
    if (alpha < 1.0f && guide_pdf < 0.0f) guide_pdf = leaf.sampling.pdf(g.wi);
    g.pdf = alpha < 1.0f ? alpha * e.pdf + (1.0f - alpha) * guide_pdf : e.pdf;
    if (!(g.pdf > 0.0f)) return g;
    g.weight = e.f * (cos_i / g.pdf);
    return g;
}

/// The BSDF sample of a vertex whose kind is not Lambert's, its direction in world space in
/// `wi_world` when valid. Out of line: the path loop's Lambert case is the hot one, and
/// every other kind's dispatch inline sat between its hot blocks (perf on the synthesis).
[[gnu::noinline]] BsdfSample sample_other(Vertex& v, float uc, glm::vec2 u, glm::vec3& wi_world) {
    const ShadingPoint& sp = v.point();
    const BsdfSample bs = bsdfs::dispatch(v.m.kind, [&](auto bsdf) {
        // wo converted inside each kind's case: Lambert ignores it, and there it is dropped.
        return decltype(bsdf)::sample(v.m, sp, v.wo(), uc, u);
    });
    if (bs.valid()) wi_world = sp.frame.to_world(bs.wi);
    return bs;
}

/// What a path needs besides the scene: depth limit, roulette and MIS choices.
struct TraceSettings {
    int max_depth = 5;
    bool russian_roulette = false;
    int roulette_depth = 3;
    bool mis = true;
};

/// What trace<..., SplitCaustics = true> is given: TraceSettings and casts_caustics()'s
/// max_roughness. Derived rather than a member, so the other loops are built from the
/// struct they had (callgrind on the synthesis: each of their instructions unchanged).
struct SplitTraceSettings : TraceSettings {
    float caustic_roughness = 0.0f;
};

/// Russian roulette after bounce depth - 1 (its dimensions from `dim`), and the end of a
/// path whose throughput is 0: false when the path ends here.
[[gnu::always_inline]] inline bool survives_roulette(const TraceSettings& settings, int depth,
                                                     std::uint32_t dim, glm::vec3& beta,
                                                     Sampler& sampler) {
    // Roulette from bounce roulette_depth on (bounce depth - 1 was just sampled; 0 is
    // the camera ray's first hit), so depth d leaves d bounces untouched.
    if (settings.russian_roulette && depth > settings.roulette_depth) {
        // Survive with probability q, reweighted by 1/q: unbiased, fewer long paths.
        const float q = std::min(0.95f, max_component(beta));
        sampler.set_dimension(dim + SampleDimensions::kBounceRoulette);
        if (!(q > 0.0f) || sampler.next_1d() >= q) return false;
        beta /= q;
    }
    return max_component(beta) > 0.0f;
}

/// Where a path's contributions go: its estimate, and with Guided a training path's
/// recorder, which shares each contribution out to the vertices before it.
template <bool Guided>
struct PathRadiance {
    glm::vec3 sum{0.0f};
    guiding::PathRecorder* recorder = nullptr;  ///< Guided and training only

    [[gnu::always_inline]] void add(const glm::vec3& c) {
        sum += c;
        if constexpr (Guided) {
            if (recorder != nullptr) recorder->add(c);
        }
    }
};

/// Step: the path left the scene along unit direction `dir` after `bounce` (depth 0: the
/// camera ray): the lights at infinity, weighed as the strategy weighs emitters. A training
/// path also gives its last vertex what the light sample taken there weighed away.
template <Strategy S, bool Guided>
[[gnu::always_inline]] inline void add_escaped(const Scene& scene, const glm::vec3& dir,
                                               const Bounce& bounce, int depth,
                                               const LightChoicePoint* chosen,
                                               const glm::vec3& beta, PathRadiance<Guided>& out) {
    out.add(beta * escaped(scene, dir, bounce, S == Strategy::Brute, depth == 0, chosen));
    if constexpr (Guided) {
        if (out.recorder != nullptr && depth > 0)
            out.recorder->add_to_last(beta * (escaped(scene, dir, bounce, true, false, chosen) -
                                              escaped(scene, dir, bounce, false, false, chosen)));
    }
}

/// Step: the emission of emitter `m` hit along unit direction `dir` after `bounce`, with
/// its MIS weight. SplitCaustics: a light that starts light paths, reached through
/// casters only (`chain` Open), closes a caustic path, which the light path counts.
template <Strategy S, bool Guided, bool SplitCaustics>
[[gnu::always_inline]] inline void add_emission(const Scene& scene, const Hit& hit,
                                                const Material& m, const glm::vec3& dir,
                                                const Bounce& bounce,
                                                const LightChoicePoint* chosen, CausticChain chain,
                                                const glm::vec3& beta, PathRadiance<Guided>& out) {
    // Brute force weighs every emitter fully (a one-sided light's back stays dark).
    float w = emitter_weight(scene, hit, dir, S == Strategy::Brute ? Bounce{} : bounce, chosen);
    if constexpr (SplitCaustics) {
        if (chain == CausticChain::Open && scene.light_of_hit(hit) != kInvalidId) w = 0.0f;
    }
    if (w > 0.0f) out.add(beta * m.emission * w);
    if constexpr (Guided) {
        // The guide learns the full emission: what the light sample weighed away too.
        if (out.recorder != nullptr) {
            const float full = emitter_weight(scene, hit, dir, Bounce{}, chosen);
            if (full > w) out.recorder->add_to_last(beta * m.emission * (full - w));
        }
    }
}

/// How a vertex is guided: the SD-tree leaf at it and the BSDF's share alpha of the
/// sampling mixture; no leaf: the plain BSDF sample.
struct GuidedVertex {
    const guiding::DirLeaf* leaf = nullptr;
    float alpha = 1.0f;
};

/// Step (Guided): whether the vertex at `p` with material `m` is guided. Not at a specular
/// lobe (a delta has no density to mix) nor a near-specular one; nor where the leaf has
/// learned nothing and the path is not recorded (the plain BSDF path gives the same
/// directions, without the mixture's bookkeeping).
template <bool Guided>
[[gnu::always_inline]] inline GuidedVertex guided_vertex(const GuideContext& guide,
                                                         const Material& m, BsdfLobe material_lobes,
                                                         const glm::vec3& p) {
    GuidedVertex g;
    if constexpr (Guided) {
        if (has_non_specular(material_lobes) && !has(material_lobes, BsdfLobe::Specular) &&
            !near_specular(m)) {
            g.leaf = &guide.tree->leaf_at(p);
            g.alpha = g.leaf->sampling.total() > 0.0f ? guide.bsdf_fraction : 1.0f;
            if (g.alpha >= 1.0f && guide.recorder == nullptr) g.leaf = nullptr;
        }
    }
    return g;
}

/// Step: the BSDF's own sample at v (whose material is m), from bounce dimensions `dim`,
/// into `bs` and its direction in world space into `wi_world`; false when there is none
/// (absorbed, or below the real surface) and the path ends. Lambert in world space, as
/// Diffuse::sample draws it: its sample needs only the shading frame's to_world, so
/// neither the geometric normal's local copy nor the ShadingPoint is built (callgrind on the
/// synthesis: fewer instructions per vertex). The other kinds out of line (sample_other).
/// Each kind's validity is tested in its own branch: Lambert's lobe is then known.
[[gnu::always_inline]] inline bool sample_bsdf_at(Vertex& v, const Material& m,
                                                  BsdfLobe material_lobes, Sampler& sampler,
                                                  std::uint32_t dim, BsdfSample& bs,
                                                  glm::vec3& wi_world) {
    sampler.set_dimension(dim + SampleDimensions::kBounceLobe);
    // Lambert's one lobe needs no choice: its kind test first spares the lobe count.
    static_assert(!chooses_lobe(bsdfs::Diffuse::kLobes));
    const float uc =
        !bsdfs::is_lambertian(m) && chooses_lobe(material_lobes) ? sampler.next_1d() : 0.0f;
    sampler.set_dimension(dim + SampleDimensions::kBounceBsdf);
    const glm::vec2 u = sampler.next_2d();
    if (bsdfs::is_lambertian(m)) [[likely]] {
        glm::vec3 wl;
        wi_world = lambert_direction(v.n, u, wl);
        // Below the real surface ends the path, as Diffuse::sample does.
        if (!(glm::dot(wi_world, v.g) > 0.0f)) return false;
        // Cosine sampling: (albedo / pi) cos / (cos / pi) = albedo.
        bs = {wl, v.albedo, cosine_hemisphere_pdf(wl.z), bsdfs::Diffuse::kLobes};
        return bs.valid();
    }
    bs = sample_other(v, uc, u, wi_world);
    return bs.valid();
}

/// One path from `camera_ray` following `S`; see the class comments in integrators.h.
/// `Bounded`: lights are chosen by LightChoice::Bounded. A template parameter, so that the
/// default (power) loop keeps its code and registers unchanged (callgrind on the synthesis).
/// Guided (PathTracer with a trained SD-tree) is a separate instantiation too, so the
/// unguided loop carries none of its code. SplitCaustics: the path counts no caustic path
/// (caustic_paths.h), which splat_caustic_path adds; its own instantiation as well, whose
/// settings are a SplitTraceSettings.
///
/// Per hit, in order: the emission there (add_emission), a Null lobe crossed (cross_null),
/// next-event estimation (sample_direct), the next direction (sample_guided at a guided
/// vertex, else sample_bsdf_at), Russian roulette (survives_roulette).
template <Strategy S, bool Bounded, bool Guided = false, bool SplitCaustics = false>
glm::vec3 trace(const Scene& scene, const Ray& camera_ray, Sampler& sampler,
                const TraceSettings& settings, const GuideContext& guide = {}) {
    static_assert(!(SplitCaustics && (Guided || S != Strategy::Path)));
    // Every contribution goes through here: a training path shares it out to its vertices.
    PathRadiance<Guided> out;
    if constexpr (Guided) out.recorder = guide.recorder;
    glm::vec3 beta(1.0f);                          // path throughput
    Ray ray = detail::copy_by_floats(camera_ray);  // no store-forwarding stall (ray_copy.h)
    // Work with unit directions (the BSDF frames need them); rescale t's range.
    const float len = glm::length(ray.direction);
    if (!(len > 0.0f) || !std::isfinite(len)) return out.sum;
    ray.direction /= len;
    ray.t_min *= len;
    ray.t_max *= len;
    Bounce bounce;  // the camera ray: emission counts fully
    // Bounded: where the light of the last vertex was chosen (its pmf depends on it).
    LightChoicePoint chosen_at;
    const LightChoicePoint* const chosen = Bounded ? &chosen_at : nullptr;
    int hidden = 0;  // objects hidden from the camera that the camera ray passed through
    std::uint32_t decisions = 0;  // Null-lobe crossing decisions, each from its own dimension
    // SplitCaustics: whether light found from here on closes a caustic path E D G+ L.
    CausticChain chain = CausticChain::Before;
    Hit hit;  // out of the loop: every intersection that returns true rewrites it whole
    ShadedMaterial shaded;  // a textured hit's material (Scene::shade); unused otherwise
    for (int depth = 0;;) {
        if (!scene.intersect_for_shading(ray, hit)) {
            add_escaped<S>(scene, ray.direction, bounce, depth, chosen, beta, out);
            break;
        }
        // camera_may_pass() first: a flag that never changes during a render (depth == 0
        // alternates per path), and camera_passes() is a lookup no scene without hidden
        // objects or one-sided materials needs.
        if (scene.camera_may_pass() && depth == 0 && scene.camera_passes(hit, ray.direction))
            [[unlikely]] {
            // Camera rays go on through hidden objects and culled backs (bounded: a ray
            // grazing such a surface many times must still end).
            if (++hidden > 64) break;
            detail::respawn(ray, hit.point, hit.geometric_normal, hit.offset, ray.direction);
            continue;
        }
        // Textures looked up and the normal map applied here, so the BSDFs get plain values.
        const Material& m = scene.shade(hit, ray.direction, shaded);
        if (m.emits())
            add_emission<S, Guided, SplitCaustics>(scene, hit, m, ray.direction, bounce, chosen,
                                                   chain, beta, out);
        // Lambert's lobes are a constant: no dispatch for the common kind.
        const BsdfLobe material_lobes =
            bsdfs::is_lambertian(m) ? bsdfs::Diffuse::kLobes : bsdfs::lobes_of(m);
        if (has(material_lobes, BsdfLobe::Null)) [[unlikely]] {
            // A crossing is no bounce: depth, the last vertex's MIS state (bounce) and light
            // choice point stay, so an emitter found behind it is weighed against the light
            // sample the last vertex took through it (transmittance()), and it comes before
            // the depth test, as that light sample's shadow ray crossed it at any depth.
            const Crossing c = cross_null(scene, m, hit, ray.direction, sampler, decisions++);
            beta *= c.weight;
            if (c.crossed) {
                if (decisions > kMaxCrossingDecisions) break;
                detail::respawn(ray, hit.point, hit.geometric_normal, hit.offset, ray.direction);
                continue;
            }
        }
        if (depth >= settings.max_depth || material_lobes == BsdfLobe::None) break;
        // This bounce's dimensions (SampleDimensions); the independent stream is unchanged.
        const std::uint32_t dim = SampleDimensions::bounce(static_cast<std::uint32_t>(depth));
        sampler.start_bounce(static_cast<std::uint32_t>(depth));
        ++depth;

        // Scene::albedo's texture lookup only for a map_Kd material: the others' albedo is
        // m's own (inline: no call per hit).
        const glm::vec3 albedo = m.albedo_texture < 0 ? m.albedo : scene.albedo(hit);
        // Every lobe is scaled by the albedo (bsdf.h): when throughput * albedo is 0 (the
        // blue floor's path meeting the red wall) the vertex can add and pass on nothing,
        // so stop without spending a light sample and shadow ray on it.
        if (!(max_component(beta * albedo) > 0.0f)) break;
        Vertex v(m, hit, ray.direction, albedo);  // its frame built when first needed
        // Light sampling alone takes the whole weight for direct lighting, without MIS, and
        // at the last scattering event, where no BSDF sample will be weighed against it --
        // except on a glossy lobe: there light sampling alone divides a peaked f by a light
        // pdf that knows nothing of it (a sample through a smooth-ish glass cube read 2800
        // times the panel's radiance), so the last vertex keeps MIS and traces its BSDF ray
        // for the emitter it may hit, as pbrt-v4's loop does at every depth.
        const bool last = depth >= settings.max_depth;
        if constexpr (SplitCaustics)
            chain = advance(
                chain, casts_caustics(
                           m, static_cast<const SplitTraceSettings&>(settings).caustic_roughness));
        const bool light_only = S == Strategy::Direct || !settings.mis ||
                                (last && !has(material_lobes, BsdfLobe::Glossy));
        if constexpr (Bounded) {
            // The point, its normal and whether light from below its plane can count.
            chosen_at = {hit.point, v.g, !has(material_lobes, BsdfLobe::Transmission)};
        }
        const GuidedVertex guided = guided_vertex<Guided>(guide, m, material_lobes, hit.point);
        if (S != Strategy::Brute && has_non_specular(material_lobes)) {
            // A caustic path's light sample (at a caster after D) is the light path's to
            // take: there only lights at infinity, which start none, count.
            const bool infinite_only = SplitCaustics && chain == CausticChain::Open;
            out.add(beta * sample_direct<Guided, SplitCaustics>(scene, hit, v, beta, sampler,
                                                                !light_only, chosen, guided.leaf,
                                                                guided.alpha, infinite_only));
            if constexpr (S == Strategy::Direct) return out.sum;
            // The last bounce: what it finds counts only if it emits without being a light
            // (lights got weight 1 from the light sample just taken). With no such emitter,
            // save the ray.
            if (last && light_only && !scene.has_unsampled_emitters()) return out.sum;
        }
        if constexpr (Guided) {
            if (guided.leaf != nullptr) {
                const GuidedSample g = sample_guided(v, *guided.leaf, guided.alpha, sampler, dim);
                if (!(max_component(g.weight) > 0.0f)) break;
                beta *= g.weight;
                bounce = {light_only ? EmitterWeight::Zero : EmitterWeight::Mis, g.pdf, hit.point};
                if (guide.recorder != nullptr)
                    guide.recorder->push(*guided.leaf, hit.point, g.wi, g.pdf, beta);
                if (!survives_roulette(settings, depth, dim, beta, sampler)) break;
                detail::respawn(ray, hit.point, hit.geometric_normal, hit.offset, g.wi);
                continue;
            }
        }
        glm::vec3 wi_world;
        BsdfSample bs;
        if (!sample_bsdf_at(v, m, material_lobes, sampler, dim, bs, wi_world)) break;
        beta *= bs.weight;
        if (has(bs.lobe, BsdfLobe::Specular))
            bounce = {EmitterWeight::Full, 0.0f, hit.point};
        else
            bounce = {light_only ? EmitterWeight::Zero : EmitterWeight::Mis, bs.pdf, hit.point};
        if (!survives_roulette(settings, depth, dim, beta, sampler)) break;
        detail::respawn(ray, hit.point, hit.geometric_normal, hit.offset, wi_world);
    }
    return out.sum;
}

/// trace<S, true>, never inlined: PathTracer::li inlines the default light choice's loop,
/// and with this one inline too it was one 14.5 KB function, each loop's hot blocks
/// between the other's (perf on the synthesis: docs/benchmarks.md, "Where the last 7 % of
/// CPU time goes").
template <Strategy S>
[[gnu::noinline]] glm::vec3 trace_bounded(const Scene& scene, const Ray& camera_ray,
                                          Sampler& sampler, const TraceSettings& settings) {
    return trace<S, true>(scene, camera_ray, sampler, settings);
}

TraceSettings trace_settings(const PathTracerSettings& s) {
    return {s.max_depth, s.russian_roulette, s.russian_roulette_depth, s.mis};
}

}  // namespace

glm::vec3 GuardedIntegrator::guard(const glm::vec3& radiance) const {
    if (std::isfinite(radiance.x) && std::isfinite(radiance.y) && std::isfinite(radiance.z))
        return radiance;
    nonfinite_.fetch_add(1, std::memory_order_relaxed);
    assert(false && "integrator produced a non-finite sample");
    return glm::vec3(0.0f);
}

DirectLighting::DirectLighting(const DirectLightingSettings& settings) : settings_(settings) {
    check_depth("max_depth", settings.max_depth, 0, kMaxDepthLimit);
}

glm::vec3 DirectLighting::li(const Scene& scene, const Ray& ray, Sampler& sampler) const {
    TraceSettings s;
    s.max_depth = settings_.max_depth;
    if (chooses_by_bound(settings_.light_choice, scene.lights().size()))
        return guard(trace_bounded<Strategy::Direct>(scene, ray, sampler, s));
    return guard(trace<Strategy::Direct, false>(scene, ray, sampler, s));
}

PathTracer::PathTracer(const PathTracerSettings& settings) : settings_(settings) {
    check(settings);
}

glm::vec3 PathTracer::li(const Scene& scene, const Ray& ray, Sampler& sampler) const {
    if (guide_ == nullptr) [[likely]] {
        if (chooses_by_bound(settings_.light_choice, scene.lights().size()))
            return guard(
                trace_bounded<Strategy::Path>(scene, ray, sampler, trace_settings(settings_)));
        return guard(trace<Strategy::Path, false>(scene, ray, sampler, trace_settings(settings_)));
    }
    return li_guided(scene, ray, sampler);
}

glm::vec3 PathTracer::li_splatting(const Scene& scene, const Ray& ray, Sampler& sampler,
                                   const SplatTarget& target) const {
    const bool split = settings_.caustic_paths.enabled && target.camera != nullptr &&
                       target.film != nullptr &&
                       target.camera->settings().projection == Projection::Perspective &&
                       !scene.may_hide_objects();
    if (!split) return li(scene, ray, sampler);
    SplitTraceSettings s;
    static_cast<TraceSettings&>(s) = trace_settings(settings_);
    s.caustic_roughness = settings_.caustic_paths.max_roughness;
    const glm::vec3 l = chooses_by_bound(settings_.light_choice, scene.lights().size())
                            ? trace<Strategy::Path, true, false, true>(scene, ray, sampler, s)
                            : trace<Strategy::Path, false, false, true>(scene, ray, sampler, s);
    splat_caustic_path(scene, sphere_, *target.camera, *target.film, sampler, s.max_depth,
                       settings_.caustic_paths.max_roughness);
    return guard(l);
}

namespace {
/// The guided path of li_guided, its light choice a template parameter as in trace.
glm::vec3 trace_guided(const Scene& scene, const Ray& ray, Sampler& sampler,
                       const TraceSettings& settings, const GuideContext& guide, bool bounded) {
    if (bounded) return trace<Strategy::Path, true, true>(scene, ray, sampler, settings, guide);
    return trace<Strategy::Path, false, true>(scene, ray, sampler, settings, guide);
}
}  // namespace

glm::vec3 PathTracer::li_guided(const Scene& scene, const Ray& ray, Sampler& sampler) const {
    GuideContext guide{guide_.get(), nullptr, settings_.guiding.bsdf_fraction};
    const bool bounded = chooses_by_bound(settings_.light_choice, scene.lights().size());
    if (!recording_)
        return guard(trace_guided(scene, ray, sampler, trace_settings(settings_), guide, bounded));
    guiding::PathRecorder recorder;
    guide.recorder = &recorder;
    const glm::vec3 l =
        trace_guided(scene, ray, sampler, trace_settings(settings_), guide, bounded);
    recorder.commit(*guide_);
    return guard(l);
}

namespace {
/// The brute-force tracer refuses the fields only PathTracer reads, rather than ignore them:
/// it samples no light, so it has no light sample to weigh (mis), no light to choose
/// (light_choice), no mixture to guide (guiding) and no caustic to leave to light paths
/// (caustic_paths). pbrt-v4 and Mitsuba 3 stop on a parameter the integrator does not
/// use, and a reference that silently drops what it was asked for could compare against
/// a different image than the caller meant. Their defaults (what ignoring gives) pass.
void refuse_path_tracer_only(const PathTracerSettings& s) {
    const auto refuse = [](const std::string& field_and_value) {
        throw Error(field_and_value +
                    ": a PathTracer setting; BruteForcePathTracer samples no light and would "
                    "ignore it (leave it at its default)");
    };
    if (!s.mis) refuse("mis = false");
    // Auto is the default (what ignoring gives); Bounded is asked for.
    if (s.light_choice == LightChoice::Bounded) refuse("light_choice = Bounded");
    if (s.guiding.enabled) refuse("guiding.enabled = true");
    if (s.caustic_paths.enabled) refuse("caustic_paths.enabled = true");
}
}  // namespace

BruteForcePathTracer::BruteForcePathTracer(const PathTracerSettings& settings)
    : settings_(settings) {
    check(settings);
    refuse_path_tracer_only(settings);
}

glm::vec3 BruteForcePathTracer::li(const Scene& scene, const Ray& ray, Sampler& sampler) const {
    return guard(trace<Strategy::Brute, false>(scene, ray, sampler, trace_settings(settings_)));
}

glm::vec3 AlbedoNormalIntegrator::li(const Scene& scene, const Ray& ray,
                                     Sampler& /*sampler*/) const {
    Hit hit;
    if (!scene.intersect(ray, hit)) return glm::vec3(0.0f);
    ShadedMaterial shaded;
    const Material& m = scene.shade(hit, ray.direction, shaded);  // normal map applied
    if (view_ == DebugView::Normal) return guard(0.5f * hit.shading_normal + 0.5f);
    // A surface that scatters nothing shows what it emits; the others what their BSDF
    // reflects or transmits (textures applied), as the renderer's albedo AOV holds it.
    if (bsdfs::lobes_of(m) == BsdfLobe::None) return guard(m.emission);
    const glm::vec3 albedo = m.albedo_texture < 0 ? m.albedo : scene.albedo(hit);
    const ShadingPoint sp{ShadingFrame::at(hit.shading_normal, hit.geometric_normal, ray.direction),
                          albedo};
    return guard(bsdfs::denoising_albedo_of(m, sp));
}

}  // namespace librt
