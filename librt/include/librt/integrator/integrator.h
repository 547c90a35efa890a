#pragma once

#include <librt/export.h>
#include <librt/geometry/ray.h>
#include <librt/sampling/sampler.h>

#include <glm/vec3.hpp>

#include <cstdint>

namespace librt {

class Camera;
class Scene;
class SplatFilm;

/// Where an integrator that also lights pixels other than its camera ray's (the
/// light-tracing strategies of a bidirectional path tracer) sends that light: the camera
/// to connect paths to, and the film of splats that every thread of the render shares
/// (SplatFilm::add is thread-safe and order-independent, so renders stay bit-identical).
/// The renderer resolves the film by the render's samples per pixel and adds it to the
/// image (renderer.h).
struct SplatTarget {
    const Camera* camera = nullptr;  ///< the render's camera
    SplatFilm* film = nullptr;       ///< full-image splat sums (camera.width() x height())
};

/// Estimates the radiance arriving along a camera ray: the one place where rendering
/// algorithms differ, hence the one virtual interface of the renderer. Implementations
/// are immutable during a render and called from many threads at once.
class LIBRT_API Integrator {
public:
    virtual ~Integrator() = default;
    /// Called once before a render, e.g. to inspect the scene's lights.
    virtual void preprocess(const Scene& /*scene*/) {}
    /// Starts learning pass `pass` (0, 1, ...) of an integrator that learns from its own
    /// samples before rendering the image (path guiding); train() in renderer.h calls it
    /// after preprocess(). Returns the samples per pixel the pass renders (and discards),
    /// 0 when there is nothing (more) to learn, which is the default.
    [[nodiscard]] virtual std::uint32_t begin_training_pass(int /*pass*/) { return 0; }
    /// Ends the pass begin_training_pass(pass) started: what its samples taught the
    /// integrator is used from the next pass (or the image) on.
    virtual void end_training_pass(int /*pass*/) {}
    /// True when the render entry points may combine the training passes' samples with the
    /// image's (each pass is then an unbiased estimate of it; see train()); false, the
    /// default, discards them. Asked after preprocess().
    [[nodiscard]] virtual bool keeps_training_samples() const { return false; }
    /// One sample of the radiance (linear RGB) travelling back along `ray`.
    [[nodiscard]] virtual glm::vec3 li(const Scene& scene, const Ray& ray,
                                       Sampler& sampler) const = 0;
    /// True when the integrator splats: the render entry points then call li_splatting
    /// with a SplatTarget instead of li. False, the default, for every integrator whose
    /// samples light only their own pixel.
    [[nodiscard]] virtual bool splats() const { return false; }
    /// li for an integrator that splats: returns the radiance for the camera ray's own
    /// pixel and adds what its paths bring to other pixels to target.film. The default
    /// ignores the target and returns li().
    [[nodiscard]] virtual glm::vec3 li_splatting(const Scene& scene, const Ray& ray,
                                                 Sampler& sampler,
                                                 const SplatTarget& /*target*/) const {
        return li(scene, ray, sampler);
    }
};

}  // namespace librt
