#pragma once

// Caustic light paths (PathTracerSettings::caustic_paths): path space split in two, so
// that each part is sampled by the strategy that suits it (the hybrid of forward and
// backward tracing LuxCoreRender offers; Jensen's caustic photon map makes the same split).
//
// A caustic path here is E D G+ L: the camera sees a surface D that is not a caustic
// caster, and from D the light arrives through one or more caustic casters G (mirrors,
// smooth glass, metals and glass of roughness <= max_roughness: casts_caustics()) from a
// light that sample_le can start a path at (not a light at infinity, not an emitter that
// is no light). Next-event estimation at D cannot build such a path, and BSDF sampling at
// D finds it only when its direction happens to meet G's image of the light: fireflies.
// A light path builds it directly: leave the light, scatter off the Gs, land on D and
// join D to the lens.
//
// So the camera path (trace<..., SplitCaustics = true> in integrators.cpp) counts every
// path but the caustic ones, and one light path per camera sample (splat_caustic_path)
// adds exactly the caustic ones, splatted where D is seen. The two sets are disjoint and
// together are all paths, each set estimated without bias, so their sum is unbiased: no
// MIS weight is needed across them, and neither part pays for the other's densities.

#include "material/bsdf_dispatch.h"

#include <librt/material/material.h>

#include <cstdint>

namespace librt {

class Camera;
class Sampler;
class Scene;
class SplatFilm;
struct SceneSphere;

/// True when a surface of material m (per-hit inputs applied, Scene::shade) is a caustic
/// caster G: every part of its BSDF is specular or a microfacet lobe of perceptual
/// roughness <= max_roughness, with no diffuse part; each BSDF kind says when it is one
/// (bsdfs::casts_caustics). The same test on both sides of the split.
/// Inline: the tests call it, and a shared librt exports only the public API.
[[nodiscard]] inline bool casts_caustics(const Material& m, float max_roughness) {
    return bsdfs::casts_caustics(m, max_roughness);
}

/// Where a camera path stands against the caustic set: after its first scattering vertex
/// x1, and while every later vertex is a caustic caster.
enum class CausticChain : std::uint8_t {
    Before,  ///< x1 not reached yet
    AtD,     ///< x1 is no caster; no vertex after it yet
    Open,    ///< x1 is no caster and x2 ... xj (j >= 2) all are: light found here is caustic
    Broken,  ///< the path is not (and cannot become) caustic
};

/// The chain after scattering at a vertex of material m, `first` when it is x1.
[[nodiscard]] inline CausticChain advance(CausticChain chain, bool caster) {
    switch (chain) {
        case CausticChain::Before:
            return caster ? CausticChain::Broken : CausticChain::AtD;
        case CausticChain::AtD:
        case CausticChain::Open:
            return caster ? CausticChain::Open : CausticChain::Broken;
        case CausticChain::Broken:
            break;
    }
    return CausticChain::Broken;
}

/// Traces one light path from a light of finite extent chosen by the scene's light
/// sampler (by power), through caustic casters only, and when it lands on a surface that
/// is not one after at least one caster, joins that point to the lens (sample_wi) and
/// splats the contribution onto `film`. A path has at most max_depth scattering events
/// counting the seen surface, as PathTracer's. Draws its numbers from sampler dimensions
/// of its own (far above the camera path's bounces).
void splat_caustic_path(const Scene& scene, const SceneSphere& sphere, const Camera& camera,
                        SplatFilm& film, Sampler& sampler, int max_depth, float max_roughness);

}  // namespace librt
