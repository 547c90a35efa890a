#include <librt/core/error.h>
#include <librt/film/film.h>

#include <cstdio>
#include <limits>
#include <string>

namespace librt {

namespace {

std::string pixel_name(int x, int y) {
    return "(" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

void check_film_size(long long width, long long height, bool with_aovs) {
    const std::string size = std::to_string(width) + " x " + std::to_string(height);
    if (width < 0 || height < 0) {
        throw Error("film size " + size + ": width and height must be >= 0");
    }
    const std::uint64_t per_pixel = sizeof(FilmPixel) + (with_aovs ? sizeof(AovPixel) : 0);
    const std::uint64_t max_pixels = Film::kMaxBytes / per_pixel;
    const auto w = static_cast<unsigned long long>(width);
    const auto h = static_cast<unsigned long long>(height);
    if (w > 0 && h > max_pixels / w) {  // by division: no product can wrap around
        char needs[64];
        std::snprintf(needs, sizeof needs, "%.4g GiB",
                      double(w) * double(h) * double(per_pixel) / double(1ull << 30u));
        throw Error("film size " + size + ": the film would need " + needs +
                    ", more than the 16 GiB limit");
    }
}

}  // namespace

Film::Film(int w, int h, bool with_aovs) : width(w), height(h) {
    check_film_size(w, h, with_aovs);
    const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
    pixels.assign(n, FilmPixel{});
    if (with_aovs) aovs.assign(n, AovPixel{});
}

void merge(Film& into, const Film& from) {
    if (into.width != from.width || into.height != from.height) {
        throw Error("cannot merge a " + std::to_string(from.width) + " x " +
                    std::to_string(from.height) + " film into a " + std::to_string(into.width) +
                    " x " + std::to_string(into.height) + " one");
    }
    if (into.has_aovs() != from.has_aovs()) {
        throw Error("cannot merge films with and without AOVs");
    }
    // Checked for every pixel before anything is copied, so a refused merge changes nothing.
    for (int y = 0; y < from.height; ++y) {
        for (int x = 0; x < from.width; ++x) {
            if (from.at(x, y).samples != 0 && into.at(x, y).samples != 0) {
                throw Error("cannot merge films that both hold samples of pixel " +
                            pixel_name(x, y) +
                            " (not bit-exact): render the later samples onto the film instead");
            }
        }
    }
    // Splats before pixels: SplatFilm::merge checks before it adds, and is the last thing
    // here that can throw.
    if (from.splats) {
        if (into.splats) {
            into.splats->merge(*from.splats);
        } else {
            into.splats = from.splats;
        }
    }
    for (std::size_t i = 0; i < from.pixels.size(); ++i) {
        if (from.pixels[i].samples == 0) continue;
        into.pixels[i] = from.pixels[i];
        if (from.has_aovs()) into.aovs[i] = from.aovs[i];
    }
}

Image resolve(const Film& film) {
    Image image(film.width, film.height);
    for (std::size_t i = 0; i < film.pixels.size(); ++i) {
        const FilmPixel& p = film.pixels[i];
        // Pixel estimate: the mean of its finite samples (the renderer's formula, unchanged).
        image.pixels[i] =
            p.finite > 0 ? glm::vec3(p.radiance / static_cast<double>(p.finite)) : glm::vec3(0.0f);
    }
    if (!film.splats) return image;
    const SplatFilm& splats = *film.splats;
    if (splats.width() != film.width || splats.height() != film.height) {
        throw Error("cannot resolve a " + std::to_string(film.width) + " x " +
                    std::to_string(film.height) + " film with " + std::to_string(splats.width()) +
                    " x " + std::to_string(splats.height()) +
                    " splats: merge its region into a film of the whole image first");
    }
    const double spp = splat_samples_per_pixel(film);
    if (spp == 0.0) return image;
    const Image splat_image = splats.resolve(spp);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] += splat_image.pixels[i];
    return image;
}

double splat_samples_per_pixel(const Film& film) {
    if (film.pixels.empty()) return 0.0;
    // An integer total (at most 2^29 pixels of 2^20 samples: exact in a double too), so
    // a complete render's divisor is its sample count exactly.
    std::uint64_t total = 0;
    for (const FilmPixel& p : film.pixels) total += p.samples;
    return static_cast<double>(total) / static_cast<double>(film.pixels.size());
}

ImageLayers resolve_layers(const Film& film) {
    ImageLayers layers;
    layers.beauty = resolve(film);
    layers.sample_count.resize(film.pixels.size());
    for (std::size_t i = 0; i < film.pixels.size(); ++i)
        layers.sample_count[i] = static_cast<float>(film.pixels[i].samples);
    if (!film.has_aovs()) return layers;
    layers.albedo = Image(film.width, film.height);
    layers.normal = Image(film.width, film.height);
    layers.depth.resize(film.pixels.size());
    for (std::size_t i = 0; i < film.pixels.size(); ++i) {
        const AovPixel& a = film.aovs[i];
        const std::uint32_t n = film.pixels[i].samples;
        // Means over the pixel's samples; a miss adds 0 to albedo and normal, and depth
        // averages only the samples that hit. The albedo's filtered mean sum(w a) / sum(w):
        // every weight of a filter has one size, so sum(w) is that size times the sum of
        // the signs, n - 2 negative, and the size cancels.
        const double signs = double(n) - 2.0 * double(a.negative);
        layers.albedo.pixels[i] = signs != 0.0 ? glm::vec3(a.albedo / signs) : glm::vec3(0.0f);
        layers.normal.pixels[i] = n > 0 ? glm::vec3(a.normal / double(n)) : glm::vec3(0.0f);
        layers.depth[i] = a.hits > 0 ? static_cast<float>(a.depth / double(a.hits))
                                     : std::numeric_limits<float>::infinity();
    }
    return layers;
}

std::uint32_t uniform_sample_count(const Film& film) {
    if (film.pixels.empty()) return 0;
    const std::uint32_t n = film.pixels.front().samples;
    for (int y = 0; y < film.height; ++y) {
        for (int x = 0; x < film.width; ++x) {
            if (film.at(x, y).samples != n) {
                throw Error("film pixel " + pixel_name(x, y) + " holds " +
                            std::to_string(film.at(x, y).samples) + " samples, pixel (0, 0) " +
                            std::to_string(n) + ": not a film of whole passes");
            }
        }
    }
    return n;
}

}  // namespace librt
