#pragma once

// Private pieces of load_gltf (librt/io/gltf.h), one stage a file:
//   gltf_file.cpp       reading bytes (the one function that touches the file system)
//   gltf_container.cpp  GLB container checks, then a JSON pre-pass on nlohmann-json
//   gltf_accessor.cpp   accessors -> floats / indices, range-checked before allocating
//   gltf_mesh.cpp       primitives -> triangles
//   gltf_nodes.cpp      node tree -> instances, cameras, lights
//   gltf_material.cpp   materials, textures, samplers, image decoding
//   gltf.cpp            load_gltf: the stages in order
// tinygltf types never leave librt/src.

#include <librt/io/gltf.h>

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
    /// The file name used in messages.
    [[nodiscard]] const std::string& file() const { return file_; }

private:
    std::string file_;
    std::vector<std::string>* warnings_;
    std::uint64_t budget_ = 0;
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

/// What the JSON pre-pass learned.
struct JsonFacts {
    std::uint64_t external_bytes = 0;  ///< bytes of the external buffers it checked
    /// External buffer files (as tinygltf will name them) and the bytes their buffers use:
    /// a longer file is read only that far.
    std::map<std::string, std::uint64_t> buffer_files;
};

/// Checks what tinygltf trusts or reads loosely, with JSON paths in the errors: the JSON
/// parses to an object, is nested at most kMaxJsonDepth deep, asset.version is 2.x, every
/// extensionsRequired entry is supported (extensionsUsed-only unknowns are warnings),
/// integers fit the fields tinygltf stores them in, external buffers exist and are large
/// enough, buffer views lie inside their buffers.
[[nodiscard]] JsonFacts check_json(const Container& container, const std::string& base_dir,
                                   std::uint64_t max_file_bytes, const Context& ctx);

/// Deepest JSON nesting accepted (tinygltf converts extras and extensions recursively).
inline constexpr int kMaxJsonDepth = 64;

/// Percent-decodes a URI reference into a relative path ("a%20b.png" -> "a b.png").
[[nodiscard]] std::string decode_uri(std::string_view uri);

/// The path tinygltf reads for `uri` relative to base_dir (its JoinPath, decoded URI).
[[nodiscard]] std::string resolve_uri(const std::string& base_dir, std::string_view uri);

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

/// Reads every mesh into scene.meshes.
void read_meshes(const tinygltf::Model& model, Context& ctx, GltfScene& scene);

/// Walks scene `scene_index` (-1: the default) into instances, cameras and lights,
/// after checking the node graph is a forest (no cycles, no node with two parents).
void read_nodes(const tinygltf::Model& model, int scene_index, Context& ctx, GltfScene& scene);

/// Reads materials, textures and samplers, and image names and URIs.
void read_materials(const tinygltf::Model& model, Context& ctx, GltfScene& scene);

/// Reasons external files could not be read, by resolved path (filled by the tinygltf
/// file callbacks, used in warnings about images).
using ReadFailures = std::map<std::string, std::string>;

/// Decodes the images textures use (PNG or JPEG); an image that is missing or does not
/// decode is a warning, and textures using it get image = -1.
void decode_images(const tinygltf::Model& model, const ReadFailures& failures, Context& ctx,
                   GltfScene& scene);

/// tinygltf's file-system callbacks routed through read_regular_file, refusing files
/// outside base_dir's candidates and any writing; failures are recorded.
struct FsRouting {
    std::string base_dir;         ///< the directory URIs are relative to
    std::uint64_t max_bytes = 0;  ///< size limit per file
    ReadFailures failures;        ///< why reads failed
    /// Files read only up to a length (JsonFacts::buffer_files).
    std::map<std::string, std::uint64_t> truncate_to;
    /// The callbacks, with this as their user data.
    [[nodiscard]] tinygltf::FsCallbacks callbacks();
};

/// tinygltf image callback: keeps the encoded bytes (decoded later by decode_images).
bool keep_encoded_image(tinygltf::Image* image, int image_index, std::string* err,
                        std::string* warn, int req_width, int req_height,
                        const unsigned char* bytes, int size, void* user_data);

}  // namespace librt::gltf_detail
