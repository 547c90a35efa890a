#include <librt/core/error.h>
#include <librt/core/finite.h>
#include <librt/material/texture.h>

#include <glm/common.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

namespace librt {
namespace {

// Position modulo n in [0, n) for any integer, negative ones included.
int wrap(int i, int n) {
    const int m = i % n;
    return m < 0 ? m + n : m;
}

// Texel index i (any integer) to [0, n) by mirrored repeat: period 2n, the second half
// reversed (texel n maps to n - 1, -1 to 0).
int mirror(int i, int n) {
    const int m = wrap(i, 2 * n);
    return m < n ? m : 2 * n - 1 - m;
}

void check_size(int width, int height, std::size_t texels, std::size_t per_texel) {
    if (width <= 0 || height <= 0) {
        std::ostringstream msg;
        msg << "texture size " << width << " x " << height << ": must be positive";
        throw Error(msg.str());
    }
    if (texels != std::size_t(width) * std::size_t(height) * per_texel) {
        std::ostringstream msg;
        msg << "texture of " << width << " x " << height << " given " << texels / per_texel
            << " texels";
        throw Error(msg.str());
    }
}

}  // namespace

float srgb_to_linear(float c) {
    // sRGB decoding: linear segment near black, power 2.4 elsewhere.
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

ImageTexture::ImageTexture(int width, int height, std::vector<glm::vec3> linear_texels)
    : width_(width), height_(height), texels_(std::move(linear_texels)) {
    check_size(width, height, texels_.size(), 1);
}

ImageTexture ImageTexture::from_rgba8(int width, int height, std::span<const std::uint8_t> rgba,
                                      ColorSpace space, const TextureSampling& sampling) {
    check_size(width, height, rgba.size(), 4);
    ImageTexture t;
    t.width_ = width;
    t.height_ = height;
    // Decoding through a table at lookup: 256 values instead of a pow per texel channel,
    // and the texels stay 4 bytes (a 4096^2 texture: 64 MiB, not 256 as floats).
    for (int i = 0; i < 256; ++i) {
        const float c = float(i) / 255.0f;
        t.decode_[std::size_t(i)] = space == ColorSpace::Srgb ? srgb_to_linear(c) : c;
    }
    t.rgba8_.assign(rgba.begin(), rgba.end());
    for (std::size_t i = 3; i < t.rgba8_.size() && !t.translucent_; i += 4)
        t.translucent_ = t.rgba8_[i] != 255;
    t.sampling_ = sampling;
    return t;
}

template <class Texel, class Fetch>
Texel ImageTexture::filtered(glm::vec2 uv, const Fetch& fetch) const {
    if (!finite(uv)) return fetch(0);
    const auto at = [&](int x, int y) -> Texel {
        return fetch(std::size_t(y) * std::size_t(width_) + std::size_t(x));
    };
    // c is the coordinate with 0 at the image's first column / row, in texture widths;
    // `repeat_c` its fractional part as the report's lookup computed it (kept to the
    // operation, so map_Kd renders bit for bit as before).
    const auto axis = [&](float c, float repeat_c, int n, TextureWrap mode) -> Axis {
        if (sampling_.filter == TextureFilter::Nearest) {
            // The texel containing c: floor(c n), wrapped (c bounded first: no int overflow).
            float s;
            if (mode == TextureWrap::Repeat) {
                s = std::floor(repeat_c * float(n));
                return {std::min(int(s), n - 1), 0, 0.0f};
            }
            if (mode == TextureWrap::ClampToEdge) {
                s = std::floor(std::clamp(c, 0.0f, 1.0f) * float(n));
                return {std::min(int(s), n - 1), 0, 0.0f};
            }
            s = std::floor((c - 2.0f * std::floor(0.5f * c)) * float(n));
            return {mirror(int(s), n), 0, 0.0f};
        }
        // Continuous texel coordinates, texel centres at integer + 0.5.
        float s;
        if (mode == TextureWrap::Repeat)
            s = repeat_c * float(n) - 0.5f;
        else if (mode == TextureWrap::ClampToEdge)
            s = std::clamp(c, -1.0f, 2.0f) * float(n) - 0.5f;
        else
            s = (c - 2.0f * std::floor(0.5f * c)) * float(n) - 0.5f;  // c in [0, 2)
        const float fs = std::floor(s);
        const int i = int(fs);
        Axis a{i, i + 1, s - fs};
        if (mode == TextureWrap::Repeat) {
            a.i0 = wrap(a.i0, n);
            a.i1 = wrap(a.i1, n);
        } else if (mode == TextureWrap::ClampToEdge) {
            a.i0 = std::clamp(a.i0, 0, n - 1);
            a.i1 = std::clamp(a.i1, 0, n - 1);
        } else {
            a.i0 = mirror(a.i0, n);
            a.i1 = mirror(a.i1, n);
        }
        return a;
    };
    // Keep only the fractional part first, so huge coordinates do not overflow int; v
    // flipped (row 0 = top).
    const float u = uv.x - std::floor(uv.x);
    const float v = uv.y - std::floor(uv.y);
    const Axis ax = axis(uv.x, u, width_, sampling_.wrap_u);
    const Axis ay = axis(1.0f - uv.y, 1.0f - v, height_, sampling_.wrap_v);
    if (sampling_.filter == TextureFilter::Nearest) return at(ax.i0, ay.i0);
    const Texel top = (1.0f - ax.w1) * at(ax.i0, ay.i0) + ax.w1 * at(ax.i1, ay.i0);
    const Texel bottom = (1.0f - ax.w1) * at(ax.i0, ay.i1) + ax.w1 * at(ax.i1, ay.i1);
    return (1.0f - ay.w1) * top + ay.w1 * bottom;
}

namespace {

// The texel indices along one axis (n texels) that lookups at coordinates c in [c0, c1]
// (0 at the first column / row, in texture widths) may read: first and count of an index
// run before wrapping, or the whole axis when that run would cover it.
struct TexelRun {
    int first = 0;
    int count = 0;
};
TexelRun texel_run(float c0, float c1, int n, TextureWrap mode, TextureFilter filter) {
    const TexelRun whole{0, n};
    if (!std::isfinite(c0) || !std::isfinite(c1) || c1 - c0 >= 1.0f) return whole;
    if (mode == TextureWrap::ClampToEdge) {
        c0 = std::clamp(c0, -1.0f, 2.0f);
        c1 = std::clamp(c1, -1.0f, 2.0f);
    } else {
        // Shifted by whole periods (1, or 2 when mirrored) so that the indices stay small.
        const float period = mode == TextureWrap::Repeat ? 1.0f : 2.0f;
        const float shift = period * std::floor(c0 / period);
        c0 -= shift;
        c1 -= shift;
    }
    // Bilinear reads floor(c n - 0.5) and the next texel, nearest floor(c n); one texel
    // more on each side covers the rounding of both.
    const float half = filter == TextureFilter::Linear ? 0.5f : 0.0f;
    const int i0 = int(std::floor(c0 * float(n) - half)) - 1;
    const int i1 =
        int(std::floor(c1 * float(n) - half)) + (filter == TextureFilter::Linear ? 2 : 1);
    if (i1 - i0 + 1 >= n) return whole;
    return {i0, i1 - i0 + 1};
}

int wrapped(int i, int n, TextureWrap mode) {
    if (mode == TextureWrap::Repeat) return wrap(i, n);
    if (mode == TextureWrap::ClampToEdge) return std::clamp(i, 0, n - 1);
    return mirror(i, n);
}

}  // namespace

std::optional<glm::vec3> ImageTexture::max_over(glm::vec2 lo, glm::vec2 hi,
                                                std::size_t budget) const {
    if (empty()) return glm::vec3(0.0f);
    // Rows run down: v in [lo.y, hi.y] is c = 1 - v in [1 - hi.y, 1 - lo.y].
    const TexelRun x = texel_run(lo.x, hi.x, width_, sampling_.wrap_u, sampling_.filter);
    const TexelRun y =
        texel_run(1.0f - hi.y, 1.0f - lo.y, height_, sampling_.wrap_v, sampling_.filter);
    if (std::size_t(x.count) * std::size_t(y.count) > budget) return std::nullopt;
    // A non-finite uv reads texel (0, 0).
    const bool finite_box = finite(lo) && finite(hi);
    glm::vec3 m = finite_box ? glm::vec3(std::numeric_limits<float>::lowest()) : texel_at(0);
    for (int j = 0; j < y.count; ++j) {
        const int row = wrapped(y.first + j, height_, sampling_.wrap_v);
        for (int i = 0; i < x.count; ++i)
            m = glm::max(m, texel(wrapped(x.first + i, width_, sampling_.wrap_u), row));
    }
    return m;
}

glm::vec3 ImageTexture::lookup(glm::vec2 uv) const {
    if (empty()) return glm::vec3(0.0f);
    return filtered<glm::vec3>(uv, [this](std::size_t i) { return texel_at(i); });
}

float ImageTexture::lookup_alpha(glm::vec2 uv) const {
    if (!translucent_) return 1.0f;
    return filtered<float>(uv, [this](std::size_t i) { return float(rgba8_[4 * i + 3]) / 255.0f; });
}

glm::mat3x2 make_texture_transform(const TextureTransform& t, bool gltf_uvs) {
    // KHR_texture_transform: T(offset) R(rotation) S(scale). R as the implementations and
    // the extension's sample model use it, (1, 0) -> (cos, -sin): the extension's GLSL
    // listing has the transpose, a known erratum (KhronosGroup/glTF issue #1563).
    const float c = std::cos(t.rotation), s = std::sin(t.rotation);
    glm::mat3x2 m;  // glm: m[column][row]; uv' = m * (u, v, 1)
    m[0] = glm::vec2(c * t.scale.x, -s * t.scale.x);
    m[1] = glm::vec2(s * t.scale.y, c * t.scale.y);
    m[2] = t.offset;
    if (gltf_uvs) {
        // Then v' = 1 - v: glTF's v runs down, ImageTexture's up.
        m[0].y = -m[0].y;
        m[1].y = -m[1].y;
        m[2].y = 1.0f - m[2].y;
    }
    return m;
}

}  // namespace librt
