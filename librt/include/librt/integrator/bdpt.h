#pragma once

#include <librt/export.h>
#include <librt/integrator/integrators.h>
#include <librt/light/light_sample.h>

#include <cstdint>

namespace librt {

/// Settings of BidirectionalPathTracer.
struct BidirectionalSettings {
    /// Scattering events per path, in [0, kMaxDepth] (as PathTracerSettings::max_depth:
    /// emission seen by the camera is depth 0).
    int max_depth = 5;
    /// Connect light subpaths to the camera (the t = 1 strategies, pbrt's "light tracing"
    /// part): they find caustics seen directly (light through glass onto a floor) that no
    /// other strategy samples well. They add light to arbitrary pixels, so they are used
    /// only through li_splatting (the render entry points call it when splats() is true);
    /// li() alone leaves them out of every weight, and stays unbiased.
    bool light_tracing = true;
    /// The fraction of camera samples that also trace a light subpath, in (0, 1]. The
    /// strategies that need one (s >= 2, and t = 1) are then taken in that fraction of the
    /// samples, their contributions divided by it, and every weight counts each strategy's
    /// expected samples (the power heuristic with sample counts, Veach 1997 section 9.2.2).
    /// Below 1 a sample costs less and the paths next-event estimation finds well get more
    /// samples for the time: where most of the image is lit that way, and the light subpaths
    /// are needed only for a few paths (a lit band, a caustic), that lowers the error at
    /// equal time (the number of light paths is what Grittmann et al. 2022, "Efficiency-aware
    /// multiple importance sampling for bidirectional rendering algorithms", tune per scene).
    float light_path_fraction = 1.0f;
    /// Randomly end both subpaths from bounce russian_roulette_depth on, surviving with
    /// their throughput relative to the subpath's start (at most 0.95), as PathTracer does.
    /// The weights leave the survival out of every strategy's density: they are still a
    /// partition of unity, so the image stays unbiased.
    bool russian_roulette = true;
    /// Bounces never rouletted, >= 0 (as PathTracerSettings::russian_roulette_depth).
    int russian_roulette_depth = 3;
    /// The largest max_depth: the vertices of both subpaths live on the stack.
    static constexpr int kMaxDepth = 64;
};

/// Bidirectional path tracing with multiple importance sampling (Veach 1997, chapter 10;
/// Veach and Guibas 1995; the formulation of pbrt 3rd ed. chapter 16). Per camera sample
/// it traces a camera subpath and a light subpath (from a light chosen by the scene's
/// light sampler, by sample_le) and joins every prefix of one to every prefix of the
/// other: s light vertices and t camera vertices, each full path weighted by the power
/// heuristic over all the (s, t) that could have made it. s = 0 is the camera path hitting
/// an emitter, s = 1 next-event estimation (sample_li, as PathTracer), t = 1 a light
/// subpath vertex joined to the lens (sample_wi, splatted; see BidirectionalSettings).
///
/// What it is for: light that reaches the camera through a small bright region that
/// only paths starting at the light find easily (a panel lighting the ceiling just above
/// it, a caustic), where PathTracer's BSDF sampling meets it by chance. Costs more per
/// sample than PathTracer (two subpaths and up to (D + 2)^2 / 2 shadow rays).
///
/// Choices, stated: light subpaths start only at lights of finite extent (area, point,
/// spot); paths lit by lights at infinity (environment, sun) are weighed between s = 0
/// and s = 1 alone, as PathTracer does. The s = 1 vertex is drawn by sample_li but
/// weighed with the density of sample_le's origin (as pbrt does), so its weight is not
/// optimal where the two differ (spherical-triangle sampling), only consistent: the weights
/// of a path still sum to 1. Surfaces with a Null lobe (bsdf.h) are crossed as PathTracer
/// crosses them and do not count as vertices; connections see lights through them.
/// librt's BSDFs are symmetric (the dielectrics carry no 1 / eta^2 radiance factor), so a
/// light subpath uses the same sample / eval / pdf with Veach's correction for shading
/// normals. Camera rays see through objects hidden from the camera, but light-subpath
/// connections to the lens could not: in a scene that hides objects from the camera the
/// t = 1 strategies are left out, as with light_tracing off. A connection to the lens
/// ends at the near clip plane (CameraWi::view_start), as camera rays start there.
class LIBRT_API BidirectionalPathTracer final : public GuardedIntegrator {
public:
    /// Throws librt::Error naming max_depth when it is outside [0, kMaxDepth],
    /// light_path_fraction outside (0, 1] or russian_roulette_depth below 0.
    explicit BidirectionalPathTracer(const BidirectionalSettings& settings = {});
    /// Records the scene's bounding sphere (sample_le of lights at infinity needs it).
    void preprocess(const Scene& scene) override;
    /// One sample without the t = 1 strategies (nothing to splat onto).
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& ray, Sampler& sampler) const override;
    /// True with light_tracing.
    [[nodiscard]] bool splats() const override { return settings_.light_tracing; }
    /// One sample with every strategy; the t = 1 ones are added to target.film.
    [[nodiscard]] glm::vec3 li_splatting(const Scene& scene, const Ray& ray, Sampler& sampler,
                                         const SplatTarget& target) const override;
    /// The settings in use.
    [[nodiscard]] const BidirectionalSettings& settings() const { return settings_; }

private:
    BidirectionalSettings settings_;
    SceneSphere sphere_{};
};

}  // namespace librt
