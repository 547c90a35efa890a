// The first two stages of load_gltf: the GLB container (header and chunk lengths), then a
// pre-pass over the JSON with nlohmann-json that checks what tinygltf would trust or read
// loosely (see check_json), so every such error names its JSON path.

#include "gltf/gltf_internal.h"

#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <system_error>

namespace librt::gltf_detail {

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr std::uint32_t kGlbMagic = 0x46546C67u;   // "glTF"
constexpr std::uint32_t kChunkJson = 0x4E4F534Au;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942u;   // "BIN\0"
constexpr std::size_t kGlbHeader = 12, kChunkHeader = 8;

std::uint32_t le32(const std::string& bytes, std::size_t at) {
    // GLB fields are little-endian.
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + at);
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8u | std::uint32_t(p[2]) << 16u |
           std::uint32_t(p[3]) << 24u;
}

/// The extensions whose absence would change the picture that librt reads.
const std::set<std::string, std::less<>>& supported_extensions() {
    static const std::set<std::string, std::less<>> names = {
        "KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_transmission",
        "KHR_materials_ior", "KHR_texture_transform", "KHR_mesh_quantization",
        "KHR_materials_anisotropy",
        // Compressed geometry and textures (gltf_draco.cpp, gltf_meshopt.cpp, texture loading).
        "KHR_draco_mesh_compression", "EXT_meshopt_compression", "EXT_texture_webp",
        "KHR_texture_basisu",
        // Layers on the metallic-roughness model, and unlit (gltf_material.cpp).
        "KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_specular",
        "KHR_materials_unlit", "KHR_materials_volume",
        // Instances of a mesh per node (gltf_nodes.cpp) and material variants (gltf_mesh.cpp).
        "EXT_mesh_gpu_instancing", "KHR_materials_variants",
        // Not rendered: kept through parsing so the warning can name each material.
        "KHR_materials_iridescence"};
    return names;
}

/// Keys tinygltf stores in an int: a larger JSON integer would wrap silently.
bool is_int_field(std::string_view key) {
    static const std::set<std::string, std::less<>> keys = {"bufferView", "buffer",
                                                            "index",      "source",
                                                            "sampler",    "texCoord",
                                                            "material",   "indices",
                                                            "mode",       "camera",
                                                            "mesh",       "skin",
                                                            "node",       "scene",
                                                            "light",      "componentType",
                                                            "minFilter",  "magFilter",
                                                            "wrapS",      "wrapT",
                                                            "input",      "output",
                                                            "width",      "height",
                                                            "skeleton",   "inverseBindMatrices"};
    return keys.count(key) != 0;
}

/// Keys of arrays (or objects) whose members tinygltf stores as ints.
bool is_int_container(std::string_view key) {
    return key == "children" || key == "nodes" || key == "joints" || key == "attributes" ||
           key == "targets";
}

/// Keys tinygltf reads as unsigned sizes (a negative value would be silently dropped).
bool is_size_field(std::string_view key) {
    return key == "byteLength" || key == "byteOffset" || key == "count" || key == "byteStride";
}

struct Frame {
    const Json* value;
    std::string path;
    int depth;
    bool free_form;           // inside extras or an extension: only the depth matters
    bool ints;                // members must be ints (children, attributes...)
    bool sparse;              // inside accessor.sparse: sizes are ints there
    bool extensions = false;  // an object's "extensions" member itself
};

/// One pass over the whole document without recursion: nesting depth, integers that
/// tinygltf would truncate or drop, and extension values that are not objects (the schema's
/// glTFProperty.extensions holds objects; tinygltf skips any other value without a word,
/// so a supported extension written as a number or an array would vanish unnoticed).
void check_structure(const Json& root, const Context& ctx) {
    std::vector<Frame> stack{{&root, "", 1, false, false, false, false}};
    // A member's path, built only when needed (an error, or a container to visit).
    auto member_path = [](const Frame& parent, bool is_object, const std::string& key,
                          std::size_t i) {
        if (!is_object) return parent.path + "[" + std::to_string(i) + "]";
        return parent.path.empty() ? key : parent.path + "." + key;
    };
    auto check_leaf = [&](const Json& v, const Frame& parent, bool is_object,
                          const std::string& key, std::size_t i) {
        if (parent.free_form || !v.is_number()) return;
        auto path = [&] { return member_path(parent, is_object, key, i); };
        const bool int_field = parent.ints || is_int_field(key) ||
                               (parent.sparse && (key == "count" || key == "byteOffset"));
        const bool size_field = !int_field && is_size_field(key);
        if (!int_field && !size_field) return;
        if (v.is_number_float()) {
            ctx.fail(path(), "expected an integer, found " + v.dump());
        }
        if (v.is_number_unsigned()) {
            const auto u = v.get<std::uint64_t>();
            const std::uint64_t limit = int_field ? std::uint64_t(std::numeric_limits<int>::max())
                                                  : (std::uint64_t{1} << 53u);
            if (u > limit) ctx.fail(path(), v.dump() + " is too large");
        } else if (size_field) {
            ctx.fail(path(), v.dump() + ": must not be negative");
        } else if (v.get<std::int64_t>() < std::numeric_limits<int>::min()) {
            ctx.fail(path(), v.dump() + " is too small");
        }
    };
    while (!stack.empty()) {
        const Frame frame = std::move(stack.back());
        stack.pop_back();
        if (frame.depth > kMaxJsonDepth) {
            ctx.fail(frame.path,
                     "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        }
        const bool is_object = frame.value->is_object();
        std::size_t i = 0;
        for (auto it = frame.value->begin(); it != frame.value->end(); ++it, ++i) {
            static const std::string no_key;
            const std::string& key = is_object ? it.key() : no_key;
            const Json& child = *it;
            const bool extensions_member = is_object && !frame.free_form && key == "extensions";
            const bool read_extension = frame.extensions && supported_extensions().count(key) != 0;
            if ((extensions_member || read_extension) && !child.is_object())
                ctx.fail(member_path(frame, true, key, i),
                         "must be a JSON object, found " + std::string(child.type_name()));
            if (child.is_structured()) {
                const bool free_form =
                    frame.free_form || (is_object && (key == "extras" || key == "extensions"));
                stack.push_back({&child, member_path(frame, is_object, key, i), frame.depth + 1,
                                 free_form, is_object && is_int_container(key),
                                 frame.sparse || (is_object && key == "sparse"),
                                 extensions_member});
            } else {
                check_leaf(child, frame, is_object, key, i);
            }
        }
    }
}

/// Integers of the extensions whose members tinygltf stores as int (a larger value would
/// wrap silently there): EXT_meshopt_compression's and KHR_draco_mesh_compression's, and
/// the whole of EXT_mesh_gpu_instancing's and KHR_materials_variants' (accessor, material
/// and variant indices, nested in objects and arrays).
void check_extension_ints(const Json& doc, const Context& ctx) {
    const auto beyond_int = [](const Json& v) {
        if (!v.is_number_integer()) return false;
        return v.is_number_unsigned()
                   ? v.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<int>::max())
                   : v.get<std::int64_t>() < std::numeric_limits<int>::min();
    };
    // Every integer below `root`, at any depth (bounded: check_structure ran first).
    const auto check_all = [&](const Json& root, const std::string& root_path) {
        std::vector<std::pair<const Json*, std::string>> stack{{&root, root_path}};
        while (!stack.empty()) {
            const auto [value, path] = std::move(stack.back());
            stack.pop_back();
            std::size_t i = 0;
            for (auto it = value->begin(); it != value->end(); ++it, ++i) {
                const std::string at =
                    value->is_object() ? path + "." + it.key() : indexed(path, i);
                if (beyond_int(*it)) ctx.fail(at, it->dump() + " is too large");
                if (it->is_structured()) stack.emplace_back(&*it, at);
            }
        }
    };
    const auto extension_tree = [&](const Json& owner, const char* name, const std::string& path) {
        if (!owner.is_object()) return;
        const auto ext = owner.find("extensions");
        if (ext == owner.end() || !ext->is_object()) return;
        const auto e = ext->find(name);
        if (e != ext->end() && e->is_structured())
            check_all(*e, (path.empty() ? "" : path + ".") + "extensions." + name);
    };
    extension_tree(doc, "KHR_materials_variants", "");
    if (const auto nodes = doc.find("nodes"); nodes != doc.end() && nodes->is_array())
        for (std::size_t i = 0; i < nodes->size(); ++i)
            extension_tree((*nodes)[i], "EXT_mesh_gpu_instancing", indexed("nodes", i));
    // Members, and members of member objects (KHR_draco_mesh_compression.attributes).
    const auto check = [&](const Json& object, const std::string& path) {
        for (auto it = object.begin(); it != object.end(); ++it) {
            const std::string at = path + "." + it.key();
            if (beyond_int(*it)) ctx.fail(at, it->dump() + " is too large");
            if (!it->is_object()) continue;
            for (auto a = it->begin(); a != it->end(); ++a)
                if (beyond_int(*a)) ctx.fail(at + "." + a.key(), a->dump() + " is too large");
        }
    };
    const auto extension = [&](const Json& owner, const char* name, const std::string& path) {
        if (!owner.is_object()) return;
        const auto ext = owner.find("extensions");
        if (ext == owner.end() || !ext->is_object()) return;
        const auto e = ext->find(name);
        if (e != ext->end() && e->is_object()) check(*e, path + ".extensions." + name);
    };
    if (const auto views = doc.find("bufferViews"); views != doc.end() && views->is_array())
        for (std::size_t i = 0; i < views->size(); ++i)
            extension((*views)[i], "EXT_meshopt_compression", indexed("bufferViews", i));
    if (const auto meshes = doc.find("meshes"); meshes != doc.end() && meshes->is_array()) {
        for (std::size_t m = 0; m < meshes->size(); ++m) {
            const Json& mesh = (*meshes)[m];
            const auto prims = mesh.is_object() ? mesh.find("primitives") : mesh.end();
            if (!mesh.is_object() || prims == mesh.end() || !prims->is_array()) continue;
            for (std::size_t p = 0; p < prims->size(); ++p) {
                const std::string path = indexed(indexed("meshes", m) + ".primitives", p);
                extension((*prims)[p], "KHR_draco_mesh_compression", path);
                extension_tree((*prims)[p], "KHR_materials_variants", path);
            }
        }
    }
}

void check_asset_and_extensions(const Json& doc, const Context& ctx) {
    const auto asset = doc.find("asset");
    if (asset == doc.end() || !asset->is_object())
        ctx.fail("asset", "missing: not a glTF 2.0 file");
    const auto version = asset->find("version");
    if (version == asset->end() || !version->is_string())
        ctx.fail("asset.version", "missing: not a glTF 2.0 file");
    const std::string v = version->get<std::string>();
    if (v.rfind("2.", 0) != 0)
        ctx.fail("asset.version", quote_untrusted(v) + ": only glTF 2.x is read");
    if (const auto min = asset->find("minVersion"); min != asset->end()) {
        if (!min->is_string() || min->get<std::string>() != "2.0")
            ctx.fail("asset.minVersion", min->dump() + ": only glTF 2.0 is read");
    }
    for (const char* list : {"extensionsRequired", "extensionsUsed"}) {
        const auto names = doc.find(list);
        if (names == doc.end()) continue;
        if (!names->is_array()) ctx.fail(list, "must be an array of names");
        const bool required = std::strcmp(list, "extensionsRequired") == 0;
        for (std::size_t i = 0; i < names->size(); ++i) {
            const Json& name = (*names)[i];
            const std::string path = indexed(list, i);
            if (!name.is_string()) ctx.fail(path, "must be a string");
            const std::string n = name.get<std::string>();
            if (supported_extensions().count(n) != 0) continue;
            if (required)
                ctx.fail(path,
                         "extension " + quote_untrusted(n) + " is required but not supported");
            // Required ones are listed in extensionsUsed too: warn only for the optional.
            const auto req = doc.find("extensionsRequired");
            const bool also_required = req != doc.end() && req->is_array() &&
                                       std::find(req->begin(), req->end(), n) != req->end();
            if (!also_required)
                ctx.warn(path, "extension " + quote_untrusted(n) + " is not supported; ignored");
        }
    }
}

/// Decoded size of a base64 payload (RFC 4648: 3 bytes per 4 characters, less padding).
std::uint64_t base64_size(std::string_view payload) {
    std::uint64_t n = payload.size();
    std::uint64_t pad = 0;
    while (pad < 2 && pad < n && payload[n - 1 - pad] == '=') ++pad;
    return n / 4 * 3 + (n % 4 == 0 ? 0 : (n % 4) * 3 / 4) - pad;
}

/// Whether a buffer is EXT_meshopt_compression's fallback: `"fallback": true`, no data.
bool meshopt_fallback(const Json& buffer) {
    const auto ext = buffer.find("extensions");
    if (ext == buffer.end() || !ext->is_object()) return false;
    const auto m = ext->find("EXT_meshopt_compression");
    if (m == ext->end() || !m->is_object()) return false;
    const auto f = m->find("fallback");
    return f != m->end() && f->is_boolean() && f->get<bool>();
}

/// byteLength of every buffer, checked against its source, whose place is recorded in
/// facts.buffers (each distinct external file counted once in facts.external_bytes).
std::vector<std::uint64_t> check_buffers(const Json& doc, const Container& container,
                                         const std::string& base_dir, const LoadLimits& limits,
                                         const Context& ctx, JsonFacts& facts) {
    std::vector<std::uint64_t> lengths;
    const auto buffers = doc.find("buffers");
    if (buffers == doc.end()) return lengths;
    if (!buffers->is_array()) ctx.fail("buffers", "must be an array");
    std::set<std::string, std::less<>> files_counted;
    for (std::size_t i = 0; i < buffers->size(); ++i) {
        const Json& b = (*buffers)[i];
        const std::string path = indexed("buffers", i);
        if (!b.is_object()) ctx.fail(path, "must be an object");
        const auto len = b.find("byteLength");
        if (len == b.end() || !len->is_number_unsigned())
            ctx.fail(path + ".byteLength", "missing or not a non-negative integer");
        const std::uint64_t byte_length = len->get<std::uint64_t>();
        lengths.push_back(byte_length);
        BufferSource source;
        source.byte_length = byte_length;
        const auto uri = b.find("uri");
        if (uri == b.end() && meshopt_fallback(b)) {
            // EXT_meshopt_compression: a buffer that only stands for the decoded views'
            // bytes and holds none (its views are decoded from another buffer).
            source.kind = BufferSource::Kind::Data;
            facts.buffers.push_back(std::move(source));
            continue;
        }
        if (uri == b.end()) {
            if (!container.binary || i != 0)
                ctx.fail(path, "has no uri (only a .glb's first buffer may omit it)");
            if (!container.has_bin) ctx.fail(path, "has no uri and the .glb has no BIN chunk");
            if (byte_length > container.bin.size()) {
                ctx.fail(path + ".byteLength", std::to_string(byte_length) +
                                                   " exceeds the .glb's BIN chunk of " +
                                                   std::to_string(container.bin.size()) + " bytes");
            }
            facts.buffers.push_back(std::move(source));
            continue;
        }
        if (!uri->is_string()) ctx.fail(path + ".uri", "must be a string");
        const std::string u = uri->get<std::string>();
        if (u.rfind("data:", 0) == 0) {
            if (!tinygltf::IsDataURI(u)) {
                ctx.fail(path + ".uri",
                         "a data: URI must be base64 application/octet-stream "
                         "or application/gltf-buffer");
            }
            const std::uint64_t got = base64_size(std::string_view(u).substr(u.find(',') + 1));
            if (got != byte_length) {
                ctx.fail(path, "byteLength " + std::to_string(byte_length) +
                                   " but its data: URI holds " + std::to_string(got) + " bytes");
            }
            source.kind = BufferSource::Kind::Data;
            std::string mime;
            if (!tinygltf::DecodeDataURI(&source.data, mime, u, byte_length, true))
                ctx.fail(path + ".uri", "its base64 data does not decode");
            facts.buffers.push_back(std::move(source));
            continue;
        }
        const std::string where = path + ".uri";
        const std::string file =
            file_in_scene_tree(base_dir, u, limits.allow_outside_files, where, ctx);
        if (const std::string why = not_regular_reason(file); !why.empty())
            ctx.fail(where, quote_untrusted(u) + " (" + quote_untrusted(file) + "): " + why);
        std::error_code ec;
        const std::uint64_t size = fs::file_size(file, ec);
        if (ec) ctx.fail(where, quote_untrusted(u) + ": " + ec.message());
        if (size > limits.max_file_bytes) {
            ctx.fail(where, quote_untrusted(u) + ": " + std::to_string(size) +
                                " bytes, more than the limit of " +
                                std::to_string(limits.max_file_bytes));
        }
        if (size < byte_length) {
            ctx.fail(path, "byteLength " + std::to_string(byte_length) + " but " +
                               quote_untrusted(u) + " has only " + std::to_string(size) + " bytes");
        }
        if (files_counted.insert(file).second) facts.external_bytes += size;
        source.kind = BufferSource::Kind::File;
        source.file = file;
        facts.buffers.push_back(std::move(source));
    }
    return lengths;
}

/// Where each image's bytes are (facts.images); an external file must lie in the scene's
/// tree (an error), while one that is missing or not a file is only recorded (a warning
/// when a texture uses it, as a viewer shows the model without that texture).
void check_images(const Json& doc, const std::string& base_dir, const LoadLimits& limits,
                  const Context& ctx, JsonFacts& facts) {
    const auto images = doc.find("images");
    if (images == doc.end()) return;
    if (!images->is_array()) ctx.fail("images", "must be an array");
    for (std::size_t i = 0; i < images->size(); ++i) {
        const Json& img = (*images)[i];
        const std::string path = indexed("images", i);
        if (!img.is_object()) ctx.fail(path, "must be an object");
        ImageSource source;
        if (const auto name = img.find("name"); name != img.end() && name->is_string())
            source.name = name->get<std::string>();
        const auto uri = img.find("uri");
        const auto view = img.find("bufferView");
        if ((uri == img.end()) == (view == img.end()))
            ctx.fail(path, "must have exactly one of uri and bufferView");
        if (view != img.end()) {
            if (!view->is_number_integer()) ctx.fail(path + ".bufferView", "must be an integer");
            source.buffer_view = view->get<int>();
        } else {
            if (!uri->is_string()) ctx.fail(path + ".uri", "must be a string");
            const std::string u = uri->get<std::string>();
            if (u.rfind("data:", 0) == 0) {
                std::string mime;
                if (!tinygltf::IsDataURI(u) ||
                    !tinygltf::DecodeDataURI(&source.data, mime, u, 0, false))
                    source.unreadable = "its data: URI is not base64 image data";
            } else {
                source.uri = u;
                source.file =
                    file_in_scene_tree(base_dir, u, limits.allow_outside_files, path + ".uri", ctx);
                source.unreadable = not_regular_reason(source.file);
                if (!source.unreadable.empty()) source.file.clear();
            }
        }
        facts.images.push_back(std::move(source));
    }
}

void check_buffer_views(const Json& doc, const std::vector<std::uint64_t>& buffer_lengths,
                        const Context& ctx) {
    const auto views = doc.find("bufferViews");
    if (views == doc.end()) return;
    if (!views->is_array()) ctx.fail("bufferViews", "must be an array");
    for (std::size_t i = 0; i < views->size(); ++i) {
        const Json& v = (*views)[i];
        const std::string path = indexed("bufferViews", i);
        if (!v.is_object()) ctx.fail(path, "must be an object");
        const auto buffer = v.find("buffer");
        if (buffer == v.end() || !buffer->is_number_integer())
            ctx.fail(path + ".buffer", "missing or not an integer");
        check_index(ctx, path + ".buffer", buffer->get<int>(), buffer_lengths.size(), "buffer");
        const auto len = v.find("byteLength");
        if (len == v.end() || !len->is_number_unsigned() || len->get<std::uint64_t>() == 0)
            ctx.fail(path + ".byteLength", "missing or not a positive integer");
        std::uint64_t offset = 0;
        if (const auto o = v.find("byteOffset"); o != v.end()) {
            if (!o->is_number_unsigned())
                ctx.fail(path + ".byteOffset", "not a non-negative integer");
            offset = o->get<std::uint64_t>();
        }
        const std::uint64_t length = len->get<std::uint64_t>();
        const std::uint64_t available = buffer_lengths[buffer->get<std::size_t>()];
        // Both are below 2^53 (check_structure), so the sum cannot overflow.
        if (offset + length > available) {
            ctx.fail(path, "bytes [" + std::to_string(offset) + ", " +
                               std::to_string(offset + length) + ") lie outside buffers[" +
                               std::to_string(buffer->get<int>()) + "] (byteLength " +
                               std::to_string(available) + ")");
        }
        if (const auto s = v.find("byteStride"); s != v.end()) {
            if (!s->is_number_unsigned())
                ctx.fail(path + ".byteStride", "not a non-negative integer");
            const std::uint64_t stride = s->get<std::uint64_t>();
            if (stride < 4 || stride > 252 || stride % 4 != 0)
                ctx.fail(path + ".byteStride",
                         std::to_string(stride) + ": must be a multiple of 4 in [4, 252]");
        }
    }
    const auto images = doc.find("images");
    if (images == doc.end() || !images->is_array()) return;
    for (std::size_t i = 0; i < images->size(); ++i) {
        const Json& img = (*images)[i];
        if (!img.is_object()) continue;
        if (const auto bv = img.find("bufferView"); bv != img.end() && bv->is_number_integer())
            check_index(ctx, indexed("images", i) + ".bufferView", bv->get<int>(), views->size(),
                        "buffer view");
    }
}

}  // namespace

Container split_container(const std::string& bytes, const Context& ctx) {
    Container c;
    if (bytes.size() < 4 || le32(bytes, 0) != kGlbMagic) {
        // Not a .glb: it must be JSON text, an object (after optional BOM and spaces).
        std::size_t first = bytes.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
        first = bytes.find_first_not_of(" \t\r\n", first);
        if (first == std::string::npos || bytes[first] != '{')
            ctx.fail("", "not a glTF file: neither a .glb (magic 'glTF') nor JSON text");
        c.json = bytes;
        return c;
    }
    c.binary = true;
    if (bytes.size() < kGlbHeader + kChunkHeader) {
        ctx.fail("", "truncated .glb: " + std::to_string(bytes.size()) +
                         " bytes, less than the 20 of its header and first chunk header");
    }
    const std::uint32_t version = le32(bytes, 4), length = le32(bytes, 8);
    if (version != 2) ctx.fail("", ".glb version " + std::to_string(version) + ": only 2 is read");
    if (length > bytes.size()) {
        ctx.fail("", "truncated .glb: its header declares " + std::to_string(length) +
                         " bytes, the file has " + std::to_string(bytes.size()));
    }
    if (length < bytes.size()) {
        ctx.warn("", std::to_string(bytes.size() - length) +
                         " bytes after the .glb's declared length ignored");
    }
    c.length = length;
    // Chunk 0 must be JSON; a BIN chunk may follow. Each: u32 length, u32 type, payload.
    const std::uint64_t json_length = le32(bytes, 12);
    if (le32(bytes, 16) != kChunkJson) ctx.fail("", ".glb chunk 0 is not of type JSON");
    if (kGlbHeader + kChunkHeader + json_length > length) {
        ctx.fail("", ".glb chunk 0 (JSON) declares " + std::to_string(json_length) +
                         " bytes but only " + std::to_string(length - 20) +
                         " follow: truncated, or a wrong chunk length");
    }
    if (json_length == 0 || json_length % 4 != 0) {
        ctx.fail("", ".glb chunk 0 (JSON) length " + std::to_string(json_length) +
                         " is not a positive multiple of 4");
    }
    c.json = std::string_view(bytes).substr(20, json_length);
    const std::uint64_t bin_at = 20 + json_length;
    if (bin_at == length) return c;
    if (bin_at + kChunkHeader > length) ctx.fail("", "truncated .glb: chunk 1 header cut short");
    const std::uint64_t bin_length = le32(bytes, bin_at);
    if (le32(bytes, bin_at + 4) != kChunkBin) ctx.fail("", ".glb chunk 1 is not of type BIN");
    if (bin_at + kChunkHeader + bin_length > length) {
        ctx.fail("", ".glb chunk 1 (BIN) declares " + std::to_string(bin_length) +
                         " bytes but only " + std::to_string(length - bin_at - kChunkHeader) +
                         " follow: truncated, or a wrong chunk length");
    }
    if (bin_length == 0 || bin_length % 4 != 0) {
        ctx.fail("", ".glb chunk 1 (BIN) length " + std::to_string(bin_length) +
                         " is not a positive multiple of 4");
    }
    c.has_bin = true;
    c.bin = std::string_view(bytes).substr(bin_at + kChunkHeader, bin_length);
    return c;
}

namespace {

/// Builds the JSON tree through nlohmann's SAX interface, leaving out what librt never
/// reads (every "extras", and extensions it does not support) so that free-form payloads
/// cost no memory, and counting the tree's bytes as it grows: the parse fails before its
/// tree passes the limit. The byte model is that of nlohmann::json on a 64-bit libstdc++
/// (16-byte values; a std::map node of 80 bytes, rounded by malloc to 96, per object
/// member; vectors that may hold twice their size; strings past the 15-byte SSO on the heap).
class PrunedTreeBuilder {
public:
    PrunedTreeBuilder(const Context& ctx, std::uint64_t limit) : ctx_(ctx), limit_(limit) {}

    bool null() { return value(Json(nullptr)); }
    bool boolean(bool v) { return value(Json(v)); }
    bool number_integer(Json::number_integer_t v) { return value(Json(v)); }
    bool number_unsigned(Json::number_unsigned_t v) { return value(Json(v)); }
    bool number_float(Json::number_float_t v, const std::string&) { return value(Json(v)); }
    bool string(std::string& v) {
        if (skipping()) return end_skipped_scalar();
        charge(48 + heap_string(v.size()));
        return value(Json(std::move(v)));
    }
    bool binary(Json::binary_t&) { return value(Json(nullptr)); }  // not produced by JSON text
    bool start_object(std::size_t) { return start(Json::object(), 64); }
    bool start_array(std::size_t) { return start(Json::array(), 32); }
    bool end_object() { return end(); }
    bool end_array() { return end(); }
    bool key(std::string& k) {
        if (skip_depth_ > 0) return true;
        const Frame& parent = frames_.back();
        // Extras are free-form application data; an unsupported extension is ignored.
        skip_next_ = k == "extras" || (parent.extensions && supported_extensions().count(k) == 0);
        key_ = std::move(k);
        return true;
    }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& e) {
        // "[json.exception.parse_error.101] parse error at line 3, column 7: ..." -> from
        // "parse", the offending token made printable and short by Error.
        std::string what = e.what();
        if (const auto at = what.find("] "); at != std::string::npos) what.erase(0, at + 2);
        ctx_.fail("", "broken JSON: " + what);
    }

    /// The tree, without what was left out.
    Json take() { return std::move(root_); }
    /// Its estimated bytes.
    [[nodiscard]] std::uint64_t bytes() const { return bytes_; }

private:
    struct Frame {
        Json* node;       // the object or array being filled
        std::string key;  // its key in its parent (or "[i]")
        bool extensions;  // an "extensions" object: its members are extension names
    };

    static std::uint64_t heap_string(std::size_t n) { return n > 15 ? n + 1 : 0; }
    bool skipping() const { return skip_depth_ > 0 || skip_next_; }
    bool end_skipped_scalar() {
        if (skip_depth_ == 0) skip_next_ = false;
        return true;
    }
    void charge(std::uint64_t b) {
        bytes_ += b;
        if (bytes_ > limit_)
            ctx_.fail(path(), "the JSON takes more than the " + std::to_string(limit_) +
                                  " bytes of memory that loading this file may use (" +
                                  "GltfLoadOptions::max_memory_bytes)");
    }
    std::string path() const {
        std::string p;
        for (std::size_t i = 1; i < frames_.size(); ++i) {
            const std::string& k = frames_[i].key;
            if (!p.empty() && k[0] != '[') p += '.';
            p += k;
        }
        return p;
    }
    /// Adds v to the current container, returning where it now lives.
    Json* place(Json v) {
        if (frames_.empty()) {
            root_ = std::move(v);
            return &root_;
        }
        Json& parent = *frames_.back().node;
        if (parent.is_array()) {
            charge(32);
            parent.push_back(std::move(v));
            return &parent.back();
        }
        charge(96 + heap_string(key_.size()));
        Json& slot = parent[key_];
        slot = std::move(v);
        return &slot;
    }
    bool value(Json v) {
        if (skipping()) return end_skipped_scalar();
        place(std::move(v));
        return true;
    }
    bool start(Json v, std::uint64_t cost) {
        if (skip_depth_ > 0 || skip_next_) {
            skip_next_ = false;
            ++skip_depth_;
            return true;
        }
        if (frames_.size() + 1 > std::size_t(kMaxJsonDepth)) {
            ctx_.fail(path(),
                      "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        }
        std::string key;
        if (!frames_.empty())
            key = frames_.back().node->is_array()
                      ? "[" + std::to_string(frames_.back().node->size()) + "]"
                      : key_;
        const bool extensions =
            !frames_.empty() && frames_.back().node->is_object() && key_ == "extensions";
        charge(cost);
        Json* node = place(std::move(v));
        frames_.push_back({node, std::move(key), extensions});
        return true;
    }
    bool end() {
        if (skip_depth_ > 0) {
            --skip_depth_;
            return true;
        }
        frames_.pop_back();
        return true;
    }

    const Context& ctx_;
    std::uint64_t limit_;
    std::uint64_t bytes_ = 0;
    Json root_;
    std::vector<Frame> frames_;
    std::string key_;
    bool skip_next_ = false;  // the next value is left out
    int skip_depth_ = 0;      // containers open inside a left-out value
};

/// Counts of what tinygltf's Model holds for the tree, times its types' sizes: the bytes
/// the Model takes (an estimate: each JSON value stored costs at most 24 more bytes).
std::uint64_t model_bytes(const Json& doc, std::uint64_t tree_bytes) {
    auto count = [&](const char* key) -> std::uint64_t {
        const auto it = doc.find(key);
        return it != doc.end() && it->is_array() ? it->size() : 0;
    };
    std::uint64_t primitives = 0;
    if (const auto meshes = doc.find("meshes"); meshes != doc.end() && meshes->is_array())
        for (const Json& m : *meshes)
            if (const auto p = m.find("primitives"); m.is_object() && p != m.end() && p->is_array())
                primitives += p->size();
    using namespace tinygltf;
    return count("nodes") * sizeof(Node) + count("meshes") * sizeof(Mesh) +
           primitives * sizeof(Primitive) + count("accessors") * sizeof(Accessor) +
           count("bufferViews") * sizeof(BufferView) + count("buffers") * sizeof(Buffer) +
           count("materials") * sizeof(Material) + count("textures") * sizeof(Texture) +
           count("images") * sizeof(Image) + count("samplers") * sizeof(Sampler) +
           count("cameras") * sizeof(Camera) + count("scenes") * sizeof(Scene) +
           count("skins") * sizeof(Skin) + count("animations") * sizeof(Animation) +
           tree_bytes * 3 / 2;
}

/// The tree as tinygltf is given it: buffers and images replaced by stand-ins that make
/// it read nothing (their bytes are in JsonFacts). A Draco primitive's indices accessor
/// has no buffer view, which tinygltf 2.7 refuses: it is moved into the extension object
/// as "librtIndices" (where decode_draco reads it; any such member there is replaced).
std::string tinygltf_text(Json& doc) {
    if (const auto meshes = doc.find("meshes"); meshes != doc.end() && meshes->is_array()) {
        for (Json& mesh : *meshes) {
            const auto prims = mesh.find("primitives");
            if (!mesh.is_object() || prims == mesh.end() || !prims->is_array()) continue;
            for (Json& prim : *prims) {
                if (!prim.is_object()) continue;
                const auto ext = prim.find("extensions");
                if (ext == prim.end() || !ext->is_object()) continue;
                const auto draco = ext->find("KHR_draco_mesh_compression");
                if (draco == ext->end() || !draco->is_object()) continue;
                draco->erase("librtIndices");
                if (const auto indices = prim.find("indices"); indices != prim.end()) {
                    (*draco)["librtIndices"] = *indices;
                    prim.erase(indices);
                }
            }
        }
    }
    if (const auto buffers = doc.find("buffers"); buffers != doc.end()) {
        for (Json& b : *buffers)
            b = Json{{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
    }
    if (const auto images = doc.find("images"); images != doc.end())
        for (Json& img : *images) img = Json{{"uri", "librt-reads-this-image-itself"}};
    return doc.dump();
}

}  // namespace

JsonFacts check_json(const Container& container, const std::string& base_dir,
                     const LoadLimits& limits, const Context& ctx) {
    JsonFacts facts;
    Json doc;
    std::uint64_t tree_bytes = 0;
    {
        PrunedTreeBuilder builder(ctx, limits.memory);
        try {
            Json::sax_parse(container.json.begin(), container.json.end(), &builder);
        } catch (const Json::exception& e) {
            ctx.fail("", std::string("broken JSON: ") + e.what());
        }
        doc = builder.take();
        tree_bytes = builder.bytes();
    }
    if (!doc.is_object()) ctx.fail("", "not a glTF file: the JSON is not an object");
    try {
        check_structure(doc, ctx);
        check_asset_and_extensions(doc, ctx);
        check_extension_ints(doc, ctx);
        const auto lengths = check_buffers(doc, container, base_dir, limits, ctx, facts);
        check_buffer_views(doc, lengths, ctx);
        check_images(doc, base_dir, limits, ctx, facts);
        facts.model_bytes = model_bytes(doc, tree_bytes);
        facts.tinygltf_json = tinygltf_text(doc);
    } catch (const Json::exception& e) {
        // A member of an unexpected JSON type that a check above did not test first.
        ctx.fail("", std::string("unexpected JSON: ") + e.what());
    }
    // tinygltf's parse holds its own tree of the text (no larger than ours) and the Model.
    facts.tinygltf_bytes = tree_bytes + facts.model_bytes + facts.tinygltf_json.size();
    return facts;
}

}  // namespace librt::gltf_detail
