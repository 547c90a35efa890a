#pragma once

#include <librt/core/image.h>
#include <librt/export.h>
#include <librt/film/film.h>

// A rectangle of an image's pixels: what a render covers when only part of the frame is
// wanted (RenderSettings::region; pbrt-v4's pixel bounds, Blender's render region), and
// what crop() cuts out of a film or an image of the whole frame.

namespace librt {

/// Pixels [x0, x1) x [y0, y1) of an image, (0, 0) its top-left pixel. All zero (the
/// default) stands for the whole image.
struct PixelRegion {
    int x0 = 0;  ///< first column
    int y0 = 0;  ///< first row
    int x1 = 0;  ///< one past the last column
    int y1 = 0;  ///< one past the last row

    /// True for the default, all zero: the whole image.
    [[nodiscard]] bool whole() const { return x0 == 0 && y0 == 0 && x1 == 0 && y1 == 0; }
    /// Columns covered.
    [[nodiscard]] int width() const { return x1 - x0; }
    /// Rows covered.
    [[nodiscard]] int height() const { return y1 - y0; }
};

/// `region` in a width x height image: [0, width) x [0, height) for whole(), else the
/// region itself. Throws librt::Error naming the region and the image size when it is
/// empty (x1 <= x0 or y1 <= y0) or does not lie within the image.
[[nodiscard]] LIBRT_API PixelRegion region_in(const PixelRegion& region, int width, int height);

/// The pixels of `region` (region_in the image's size) as an image of the region's size.
[[nodiscard]] LIBRT_API Image crop(const Image& image, const PixelRegion& region);

/// The records of `region` (region_in the film's size), radiance and AOVs, as a film of the
/// region's size: resolve() and resolve_layers() of it are those of the whole film cut to
/// the region. Throws librt::Error as region_in does, and for a film with splats (they
/// are divided by the whole image's sample count: a region of them is not the same image).
[[nodiscard]] LIBRT_API Film crop(const Film& film, const PixelRegion& region);

}  // namespace librt
