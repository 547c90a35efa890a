#pragma once

#include <librt/export.h>

#include <glm/mat3x2.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace librt {

/// What a lookup does outside [0, 1] along one axis (glTF sampler wrapS / wrapT).
enum class TextureWrap : std::uint8_t {
    Repeat,          ///< tiles the image (glTF REPEAT, 10497; the OBJ / MTL default)
    ClampToEdge,     ///< the edge texels continue outward (glTF CLAMP_TO_EDGE, 33071)
    MirroredRepeat,  ///< tiles, every other tile mirrored (glTF MIRRORED_REPEAT, 33648)
};

/// How texels are combined at a lookup.
enum class TextureFilter : std::uint8_t {
    Linear,   ///< bilinear between the four nearest texel centres (glTF LINEAR)
    Nearest,  ///< the texel containing the point (glTF NEAREST)
};

/// How texel bytes are turned into the linear values a renderer needs.
enum class ColorSpace : std::uint8_t {
    Srgb,    ///< colours (base colour, emission, map_Kd): the sRGB transfer function inverted
    Linear,  ///< data (metallic-roughness, normals, alpha): byte / 255 as it is
};

/// How an ImageTexture is sampled.
struct TextureSampling {
    TextureWrap wrap_u = TextureWrap::Repeat;      ///< along u (columns)
    TextureWrap wrap_v = TextureWrap::Repeat;      ///< along v (rows)
    TextureFilter filter = TextureFilter::Linear;  ///< between texels
};

/// An RGB(A) image a material looks up: linear floats (the constructor, for HDR data), or
/// 8-bit texels kept as 8 bits, 4 bytes a texel, and decoded through a 256-entry table of
/// their colour space at lookup (from_rgba8; io/texture_io.h load_texture reads one from a
/// file): a quarter of the floats' memory, the same values.
///
/// Lookups use OBJ texture coordinates: u runs left to right and v bottom to top (the
/// image's first row is v = 1); the texel centres sit at (i + 0.5) / width. Outside [0, 1]
/// the sampling's wrap modes apply (repeat by default), and the filter is bilinear between
/// the four nearest texel centres by default. (glTF's v runs down: a material's TextureSlot
/// flips it, see make_texture_transform.) No mipmaps: a path tracer's many samples per
/// pixel average what minification would.
class LIBRT_API ImageTexture {
public:
    ImageTexture() = default;
    /// A texture from linear texels in row-major order, top row first; throws
    /// librt::Error if the size is not positive or texels.size() != width * height.
    ImageTexture(int width, int height, std::vector<glm::vec3> linear_texels);

    /// A texture from 8-bit RGBA texels (row-major, top row first, 4 bytes each), kept as
    /// they are: RGB decoded by `space` at lookup, alpha always linear (a/255; has_alpha()
    /// only when some texel is below 255).
    /// Throws librt::Error if the size is not positive or rgba.size() != 4 width height.
    [[nodiscard]] static ImageTexture from_rgba8(int width, int height,
                                                 std::span<const std::uint8_t> rgba,
                                                 ColorSpace space,
                                                 const TextureSampling& sampling = {});

    /// Filtered linear RGB at texture coordinates uv (the sampling's wrap modes and
    /// filter; v up). A non-finite uv gives the texel at (0, 0) instead of NaN.
    [[nodiscard]] glm::vec3 lookup(glm::vec2 uv) const;
    /// Filtered alpha at uv, as lookup() filters colour; 1 when the texture has no alpha.
    [[nodiscard]] float lookup_alpha(glm::vec2 uv) const;

    /// Per channel, the largest texel any lookup() at a uv in the box [lo, hi] reads (the
    /// sampling's wrap modes and filter, one texel of margin for rounding): an upper bound
    /// of lookup() there, 0 where the box is black. Empty when more than `budget` texels
    /// would have to be read.
    [[nodiscard]] std::optional<glm::vec3> max_over(glm::vec2 lo, glm::vec2 hi,
                                                    std::size_t budget) const;
    /// The linear RGB of the texel in column x, row y (row 0 at the top), without wrapping.
    [[nodiscard]] glm::vec3 texel(int x, int y) const {
        return texel_at(std::size_t(y) * std::size_t(width_) + std::size_t(x));
    }
    [[nodiscard]] int width() const { return width_; }    ///< texels per row
    [[nodiscard]] int height() const { return height_; }  ///< number of rows
    /// True when default-made.
    [[nodiscard]] bool empty() const { return texels_.empty() && rgba8_.empty(); }
    /// True when the texture carries an alpha channel (some texel not opaque).
    [[nodiscard]] bool has_alpha() const { return translucent_; }
    /// True when the texels are kept as 8 bits (from_rgba8).
    [[nodiscard]] bool eight_bit() const { return !rgba8_.empty(); }
    /// Bytes the texels take: 12 a texel as floats, 4 as 8 bits.
    [[nodiscard]] std::size_t texel_bytes() const {
        return texels_.size() * sizeof(glm::vec3) + rgba8_.size();
    }
    /// How lookups wrap and filter.
    [[nodiscard]] const TextureSampling& sampling() const { return sampling_; }
    /// Changes how lookups wrap and filter.
    void set_sampling(const TextureSampling& sampling) { sampling_ = sampling; }

private:
    /// The two texels along one axis and the weight of the second, for coordinate c.
    struct Axis {
        int i0, i1;
        float w1;
    };
    /// Texel `i`'s linear RGB, from the floats or decoded from 8 bits.
    [[nodiscard]] glm::vec3 texel_at(std::size_t i) const {
        if (texels_.empty()) {
            const std::uint8_t* p = &rgba8_[4 * i];
            return {decode_[p[0]], decode_[p[1]], decode_[p[2]]};
        }
        return texels_[i];
    }
    /// The sampling's filter over the texels, each read by fetch(index).
    template <class Texel, class Fetch>
    Texel filtered(glm::vec2 uv, const Fetch& fetch) const;

    int width_ = 0;
    int height_ = 0;
    std::vector<glm::vec3> texels_;    ///< linear floats; empty when 8-bit
    std::vector<std::uint8_t> rgba8_;  ///< 8-bit RGBA, 4 bytes a texel; empty when floats
    std::array<float, 256> decode_{};  ///< 8-bit RGB value to linear (the colour space's)
    bool translucent_ = false;         ///< some 8-bit alpha below 255
    TextureSampling sampling_;
};

/// The KHR_texture_transform of a texture reference: uv' = T(offset) R(rotation) S(scale)
/// uv, in glTF's uv space (v down).
struct TextureTransform {
    glm::vec2 offset{0.0f};  ///< translation
    float rotation = 0.0f;   ///< radians; R maps (1, 0) to (cos, -sin) (see the .cpp)
    glm::vec2 scale{1.0f};   ///< per-axis scale
};

/// A material's use of a scene texture: which one, and the affine map from the mesh's uvs
/// to the texture's coordinates.
struct TextureSlot {
    std::int32_t texture = -1;    ///< scene texture id (Scene::add_texture); -1: none
    glm::mat3x2 transform{1.0f};  ///< uv -> texture coordinates (make_texture_transform)
    /// Which of a mesh's uv sets it reads: 0 TriangleMesh::uvs (and a sphere's uv), 1
    /// TriangleMesh::uvs1 (glTF's other TEXCOORD_n; (0, 0) where a mesh has none).
    std::uint8_t uv_set = 0;
    /// True when a texture is bound.
    [[nodiscard]] bool bound() const { return texture >= 0; }
    /// The texture coordinates of mesh uv `uv`.
    [[nodiscard]] glm::vec2 map(glm::vec2 uv) const { return transform * glm::vec3(uv, 1.0f); }
};

/// The affine map from a mesh's stored uvs to ImageTexture coordinates (what
/// TextureSlot::transform holds): the KHR_texture_transform `t` applied in glTF's uv space,
/// then v flipped (v' = 1 - v) when `gltf_uvs` (uvs stored as glTF states them, v down).
/// For OBJ uvs (already v up) and no transform, the identity.
[[nodiscard]] LIBRT_API glm::mat3x2 make_texture_transform(const TextureTransform& t,
                                                           bool gltf_uvs);

/// The sRGB transfer function inverted (IEC 61966-2-1): c / 12.92 below 0.04045, else
/// ((c + 0.055) / 1.055)^2.4, for c in [0, 1].
[[nodiscard]] LIBRT_API float srgb_to_linear(float c);

}  // namespace librt
