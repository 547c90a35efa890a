#pragma once

#include <librt/export.h>
#include <librt/io/gltf.h>
#include <librt/io/loaded_scene.h>
#include <librt/render/material.h>

#include <cstdint>

// A loaded glTF file (io/gltf.h) turned into a librt Scene and camera: every primitive of
// a glTF mesh becomes one mesh prototype, stored and BVH-built once, and every node placing
// the mesh an instance of each; materials, textures, punctual lights and cameras mapped to
// librt's.

namespace librt {

/// librt's material for a glTF material; the ONE place that mapping lives. Today's kinds:
/// transmission > 0 -> dielectric(ior) tinted by the base colour; metallic 1 with roughness
/// below 0.1 -> mirror tinted by the base colour; otherwise diffuse of the base colour
/// (clamped to [0, 1]) with `base_color_texture` (a scene texture id, -1 for none) as its
/// albedo texture. Emission = emissive_factor * emissive_strength, on every kind.
/// Rough metals and glossy plastics are diffuse until the GGX kinds land.
[[nodiscard]] LIBRT_API Material material_from_gltf(const GltfMaterial& material,
                                                    std::int32_t base_color_texture = -1);

/// Builds the Scene of `gltf` (taken by value: its vertex arrays are moved into the
/// prototypes). Textures: the base colour image, sRGB-decoded and multiplied by the
/// factor, becomes an ImageTexture; uvs are taken from the texture's coordinate set, through
/// its KHR_texture_transform, and flipped (v' = 1 - v: glTF's v runs down, ImageTexture's
/// up). KHR_lights_punctual point lights become PointLights of intensity candela / 683 W/sr
/// (Blender's convention, see docs/render-your-own-scene.md); spot and directional lights,
/// orthographic cameras, emissive, normal, metallic-roughness and occlusion textures and
/// alpha MASK/BLEND are warned about and ignored. A scene with no supported light and no
/// emissive surface gets default_light() (warned). Throws librt::Error for a camera option
/// naming no camera ("camera = NAME: ..."), or a value Scene refuses.
[[nodiscard]] LIBRT_API LoadedScene scene_from_gltf(GltfScene gltf,
                                                    const SceneFileOptions& options = {});

}  // namespace librt
