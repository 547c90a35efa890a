// glTF materials to librt's MetallicRoughness kind, with their textures, samplers,
// KHR_texture_transform, alpha modes and double-sidedness (see gltf_scene_materials.h).

#include "gltf/gltf_scene_materials.h"

#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>
#include <librt/geometry/tangents.h>
#include <librt/gltf/gltf_scene.h>

#include <glm/common.hpp>

#include <algorithm>

namespace librt {
namespace {

/// The slot of a texture reference: its scene texture and its uv map (glTF uvs, v down,
/// through KHR_texture_transform, to ImageTexture coordinates).
TextureSlot slot(const GltfTextureRef& ref, std::int32_t id) {
    TextureSlot s;
    if (id < 0) return s;
    s.texture = id;
    TextureTransform t;
    if (ref.has_transform) t = {ref.transform.offset, ref.transform.rotation, ref.transform.scale};
    s.transform = make_texture_transform(t, true);
    return s;
}

}  // namespace

bool gltf_solid_glass(const GltfMaterial& m, const GltfMaterialChoices& choices) {
    return m.transmission_factor >= 1.0f && m.metallic_factor <= 0.0f &&
           (m.thickness_factor > 0.0f || choices.solid_transmission);
}

Material material_from_gltf(const GltfMaterial& m, const GltfMaterialTextures& textures,
                            const GltfMaterialChoices& choices) {
    const glm::vec3 base = glm::clamp(glm::vec3(m.base_color_factor), 0.0f, 1.0f);
    // KHR_materials_ior allows 0 (a reflection-only limit): librt needs ior > 0, so 0
    // becomes the default 1.5 (scene_from_gltf warns).
    const float ior = m.ior > 0.0f ? m.ior : 1.5f;
    Material out = Material::metallic_roughness(base, std::clamp(m.metallic_factor, 0.0f, 1.0f),
                                                std::clamp(m.roughness_factor, 0.0f, 1.0f), ior,
                                                std::clamp(m.transmission_factor, 0.0f, 1.0f));
    // KHR_materials_emissive_strength scales the factor (the extension's definition).
    out.emission = glm::max(m.emissive_factor * m.emissive_strength, glm::vec3(0.0f));
    out.base_color_texture = slot(m.base_color_texture, textures.base_color);
    out.metallic_roughness_texture =
        slot(m.metallic_roughness_texture, textures.metallic_roughness);
    out.emission_texture = slot(m.emissive_texture, textures.emissive);
    out.normal_texture = slot(m.normal_texture, textures.normal);
    out.normal_scale = m.normal_texture.scale;
    out.anisotropy = std::clamp(m.anisotropy_strength, 0.0f, 1.0f);
    out.anisotropy_rotation = m.anisotropy_rotation;
    out.anisotropy_texture = slot(m.anisotropy_texture, textures.anisotropy);
    out.clearcoat = std::clamp(m.clearcoat_factor, 0.0f, 1.0f);
    out.clearcoat_roughness = std::clamp(m.clearcoat_roughness_factor, 0.0f, 1.0f);
    out.clearcoat_texture = slot(m.clearcoat_texture, textures.clearcoat);
    out.clearcoat_roughness_texture =
        slot(m.clearcoat_roughness_texture, textures.clearcoat_roughness);
    out.clearcoat_normal_texture = slot(m.clearcoat_normal_texture, textures.clearcoat_normal);
    out.clearcoat_normal_scale = m.clearcoat_normal_texture.scale;
    out.sheen_color = glm::clamp(m.sheen_color_factor, 0.0f, 1.0f);
    out.sheen_roughness = std::clamp(m.sheen_roughness_factor, 0.0f, 1.0f);
    out.specular = std::clamp(m.specular_factor, 0.0f, 1.0f);
    out.specular_color = glm::max(m.specular_color_factor, glm::vec3(0.0f));
    out.sheen_color_texture = slot(m.sheen_color_texture, textures.sheen_color);
    out.sheen_roughness_texture = slot(m.sheen_roughness_texture, textures.sheen_roughness);
    out.specular_texture = slot(m.specular_texture, textures.specular);
    out.specular_color_texture = slot(m.specular_color_texture, textures.specular_color);
    out.transmission_texture = slot(m.transmission_texture, textures.transmission);
    out.diffuse_model = choices.diffuse_model;
    if (gltf_solid_glass(m, choices) && !m.unlit) {
        // Solid glass: refraction through the closed mesh, at the glTF material's Fresnel
        // (ior) and roughness, tinted by the base colour; the volume's absorption inside.
        const Material thin = out;
        out = Material::rough_dielectric(ior, thin.roughness, base);
        out.emission = thin.emission;
        out.emission_texture = thin.emission_texture;
        out.normal_texture = thin.normal_texture;
        out.normal_scale = thin.normal_scale;
        if (m.thickness_factor > 0.0f) {
            out.attenuation_color = glm::clamp(m.attenuation_color, 1e-4f, 1.0f);
            out.attenuation_distance = m.attenuation_distance;
        }
    }
    if (m.unlit) {
        // KHR_materials_unlit: the base colour as emission, reflecting nothing, never
        // light-sampled (Material::unlit); the layers above do not apply.
        const Material lit = out;
        out = Material::emissive(base);
        out.unlit = true;
        out.base_color = base;
        out.base_color_texture = lit.base_color_texture;
    }
    out.occlusion_texture = slot(m.occlusion_texture, textures.occlusion);
    out.occlusion_strength = std::clamp(m.occlusion_texture.scale, 0.0f, 1.0f);
    out.alpha = std::clamp(m.base_color_factor.w, 0.0f, 1.0f);
    if (m.alpha_mode == GltfAlphaMode::Mask)
        out.alpha_cutoff = std::clamp(m.alpha_cutoff, 0.0f, 1.0f);
    else if (m.alpha_mode == GltfAlphaMode::Blend)
        out.alpha_blend = true;  // partial coverage as stochastic opacity (Scene)
    // A thin transmitting surface must be crossed from both sides (a glass bottle's far
    // wall is seen from inside): transmission makes it double-sided whatever the flag.
    out.double_sided =
        m.double_sided || out.transmission > 0.0f || out.kind == MaterialKind::RoughDielectric;
    validate(out);
    return out;
}

namespace gltf_detail {

std::string named(std::string_view json_path, std::string_view name) {
    std::string out(json_path);
    out += ' ';
    out += quote_untrusted(name);
    return out;
}

MaterialBuilder::MaterialBuilder(const GltfScene& gltf, Scene& scene,
                                 std::vector<std::string>& warnings,
                                 const GltfMaterialChoices& choices)
    : gltf_(gltf),
      scene_(scene),
      warnings_(warnings),
      built_(gltf.materials.size()),
      done_(gltf.materials.size(), false),
      choices_(choices) {
    // glTF's default material: white, metallic 1, roughness 1 (spec 3.9.6) would be a
    // rough metal; librt keeps its grey diffuse default for primitives without one.
    default_.id = scene.add_material(Material::diffuse(glm::vec3(0.8f)));
}

std::int32_t MaterialBuilder::texture(const GltfTextureRef& ref, ColorSpace space) {
    if (!ref.valid() || std::size_t(ref.texture) >= gltf_.textures.size()) return -1;
    const auto key = std::make_pair(ref.texture, space);
    if (const auto it = textures_.find(key); it != textures_.end()) return it->second;
    std::int32_t id = -1;
    const GltfTexture& t = gltf_.textures[std::size_t(ref.texture)];
    if (t.image >= 0 && std::size_t(t.image) < gltf_.images.size()) {
        const GltfImage& img = gltf_.images[std::size_t(t.image)];
        if (img.width > 0 && img.height > 0) {
            const auto wrap = [](GltfWrap w) {
                return w == GltfWrap::ClampToEdge      ? TextureWrap::ClampToEdge
                       : w == GltfWrap::MirroredRepeat ? TextureWrap::MirroredRepeat
                                                       : TextureWrap::Repeat;
            };
            // NEAREST magnification reads texels; anything else (and mipmapped
            // minification, which librt does without) is bilinear.
            const TextureSampling sampling{wrap(t.wrap_s), wrap(t.wrap_t),
                                           t.mag_filter == GltfFilter::Nearest
                                               ? TextureFilter::Nearest
                                               : TextureFilter::Linear};
            id = scene_.add_texture(
                ImageTexture::from_rgba8(img.width, img.height, img.rgba, space, sampling));
        }
    }
    textures_[key] = id;
    return id;
}

const SceneMaterial& MaterialBuilder::material(int index) {
    if (index < 0 || std::size_t(index) >= gltf_.materials.size()) return default_;
    SceneMaterial& out = built_[std::size_t(index)];
    if (done_[std::size_t(index)]) return out;
    done_[std::size_t(index)] = true;
    const GltfMaterial& m = gltf_.materials[std::size_t(index)];
    const std::string who = named("materials[" + std::to_string(index) + "]", m.name) + ": ";
    // The first texture's uv set is the mesh's uvs; a texture on the other set (glTF
    // reads TEXCOORD_0 and _1) reads the mesh's uvs1, stored only for such materials.
    const GltfTextureRef* const refs[] = {&m.base_color_texture,
                                          &m.metallic_roughness_texture,
                                          &m.emissive_texture,
                                          &m.normal_texture,
                                          &m.anisotropy_texture,
                                          &m.clearcoat_texture,
                                          &m.clearcoat_roughness_texture,
                                          &m.clearcoat_normal_texture,
                                          &m.sheen_color_texture,
                                          &m.sheen_roughness_texture,
                                          &m.specular_texture,
                                          &m.specular_color_texture,
                                          &m.transmission_texture,
                                          &m.occlusion_texture};
    for (const GltfTextureRef* ref : refs) {
        if (!ref->valid()) continue;
        if (out.uv_set < 0) out.uv_set = ref->tex_coord;
        out.second_set = out.second_set || ref->tex_coord != out.uv_set;
    }
    const auto use = [&](const GltfTextureRef& ref, ColorSpace space) {
        return texture(ref, space);
    };
    GltfMaterialTextures ids;
    ids.base_color = use(m.base_color_texture, ColorSpace::Srgb);
    ids.metallic_roughness = use(m.metallic_roughness_texture, ColorSpace::Linear);
    ids.emissive = use(m.emissive_texture, ColorSpace::Srgb);
    ids.normal = use(m.normal_texture, ColorSpace::Linear);
    ids.anisotropy = use(m.anisotropy_texture, ColorSpace::Linear);
    ids.clearcoat = use(m.clearcoat_texture, ColorSpace::Linear);
    ids.clearcoat_roughness = use(m.clearcoat_roughness_texture, ColorSpace::Linear);
    ids.clearcoat_normal = use(m.clearcoat_normal_texture, ColorSpace::Linear);
    ids.sheen_color = use(m.sheen_color_texture, ColorSpace::Srgb);
    ids.sheen_roughness = use(m.sheen_roughness_texture, ColorSpace::Linear);
    ids.specular = use(m.specular_texture, ColorSpace::Linear);
    ids.specular_color = use(m.specular_color_texture, ColorSpace::Srgb);
    ids.transmission = use(m.transmission_texture, ColorSpace::Linear);
    if (m.iridescence)
        warnings_.push_back(who +
                            "KHR_materials_iridescence is not supported: drawn without "
                            "iridescence");
    if (m.unlit && (m.clearcoat_factor > 0.0f || m.sheen_color_factor != glm::vec3(0.0f)))
        warnings_.push_back(who + "KHR_materials_unlit: its other extensions are ignored");
    ids.occlusion = use(m.occlusion_texture, ColorSpace::Linear);
    if (m.ior == 0.0f) warnings_.push_back(who + "KHR_materials_ior 0 read as 1.5");
    transmission_notes(m, who);
    Material material;
    try {
        material = material_from_gltf(m, ids, choices_);
        // Slots on the other uv set read the mesh's second one.
        const std::pair<const GltfTextureRef*, TextureSlot*> slots[] = {
            {&m.base_color_texture, &material.base_color_texture},
            {&m.metallic_roughness_texture, &material.metallic_roughness_texture},
            {&m.emissive_texture, &material.emission_texture},
            {&m.normal_texture, &material.normal_texture},
            {&m.anisotropy_texture, &material.anisotropy_texture},
            {&m.clearcoat_texture, &material.clearcoat_texture},
            {&m.clearcoat_roughness_texture, &material.clearcoat_roughness_texture},
            {&m.clearcoat_normal_texture, &material.clearcoat_normal_texture},
            {&m.sheen_color_texture, &material.sheen_color_texture},
            {&m.sheen_roughness_texture, &material.sheen_roughness_texture},
            {&m.specular_texture, &material.specular_texture},
            {&m.specular_color_texture, &material.specular_color_texture},
            {&m.transmission_texture, &material.transmission_texture},
            {&m.occlusion_texture, &material.occlusion_texture}};
        for (const auto& [ref, s] : slots)
            if (ref->valid() && ref->tex_coord != out.uv_set) s->uv_set = 1;
        out.id = scene_.add_material(material);
    } catch (const Error& e) {
        throw Error(who + e.what());  // a value Material refuses, named with the material
    }
    // An unlit surface lights nothing that needs a light of its own: the file's other
    // surfaces still get the default light.
    emissive_ = emissive_ || (material.emits() && !material.unlit);
    // A normal map and an anisotropy direction both need the tangent frame, and so uvs
    // (TEXCOORD_0 when no texture chose a set) for generated tangents.
    out.needs_tangents = material.needs_tangent_frame();
    out.textured = out.uv_set >= 0;
    if (material.anisotropy > 0.0f && out.uv_set < 0) out.uv_set = 0;
    return out;
}

void MaterialBuilder::transmission_notes(const GltfMaterial& m, const std::string& who) {
    if (m.thickness_texture.valid())
        warnings_.push_back(who +
                            "KHR_materials_volume thickness texture ignored (a closed "
                            "mesh's own thickness is what light crosses)");
    if (!(m.transmission_factor > 0.0f) || m.unlit) return;
    const bool solid = m.thickness_factor > 0.0f || choices_.solid_transmission;
    if (!solid) {
        // The hint a Blender user needs: Blender exports solid glass exactly so.
        warnings_.push_back(who +
                            "KHR_materials_transmission without KHR_materials_volume is "
                            "thin-walled (the glTF default; Blender and Cycles show solid "
                            "glass): rt_render --solid-transmission refracts it as solid");
    } else if (!gltf_solid_glass(m, choices_)) {
        warnings_.push_back(who +
                            "solid transmission needs transmission 1 and metallic 0: "
                            "drawn thin-walled");
    } else {
        const bool dropped = m.base_color_texture.valid() || m.metallic_roughness_texture.valid() ||
                             m.transmission_texture.valid() || m.clearcoat_factor > 0.0f ||
                             m.sheen_color_factor != glm::vec3(0.0f) || m.specular_factor != 1.0f ||
                             m.specular_color_factor != glm::vec3(1.0f) ||
                             m.anisotropy_strength > 0.0f;
        if (dropped)
            warnings_.push_back(who +
                                "drawn as solid glass (ior, roughness, base colour factor): its "
                                "textures other than normal and emissive, clear coat, sheen, "
                                "specular and anisotropy are ignored");
    }
}

void MaterialBuilder::attributes(const GltfPrimitive& prim, const SceneMaterial& m,
                                 TriangleMesh& mesh, const std::string& who) {
    // COLOR_0 multiplies the base colour (glTF 2.0 sec. 3.9.2); kept unless all white.
    if (prim.colors.size() == mesh.positions.size() &&
        std::any_of(prim.colors.begin(), prim.colors.end(),
                    [](const glm::vec4& c) { return c != glm::vec4(1.0f); }))
        mesh.colors = prim.colors;
    if (m.uv_set < 0) return;
    if (m.second_set) {
        const int other = 1 - m.uv_set;
        const std::vector<glm::vec2>& uvs1 = other == 1 ? prim.uv1 : prim.uv0;
        if (uvs1.size() == mesh.positions.size())
            mesh.uvs1 = uvs1;  // glTF's own (v down), as the first set
        else
            warnings_.push_back(who + ": no TEXCOORD_" + std::to_string(other) +
                                " for its material's textures on it: they read uv (0, 0)");
    }
    const std::vector<glm::vec2>& uvs = m.uv_set == 1 ? prim.uv1 : prim.uv0;
    const bool given_tangents = prim.tangents.size() == mesh.positions.size();
    if (uvs.size() != mesh.positions.size()) {
        if (!(m.needs_tangents && given_tangents && !m.textured))
            warnings_.push_back(who + ": no TEXCOORD_" + std::to_string(m.uv_set) +
                                " for its material's textures or tangents: they read uv (0, 0)");
        mesh.uvs.assign(mesh.positions.size(), glm::vec2(0.0f));
        if (m.needs_tangents && given_tangents) mesh.tangents = prim.tangents;
        return;
    }
    mesh.uvs = uvs;  // glTF's own (v down): the slots' transforms flip v
    if (!m.needs_tangents) return;
    if (given_tangents)
        mesh.tangents = prim.tangents;
    else
        mesh.tangents = generate_tangents(mesh, true);
}

}  // namespace gltf_detail
}  // namespace librt
