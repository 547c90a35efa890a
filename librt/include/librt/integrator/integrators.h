#pragma once

#include <librt/export.h>
#include <librt/integrator/guiding.h>
#include <librt/integrator/integrator.h>
#include <librt/light/light_sample.h>
#include <librt/light/light_sampler.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>

// The report's rendering algorithms, from its hard-shadow figure to its full getColor, plus
// a brute-force reference and a debug view. All run one path loop (no recursion) built of
// the same pieces: the BSDF seam (bsdf.h) at every hit, one light chosen by the scene's
// light sampler for next-event estimation (light.h, light_sampler.h), shadow rays from
// shadow_ray.h. They differ only in which sampling strategies they use and how they weigh
// them. They allocate nothing per ray and never return NaN or Inf.
//
// Depth convention, shared by all: max_depth counts scattering events (diffuse, mirror or
// glass bounces) along the path. Emission seen by the camera counts at depth 0, so
// max_depth = 0 shows only emitters and max_depth = 1 gives direct lighting at the first
// surface; light sampling at a diffuse hit is part of that hit's scattering event.

namespace librt {

namespace guiding {
class SdTree;
}

/// Common base: guards every estimate against NaN and Inf. A non-finite sample is
/// replaced by 0 and counted (atomically, as li() runs on many threads); a debug build
/// also asserts, since it means a bug or a degenerate scene.
class LIBRT_API GuardedIntegrator : public Integrator {
public:
    /// How many samples were non-finite and replaced by 0 since construction.
    [[nodiscard]] std::uint64_t nonfinite_count() const {
        return nonfinite_.load(std::memory_order_relaxed);
    }

protected:
    /// Returns radiance, or 0 (counted) when any component is NaN or infinite.
    [[nodiscard]] glm::vec3 guard(const glm::vec3& radiance) const;

private:
    mutable std::atomic<std::uint64_t> nonfinite_{0};
};

/// Settings of DirectLighting.
struct DirectLightingSettings {
    int max_depth = 5;  ///< mirror and glass bounces followed, in [0, 1000]
    /// How the light sampled at a hit is chosen (Power: the report's images, bit for bit).
    LightChoice light_choice = LightChoice::Power;
};

/// The report's first figure: at the first non-specular hit, next-event estimation of one
/// light chosen by the scene's light sampler (a point light: hard shadow ray,
/// I cos(theta) / d^2 * f; a sphere light: one sample of the cone it subtends), weight 1;
/// no indirect light. Mirrors and glass are followed up to max_depth; emitters seen
/// directly or through mirrors and glass show their radiance.
class LIBRT_API DirectLighting final : public GuardedIntegrator {
public:
    /// Throws librt::Error naming max_depth when it is outside [0, 1000].
    explicit DirectLighting(const DirectLightingSettings& settings = {});
    /// One sample of the direct radiance along ray.
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& ray, Sampler& sampler) const override;
    /// The settings in use.
    [[nodiscard]] const DirectLightingSettings& settings() const { return settings_; }

private:
    DirectLightingSettings settings_;
};

/// PathTracer's caustic light paths: the light that reaches a surface the camera sees
/// through mirrors, glass or smooth metal (a caustic, E D G+ L) is traced from the lights
/// and splatted, and the camera paths leave it out (a split of path space, not a MIS
/// weight, so each half stays as cheap as it was: src/integrator/caustic_paths.h). Off by
/// default. Used by the render entry points, which call li_splatting when splats() is
/// true; li() alone renders every path as without it.
struct CausticPathSettings {
    bool enabled = false;  ///< trace the caustics from the lights (needs a splat film)
    /// Perceptual roughness, in [0, 1], up to which a metal or glass (Conductor,
    /// RoughDielectric, a MetallicRoughness wholly metal or wholly transmissive) casts
    /// caustics; mirrors and smooth glass always do, nothing with a diffuse part does.
    /// 0.5 (GGX alpha 0.25): above it next-event estimation handles the lobe well.
    float max_roughness = 0.5f;
};

/// Settings of PathTracer and BruteForcePathTracer.
struct PathTracerSettings {
    // Defaults converge to the right image: a 5-bounce cut is ~7% too dark in a closed
    // room, while roulette keeps the mean length of paths short. The report's apps set
    // 5 bounces and no roulette explicitly (apps/common/cli.cpp).
    int max_depth = 1000;          ///< scattering events per path, in [0, 1000] (report: 5)
    bool russian_roulette = true;  ///< randomly end paths from bounce russian_roulette_depth on
    /// Bounces never rouletted, >= 0: roulette decides after bounce d, d + 1, ... (bounce 0
    /// is the camera ray's first hit), so 0 may end a path after its first bounce and d
    /// leaves every path of at most d bounces untouched.
    int russian_roulette_depth = 3;
    /// PathTracer only (BruteForcePathTracer refuses false): weigh light and BSDF samples
    /// by the power heuristic (true), or give light samples the whole weight and count
    /// nothing for light-sampled emitters that a BSDF-sampled ray hits (false: next-event
    /// estimation only, the report's rule).
    bool mis = true;
    /// PathTracer only (BruteForcePathTracer refuses Bounded): how the light sampled at a
    /// vertex is chosen. Bounded spends no sample on lights that cannot reach the point and
    /// favours near ones; Power keeps the images of before the bounded choice bit for bit;
    /// Auto (the default, the best measured) is Bounded above 16 lights, else Power.
    LightChoice light_choice = LightChoice::Auto;
    /// PathTracer only: path guiding (guiding.h), off by default (BruteForcePathTracer
    /// refuses it on).
    GuidingSettings guiding{};
    /// PathTracer only: caustics traced from the lights (not with guiding), off by default
    /// (BruteForcePathTracer refuses them on).
    CausticPathSettings caustic_paths{};
};

/// The report's full getColor as a loop with multiple importance sampling: at every
/// non-specular hit, next-event estimation of one light (chosen by the scene's light
/// sampler; a sphere light sampled in the cone it subtends, where the report picked a
/// point on its surface) and one BSDF sample (cosine-weighted at a diffuse surface), both
/// weighted by the power heuristic (Veach 1997): a light-sampled emitter hit by the BSDF
/// ray counts with the BSDF strategy's weight. Specular hits (mirror, glass) only sample
/// their BSDF, and an emitter seen by the camera or through them counts fully. Emitters
/// that are no light (emissive meshes, glowing diffuse surfaces) are not light-sampled,
/// so they always count fully. At the last scattering event (depth = max_depth) of a
/// surface without a glossy lobe the light sample takes the whole weight and hit lights
/// count nothing (one strategy, so the weights still sum to 1), which lets the path stop
/// without tracing that last ray unless some emitter is not light-sampled; a glossy last
/// vertex keeps MIS and traces its BSDF ray for the emitter it may hit (light sampling
/// alone would divide its peaked f by a light pdf blind to it: fireflies). With
/// settings.mis = false every non-specular vertex takes the light sample's whole weight
/// (next-event estimation only).
///
/// With settings.guiding.enabled, preprocess() builds an empty SD-tree over the scene and
/// the training passes (train() in renderer.h) teach it the incident radiance; at a vertex
/// with no specular lobe the direction is then drawn from the BSDF with probability
/// guiding.bsdf_fraction and from the learned distribution otherwise, weighted by the
/// mixture's density (docs/sampling.md). Without training it renders unguided.
///
/// With settings.caustic_paths.enabled, li_splatting also traces one light path per
/// camera sample for the caustics (CausticPathSettings), when the camera is perspective
/// and the scene hides nothing from it (a light path's join to the lens cannot pass
/// hidden objects as camera rays do); otherwise it is li().
class LIBRT_API PathTracer final : public GuardedIntegrator {
public:
    /// Throws librt::Error naming max_depth, russian_roulette_depth, the guiding parameter
    /// or caustic_paths.max_roughness out of range, or guiding and caustic paths together.
    explicit PathTracer(const PathTracerSettings& settings = {});
    ~PathTracer() override;
    /// With guiding: an empty SD-tree over the scene's bounds (what was learned is dropped).
    /// Records the scene's bounding sphere (light paths start from it).
    void preprocess(const Scene& scene) override;
    /// With guiding: 2^pass samples per pixel for pass < training_passes, recorded.
    [[nodiscard]] std::uint32_t begin_training_pass(int pass) override;
    /// With guiding: what the pass recorded guides the next pass (or the image).
    void end_training_pass(int pass) override;
    /// With guiding and guiding.keep_training_samples: true (render() combines the passes).
    [[nodiscard]] bool keeps_training_samples() const override;
    /// One sample of the radiance along ray.
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& ray, Sampler& sampler) const override;
    /// True with caustic paths.
    [[nodiscard]] bool splats() const override { return settings_.caustic_paths.enabled; }
    /// With caustic paths: the camera path without them, and one caustic light path splatted
    /// onto target.film.
    [[nodiscard]] glm::vec3 li_splatting(const Scene& scene, const Ray& ray, Sampler& sampler,
                                         const SplatTarget& target) const override;
    /// The settings in use.
    [[nodiscard]] const PathTracerSettings& settings() const { return settings_; }
    /// Spatial leaves of the SD-tree (0 without guiding or before preprocess()).
    [[nodiscard]] std::size_t guiding_leaf_count() const;

private:
    [[nodiscard]] glm::vec3 li_guided(const Scene& scene, const Ray& ray, Sampler& sampler) const;

    PathTracerSettings settings_;
    SceneSphere sphere_{};                    // the scene's, from preprocess()
    std::unique_ptr<guiding::SdTree> guide_;  // with guiding, after preprocess()
    bool recording_ = false;                  // a training pass is running
};

/// The reference: the same paths as PathTracer with no light sampling at all; emission
/// counts whenever a path hits an emitter. It converges to the same image for sphere
/// lights and emissive surfaces, only more slowly. Point lights contribute NOTHING: a
/// point has no area, so no sampled direction ever hits it (with point lights only it
/// renders black), which is why it is the ground truth only for area lights.
class LIBRT_API BruteForcePathTracer final : public GuardedIntegrator {
public:
    /// Throws librt::Error naming max_depth or russian_roulette_depth when out of range,
    /// or a PathTracer-only field set away from its default (mis = false, light_choice =
    /// Bounded, guiding.enabled, caustic_paths.enabled): it would have no effect here.
    explicit BruteForcePathTracer(const PathTracerSettings& settings = {});
    /// One sample of the radiance along ray.
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& ray, Sampler& sampler) const override;
    /// The settings in use.
    [[nodiscard]] const PathTracerSettings& settings() const { return settings_; }

private:
    PathTracerSettings settings_;
};

/// What AlbedoNormalIntegrator shows.
enum class DebugView : std::uint8_t {
    Albedo,  ///< denoising_albedo (bsdf.h) of scattering surfaces, emission of pure emitters
    Normal,  ///< shading normal mapped from [-1, 1] to [0, 1] per axis
};

/// Debug view of the first surface hit; black where nothing is hit.
class LIBRT_API AlbedoNormalIntegrator final : public GuardedIntegrator {
public:
    /// Shows the given view.
    explicit AlbedoNormalIntegrator(DebugView view = DebugView::Albedo) : view_(view) {}
    /// The albedo or normal at the first hit.
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& ray, Sampler& sampler) const override;
    /// The view in use.
    [[nodiscard]] DebugView view() const { return view_; }

private:
    DebugView view_;
};

}  // namespace librt
