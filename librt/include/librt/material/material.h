#pragma once

#include <librt/export.h>
#include <librt/material/texture.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <limits>

namespace librt {

/// The kinds of surface: the report's four (its getColor branches on exactly these), then
/// the microfacet kinds (docs/materials-and-lights.md gives their formulas).
enum class MaterialKind : std::uint8_t {
    Diffuse,     ///< Lambertian reflector: albedo / pi
    Mirror,      ///< perfect specular reflection, tinted by albedo
    Dielectric,  ///< smooth glass: Snell refraction, total internal reflection, Schlick Fresnel
    Emissive,    ///< a light's surface: emits, reflects nothing
    Conductor,   ///< rough metal: GGX, Smith G2, Fresnel of the complex index eta + i k
    RoughDielectric,    ///< rough glass: GGX reflection and transmission (Walter et al. 2007)
    MetallicRoughness,  ///< the glTF 2.0 metallic-roughness material (spec Appendix B)
};

/// Metals with tabulated complex indices of refraction (Material::conductor).
enum class Metal : std::uint8_t {
    Gold,       ///< Au
    Silver,     ///< Ag
    Copper,     ///< Cu
    Aluminium,  ///< Al
};

/// The diffuse base of MaterialKind::MetallicRoughness (Material::diffuse_model).
enum class DiffuseModel : std::uint8_t {
    /// glTF 2.0 Appendix B: Lambert, c / pi, under the specular layer's (1 - F(V.H)).
    Lambert,
    /// Burley 2012 ("Physically Based Shading at Disney"), as Blender's Principled BSDF:
    /// c / pi (1 + (F_D90 - 1)(1 - cos_l)^5)(1 + (F_D90 - 1)(1 - cos_v)^5), F_D90 = 0.5 +
    /// 2 roughness cos^2(theta_d), without the (1 - F) factor.
    Burley,
};

/// A surface description as a tagged struct rather than a virtual BSDF hierarchy:
/// materials are plain copyable values stored contiguously in the Scene, a hit refers to
/// one by a 32-bit id instead of a shared_ptr, and the BSDF functions of bsdf.h dispatch
/// on `kind` in one switch without an indirect call. A new kind adds its enumerator, its
/// parameters here, a BSDF header of its own in librt/src/material/ and one case in
/// src/material/bsdf_dispatch.h (docs/architecture.md, "Adding a BSDF kind").
///
/// Emission is honoured for every kind (a diffuse surface may also glow, which the white
/// furnace test uses); Emissive only adds "reflects nothing".
struct LIBRT_API Material {
    MaterialKind kind = MaterialKind::Diffuse;  ///< which BSDF applies (bsdf.h)
    /// Diffuse reflectance in [0, 1] per channel, or the tint of a mirror or dielectric
    /// (1 = colourless). Unused by Emissive.
    glm::vec3 albedo{0.8f};
    /// Scene texture id whose lookup replaces `albedo` (Diffuse only); -1 for none.
    std::int32_t albedo_texture = -1;
    /// Index of refraction inside a Dielectric, relative to the outside (air, 1.0).
    float ior = 1.5f;
    /// Dielectric only: when true, reflect with the Schlick probability F and refract
    /// otherwise; when false, always refract like the report (total internal reflection
    /// still reflects).
    bool fresnel = true;
    /// Emitted radiance (W / (sr m^2) in scene units), the same on both sides of the surface.
    glm::vec3 emission{0.0f};
    /// Perceptual roughness in [0, 1] of the microfacet kinds: GGX alpha = roughness^2
    /// (clamped to >= 1e-3); 0 makes Conductor and RoughDielectric perfectly smooth.
    float roughness = 0.0f;
    /// Conductor: real part of the complex index of refraction per RGB channel.
    glm::vec3 eta{1.0f};
    /// Conductor: imaginary part (extinction coefficient) of the index per RGB channel.
    glm::vec3 k{0.0f};
    /// MetallicRoughness: glTF baseColorFactor (linear), the diffuse colour and metal F0.
    glm::vec3 base_color{1.0f};
    /// MetallicRoughness: glTF metallicFactor in [0, 1].
    float metallic = 0.0f;
    /// MetallicRoughness: KHR_materials_transmission factor in [0, 1] (thin-walled).
    float transmission = 0.0f;
    /// MetallicRoughness: the diffuse base's model (glTF's Lambert by default).
    DiffuseModel diffuse_model = DiffuseModel::Lambert;
    /// Beer-Lambert absorption inside a closed surface (KHR_materials_volume): the colour,
    /// each component in (0, 1], that remains of light after attenuation_distance inside.
    /// Scene::shade applies c^(t / d) for the segment of length t that reached the surface
    /// from its back (the inside of a closed mesh, the winding's normal pointing out).
    glm::vec3 attenuation_color{1.0f};
    /// Distance (scene units, > 0) after which attenuation_color remains; infinity: none.
    float attenuation_distance = std::numeric_limits<float>::infinity();

    // Per-hit inputs (Scene::shade evaluates them where a hit is finished, so the BSDFs
    // receive plain values; a material with none of them costs nothing per hit).
    /// Texture (sRGB) whose RGB multiplies base_color (MetallicRoughness) and whose alpha
    /// multiplies `alpha`.
    TextureSlot base_color_texture;
    /// Texture (linear) whose G channel multiplies roughness and B channel metallic.
    TextureSlot metallic_roughness_texture;
    /// Texture (sRGB) whose RGB multiplies emission (a mesh's triangle lights evaluate it
    /// at their sampled points).
    TextureSlot emission_texture;
    /// Tangent-space normal map (linear; glTF's convention: x along the tangent (u), y
    /// along the bitangent (v up), z out of the surface), on meshes with tangents.
    TextureSlot normal_texture;
    /// Multiplies the normal map's x and y (glTF normalTexture.scale).
    float normal_scale = 1.0f;
    /// Coverage in [0, 1] (glTF baseColorFactor's alpha), times base_color_texture's alpha.
    float alpha = 1.0f;
    /// Alpha test: where the coverage is below this, rays pass through the surface (glTF
    /// alphaMode MASK's alphaCutoff); 0 = opaque, no test.
    float alpha_cutoff = 0.0f;
    /// Partial coverage (glTF alphaMode BLEND): every ray (camera, bounce, shadow) passes
    /// the surface with probability 1 - coverage, decided per ray and primitive by a hash
    /// (stochastic opacity; Scene's class comment). alpha_cutoff is then not used.
    bool alpha_blend = false;
    /// False: the surface is one-sided (glTF doubleSided = false): camera rays pass through
    /// its back (back-face culling), and every other ray that meets the back finds it
    /// scattering and emitting nothing (see docs/materials-and-lights.md).
    bool double_sided = true;
    /// Emissive only (glTF KHR_materials_unlit): the emission is the base colour (times its
    /// texture and the vertex colour, per hit), seen by every ray but never light-sampled:
    /// BSDF sampling finds it (Scene's unsampled emitters).
    bool unlit = false;

    // Anisotropy (KHR_materials_anisotropy; docs/materials-and-lights.md, "Anisotropy").
    /// Anisotropy strength in [0, 1] of the GGX lobes (Conductor, RoughDielectric,
    /// MetallicRoughness): alpha_t = mix(alpha, 1, anisotropy^2) along the anisotropy
    /// direction, alpha_b = alpha across it (glTF anisotropyStrength); 0 is isotropic.
    float anisotropy = 0.0f;
    /// Angle in radians of the anisotropy direction, counter-clockwise about the normal
    /// from the surface tangent (increasing u) toward the bitangent (glTF anisotropyRotation).
    float anisotropy_rotation = 0.0f;
    /// Texture (linear) whose RG, mapped to [-1, 1], is a direction in tangent-bitangent
    /// space turned by anisotropy_rotation, and whose B multiplies anisotropy (glTF
    /// anisotropyTexture).
    TextureSlot anisotropy_texture;
    /// Per hit: the world direction along which alpha_t lies. Scene::shade sets it from the
    /// surface's tangent frame, anisotropy_rotation and anisotropy_texture; the BSDFs
    /// project it onto the shading plane (zero: the shading frame's own x axis). A caller
    /// of bsdf.h's functions without a Scene sets it itself.
    glm::vec3 anisotropy_direction{0.0f};

    // The layers and Fresnel controls of the glTF extensions (MetallicRoughness only;
    // docs/materials-and-lights.md, "glTF material extensions"). At their defaults they
    // leave the metallic-roughness BSDF as it is, at the cost of one predictable branch.
    /// KHR_materials_clearcoat clearcoatFactor in [0, 1]: the weight of a GGX dielectric
    /// coat of IOR 1.5 over the whole material; 0 is no coat.
    float clearcoat = 0.0f;
    /// KHR_materials_clearcoat clearcoatRoughnessFactor in [0, 1] (perceptual; GGX alpha
    /// = its square).
    float clearcoat_roughness = 0.0f;
    /// KHR_materials_specular specularFactor in [0, 1]: scales the dielectric's Fresnel
    /// (its F0 and F90).
    float specular = 1.0f;
    /// KHR_materials_specular specularColorFactor, each component >= 0 (finite): tints the
    /// dielectric's F0 (min(F0 colour, 1)).
    glm::vec3 specular_color{1.0f};
    /// KHR_materials_sheen sheenColorFactor in [0, 1] per channel: the colour of a Charlie
    /// sheen lobe over the material; black is no sheen.
    glm::vec3 sheen_color{0.0f};
    /// KHR_materials_sheen sheenRoughnessFactor in [0, 1] (Charlie's alpha = its square).
    float sheen_roughness = 0.0f;
    /// Texture (linear) whose R multiplies clearcoat (clearcoatTexture).
    TextureSlot clearcoat_texture;
    /// Texture (linear) whose G multiplies clearcoat_roughness (clearcoatRoughnessTexture).
    TextureSlot clearcoat_roughness_texture;
    /// Tangent-space normal map of the coat (clearcoatNormalTexture; linear, normal_texture's
    /// convention): the coat's own shading normal, bent from the interpolated normal, while
    /// the layers under the coat keep normal_texture's.
    TextureSlot clearcoat_normal_texture;
    /// Multiplies the coat's normal map's x and y (clearcoatNormalTexture.scale).
    float clearcoat_normal_scale = 1.0f;
    /// Per hit: the coat's shading normal (world, unit; on the side the geometric normal
    /// faces). Scene::shade sets it from clearcoat_normal_texture; zero: the coat uses the
    /// shading normal. A caller of bsdf.h's functions without a Scene sets it itself.
    glm::vec3 clearcoat_normal{0.0f};
    /// Texture (sRGB) whose RGB multiplies sheen_color (sheenColorTexture).
    TextureSlot sheen_color_texture;
    /// Texture (linear) whose alpha multiplies sheen_roughness (sheenRoughnessTexture).
    TextureSlot sheen_roughness_texture;
    /// Texture (linear) whose alpha multiplies specular (specularTexture).
    TextureSlot specular_texture;
    /// Texture (sRGB) whose RGB multiplies specular_color (specularColorTexture).
    TextureSlot specular_color_texture;
    /// Texture (linear) whose R multiplies transmission (transmissionTexture).
    TextureSlot transmission_texture;
    /// Ambient occlusion (glTF occlusionTexture, linear R): applied to the albedo AOV only,
    /// as 1 + occlusion_strength (R - 1), never to the rendered light (the path tracer
    /// computes occlusion itself); not a per-hit input of shading.
    TextureSlot occlusion_texture;
    /// glTF occlusionTexture.strength in [0, 1].
    float occlusion_strength = 1.0f;

    /// A Lambertian surface of the given reflectance.
    [[nodiscard]] static Material diffuse(const glm::vec3& albedo);
    /// A perfect mirror; tint multiplies what it reflects.
    [[nodiscard]] static Material mirror(const glm::vec3& tint = glm::vec3(1.0f));
    /// Smooth glass of the given index of refraction (the report's 1.4 sphere: dielectric(1.4f)).
    [[nodiscard]] static Material dielectric(float ior, bool fresnel = true,
                                             const glm::vec3& tint = glm::vec3(1.0f));
    /// A rough conductor of complex index eta + i k per channel (relative to the outside).
    [[nodiscard]] static Material conductor(const glm::vec3& eta, const glm::vec3& k,
                                            float roughness);
    /// A rough conductor of a tabulated metal (n, k near 650 / 550 / 450 nm).
    [[nodiscard]] static Material conductor(Metal metal, float roughness);
    /// A rough conductor from the artist form of Gulbrandsen 2014 ("Artist Friendly
    /// Metallic Fresnel"): reflectance at normal incidence and edge tint, each in [0, 1],
    /// mapped to eta and k (reflectance is clamped to 0.999).
    [[nodiscard]] static Material conductor_artist(const glm::vec3& reflectance,
                                                   const glm::vec3& edge_tint, float roughness);
    /// Rough glass of the given index and roughness; roughness 0 is dielectric(ior, true, tint).
    [[nodiscard]] static Material rough_dielectric(float ior, float roughness,
                                                   const glm::vec3& tint = glm::vec3(1.0f));
    /// The glTF 2.0 metallic-roughness material (ior 1.5 gives the spec's F0 = 0.04).
    [[nodiscard]] static Material metallic_roughness(const glm::vec3& base_color, float metallic,
                                                     float roughness, float ior = 1.5f,
                                                     float transmission = 0.0f);
    /// A pure emitter of the given radiance (what a sphere light's surface is made of).
    [[nodiscard]] static Material emissive(const glm::vec3& radiance);

    /// True when the surface emits anything.
    [[nodiscard]] bool emits() const {
        return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f;
    }
    /// True when the material has an input that varies per hit (a texture slot, a normal
    /// map, an alpha test, an anisotropy direction) or a one-sided back: Scene::shade then
    /// evaluates it per hit.
    /// (albedo_texture, the report's map_Kd, is looked up by Scene::albedo as before.)
    [[nodiscard]] bool varies_per_hit() const {
        return base_color_texture.bound() || metallic_roughness_texture.bound() ||
               emission_texture.bound() || normal_texture.bound() || cuts_out() || !double_sided ||
               anisotropy > 0.0f || clearcoat_texture.bound() ||
               clearcoat_roughness_texture.bound() || clearcoat_normal_texture.bound() ||
               sheen_color_texture.bound() || sheen_roughness_texture.bound() ||
               specular_texture.bound() || specular_color_texture.bound() ||
               transmission_texture.bound() || absorbs_inside();
    }
    /// True when the interior absorbs (attenuation_distance finite, attenuation_color not
    /// white): Scene::shade then attenuates the segments that reach the surface's back.
    [[nodiscard]] bool absorbs_inside() const {
        return attenuation_distance < std::numeric_limits<float>::infinity() &&
               (attenuation_color.x < 1.0f || attenuation_color.y < 1.0f ||
                attenuation_color.z < 1.0f);
    }
    /// True when the material reads the surface's tangent frame: a normal map (the base's
    /// or the coat's) or an anisotropy direction (meshes without tangents get them from
    /// their uvs).
    [[nodiscard]] bool needs_tangent_frame() const {
        return normal_texture.bound() || clearcoat_normal_texture.bound() || anisotropy > 0.0f;
    }
    /// Beer-Lambert transmittance of the interior over a path of `length` (scene units):
    /// attenuation_color^(length / attenuation_distance) (1 when it does not absorb).
    [[nodiscard]] glm::vec3 interior_transmittance(float length) const;
    /// True when rays may pass the surface where it is not covered: an alpha test
    /// (alpha_cutoff > 0) or partial coverage (alpha_blend).
    [[nodiscard]] bool cuts_out() const { return alpha_cutoff > 0.0f || alpha_blend; }
    /// True when every lobe of the material's BSDF is a delta distribution (no light
    /// sampling there); see lobes() in bsdf.h.
    [[nodiscard]] bool is_specular() const;
};

/// Throws librt::Error naming the parameter and its value when an albedo component is
/// outside [0, 1] (or NaN), emission has a negative or non-finite component, ior is not
/// finite and positive, albedo_texture is below -1, roughness, metallic, transmission or
/// a base_color component is outside [0, 1], or eta or k has a negative or non-finite
/// component; a texture slot's id is below -1 or its transform not finite; normal_scale is
/// not finite; alpha, alpha_cutoff or anisotropy is outside [0, 1]; anisotropy_rotation,
/// anisotropy_direction, clearcoat_normal_scale or clearcoat_normal is not finite; clearcoat,
/// clearcoat_roughness, specular, sheen_roughness or a sheen_color component is outside [0, 1],
/// specular_color has a negative or non-finite component, occlusion_strength is outside [0, 1],
/// unlit is set on a kind other than Emissive, diffuse_model is not a DiffuseModel, an
/// attenuation_color component is outside (0, 1], or attenuation_distance is not positive (or NaN).
LIBRT_API void validate(const Material& material);

}  // namespace librt
