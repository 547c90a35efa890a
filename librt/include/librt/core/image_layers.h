#pragma once

#include <librt/core/image.h>

#include <vector>

namespace librt {

/// A rendered image with its AOV layers (arbitrary output variables), what denoisers and
/// compositors read: the film resolves into it (film/film.h) and io/exr.h writes it.
/// Every layer but `beauty` is optional (empty = absent); a present one has the beauty's
/// size, row-major with the top row first.
struct ImageLayers {
    Image beauty;  ///< linear RGB radiance, not tone-mapped
    /// RGB albedo of the first non-specular hit (what its BSDF reflects or transmits:
    /// bsdf.h, denoising_albedo), or 0x0.
    Image albedo;
    /// Its unit shading normal in world space, the scene's own axes (Y up, as in glTF and
    /// the default camera), not the camera's; or 0x0.
    Image normal;
    /// width * height planar depths of the first hit (distance from the camera's lens plane
    /// along its optical axis, what compositors read as Z; not the ray's length), or empty.
    std::vector<float> depth;
    std::vector<float> sample_count;  ///< width * height samples per pixel, or empty
    /// The beauty denoised (render/denoiser.h), or 0x0. The beauty itself stays the
    /// unbiased estimate.
    Image denoised;
};

}  // namespace librt
