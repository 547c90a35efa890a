#pragma once

#include <librt/export.h>
#include <librt/gltf/gltf.h>
#include <librt/io/loaded_scene.h>
#include <librt/material/material.h>

#include <cstdint>

// A loaded glTF file (gltf/gltf.h) turned into a librt Scene and camera: every primitive of
// a glTF mesh becomes one mesh prototype, stored and BVH-built once, and every node placing
// the mesh an instance of each; materials, textures, punctual lights and cameras mapped to
// librt's.

namespace librt {

/// Scene texture ids of a glTF material's textures, -1 for none (scene_from_gltf adds
/// them: base colour and emissive decoded as sRGB, the others as linear data).
struct GltfMaterialTextures {
    std::int32_t base_color = -1;           ///< baseColorTexture (sRGB RGBA)
    std::int32_t metallic_roughness = -1;   ///< metallicRoughnessTexture (linear; G, B)
    std::int32_t emissive = -1;             ///< emissiveTexture (sRGB)
    std::int32_t normal = -1;               ///< normalTexture (linear, tangent space)
    std::int32_t anisotropy = -1;           ///< anisotropyTexture (linear; RG direction, B)
    std::int32_t clearcoat = -1;            ///< clearcoatTexture (linear; R)
    std::int32_t clearcoat_roughness = -1;  ///< clearcoatRoughnessTexture (linear; G)
    std::int32_t clearcoat_normal = -1;     ///< clearcoatNormalTexture (linear, tangent space)
    std::int32_t sheen_color = -1;          ///< sheenColorTexture (sRGB; RGB)
    std::int32_t sheen_roughness = -1;      ///< sheenRoughnessTexture (linear; A)
    std::int32_t specular = -1;             ///< specularTexture (linear; A)
    std::int32_t specular_color = -1;       ///< specularColorTexture (sRGB; RGB)
    std::int32_t transmission = -1;         ///< transmissionTexture (linear; R)
    std::int32_t occlusion = -1;            ///< occlusionTexture (linear; R), albedo AOV only
};

/// Where librt's reading of a glTF material departs from the glTF model, on request
/// (SceneFileOptions::diffuse_model and solid_transmission).
struct GltfMaterialChoices {
    /// Material::diffuse_model of every material.
    DiffuseModel diffuse_model = DiffuseModel::Lambert;
    /// Transmission without KHR_materials_volume read as solid glass, not thin-walled.
    bool solid_transmission = false;
};

/// True when material_from_gltf makes `material` solid glass (MaterialKind::RoughDielectric)
/// under `choices`: transmission factor 1, metallic factor 0, and KHR_materials_volume's
/// thickness above 0 or choices.solid_transmission.
[[nodiscard]] LIBRT_API bool gltf_solid_glass(const GltfMaterial& material,
                                              const GltfMaterialChoices& choices = {});

/// librt's material for a glTF material; the ONE place that mapping lives. Every glTF
/// material becomes MaterialKind::MetallicRoughness (glTF 2.0 Appendix B): base colour,
/// metallic and roughness factors (clamped to [0, 1]), ior from KHR_materials_ior (0, the
/// extension's reflection-only limit, read as 1.5), KHR_materials_transmission as its
/// thin-walled transmission; emission = emissive_factor * KHR_materials_emissive_strength;
/// KHR_materials_anisotropy's strength, rotation and texture as Material::anisotropy,
/// anisotropy_rotation and anisotropy_texture; KHR_materials_clearcoat's factors and
/// textures, KHR_materials_sheen's and KHR_materials_specular's factors as Material's
/// clearcoat*, sheen_* and specular* fields; KHR_materials_unlit as an Emissive material
/// with Material::unlit, emitting its base colour (times its texture). The textures in `textures`
/// fill its slots, each with its KHR_texture_transform and the flip of glTF's downward v (the mesh
/// keeps glTF's uvs); normalTexture.scale and the base colour alpha are kept. alphaMode MASK sets
/// alpha_cutoff to alphaCutoff; BLEND sets alpha_blend (partial coverage: stochastic opacity);
/// OPAQUE has no alpha test. doubleSided false makes the material one-sided (camera rays pass its
/// back; other rays find it black), except with transmission, which must be crossed from both
/// sides. The occlusion texture
/// (with its strength) goes to the albedo AOV only (a path tracer computes occlusion). Not used:
/// the sheen and specular textures, the clear coat's normal map or KHR_materials_iridescence
/// (scene_from_gltf warns). choices.diffuse_model sets Material::diffuse_model. A solid glass
/// (gltf_solid_glass: KHR_materials_volume, or choices.solid_transmission) becomes
/// Material::rough_dielectric(ior, roughness, base colour) with its emission, normal map and
/// alpha test, double-sided, and KHR_materials_volume's attenuation colour (components below
/// 1e-4 raised to it) and distance as Material's (Beer-Lambert inside); its other layers and
/// textures are not used (scene_from_gltf warns). Transmission below 1 or with metal stays
/// thin-walled.
[[nodiscard]] LIBRT_API Material material_from_gltf(const GltfMaterial& material,
                                                    const GltfMaterialTextures& textures = {},
                                                    const GltfMaterialChoices& choices = {});

/// Builds the Scene of `gltf` (taken by value: its vertex arrays are moved into the
/// scene). A mesh placed by several nodes becomes a prototype per primitive, placed by an
/// instance per node; a mesh placed by one node is baked into world space (transform())
/// and added as a mesh per primitive, which traces faster. Materials through
/// material_from_gltf; each texture an ImageTexture once
/// per colour space it is used in, with its sampler's wrap modes (NEAREST magnification
/// reads texels, anything else is bilinear; no mipmaps). A material's textures share one
/// uv set as the mesh's uvs (the first texture's) and, when a texture reads the other
/// TEXCOORD_n, that one as TriangleMesh::uvs1 (the slot's uv_set 1), which its primitives store
/// with glTF's v (an anisotropic material without textures: TEXCOORD_0); a normal-mapped or
/// anisotropic primitive keeps its TANGENTs, or gets generate_tangents'
/// (geometry/tangents.h). KHR_lights_punctual point lights become PointLights of intensity
/// candela / 683 W/sr (Blender's convention), or candela W/sr with options.light_units
/// Photometric (PunctualLightUnits; docs/render-your-own-scene.md); spot and directional
/// lights likewise; COLOR_0 (unless all white) is kept as the mesh's vertex
/// colours (Scene::shade multiplies them in); orthographic cameras, occlusion and
/// transmission textures are warned about or ignored. A scene none of whose punctual lights
/// loads (emissive surfaces or not) gets add_studio_lighting (scene/default_lighting.h) for
/// the chosen camera when options.default_lighting, noted in LoadedScene::lighting_note. A
/// node whose world transform cannot be inverted in float (determinant 0, beyond float or below
/// 1e-30) places no mesh or light (warned) and is refused for the camera. Throws librt::Error for a
/// camera option naming no camera ("camera = NAME: ..."), a camera Camera refuses, or a value Scene
/// refuses, each prefixed with the JSON path of the object concerned ("nodes[4] 'lamp': ..."); the
/// messages do not name the file (load_scene_file prefixes it). A name from the file is
/// quoted in messages by quote_untrusted (core/untrusted_text.h: escaped, capped) and every
/// warning is one printable line; LoadedScene::camera_name keeps the name as it is. The
/// result's files_read is gltf.files_read.
[[nodiscard]] LIBRT_API LoadedScene scene_from_gltf(GltfScene gltf,
                                                    const SceneFileOptions& options = {});

}  // namespace librt
