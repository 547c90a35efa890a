// Materials (metallic-roughness and the KHR_materials_* / KHR_texture_transform extensions
// librt reads), textures, samplers and image decoding (stb_image for PNG and JPEG, libwebp
// for WebP).

#include "gltf/gltf_internal.h"
#include "io/image_decode_failure.h"
#include "io/png_check.h"

#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>

#include <stb/stb_image.h>
#include <webp/decode.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <string>

namespace librt::gltf_detail {

namespace {

using tinygltf::ExtensionMap;
using tinygltf::Value;

/// A finite number in [lo, hi]; out-of-range values are clamped with a warning.
float unit_factor(double v, float lo, float hi, const std::string& path, const Context& ctx) {
    if (!std::isfinite(v)) ctx.fail(path, "is not finite");
    if (v < lo || v > hi) {
        ctx.warn(path, number_text(v) + " outside [" + number_text(lo) + ", " + number_text(hi) +
                           "]; clamped");
        v = std::clamp(v, double(lo), double(hi));
    }
    return float(v);
}

/// An optional number member of an extension object.
bool ext_number(const Value& ext, const char* key, double* out) {
    if (!ext.IsObject() || !ext.Has(key) || !ext.Get(key).IsNumber()) return false;
    *out = ext.Get(key).GetNumberAsDouble();
    return true;
}

/// KHR_texture_transform of a texture info's extensions, when present.
void read_transform(const ExtensionMap& extensions, GltfTextureRef& ref, const std::string& path,
                    const Context& ctx) {
    const auto it = extensions.find("KHR_texture_transform");
    if (it == extensions.end()) return;
    const Value& t = it->second;
    const std::string at = path + ".extensions.KHR_texture_transform";
    ref.has_transform = true;
    auto vec2 = [&](const char* key, glm::vec2& out) {
        if (!t.IsObject() || !t.Has(key)) return;
        const Value& v = t.Get(key);
        if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber())
            ctx.fail(at + "." + key, "must be 2 numbers");
        out = glm::vec2(float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble()));
        if (!std::isfinite(out.x) || !std::isfinite(out.y))
            ctx.fail(at + "." + key, "is not finite");
    };
    vec2("offset", ref.transform.offset);
    vec2("scale", ref.transform.scale);
    double rotation = 0.0;
    if (ext_number(t, "rotation", &rotation)) {
        ref.transform.rotation = finite_float(rotation, at + ".rotation", ctx);
    }
    if (t.IsObject() && t.Has("texCoord")) {
        if (!t.Get("texCoord").IsInt()) ctx.fail(at + ".texCoord", "must be an integer");
        ref.tex_coord = t.Get("texCoord").Get<int>();
    }
}

/// `scale` is normalTexture.scale or occlusionTexture.strength (`scale_key` names it), 1
/// for the others.
GltfTextureRef texture_ref(int index, int tex_coord, double scale, const ExtensionMap& extensions,
                           const std::string& path, std::size_t texture_count, const Context& ctx,
                           const char* scale_key = "scale") {
    GltfTextureRef ref;
    if (index == -1) return ref;
    check_index(ctx, path + ".index", index, texture_count, "texture");
    ref.texture = index;
    ref.tex_coord = tex_coord;
    ref.scale = finite_float(scale, path + "." + scale_key, ctx);
    read_transform(extensions, ref, path, ctx);
    if (ref.tex_coord < 0 || ref.tex_coord > 1) {
        ctx.warn(path + ".texCoord", std::to_string(ref.tex_coord) +
                                         ": only TEXCOORD_0 and _1 are read; texture ignored");
        ref = GltfTextureRef{};
    }
    return ref;
}

/// The texture info `key` of an extension object (KHR_materials_transmission's
/// transmissionTexture, KHR_materials_anisotropy's anisotropyTexture), or none; with
/// `normal`, a normalTextureInfo whose optional "scale" (default 1) is read too.
GltfTextureRef ext_texture(const Value& ext, const char* key, const std::string& path,
                           std::size_t textures, const Context& ctx, bool normal = false) {
    if (!ext.IsObject() || !ext.Has(key)) return {};
    const std::string at = path + "." + key;
    const Value& t = ext.Get(key);
    if (!t.IsObject() || !t.Has("index") || !t.Get("index").IsInt())
        ctx.fail(at + ".index", "missing or not an integer");
    const int tc =
        t.Has("texCoord") && t.Get("texCoord").IsInt() ? t.Get("texCoord").Get<int>() : 0;
    ExtensionMap nested;
    if (t.Has("extensions") && t.Get("extensions").IsObject())
        for (const std::string& k : t.Get("extensions").Keys())
            nested[k] = t.Get("extensions").Get(k);
    double scale = 1.0;
    if (normal && t.Has("scale")) {
        if (!t.Get("scale").IsNumber()) ctx.fail(at + ".scale", "must be a number");
        scale = t.Get("scale").GetNumberAsDouble();
    }
    return texture_ref(t.Get("index").Get<int>(), tc, scale, nested, at, textures, ctx);
}

/// An optional number member `key` of the extension object at `at`: false when absent,
/// an error naming the path when not a finite number.
bool ext_member(const Value& ext, const std::string& at, const char* key, double* out,
                const Context& ctx) {
    if (!ext.Has(key)) return false;
    const Value& v = ext.Get(key);
    if (!v.IsNumber()) ctx.fail(at + "." + key, "must be a number");
    *out = v.GetNumberAsDouble();
    if (!std::isfinite(*out)) ctx.fail(at + "." + key, "is not finite");
    return true;
}

/// An optional array of 3 numbers `key` of the extension object at `at`, each in [lo, hi]
/// (clamped with a warning); an error naming the path when malformed.
void ext_color(const Value& ext, const std::string& at, const char* key, float lo, float hi,
               glm::vec3& out, const Context& ctx) {
    if (!ext.Has(key)) return;
    const Value& v = ext.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 3) ctx.fail(at + "." + key, "must be 3 numbers");
    for (int i = 0; i < 3; ++i) {
        const Value& c = v.Get(i);
        const std::string ci = indexed(at + "." + key, std::size_t(i));
        if (!c.IsNumber()) ctx.fail(ci, "must be a number");
        out[i] = unit_factor(c.GetNumberAsDouble(), lo, hi, ci, ctx);
    }
}

/// The PBR extensions layered on the metallic-roughness model (KHR_materials_clearcoat,
/// _sheen, _specular, _unlit, _iridescence) read into g; `ep` is the material's
/// "materials[i].extensions." path.
void read_layer_extensions(const ExtensionMap& extensions, const std::string& ep,
                           std::size_t textures, const Context& ctx, GltfMaterial& g) {
    const auto object = [&](const char* name) -> const Value* {
        const auto it = extensions.find(name);
        if (it == extensions.end()) return nullptr;
        if (!it->second.IsObject()) ctx.fail(ep + name, "must be an object");
        return &it->second;
    };
    double v = 0.0;
    if (object("KHR_materials_unlit") != nullptr) g.unlit = true;
    if (object("KHR_materials_iridescence") != nullptr) g.iridescence = true;
    if (const Value* e = object("KHR_materials_clearcoat")) {
        const std::string at = ep + "KHR_materials_clearcoat";
        if (ext_member(*e, at, "clearcoatFactor", &v, ctx))
            g.clearcoat_factor = unit_factor(v, 0, 1, at + ".clearcoatFactor", ctx);
        if (ext_member(*e, at, "clearcoatRoughnessFactor", &v, ctx))
            g.clearcoat_roughness_factor =
                unit_factor(v, 0, 1, at + ".clearcoatRoughnessFactor", ctx);
        g.clearcoat_texture = ext_texture(*e, "clearcoatTexture", at, textures, ctx);
        g.clearcoat_roughness_texture =
            ext_texture(*e, "clearcoatRoughnessTexture", at, textures, ctx);
        g.clearcoat_normal_texture =
            ext_texture(*e, "clearcoatNormalTexture", at, textures, ctx, true);
    }
    if (const Value* e = object("KHR_materials_sheen")) {
        const std::string at = ep + "KHR_materials_sheen";
        ext_color(*e, at, "sheenColorFactor", 0, 1, g.sheen_color_factor, ctx);
        if (ext_member(*e, at, "sheenRoughnessFactor", &v, ctx))
            g.sheen_roughness_factor = unit_factor(v, 0, 1, at + ".sheenRoughnessFactor", ctx);
        g.sheen_color_texture = ext_texture(*e, "sheenColorTexture", at, textures, ctx);
        g.sheen_roughness_texture = ext_texture(*e, "sheenRoughnessTexture", at, textures, ctx);
    }
    if (const Value* e = object("KHR_materials_volume")) {
        const std::string at = ep + "KHR_materials_volume";
        if (ext_member(*e, at, "thicknessFactor", &v, ctx)) {
            if (v < 0) ctx.fail(at + ".thicknessFactor", number_text(v) + ": must be >= 0");
            g.thickness_factor = finite_float(v, at + ".thicknessFactor", ctx);
        }
        g.thickness_texture = ext_texture(*e, "thicknessTexture", at, textures, ctx);
        if (ext_member(*e, at, "attenuationDistance", &v, ctx)) {
            if (!(v > 0)) ctx.fail(at + ".attenuationDistance", number_text(v) + ": must be > 0");
            g.attenuation_distance = finite_float(v, at + ".attenuationDistance", ctx);
        }
        ext_color(*e, at, "attenuationColor", 0, 1, g.attenuation_color, ctx);
    }
    if (const Value* e = object("KHR_materials_specular")) {
        const std::string at = ep + "KHR_materials_specular";
        if (ext_member(*e, at, "specularFactor", &v, ctx))
            g.specular_factor = unit_factor(v, 0, 1, at + ".specularFactor", ctx);
        // The extension allows any colour >= 0 (F0 is clamped to 1 where it is used).
        ext_color(*e, at, "specularColorFactor", 0, std::numeric_limits<float>::max(),
                  g.specular_color_factor, ctx);
        g.specular_texture = ext_texture(*e, "specularTexture", at, textures, ctx);
        g.specular_color_texture = ext_texture(*e, "specularColorTexture", at, textures, ctx);
    }
}

GltfMaterial read_material(const tinygltf::Material& m, const std::string& path,
                           std::size_t textures, const Context& ctx) {
    GltfMaterial g;
    g.name = m.name;
    const auto& pbr = m.pbrMetallicRoughness;
    const std::string pp = path + ".pbrMetallicRoughness";
    if (pbr.baseColorFactor.size() != 4) ctx.fail(pp + ".baseColorFactor", "must have 4 numbers");
    for (int i = 0; i < 4; ++i)
        g.base_color_factor[i] = unit_factor(pbr.baseColorFactor[std::size_t(i)], 0, 1,
                                             indexed(pp + ".baseColorFactor", std::size_t(i)), ctx);
    g.base_color_texture =
        texture_ref(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, 1.0,
                    pbr.baseColorTexture.extensions, pp + ".baseColorTexture", textures, ctx);
    g.metallic_factor = unit_factor(pbr.metallicFactor, 0, 1, pp + ".metallicFactor", ctx);
    g.roughness_factor = unit_factor(pbr.roughnessFactor, 0, 1, pp + ".roughnessFactor", ctx);
    const auto& mr = pbr.metallicRoughnessTexture;
    g.metallic_roughness_texture = texture_ref(mr.index, mr.texCoord, 1.0, mr.extensions,
                                               pp + ".metallicRoughnessTexture", textures, ctx);
    const auto& nt = m.normalTexture;
    g.normal_texture = texture_ref(nt.index, nt.texCoord, nt.scale, nt.extensions,
                                   path + ".normalTexture", textures, ctx);
    const auto& ot = m.occlusionTexture;
    g.occlusion_texture = texture_ref(ot.index, ot.texCoord, ot.strength, ot.extensions,
                                      path + ".occlusionTexture", textures, ctx, "strength");
    if (m.emissiveFactor.size() != 3) ctx.fail(path + ".emissiveFactor", "must have 3 numbers");
    for (int i = 0; i < 3; ++i)
        g.emissive_factor[i] = unit_factor(m.emissiveFactor[std::size_t(i)], 0, 1,
                                           indexed(path + ".emissiveFactor", std::size_t(i)), ctx);
    const auto& et = m.emissiveTexture;
    g.emissive_texture = texture_ref(et.index, et.texCoord, 1.0, et.extensions,
                                     path + ".emissiveTexture", textures, ctx);
    if (m.alphaMode == "OPAQUE")
        g.alpha_mode = GltfAlphaMode::Opaque;
    else if (m.alphaMode == "MASK")
        g.alpha_mode = GltfAlphaMode::Mask;
    else if (m.alphaMode == "BLEND")
        g.alpha_mode = GltfAlphaMode::Blend;
    else
        ctx.fail(path + ".alphaMode",
                 quote_untrusted(m.alphaMode) + ": must be OPAQUE, MASK or BLEND");
    if (!std::isfinite(m.alphaCutoff) || m.alphaCutoff < 0)
        ctx.fail(path + ".alphaCutoff", "must be finite and >= 0");
    g.alpha_cutoff = finite_float(m.alphaCutoff, path + ".alphaCutoff", ctx);
    g.double_sided = m.doubleSided;

    const std::string ep = path + ".extensions.";
    double v = 0.0;
    if (const auto it = m.extensions.find("KHR_materials_emissive_strength");
        it != m.extensions.end() && ext_number(it->second, "emissiveStrength", &v)) {
        const std::string at = ep + "KHR_materials_emissive_strength.emissiveStrength";
        if (!std::isfinite(v) || v < 0) ctx.fail(at, "must be finite and >= 0");
        g.emissive_strength = finite_float(v, at, ctx);
    }
    if (const auto it = m.extensions.find("KHR_materials_transmission"); it != m.extensions.end()) {
        const std::string tp = ep + "KHR_materials_transmission";
        if (ext_number(it->second, "transmissionFactor", &v))
            g.transmission_factor = unit_factor(v, 0, 1, tp + ".transmissionFactor", ctx);
        g.transmission_texture = ext_texture(it->second, "transmissionTexture", tp, textures, ctx);
    }
    if (const auto it = m.extensions.find("KHR_materials_anisotropy"); it != m.extensions.end()) {
        const std::string ap = ep + "KHR_materials_anisotropy";
        const Value& a = it->second;
        if (!a.IsObject()) ctx.fail(ap, "must be an object");
        const auto number = [&](const char* key, double* out) {
            if (!a.Has(key)) return false;
            const Value& number_value = a.Get(key);
            if (!number_value.IsNumber()) ctx.fail(ap + "." + key, "must be a number");
            *out = number_value.GetNumberAsDouble();
            if (!std::isfinite(*out)) ctx.fail(ap + "." + key, "is not finite");
            return true;
        };
        if (number("anisotropyStrength", &v))
            g.anisotropy_strength = unit_factor(v, 0, 1, ap + ".anisotropyStrength", ctx);
        if (number("anisotropyRotation", &v))
            g.anisotropy_rotation = finite_float(v, ap + ".anisotropyRotation", ctx);
        g.anisotropy_texture = ext_texture(a, "anisotropyTexture", ap, textures, ctx);
    }
    read_layer_extensions(m.extensions, ep, textures, ctx, g);
    if (const auto it = m.extensions.find("KHR_materials_ior");
        it != m.extensions.end() && ext_number(it->second, "ior", &v)) {
        // The extension allows 0 (a reflection-only limit) or >= 1.
        if (!std::isfinite(v) || (v != 0.0 && v < 1.0))
            ctx.fail(ep + "KHR_materials_ior.ior", number_text(v) + ": must be 0 or >= 1");
        g.ior = finite_float(v, ep + "KHR_materials_ior.ior", ctx);
    }
    return g;
}

GltfWrap wrap_mode(int mode, const std::string& path, const Context& ctx) {
    switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT:
            return GltfWrap::Repeat;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return GltfWrap::ClampToEdge;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return GltfWrap::MirroredRepeat;
        default:
            ctx.fail(path, std::to_string(mode) + " is not a glTF wrap mode");
    }
}

GltfFilter filter_mode(int mode, const std::string& path, const Context& ctx) {
    switch (mode) {
        case -1:
            return GltfFilter::Unset;
        case TINYGLTF_TEXTURE_FILTER_NEAREST:
            return GltfFilter::Nearest;
        case TINYGLTF_TEXTURE_FILTER_LINEAR:
            return GltfFilter::Linear;
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
            return GltfFilter::NearestMipmapNearest;
        case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST:
            return GltfFilter::LinearMipmapNearest;
        case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
            return GltfFilter::NearestMipmapLinear;
        case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR:
            return GltfFilter::LinearMipmapLinear;
        default:
            ctx.fail(path, std::to_string(mode) + " is not a glTF filter");
    }
}

/// The image texture `t` shows: EXT_texture_webp's source when present (librt decodes
/// WebP), else `source`. KHR_texture_basisu's KTX2 images have no decoder in Debian: its
/// fallback `source` is used with a warning, and without one the file cannot be rendered
/// as meant, which is an error naming the texture.
int texture_source(const tinygltf::Texture& t, const std::string& path, std::size_t images,
                   const Context& ctx) {
    const auto ext_source = [&](const char* name) {
        const auto it = t.extensions.find(name);
        if (it == t.extensions.end()) return -2;  // absent
        const std::string at = path + ".extensions." + name + ".source";
        const Value& e = it->second;
        if (!e.IsObject() || !e.Has("source") || !e.Get("source").IsInt())
            ctx.fail(at, "missing or not an integer");
        const int index = e.Get("source").Get<int>();
        check_index(ctx, at, index, images, "image");
        return index;
    };
    if (t.source != -1) check_index(ctx, path + ".source", t.source, images, "image");
    if (const int webp = ext_source("EXT_texture_webp"); webp >= 0) return webp;
    if (ext_source("KHR_texture_basisu") >= 0) {
        if (t.source == -1)
            ctx.fail(path + ".extensions.KHR_texture_basisu",
                     "KHR_texture_basisu (a KTX2 / Basis Universal image) cannot be decoded by "
                     "librt, and the texture has no fallback PNG or JPEG source");
        ctx.warn(path, "KHR_texture_basisu (KTX2) is not decoded; its fallback source images[" +
                           std::to_string(t.source) + "] is used");
    }
    return t.source;
}

/// Most texels an image may decode to: 2^26 (ImageTexture's limit: 8192 x 8192).
constexpr std::uint64_t kMaxTexels = std::uint64_t{1} << 26u;

/// Decodes a WebP image into RGBA8, or returns the reason it cannot. WebPGetInfo reads
/// only the header: the size is bounded and charged before any texel is decoded.
std::string decode_webp(const unsigned char* bytes, std::size_t size, GltfImage& image,
                        Context& ctx, const std::string& path) {
    int w = 0, h = 0;
    if (WebPGetInfo(bytes, size, &w, &h) == 0 || w <= 0 || h <= 0)
        return "not a valid WebP image (its header does not parse)";
    const std::uint64_t texels = std::uint64_t(w) * std::uint64_t(h);
    if (texels > kMaxTexels)
        return std::to_string(w) + " x " + std::to_string(h) + " texels, more than the limit";
    ctx.spend(texels * 4, path);
    image.rgba.assign(texels * 4, 0);
    // Decoded into our own buffer: libwebp allocates nothing beyond its working state.
    if (WebPDecodeRGBAInto(bytes, size, image.rgba.data(), image.rgba.size(), w * 4) == nullptr) {
        std::vector<unsigned char>().swap(image.rgba);
        return "cannot decode: corrupt or truncated WebP data";
    }
    image.width = w;
    image.height = h;
    return {};
}

/// Decodes PNG, JPEG or WebP bytes into RGBA8, or returns the reason it cannot.
std::string decode(const unsigned char* bytes, std::size_t size, GltfImage& image, Context& ctx,
                   const std::string& path) {
    const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0;
    const bool jpeg = size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
    // WebP (EXT_texture_webp, or an image whose mimeType is image/webp): "RIFF" size "WEBP".
    if (size >= 12 && std::memcmp(bytes, "RIFF", 4) == 0 && std::memcmp(bytes + 8, "WEBP", 4) == 0)
        return decode_webp(bytes, size, image, ctx, path);
    if (!png && !jpeg) return "not a PNG, JPEG or WebP image";
    if (size > std::size_t(std::numeric_limits<int>::max())) return "larger than 2 GiB";
    int w = 0, h = 0, channels = 0;
    const std::string_view encoded(reinterpret_cast<const char*>(bytes), size);
    if (stbi_info_from_memory(bytes, int(size), &w, &h, &channels) == 0 || w <= 0 || h <= 0)
        return "cannot decode: " + detail::image_decode_failure(encoded);
    const std::uint64_t texels = std::uint64_t(w) * std::uint64_t(h);
    if (texels > kMaxTexels)
        return std::to_string(w) + " x " + std::to_string(h) + " texels, more than the limit";
    // A PNG is judged by its decoded size alone (the budget, below): stb inflates its
    // data to the size the header gives and fails when the zlib stream ends short, so a
    // small file claiming a big image costs no decoding, and a valid one (8192^2 1-bit
    // texels deflate to 8 KB) must not be refused for compressing well. stb's JPEG
    // decoder reads zeros past the end of its data instead and decodes a truncated file
    // to a wrong image at the claimed size's cost: for JPEG a claim of more than 4096
    // texels per byte is refused as corrupt (as in load_texture).
    if (jpeg && texels > 4096u * std::uint64_t(size) + 65536u)
        return "its header claims more texels than the data can hold";
    // A PNG whose stream inflates past its header is refused before stb would grow its
    // buffer for it. The inflated data stb holds while decoding (1/32 of the output for a
    // 1-bit grey image, 3/4 for 8-bit RGB) is transient and not charged: charging it would
    // refuse a valid 8192^2 image of a few kilobytes, whose output alone fills the
    // 256 MiB every file is allowed (docs/robustness.md).
    if (png) {
        const detail::PngDataCheck check = detail::check_png_data(encoded);
        if (!check.problem.empty()) return check.problem;
    }
    ctx.spend(texels * 4, path);
    std::unique_ptr<stbi_uc, void (*)(void*)> data(
        stbi_load_from_memory(bytes, int(size), &w, &h, &channels, 4), stbi_image_free);
    if (!data) return "cannot decode: " + detail::image_decode_failure(encoded);
    image.width = w;
    image.height = h;
    image.rgba.assign(data.get(), data.get() + texels * 4);
    return {};
}

}  // namespace

void read_materials(const tinygltf::Model& model, const std::vector<ImageSource>& images,
                    Context& ctx, GltfScene& scene) {
    for (const ImageSource& source : images) {
        GltfImage image;
        image.name = source.name;
        image.uri = source.uri;
        scene.images.push_back(std::move(image));
    }
    for (std::size_t i = 0; i < model.textures.size(); ++i) {
        const tinygltf::Texture& t = model.textures[i];
        const std::string path = indexed("textures", i);
        GltfTexture g;
        g.name = t.name;
        const int source = texture_source(t, path, model.images.size(), ctx);
        if (source == -1) {
            ctx.warn(path, "no source image (or only an unsupported extension's); texture ignored");
        } else {
            g.image = source;
        }
        if (t.sampler != -1) {
            check_index(ctx, path + ".sampler", t.sampler, model.samplers.size(), "sampler");
            const tinygltf::Sampler& s = model.samplers[std::size_t(t.sampler)];
            const std::string sp = indexed("samplers", std::size_t(t.sampler));
            g.wrap_s = wrap_mode(s.wrapS, sp + ".wrapS", ctx);
            g.wrap_t = wrap_mode(s.wrapT, sp + ".wrapT", ctx);
            g.mag_filter = filter_mode(s.magFilter, sp + ".magFilter", ctx);
            g.min_filter = filter_mode(s.minFilter, sp + ".minFilter", ctx);
        }
        scene.textures.push_back(std::move(g));
    }
    for (std::size_t i = 0; i < model.materials.size(); ++i)
        scene.materials.push_back(
            read_material(model.materials[i], indexed("materials", i), model.textures.size(), ctx));
}

void decode_images(const tinygltf::Model& model, const std::vector<ImageSource>& sources,
                   const LoadLimits& limits, Context& ctx, GltfScene& scene) {
    std::vector<unsigned char> used(sources.size(), 0);
    for (const GltfTexture& t : scene.textures)
        if (t.image >= 0) used[std::size_t(t.image)] = 1;
    std::vector<unsigned char> ok(sources.size(), 0);
    // The first image that names each file: a file is read and decoded once, however
    // many images name it, and textures of the others use that first image.
    std::map<std::string, std::size_t> first_of_file;
    std::vector<std::size_t> same_as(sources.size());
    for (std::size_t i = 0; i < sources.size(); ++i) {
        same_as[i] = i;
        if (!used[i] || sources[i].file.empty()) continue;
        const auto [it, fresh] = first_of_file.emplace(sources[i].file, i);
        if (!fresh) same_as[i] = it->second;
    }
    for (std::size_t i = 0; i < sources.size(); ++i) {
        if (!used[i] || same_as[i] != i) continue;
        const ImageSource& source = sources[i];
        const std::string path = indexed("images", i);
        std::string problem = source.unreadable;
        std::string file_bytes;
        std::string_view encoded;
        if (!problem.empty()) {
            if (!source.uri.empty()) problem = quote_untrusted(source.uri) + ": " + problem;
        } else if (source.buffer_view >= 0) {
            check_index(ctx, path + ".bufferView", source.buffer_view, model.bufferViews.size(),
                        "buffer view");
            // Its buffer exists and the view lies in it (the pre-pass checked both).
            const tinygltf::BufferView& bv = model.bufferViews[std::size_t(source.buffer_view)];
            const std::string_view buffer = ctx.buffer(std::size_t(bv.buffer));
            if (const auto* decoded = ctx.view_bytes(std::size_t(source.buffer_view)))
                encoded = std::string_view(reinterpret_cast<const char*>(decoded->data()),
                                           bv.byteLength);  // meshopt: >= byteLength bytes
            else if (bv.byteOffset > buffer.size() || bv.byteLength > buffer.size() - bv.byteOffset)
                problem = "its buffer view lies outside the buffer";
            else
                encoded = buffer.substr(bv.byteOffset, bv.byteLength);
        } else if (!source.file.empty()) {
            try {
                file_bytes = read_regular_file(source.file, limits.max_file_bytes);
                encoded = file_bytes;
                // A file read raises the memory bound as much as it raises what is held.
                if (limits.grow_with_reads) ctx.add_budget(kMemoryPerByteRead * file_bytes.size());
            } catch (const Error& e) {
                problem = e.what();
            }
        } else {
            encoded = std::string_view(reinterpret_cast<const char*>(source.data.data()),
                                       source.data.size());
        }
        if (problem.empty() && encoded.empty()) problem = "no image data";
        if (problem.empty())
            problem = decode(reinterpret_cast<const unsigned char*>(encoded.data()), encoded.size(),
                             scene.images[i], ctx, path);
        if (problem.empty()) {
            ok[i] = 1;
            // A file the image came from, listed once even when a buffer names it too.
            const auto listed = [&](const FileRead& f) { return f.path == source.file; };
            if (!file_bytes.empty() &&
                std::none_of(scene.files_read.begin(), scene.files_read.end(), listed))
                scene.files_read.push_back({source.file, digest_of(file_bytes)});
        } else {
            ctx.warn(path, problem + "; textures using it are ignored (factors alone)");
        }
    }
    for (GltfTexture& t : scene.textures) {
        if (t.image < 0) continue;
        const std::size_t first = same_as[std::size_t(t.image)];
        t.image = ok[first] ? int(first) : -1;
    }
}

}  // namespace librt::gltf_detail
