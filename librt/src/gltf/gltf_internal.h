#pragma once

// Private pieces of load_gltf (librt/gltf/gltf.h), one stage a file:
//   gltf_file.cpp       reading bytes (the one function that touches the file system)
//   gltf_container.cpp  GLB container checks, then a JSON pre-pass on nlohmann-json
//   gltf_accessor.cpp   accessors -> floats / indices, range-checked before allocating
//   gltf_mesh.cpp       primitives -> triangles
//   gltf_nodes.cpp      node tree -> instances, cameras, lights
//   gltf_material.cpp   materials, textures, samplers, image decoding
//   gltf.cpp            load_gltf: the stages in order
// tinygltf types never leave librt/src.

#include "io/file_io.h"

#include <librt/gltf/gltf.h>

#include <tiny_gltf.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace librt::gltf_detail {

/// The whole of a regular file, at most max_bytes. Stats the path before opening it, so
/// FIFOs, devices, sockets and directories are refused (named in the librt::Error)
/// without blocking. The single place glTF loading reads files: a shared io helper can
/// replace it.
[[nodiscard]] std::string read_regular_file(const std::filesystem::path& path,
                                            std::uint64_t max_bytes);

/// Where errors and warnings go, and the allowance of decoded bytes left.
class Context {
public:
    /// Errors and warnings name `file`; warnings are appended to *warnings.
    Context(std::string file, std::vector<std::string>* warnings)
        : file_(std::move(file)), warnings_(warnings) {}
    /// Throws librt::Error "file: json_path: what" (without the path part when empty).
    [[noreturn]] void fail(std::string_view json_path, std::string_view what) const;
    /// Appends the warning "file: json_path: what".
    void warn(std::string_view json_path, std::string_view what) const;
    /// Takes `bytes` from the allowance of decoded output, or fails naming json_path: the
    /// loader's memory stays a bounded multiple of the bytes it read.
    void spend(std::uint64_t bytes, std::string_view json_path);
    /// Sets the allowance of decoded output in bytes.
    void set_budget(std::uint64_t bytes) { budget_ = bytes; }
    /// Adds to the allowance (a file read raises the memory bound).
    void add_budget(std::uint64_t bytes) { budget_ += bytes; }
    /// The file name used in messages.
    [[nodiscard]] const std::string& file() const { return file_; }
    /// Sets the bytes of each buffers[i] (views into memory that outlives the Context).
    void set_buffers(std::vector<std::string_view> buffers) { buffers_ = std::move(buffers); }
    /// The bytes of buffers[index] (index checked by the caller).
    [[nodiscard]] std::string_view buffer(std::size_t index) const { return buffers_[index]; }
    /// How many buffers there are.
    [[nodiscard]] std::size_t buffer_count() const { return buffers_.size(); }
    /// Sets the decoded bytes of bufferViews[view] (EXT_meshopt_compression), read instead
    /// of its buffer's bytes.
    void set_view_bytes(std::size_t view, std::vector<unsigned char> bytes) {
        decoded_views_[view] = std::move(bytes);
    }
    /// The decoded bytes of bufferViews[view], or null when it is read from its buffer.
    [[nodiscard]] const std::vector<unsigned char>* view_bytes(std::size_t view) const {
        const auto it = decoded_views_.find(view);
        return it == decoded_views_.end() ? nullptr : &it->second;
    }

private:
    std::string file_;
    std::vector<std::string>* warnings_;
    std::uint64_t budget_ = 0;
    std::vector<std::string_view> buffers_;
    std::map<std::size_t, std::vector<unsigned char>> decoded_views_;
};

/// The file's bytes seen as glTF: the JSON text and, for a .glb, its BIN chunk.
struct Container {
    bool binary = false;       ///< a .glb
    std::string_view json;     ///< the JSON text (a view into the file's bytes)
    std::string_view bin;      ///< the GLB BIN chunk's payload; empty when absent
    bool has_bin = false;      ///< the GLB has a BIN chunk
    std::uint64_t length = 0;  ///< the GLB's declared length (<= the file's size)
};

/// Splits the bytes into JSON and BIN, checking a .glb's header and chunk lengths.
[[nodiscard]] Container split_container(const std::string& bytes, const Context& ctx);

/// Where one buffer's bytes come from. tinygltf never reads a file: librt reads each
/// distinct file once (load_gltf) and accessors read the bytes through Context::buffer.
struct BufferSource {
    /// The source's kind.
    enum class Kind {
        Bin,   ///< the .glb's BIN chunk
        File,  ///< an external file, `file`
        Data,  ///< a data: URI, decoded into `data`; or no bytes at all for the
               ///< EXT_meshopt_compression fallback buffer (`data` empty)
    };
    Kind kind = Kind::Bin;            ///< where the bytes are
    std::string file;                 ///< Kind::File: canonical path, inside the scene's tree
    std::vector<unsigned char> data;  ///< Kind::Data: the decoded bytes
    std::uint64_t byte_length = 0;    ///< the buffer's byteLength (checked against the source)
};

/// Where one image's encoded bytes come from (at most one of file, buffer_view, data).
struct ImageSource {
    std::string name;                 ///< its name, may be empty
    std::string uri;                  ///< its uri as written, when external (not data:)
    std::string file;                 ///< canonical path of that file when it can be read
    std::string unreadable;           ///< why an external uri cannot be read, else empty
    int buffer_view = -1;             ///< its bufferView, else -1
    std::vector<unsigned char> data;  ///< the bytes of a data: URI
};

/// Limits of one load, from GltfLoadOptions.
struct LoadLimits {
    std::uint64_t max_file_bytes = 0;  ///< largest file read
    bool allow_outside_files = false;  ///< files outside the scene's directory may be read
    std::uint64_t memory = 0;          ///< bytes the JSON stages may take (see check_json)
    bool grow_with_reads = true;       ///< each file read raises the bound (no fixed bound)
};

/// The default memory bound of a load: kMemoryPerByteRead times the bytes of the files it
/// reads, plus kMemoryBaseline (the library's one bound, io/file_io.h).
inline constexpr std::uint64_t kMemoryPerByteRead = detail::kLoadMemoryPerByteRead;
/// See kMemoryPerByteRead.
inline constexpr std::uint64_t kMemoryBaseline = detail::kLoadMemoryBaseline;

/// What the JSON pre-pass learned, and the JSON that tinygltf parses.
struct JsonFacts {
    /// The document as tinygltf reads it: no extras, no unsupported extensions, every
    /// buffer a one-byte data: URI and every image an unreadable name (their bytes come
    /// from `buffers` and `images`), so tinygltf never touches a file.
    std::string tinygltf_json;
    std::vector<BufferSource> buffers;  ///< one per buffers[i]
    std::vector<ImageSource> images;    ///< one per images[i]
    std::uint64_t external_bytes = 0;   ///< bytes of the distinct external buffer files
    /// Estimated peak bytes of tinygltf's parse of tinygltf_json (its JSON tree and Model).
    std::uint64_t tinygltf_bytes = 0;
    /// Estimated bytes of the Model that stays while librt decodes it.
    std::uint64_t model_bytes = 0;
};

/// Checks what tinygltf trusts or reads loosely, with JSON paths in the errors: the JSON
/// parses to an object, is nested at most kMaxJsonDepth deep, asset.version is 2.x, every
/// extensionsRequired entry is supported (extensionsUsed-only unknowns are warnings),
/// integers fit the fields tinygltf stores them in, external buffers and images lie in the
/// scene's directory tree (unless allowed), buffers exist and are large enough, buffer
/// views lie inside their buffers. Extras and unsupported extensions are dropped while
/// parsing, and the parse fails before its tree passes limits.memory.
[[nodiscard]] JsonFacts check_json(const Container& container, const std::string& base_dir,
                                   const LoadLimits& limits, const Context& ctx);

/// The canonical path of the file a relative URI names from `base_dir`, refused (failing
/// at json_path) when it is absolute, has a scheme, or leads outside base_dir's tree
/// through "..", or a symlink, unless allow_outside. The file need not exist.
[[nodiscard]] std::string file_in_scene_tree(const std::string& base_dir, std::string_view uri,
                                             bool allow_outside, const std::string& json_path,
                                             const Context& ctx);

/// "a directory", "a FIFO"... for a path that is not a regular file; empty for a regular
/// file; "no such file" when it does not exist.
[[nodiscard]] std::string not_regular_reason(const std::string& path);

/// Deepest JSON nesting accepted (tinygltf converts extras and extensions recursively).
inline constexpr int kMaxJsonDepth = 64;

/// Percent-decodes a URI reference into a relative path ("a%20b.png" -> "a b.png").
[[nodiscard]] std::string decode_uri(std::string_view uri);

/// A number as messages show it: six significant digits, exponent when large or small
/// ("1e+300", "0.5"), where std::to_string would print 301 digits or "0.000000".
[[nodiscard]] inline std::string number_text(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

/// `v` as a float, or a failure naming json_path when it is not finite or does not fit a
/// float (|v| > 3.4e38 would become infinite, a value that the double parsed as finite).
[[nodiscard]] inline float finite_float(double v, const std::string& json_path,
                                        const Context& ctx) {
    if (!std::isfinite(v)) ctx.fail(json_path, "is not finite");
    if (!std::isfinite(float(v)))
        ctx.fail(json_path, number_text(v) + ": beyond the float range (|value| <= 3.4e38)");
    return float(v);
}

/// "accessors[7]" and friends.
[[nodiscard]] std::string indexed(std::string_view array, std::size_t index);

/// A check that `index` refers into an array of `count` objects; fails naming json_path.
void check_index(const Context& ctx, std::string_view json_path, int index, std::size_t count,
                 std::string_view what);

/// Reads accessor `index` as `components` floats per element (normalised integers
/// converted, sparse values applied). `types` lists the accepted glTF types
/// (TINYGLTF_TYPE_*). json_path names the use (e.g. "meshes[0].primitives[1].attributes.
/// NORMAL"). Returns count * components floats; *components_out gets the element's
/// component count.
[[nodiscard]] std::vector<float> read_float_accessor(const tinygltf::Model& model, int index,
                                                     const std::vector<int>& types,
                                                     const std::string& json_path, Context& ctx,
                                                     int* components_out);

/// Reads accessor `index` as unsigned indices (SCALAR u8/u16/u32).
[[nodiscard]] std::vector<std::uint32_t> read_index_accessor(const tinygltf::Model& model,
                                                             int index,
                                                             const std::string& json_path,
                                                             Context& ctx);

/// Element count of accessor `index` (validated by check_index first).
[[nodiscard]] std::size_t accessor_count(const tinygltf::Model& model, int index);

/// Decodes every buffer view carrying EXT_meshopt_compression into the Context
/// (Context::view_bytes), checking mode, count, byteStride and filter and charging the
/// decoded bytes before allocating them. Errors name bufferViews[i].extensions.
/// EXT_meshopt_compression.
void decode_meshopt_views(const tinygltf::Model& model, Context& ctx);

/// What a KHR_draco_mesh_compression primitive decodes to: each attribute the extension
/// names, as count x components floats (the accessor's type), and the triangle indices.
struct DracoPrimitive {
    std::map<std::string, std::vector<float>, std::less<>> attributes;  ///< by glTF name
    std::vector<std::uint32_t> indices;                                 ///< 3 per triangle
};

/// Whether the primitive carries KHR_draco_mesh_compression.
[[nodiscard]] bool has_draco(const tinygltf::Primitive& prim);

/// Decodes the primitive's Draco stream. Its claimed counts must match the primitive's
/// accessors (POSITION's count, the indices' count) before anything is decoded, and the
/// output is charged to the allowance; errors name `prim_path`.extensions.
/// KHR_draco_mesh_compression.
[[nodiscard]] DracoPrimitive decode_draco(const tinygltf::Model& model,
                                          const tinygltf::Primitive& prim,
                                          const std::string& prim_path, Context& ctx);

/// Reads KHR_materials_variants' names into scene.variants and returns the index of
/// `wanted` among them (-1 when empty); a name the file does not define fails, listing those
/// it does.
int read_variants(const tinygltf::Model& model, const std::string& wanted, const Context& ctx,
                  GltfScene& scene);

/// Reads every mesh into scene.meshes; a primitive whose KHR_materials_variants mappings
/// name `variant` (an index into scene.variants, -1: none) takes that mapping's material.
void read_meshes(const tinygltf::Model& model, int variant, Context& ctx, GltfScene& scene);

/// Walks scene `scene_index` (-1: the default) into instances, cameras and lights,
/// after checking the node graph is a forest (no cycles, no node with two parents).
void read_nodes(const tinygltf::Model& model, int scene_index, Context& ctx, GltfScene& scene);

/// Reads materials, textures and samplers, and image names and URIs (from `images`).
void read_materials(const tinygltf::Model& model, const std::vector<ImageSource>& images,
                    Context& ctx, GltfScene& scene);

/// Decodes the images textures use (PNG or JPEG) from their sources; an image that is
/// missing or does not decode is a warning, and textures using it get image = -1. Each
/// distinct file is read once: textures of an image naming the same file as an earlier
/// one use the earlier image.
void decode_images(const tinygltf::Model& model, const std::vector<ImageSource>& sources,
                   const LoadLimits& limits, Context& ctx, GltfScene& scene);

/// The number of components of an accessor type (SCALAR 1 ... VEC4 4); 0 for the matrices,
/// which are never vertex attributes librt reads.
[[nodiscard]] int type_components(int type);

/// tinygltf's file-system callbacks: every file is reported missing and no file is read
/// or written (librt reads buffers and images itself, see JsonFacts).
[[nodiscard]] tinygltf::FsCallbacks no_file_access();

/// tinygltf image callback: keeps nothing (decode_images reads ImageSource instead).
bool ignore_image(tinygltf::Image* image, int image_index, std::string* err, std::string* warn,
                  int req_width, int req_height, const unsigned char* bytes, int size,
                  void* user_data);

}  // namespace librt::gltf_detail
