#pragma once

// Toy integrators that splat (Integrator::splats), whose images are known in closed form or
// depend on every random number they draw, shared by the render and MPI splatting tests.

#include "film/camera_importance.h"

#include <librt/film/camera.h>
#include <librt/film/splat_film.h>
#include <librt/integrator/integrator.h>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cstdint>

namespace librt::testing {

/// Each camera sample splats 1 at its own ray's raster position and returns 0: with a box
/// filter every pixel of a complete render resolves to exactly 1.
class OwnPixelSplatter final : public Integrator {
public:
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& /*ray*/,
                               Sampler& /*sampler*/) const override {
        return glm::vec3(0.0f);
    }
    [[nodiscard]] bool splats() const override { return true; }
    [[nodiscard]] glm::vec3 li_splatting(const Scene& /*scene*/, const Ray& ray,
                                         Sampler& /*sampler*/,
                                         const SplatTarget& target) const override {
        if (const auto raster = raster_of(*target.camera, ray)) {
            target.film->add(*raster, glm::vec3(1.0f));
        }
        return glm::vec3(0.0f);
    }
};

/// Returns a colour of the sampler's and the ray's numbers for its own pixel and splats
/// `value` times a random factor in [0, 1) (or exactly `value` when `fixed`) at a raster
/// position uniform over the image grown by `margin` pixels on every side (splats there
/// fall partly or wholly off the film). Optionally learns in passes of 2 and 3 samples per
/// pixel that it keeps (keeps_training_samples), like path guiding.
class RandomSplatter : public Integrator {
public:
    struct Options {
        glm::vec3 value{1.0f, 0.5f, 0.25f};
        bool fixed = false;  ///< splat exactly `value`
        float margin = 0.0f;
        bool trains = false;  ///< two kept training passes
    };
    RandomSplatter() = default;
    explicit RandomSplatter(const Options& options) : options_(options) {}

    [[nodiscard]] std::uint32_t begin_training_pass(int pass) override {
        return options_.trains && pass < 2 ? std::uint32_t(2 + pass) : 0;
    }
    [[nodiscard]] bool keeps_training_samples() const override { return options_.trains; }
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& ray,
                               Sampler& sampler) const override {
        return own(ray, sampler);
    }
    [[nodiscard]] bool splats() const override { return true; }
    [[nodiscard]] glm::vec3 li_splatting(const Scene& /*scene*/, const Ray& ray, Sampler& sampler,
                                         const SplatTarget& target) const override {
        const glm::vec2 u = sampler.next_2d();
        const float m = options_.margin;
        const glm::vec2 raster(u.x * (float(target.camera->width()) + 2.0f * m) - m,
                               u.y * (float(target.camera->height()) + 2.0f * m) - m);
        const float factor = options_.fixed ? 1.0f : sampler.next_1d();
        target.film->add(raster, options_.value * factor);
        return own(ray, sampler);
    }

private:
    static glm::vec3 own(const Ray& ray, Sampler& sampler) {
        const float a = sampler.next_1d();
        const glm::vec2 b = sampler.next_2d();
        return {a + ray.direction.x, b.x * ray.origin.y + 0.5f, b.y - ray.direction.y};
    }
    Options options_;
};

/// A camera of w x h pixels: pinhole rays through pixel centres (a box splat filter) when
/// `centres`, else Gaussian pixel jitter and a Gaussian lens (a truncated Gaussian filter).
inline Camera splat_test_camera(int w, int h, bool centres) {
    CameraSettings s;
    s.width = w;
    s.height = h;
    s.position = {0.0f, 1.0f, 5.0f};
    if (centres) {
        s.pixel_jitter = PixelJitter::None;
    } else {
        s.pixel_jitter = PixelJitter::Gaussian;
        s.lens = LensModel::Gaussian;
        s.lens_sigma = 0.3f;
    }
    return Camera(s);
}

}  // namespace librt::testing
