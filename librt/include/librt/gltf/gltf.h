#pragma once

#include <librt/export.h>
#include <librt/io/file_digest.h>

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

// A glTF 2.0 file (.gltf with its .bin and images, or .glb) read into plain data: meshes
// as prototypes, the node tree flattened into world transforms (instances, cameras,
// lights), the metallic-roughness materials as glTF states them, and decoded images.
// Turning this into a librt Scene (materials, lights, instancing) is the caller's step.

namespace librt {

/// One triangle primitive of a glTF mesh. Per-vertex arrays are empty or as long as
/// positions; triangles index positions (strips and fans are already converted).
struct GltfPrimitive {
    std::vector<glm::vec3> positions;   ///< POSITION, in the mesh's space
    std::vector<glm::vec3> normals;     ///< NORMAL, optional
    std::vector<glm::vec4> tangents;    ///< TANGENT (xyz, w = bitangent sign), optional
    std::vector<glm::vec2> uv0;         ///< TEXCOORD_0, optional (glTF's v axis: down)
    std::vector<glm::vec2> uv1;         ///< TEXCOORD_1, optional
    std::vector<glm::vec4> colors;      ///< COLOR_0 as RGBA (alpha 1 for RGB), optional
    std::vector<glm::uvec3> triangles;  ///< three indices into positions per triangle
    int material = -1;                  ///< index into GltfScene::materials; -1: default
};

/// A glTF mesh: the prototype every node that names it places.
struct GltfMesh {
    std::string name;                       ///< the mesh's name, may be empty
    std::vector<GltfPrimitive> primitives;  ///< its triangle primitives (others are skipped)
    /// Triangles over all primitives.
    [[nodiscard]] std::size_t triangle_count() const {
        std::size_t n = 0;
        for (const GltfPrimitive& p : primitives) n += p.triangles.size();
        return n;
    }
};

/// One placement of a mesh: a node of the chosen scene that names it, or one of the node's
/// EXT_mesh_gpu_instancing instances.
struct GltfInstance {
    int mesh = -1;          ///< index into GltfScene::meshes
    int node = -1;          ///< the glTF node index
    glm::mat4 world{1.0f};  ///< mesh space to world, the node's transforms composed
    std::string node_name;  ///< the node's name, may be empty
    /// EXT_mesh_gpu_instancing: which of the node's instances (world = the node's world
    /// times the instance's T * R * S); -1 for a node placing its mesh itself.
    int gpu_instance = -1;
};

/// A camera placed by a node. glTF cameras look down their local -z with +y up.
struct GltfCamera {
    /// Projection kind.
    enum class Type {
        Perspective,   ///< yfov, aspect_ratio, znear, zfar
        Orthographic,  ///< xmag, ymag, znear, zfar
    };
    Type type = Type::Perspective;  ///< perspective or orthographic
    std::string name;               ///< the camera's name, else the node's, may be empty
    int camera = -1;                ///< the glTF camera index
    int node = -1;                  ///< the glTF node index
    glm::mat4 world{1.0f};          ///< camera space to world
    float yfov = 0.0f;              ///< perspective: vertical field of view, radians
    float aspect_ratio = 0.0f;      ///< perspective: width / height; 0 when the file gives none
    float xmag = 0.0f;              ///< orthographic: half width of the view
    float ymag = 0.0f;              ///< orthographic: half height of the view
    float znear = 0.0f;             ///< near clip distance
    float zfar = 0.0f;              ///< far clip distance; 0 = infinite
};

/// A KHR_lights_punctual light placed by a node. Units are the extension's: point and
/// spot intensity in candela (lm/sr), directional in lux (lm/m^2).
struct GltfLight {
    /// Light kind.
    enum class Type {
        Point,        ///< from the node's origin in every direction
        Spot,         ///< a point light limited to a cone around local -z
        Directional,  ///< parallel light along local -z (a sun)
    };
    Type type = Type::Point;        ///< point, spot or directional
    std::string name;               ///< the light's name, else the node's, may be empty
    int light = -1;                 ///< index into the extension's lights array
    int node = -1;                  ///< the glTF node index
    glm::mat4 world{1.0f};          ///< light space to world; spot and sun shine down local -z
    glm::vec3 color{1.0f};          ///< linear RGB
    float intensity = 1.0f;         ///< candela (point, spot) or lux (directional)
    float range = 0.0f;             ///< cut-off distance; 0 = infinite
    float inner_cone_angle = 0.0f;  ///< spot: full intensity inside this angle, radians
    float outer_cone_angle = 0.78539816f;  ///< spot: no light outside this angle, radians
};

/// KHR_texture_transform of one texture reference: uv' = T(offset) R(rotation) S(scale) uv.
struct GltfTextureTransform {
    glm::vec2 offset{0.0f};  ///< translation in uv
    float rotation = 0.0f;   ///< radians, counter-clockwise in uv
    glm::vec2 scale{1.0f};   ///< scale in uv
    /// The 3x3 matrix that maps (u, v, 1) as the extension specifies.
    [[nodiscard]] LIBRT_API glm::mat3 matrix() const;
};

/// A material's reference to a texture.
struct GltfTextureRef {
    int texture = -1;                ///< index into GltfScene::textures; -1: none
    int tex_coord = 0;               ///< which TEXCOORD_n (after KHR_texture_transform's override)
    float scale = 1.0f;              ///< normalTexture.scale or occlusionTexture.strength, else 1
    bool has_transform = false;      ///< KHR_texture_transform present
    GltfTextureTransform transform;  ///< identity unless has_transform
    /// True when a texture is referenced.
    [[nodiscard]] bool valid() const { return texture >= 0; }
};

/// How a material's alpha is used.
enum class GltfAlphaMode {
    Opaque,  ///< alpha ignored
    Mask,    ///< cut out where alpha < alpha_cutoff
    Blend,   ///< alpha blending (partial coverage)
};

/// A glTF metallic-roughness material, with the extensions librt reads, as stated in the
/// file (no conversion to librt's materials).
struct GltfMaterial {
    std::string name;                           ///< may be empty
    glm::vec4 base_color_factor{1.0f};          ///< linear RGBA
    GltfTextureRef base_color_texture;          ///< sRGB RGBA, multiplies the factor
    float metallic_factor = 1.0f;               ///< in [0, 1]
    float roughness_factor = 1.0f;              ///< perceptual roughness in [0, 1]
    GltfTextureRef metallic_roughness_texture;  ///< linear: G = roughness, B = metallic
    GltfTextureRef normal_texture;              ///< tangent-space normals; scale in .scale
    GltfTextureRef occlusion_texture;           ///< R = occlusion; strength in .scale
    glm::vec3 emissive_factor{0.0f};            ///< linear RGB
    GltfTextureRef emissive_texture;            ///< sRGB RGB, multiplies the factor
    float emissive_strength = 1.0f;             ///< KHR_materials_emissive_strength
    float transmission_factor = 0.0f;           ///< KHR_materials_transmission
    GltfTextureRef transmission_texture;        ///< KHR_materials_transmission, R channel
    float ior = 1.5f;                           ///< KHR_materials_ior
    float anisotropy_strength = 0.0f;  ///< KHR_materials_anisotropy anisotropyStrength, [0, 1]
    float anisotropy_rotation = 0.0f;  ///< KHR_materials_anisotropy anisotropyRotation, radians
    /// KHR_materials_anisotropy anisotropyTexture (linear): RG direction, B strength.
    GltfTextureRef anisotropy_texture;
    bool unlit = false;                          ///< KHR_materials_unlit present
    float clearcoat_factor = 0.0f;               ///< KHR_materials_clearcoat, [0, 1]
    GltfTextureRef clearcoat_texture;            ///< KHR_materials_clearcoat, R channel
    float clearcoat_roughness_factor = 0.0f;     ///< KHR_materials_clearcoat, [0, 1]
    GltfTextureRef clearcoat_roughness_texture;  ///< KHR_materials_clearcoat, G channel
    GltfTextureRef clearcoat_normal_texture;     ///< KHR_materials_clearcoat; scale in .scale
    glm::vec3 sheen_color_factor{0.0f};          ///< KHR_materials_sheen, linear, [0, 1]
    GltfTextureRef sheen_color_texture;          ///< KHR_materials_sheen, sRGB RGB
    float sheen_roughness_factor = 0.0f;         ///< KHR_materials_sheen, [0, 1]
    GltfTextureRef sheen_roughness_texture;      ///< KHR_materials_sheen, A channel
    float specular_factor = 1.0f;                ///< KHR_materials_specular, [0, 1]
    GltfTextureRef specular_texture;             ///< KHR_materials_specular, A channel
    glm::vec3 specular_color_factor{1.0f};       ///< KHR_materials_specular, linear, >= 0
    GltfTextureRef specular_color_texture;       ///< KHR_materials_specular, sRGB RGB
    bool iridescence = false;  ///< KHR_materials_iridescence present (not rendered)
    /// KHR_materials_volume thicknessFactor (>= 0; 0, the default, and without the
    /// extension: thin-walled). Above 0 the mesh is a closed volume: solid glass.
    float thickness_factor = 0.0f;
    GltfTextureRef thickness_texture;  ///< KHR_materials_volume, G channel (not used)
    /// KHR_materials_volume attenuationDistance (> 0; infinity: no absorption).
    float attenuation_distance = std::numeric_limits<float>::infinity();
    /// KHR_materials_volume attenuationColor, linear, [0, 1]: what remains after
    /// attenuation_distance inside.
    glm::vec3 attenuation_color{1.0f};
    GltfAlphaMode alpha_mode = GltfAlphaMode::Opaque;  ///< OPAQUE, MASK or BLEND
    float alpha_cutoff = 0.5f;                         ///< MASK: alpha below this is cut out
    bool double_sided = false;                         ///< back faces are seen (else culled)
};

/// Texture wrap mode of a sampler (per axis).
enum class GltfWrap {
    Repeat,          ///< REPEAT (10497), the default
    ClampToEdge,     ///< CLAMP_TO_EDGE (33071)
    MirroredRepeat,  ///< MIRRORED_REPEAT (33648)
};

/// Texture filter of a sampler; Unset when the file leaves it to the renderer.
enum class GltfFilter {
    Unset,                 ///< not given: the renderer chooses
    Nearest,               ///< NEAREST (9728)
    Linear,                ///< LINEAR (9729)
    NearestMipmapNearest,  ///< NEAREST_MIPMAP_NEAREST (9984)
    LinearMipmapNearest,   ///< LINEAR_MIPMAP_NEAREST (9985)
    NearestMipmapLinear,   ///< NEAREST_MIPMAP_LINEAR (9986)
    LinearMipmapLinear,    ///< LINEAR_MIPMAP_LINEAR (9987)
};

/// A decoded image: 8-bit RGBA, row-major, top row first, values as stored (sRGB or
/// linear depends on the use: base colour and emissive are sRGB, the others linear).
struct GltfImage {
    std::string name;                ///< the image's name, may be empty
    std::string uri;                 ///< its uri when external (not data:), else empty
    int width = 0;                   ///< texels per row; 0 when not decoded
    int height = 0;                  ///< rows; 0 when not decoded
    std::vector<std::uint8_t> rgba;  ///< width * height * 4 bytes; empty when not decoded
};

/// A texture: an image and how to sample it.
struct GltfTexture {
    std::string name;                           ///< may be empty
    int image = -1;                             ///< index into GltfScene::images; -1: unusable
    GltfWrap wrap_s = GltfWrap::Repeat;         ///< wrap along u
    GltfWrap wrap_t = GltfWrap::Repeat;         ///< wrap along v
    GltfFilter mag_filter = GltfFilter::Unset;  ///< magnification filter
    GltfFilter min_filter = GltfFilter::Unset;  ///< minification filter
};

/// Everything load_gltf reads from one glTF file, for one of its scenes.
struct GltfScene {
    std::vector<GltfMesh> meshes;         ///< every glTF mesh, in file order (each stored once)
    std::vector<GltfInstance> instances;  ///< the scene's nodes that place a mesh
    std::vector<GltfCamera> cameras;      ///< the scene's nodes that place a camera
    std::vector<GltfLight> lights;        ///< the scene's nodes that place a punctual light
    std::vector<GltfMaterial> materials;  ///< every material, in file order
    std::vector<GltfTexture> textures;    ///< every texture, in file order
    std::vector<GltfImage> images;        ///< every image (decoded when a texture uses it)
    /// KHR_materials_variants: the names of the file's variants, in file order (empty
    /// without the extension). Primitives carry the chosen variant's material.
    std::vector<std::string> variants;
    std::vector<std::string> warnings;  ///< what was skipped or repaired, "file: path: what"
    /// Every file the scene was made from, each once, with the digest of its bytes: the glTF
    /// file (its path as given), then each external buffer, then each image file a texture
    /// uses (canonical paths). An image that could not be read or decoded (a warning; its
    /// textures are ignored) is not listed.
    std::vector<FileRead> files_read;
    /// Triangles stored: over all meshes, each counted once.
    [[nodiscard]] LIBRT_API std::size_t triangles_stored() const;
    /// Triangles placed: over all instances, each mesh counted per instance.
    [[nodiscard]] LIBRT_API std::size_t triangles_placed() const;
};

/// How load_gltf reads a file.
struct GltfLoadOptions {
    /// Scene to load: -1 takes the file's default scene (its "scene", else scene 0; with
    /// no scenes at all, every root node, with a warning).
    int scene = -1;
    /// KHR_materials_variants: the variant (by name) whose materials primitives take where
    /// their mappings name it; empty = every primitive's own material. A name the file does
    /// not define is an error listing the names it does.
    std::string variant;
    /// Largest file read (the .gltf/.glb, each .bin and each image); larger ones are errors.
    std::uint64_t max_file_bytes = std::uint64_t{1} << 30u;
    /// Decode the images that textures use (false leaves every GltfImage undecoded).
    bool decode_images = true;
    /// Read buffers and images outside the directory tree of the glTF file (absolute paths,
    /// "..", symlinks that lead out, file: URIs). Off: a scene file downloaded from anywhere
    /// can read only the files that came with it; turn on only for files you trust.
    bool allow_outside_files = false;
    /// Most bytes loading may take; 0: 16 times the bytes of the files read, plus 256 MiB.
    /// A file that would need more is refused (librt::Error) before the memory is taken.
    std::uint64_t max_memory_bytes = 0;
};

/// Reads a glTF 2.0 file: JSON .gltf (buffers and images external or data: URIs) or
/// binary .glb, chosen by content, not by extension.
///
/// - Meshes: primitives of mode TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN become
///   triangles (strips keep a consistent winding); POINTS and LINES* are skipped with a
///   warning. Indices u8/u16/u32 or none; POSITION, NORMAL, TANGENT, TEXCOORD_0/1 and
///   COLOR_0 in any type the spec (and KHR_mesh_quantization) allows, normalised
///   integers converted, sparse accessors applied. Compressed geometry is decoded:
///   KHR_draco_mesh_compression (Draco bitstream 2.2) and EXT_meshopt_compression.
/// - Images: PNG, JPEG and WebP (EXT_texture_webp, or an image/webp image); a
///   KHR_texture_basisu (KTX2) texture uses its fallback source with a warning, and is
///   an error without one.
/// - Nodes: TRS or matrix, composed from the scene's roots down; every node naming a mesh,
///   camera or KHR_lights_punctual light adds an instance, camera or light. A node with
///   EXT_mesh_gpu_instancing adds an instance per element of its TRANSLATION, ROTATION
///   (quaternion) and SCALE accessors instead (all of one count; wrong types and counts are
///   errors naming the attribute's JSON path).
/// - KHR_materials_variants: GltfScene::variants lists the names; options.variant gives each
///   primitive whose mappings name it the mapped material.
/// - Errors, thrown as librt::Error before anything is returned, name the file and the
///   JSON path: "scene.gltf: meshes[3].primitives[0].indices: index 9123 >= vertex count
///   9000". They cover: not glTF, broken JSON, a truncated .glb or a wrong chunk length, a
///   path that is missing, not a regular file (FIFO, device, directory) or larger than
///   max_file_bytes, a missing .bin, a buffer view or accessor outside its buffer,
///   indices out of range, references to missing objects, non-finite numbers and numbers
///   a float cannot hold (yfov 1e-300 rounds to 0, znear 1e300 to infinity), a POSITION
///   coordinate beyond kMaxMeshCoordinate, a node matrix that is not affine, a cycle in
///   the node graph or a node with two parents, an extension in extensionsRequired that
///   librt does not support, a corrupt Draco or meshopt stream. Memory is bounded by a
///   multiple of the bytes read.
/// - Warnings (GltfScene::warnings): an unknown extension only in extensionsUsed, a
///   missing or undecodable image (the material keeps its factor alone), skipped
///   primitives, ignored skins and morph targets.
[[nodiscard]] LIBRT_API GltfScene load_gltf(const std::filesystem::path& path,
                                            const GltfLoadOptions& options = {});

}  // namespace librt
