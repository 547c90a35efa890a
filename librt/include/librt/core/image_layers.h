#pragma once

#include <librt/core/image.h>

#include <vector>

namespace librt {

/// A rendered image with its AOV layers (arbitrary output variables), what denoisers and
/// compositors read: the film resolves into it (film/film.h) and io/exr.h writes it.
/// Every layer but `beauty` is optional (empty = absent); a present one has the beauty's
/// size, row-major with the top row first.
struct ImageLayers {
    Image beauty;              ///< linear RGB radiance, not tone-mapped
    Image albedo;              ///< RGB albedo of the first non-specular hit, or 0x0
    Image normal;              ///< its shading normal (world x, y, z), or 0x0
    std::vector<float> depth;  ///< width * height camera distances of the first hit, or empty
    std::vector<float> sample_count;  ///< width * height samples per pixel, or empty
};

}  // namespace librt
