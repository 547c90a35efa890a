#pragma once

#include <librt/export.h>
#include <librt/geometry/ray.h>
#include <librt/render/sampler.h>

#include <glm/vec3.hpp>

namespace librt {

class Scene;

/// Estimates the radiance arriving along a camera ray: the one place where rendering
/// algorithms differ, hence the one virtual interface of the renderer. Implementations
/// are immutable during a render and called from many threads at once.
class LIBRT_API Integrator {
public:
    virtual ~Integrator() = default;
    /// Called once before a render, e.g. to inspect the scene's lights.
    virtual void preprocess(const Scene& /*scene*/) {}
    /// One sample of the radiance (linear RGB) travelling back along `ray`.
    [[nodiscard]] virtual glm::vec3 li(const Scene& scene, const Ray& ray,
                                       Sampler& sampler) const = 0;
};

}  // namespace librt
