#pragma once

#include <librt/geometry/sphere.h>
#include <librt/light/light_sample.h>

#include <span>

namespace librt {

/// What a light learns of its scene before rendering (each kind's preprocess, called by
/// Scene::commit once the geometry is built).
struct SceneSummary {
    /// The scene's bounds as a sphere: lights at infinity take its radius for power().
    SceneSphere sphere;
    /// The scene's opaque analytic spheres that are no light's surface: they may bury part
    /// of a sphere light (sphere_light_cuts.h), which then samples only what a point sees.
    std::span<const DoubleSphere> opaque_spheres;
};

}  // namespace librt
