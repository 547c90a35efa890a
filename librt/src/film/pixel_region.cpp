#include <librt/core/error.h>
#include <librt/film/pixel_region.h>

#include <string>

namespace librt {

PixelRegion region_in(const PixelRegion& r, int width, int height) {
    if (r.whole()) return {0, 0, width, height};
    if (r.x0 < 0 || r.y0 < 0 || r.x1 <= r.x0 || r.y1 <= r.y0 || r.x1 > width || r.y1 > height) {
        throw Error("region [" + std::to_string(r.x0) + ", " + std::to_string(r.x1) + ") x [" +
                    std::to_string(r.y0) + ", " + std::to_string(r.y1) +
                    "): must be a non-empty rectangle within the " + std::to_string(width) + " x " +
                    std::to_string(height) + " image");
    }
    return r;
}

namespace {

/// Copies the rows of `r` out of a row-major `from` of row length `width`.
template <class T>
std::vector<T> cut(const std::vector<T>& from, int width, const PixelRegion& r) {
    std::vector<T> out;
    out.reserve(std::size_t(r.width()) * std::size_t(r.height()));
    for (int y = r.y0; y < r.y1; ++y) {
        const auto row = from.begin() + std::ptrdiff_t(y) * width;
        out.insert(out.end(), row + r.x0, row + r.x1);
    }
    return out;
}

}  // namespace

Image crop(const Image& image, const PixelRegion& region) {
    const PixelRegion r = region_in(region, image.width, image.height);
    Image out;
    out.width = r.width();
    out.height = r.height();
    out.pixels = cut(image.pixels, image.width, r);
    return out;
}

Film crop(const Film& film, const PixelRegion& region) {
    const PixelRegion r = region_in(region, film.width, film.height);
    if (film.splats)
        throw Error("crop: the film has splats, which cover the whole image (crop its image)");
    Film out;
    out.width = r.width();
    out.height = r.height();
    out.pixels = cut(film.pixels, film.width, r);
    if (film.has_aovs()) out.aovs = cut(film.aovs, film.width, r);
    return out;
}

}  // namespace librt
