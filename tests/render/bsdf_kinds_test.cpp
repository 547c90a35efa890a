// The checklist for a new BSDF kind (docs/architecture.md, "Adding a BSDF kind"), guarded:
// a kind type must answer every fact of BsdfKind (a dummy kind that misses one is refused at
// compile time), every MaterialKind has its case in dispatch() (the case label is the
// type's own kKind), and the facts each kind states agree with what its sample() does, for
// example materials of every kind: an opaque kind never transmits, a transmitting one
// does, sampled lobes are among the flagged ones, a near-specular kind and a caustic
// caster sample only narrow (large-density) or delta lobes and never a diffuse one, and a
// vertex colour darkens the kind. A new kind must add its examples below (the switch in
// examples() does not compile without them).

#include "material/bsdf_dispatch.h"
#include "material/bsdf_kind.h"

#include <librt/material/bsdf.h>
#include <librt/material/material.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/warp.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace librt {
namespace {

// ---- The concept: a kind missing a fact is no BsdfKind --------------------------------

/// A kind with every fact: what the checklist asks a new kind to write.
struct DummyKind {
    static constexpr MaterialKind kKind = MaterialKind::Diffuse;
    static constexpr BsdfLobe kLobes = BsdfLobe::DiffuseReflection;
    static BsdfSample sample(const Material&, const ShadingPoint&, const glm::vec3&, float,
                             glm::vec2) {
        return {};
    }
    static glm::vec3 eval(const Material&, const ShadingPoint&, const glm::vec3&,
                          const glm::vec3&) {
        return glm::vec3(0.0f);
    }
    static float pdf(const Material&, const ShadingPoint&, const glm::vec3&, const glm::vec3&) {
        return 0.0f;
    }
    static bool transmits(const Material&) { return false; }
    static bool near_specular(const Material&, float) { return false; }
    static bool casts_caustics(const Material&, float) { return false; }
    static void multiply_color(Material&, const glm::vec3&) {}
    static glm::vec3 denoising_albedo(const Material&, const ShadingPoint&) {
        return glm::vec3(0.0f);
    }
};
static_assert(bsdfs::BsdfKind<DummyKind>);

// The same dummy without one fact each.
struct NoKind : DummyKind {
    static constexpr int kKind = 0;  // not a MaterialKind
};
struct NoLobes {
    static constexpr MaterialKind kKind = MaterialKind::Diffuse;
    using D = DummyKind;
    static constexpr auto sample = &D::sample;
};
struct NoTransmits : DummyKind {
    static void transmits() {}
};
struct NoNearSpecular : DummyKind {
    static void near_specular() {}
};
struct NoCaustics : DummyKind {
    static void casts_caustics() {}
};
struct NoColor : DummyKind {
    static void multiply_color() {}
};
struct NoDenoisingAlbedo : DummyKind {
    static void denoising_albedo() {}
};
static_assert(!bsdfs::BsdfKind<NoKind>);
static_assert(!bsdfs::BsdfKind<NoLobes>);
static_assert(!bsdfs::BsdfKind<NoTransmits>);
static_assert(!bsdfs::BsdfKind<NoNearSpecular>);
static_assert(!bsdfs::BsdfKind<NoCaustics>);
static_assert(!bsdfs::BsdfKind<NoDenoisingAlbedo>);
static_assert(!bsdfs::BsdfKind<NoColor>);

// Every registered type is a BsdfKind, and the dispatch knows where the enumerators end.
static_assert(bsdfs::BsdfKind<bsdfs::Diffuse> && bsdfs::BsdfKind<bsdfs::Mirror> &&
              bsdfs::BsdfKind<bsdfs::Dielectric> && bsdfs::BsdfKind<bsdfs::Emissive> &&
              bsdfs::BsdfKind<bsdfs::Conductor> && bsdfs::BsdfKind<bsdfs::RoughDielectric> &&
              bsdfs::BsdfKind<bsdfs::MetallicRoughness>);
static_assert(bsdfs::has_bsdf(MaterialKind::Diffuse) &&
              bsdfs::has_bsdf(MaterialKind::MetallicRoughness));
static_assert(!bsdfs::has_bsdf(MaterialKind(200)));

// ---- Example materials of every kind ------------------------------------------------

Material anisotropic(Material m, float strength) {
    m.anisotropy = strength;
    m.anisotropy_direction = glm::normalize(glm::vec3(1.0f, 0.3f, 0.2f));
    return m;
}

// A MaterialKind without examples is an error (-Wswitch), as in dispatch().
#pragma GCC diagnostic push
#pragma GCC diagnostic error "-Wswitch"
/// Materials of `kind` that between them reach every lobe and every answer of its facts.
std::vector<Material> examples(MaterialKind kind) {
    const glm::vec3 c(0.8f, 0.5f, 0.3f);
    switch (kind) {
        case MaterialKind::Diffuse:
            return {Material::diffuse(c)};
        case MaterialKind::Mirror:
            return {Material::mirror(), Material::mirror(c)};
        case MaterialKind::Dielectric:
            return {Material::dielectric(1.5f), Material::dielectric(1.4f, false),
                    Material::dielectric(1.33f, true, c)};
        case MaterialKind::Emissive:
            return {Material::emissive(glm::vec3(2.0f))};
        case MaterialKind::Conductor:
            return {Material::conductor(Metal::Gold, 0.0f), Material::conductor(Metal::Gold, 0.05f),
                    Material::conductor(Metal::Copper, 0.5f),
                    anisotropic(Material::conductor(Metal::Silver, 0.3f), 0.8f)};
        case MaterialKind::RoughDielectric:
            return {Material::rough_dielectric(1.5f, 0.0f), Material::rough_dielectric(1.5f, 0.05f),
                    Material::rough_dielectric(1.33f, 0.5f, c),
                    anisotropic(Material::rough_dielectric(1.5f, 0.4f), 0.6f)};
        case MaterialKind::MetallicRoughness:
            return {Material::metallic_roughness(c, 0.0f, 0.5f),
                    Material::metallic_roughness(c, 1.0f, 0.05f),
                    Material::metallic_roughness(c, 0.5f, 0.3f),
                    Material::metallic_roughness(c, 0.0f, 0.4f, 1.5f, 0.8f),
                    Material::metallic_roughness(c, 0.0f, 0.0f, 1.5f, 1.0f),
                    Material::metallic_roughness(c, 1.0f, 0.5f, 1.5f, 0.5f),
                    anisotropic(Material::metallic_roughness(c, 0.3f, 0.4f), 0.7f)};
    }
    return {};
}
#pragma GCC diagnostic pop

/// Every kind dispatch() registers, in enumerator order (they are numbered from 0).
std::vector<MaterialKind> registered_kinds() {
    std::vector<MaterialKind> kinds;
    for (int i = 0; i < 256 && bsdfs::has_bsdf(MaterialKind(i)); ++i)
        kinds.push_back(MaterialKind(i));
    return kinds;
}

std::string describe(const Material& m) {
    return "kind " + std::to_string(int(m.kind)) + ", roughness " + std::to_string(m.roughness) +
           ", metallic " + std::to_string(m.metallic) + ", transmission " +
           std::to_string(m.transmission) + ", anisotropy " + std::to_string(m.anisotropy);
}

/// A flat surface (shading normal = geometric normal = +z in world space) hit from a
/// random direction over the whole sphere, so both sides (front: entering glass) occur.
ShadingPoint random_point(const Material& m, Pcg32& rng) {
    glm::vec3 incoming = sample_uniform_sphere(rng.next_vec2());
    if (std::fabs(incoming.z) < 0.05f) incoming.z = incoming.z < 0.0f ? -0.05f : 0.05f;
    const glm::vec3 n(0.0f, 0.0f, 1.0f);
    // The albedo as the path loop gives it: the material's own (no texture here).
    return {ShadingFrame::at(n, n, glm::normalize(incoming)), m.albedo};
}

/// A local direction on wo's side (z > 0), not grazing.
glm::vec3 upper_direction(Pcg32& rng) {
    glm::vec3 w = sample_uniform_sphere(rng.next_vec2());
    w.z = std::max(std::fabs(w.z), 0.05f);
    return glm::normalize(w);
}

/// What sample() did for one material over many (point, wo, random numbers).
struct Observed {
    int valid = 0;
    int reflected = 0;
    int transmitted = 0;
    int diffuse = 0;
    int specular = 0;
    std::vector<float> densities;  ///< of the non-specular samples
    float max_pass_through = 0.0f;
};

constexpr float kNarrowLimit = 0.1f;  ///< near_specular's limit in the path loop's guiding
/// A roughness limit above 0 (near_specular's is strict): every delta lobe is below it.
constexpr float kTinyRoughness = 1e-3f;
/// A sampled density no cosine lobe reaches (its peak is 1 / pi): a median above it is a
/// narrow lobe.
constexpr float kNarrowDensity = 10.0f;

Observed observe(const Material& m, int n) {
    Pcg32 rng(17, 3);
    Observed o;
    for (int i = 0; i < n; ++i) {
        const ShadingPoint p = random_point(m, rng);
        const glm::vec3 w = upper_direction(rng);
        const glm::vec3 through = pass_through(m, p, w);
        o.max_pass_through = std::max({o.max_pass_through, through.x, through.y, through.z});
        const BsdfSample s = sample(m, p, w, rng.next_float(), rng.next_vec2());
        if (!s.valid()) continue;
        ++o.valid;
        EXPECT_EQ(s.lobe & lobes(m), s.lobe) << describe(m) << ": a sample of an unflagged lobe";
        EXPECT_EQ(int(has(s.lobe, BsdfLobe::Reflection)) + int(has(s.lobe, BsdfLobe::Transmission)),
                  1)
            << describe(m) << ": a sample reflects or transmits";
        if (has(s.lobe, BsdfLobe::Transmission)) {
            EXPECT_LT(s.wi.z, 0.0f) << describe(m) << ": a transmission stays on wo's side";
            ++o.transmitted;
        } else {
            EXPECT_GT(s.wi.z, 0.0f) << describe(m) << ": a reflection crosses the surface";
            ++o.reflected;
        }
        if (has(s.lobe, BsdfLobe::Diffuse)) ++o.diffuse;
        if (has(s.lobe, BsdfLobe::Specular)) {
            ++o.specular;
        } else {
            // A sample of a lobe with a density has pdf()'s density there.
            const float density = pdf(m, p, w, s.wi);
            EXPECT_NEAR(density, s.pdf, 1e-3f * s.pdf) << describe(m);
            o.densities.push_back(s.pdf);
        }
        if (!has_non_specular(lobes(m))) {
            // Delta lobes only: nothing for eval() and pdf() anywhere.
            EXPECT_EQ(eval(m, p, w, s.wi), glm::vec3(0.0f)) << describe(m);
            EXPECT_EQ(pdf(m, p, w, s.wi), 0.0f) << describe(m);
        }
    }
    return o;
}

float median(std::vector<float> v) {
    if (v.empty()) return 0.0f;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
}

TEST(BsdfKinds, EveryEnumeratorHasItsOwnBsdfType) {
    const std::vector<MaterialKind> kinds = registered_kinds();
    // The report's four and the three microfacet kinds at least, numbered from 0.
    ASSERT_GE(kinds.size(), 7u);
    EXPECT_EQ(kinds.back(), MaterialKind(kinds.size() - 1));
    for (const MaterialKind kind : kinds) {
        // The type under each enumerator's case says it is that enumerator's.
        EXPECT_EQ(bsdfs::dispatch(kind, [](auto bsdf) { return decltype(bsdf)::kKind; }), kind);
        EXPECT_FALSE(examples(kind).empty()) << "kind " << int(kind) << " has no examples";
    }
}

TEST(BsdfKinds, FlagsAgreeWithSampling) {
    for (const MaterialKind kind : registered_kinds()) {
        bool kind_transmits = false, kind_transmitted = false;
        for (const Material& m : examples(kind)) {
            ASSERT_EQ(m.kind, kind);
            SCOPED_TRACE(describe(m));
            const BsdfLobe flags = lobes(m);
            const BsdfLobe all = bsdfs::dispatch(kind, [](auto b) { return decltype(b)::kLobes; });
            EXPECT_EQ(flags & all, flags) << "lobes(m) outside the kind's kLobes";
            EXPECT_EQ(bsdfs::lobes_of(m), flags);

            const Observed o = observe(m, 4000);
            const bool transmits = bsdfs::transmits(m);
            kind_transmits = kind_transmits || transmits;
            kind_transmitted = kind_transmitted || o.transmitted > 0 || o.max_pass_through > 0.0f;
            if (flags == BsdfLobe::None) {
                EXPECT_EQ(o.valid, 0) << "a kind without lobes scatters";
                continue;
            }
            EXPECT_GT(o.valid, 0);
            if (!transmits) {
                // Opaque: no lobe, sample or Null lobe lets light through.
                EXPECT_FALSE(has(flags, BsdfLobe::Transmission | BsdfLobe::Null));
                EXPECT_EQ(o.transmitted, 0);
                EXPECT_EQ(o.max_pass_through, 0.0f);
                EXPECT_FALSE(may_pass_through(m));
            }
            if (has(flags, BsdfLobe::Transmission)) {
                EXPECT_TRUE(transmits);
                EXPECT_GT(o.transmitted, 0) << "a transmission lobe that never transmits";
            }
            if (has(flags, BsdfLobe::Null)) {
                EXPECT_TRUE(transmits);
                EXPECT_GT(o.max_pass_through, 0.0f) << "a Null lobe that lets nothing through";
            }
            if (may_pass_through(m)) {
                EXPECT_TRUE(transmits);
            }
            EXPECT_GT(o.reflected, 0) << "every scattering kind here reflects some light";
            if (!has(flags, BsdfLobe::Specular)) {
                EXPECT_EQ(o.specular, 0);
            }
            if (!has(flags, BsdfLobe::Diffuse)) {
                EXPECT_EQ(o.diffuse, 0);
            }

            // Near-specular and caustic casters: delta or narrow lobes, never a diffuse one.
            const bool narrow = bsdfs::near_specular(m, kNarrowLimit);
            const bool caster = bsdfs::casts_caustics(m, kNarrowLimit);
            if (narrow || caster) {
                EXPECT_EQ(o.diffuse, 0) << "near-specular or caster, yet a diffuse sample";
                if (!o.densities.empty()) {
                    EXPECT_GT(median(o.densities), kNarrowDensity)
                        << "near-specular or caster, yet a wide lobe";
                }
            }
            // A caster at a limit casts at any larger one; a diffuse sample casts at none.
            if (caster) {
                EXPECT_TRUE(bsdfs::casts_caustics(m, 1.0f));
            }
            if (o.diffuse > 0) {
                EXPECT_FALSE(bsdfs::casts_caustics(m, 1.0f));
            }
            // Only delta lobes: near-specular and a caster whatever the limit.
            if (!has_non_specular(flags)) {
                EXPECT_TRUE(bsdfs::near_specular(m, kTinyRoughness));
                EXPECT_TRUE(bsdfs::casts_caustics(m, 0.0f));
            }
        }
        EXPECT_EQ(kind_transmits, kind_transmitted)
            << "kind " << int(kind) << ": transmits() disagrees with its samples";
    }
}

TEST(BsdfKinds, VertexColourDarkensEveryKind) {
    // multiply_color must reach the colour the kind scatters with: halving it never adds
    // light (to eval, a delta sample's weight or a Null lobe's pass-through) and, for a
    // kind with lobes, takes some away.
    for (const MaterialKind kind : registered_kinds()) {
        for (const Material& m : examples(kind)) {
            SCOPED_TRACE(describe(m));
            Material dark = m;
            bsdfs::multiply_color(dark, glm::vec3(0.5f));
            if (lobes(m) == BsdfLobe::None) continue;
            Pcg32 rng(5, 9);
            float lost = 0.0f;
            for (int i = 0; i < 2000; ++i) {
                const ShadingPoint p = random_point(m, rng);
                const ShadingPoint p_dark{p.frame, dark.albedo};
                const glm::vec3 wo = upper_direction(rng);
                const float uc = rng.next_float();
                const glm::vec2 u = rng.next_vec2();
                // A Null lobe's colour (thin transmission) is the kind's colour too.
                const glm::vec3 t = pass_through(m, p, wo), td = pass_through(dark, p_dark, wo);
                for (int c = 0; c < 3; ++c) EXPECT_LE(td[c], t[c]);
                lost += (t.x + t.y + t.z) - (td.x + td.y + td.z);
                if (has_non_specular(lobes(m))) {
                    const glm::vec3 wi = sample_uniform_sphere(u);
                    const glm::vec3 f = eval(m, p, wo, wi), fd = eval(dark, p_dark, wo, wi);
                    for (int c = 0; c < 3; ++c) EXPECT_LE(fd[c], f[c] * (1.0f + 1e-5f) + 1e-7f);
                    lost += (f.x + f.y + f.z) - (fd.x + fd.y + fd.z);
                } else {
                    // Delta lobes: the same direction, a darker weight.
                    const BsdfSample s = sample(m, p, wo, uc, u);
                    const BsdfSample sd = sample(dark, p_dark, wo, uc, u);
                    ASSERT_EQ(s.valid(), sd.valid());
                    if (!s.valid()) continue;
                    EXPECT_EQ(s.wi, sd.wi);
                    for (int c = 0; c < 3; ++c) EXPECT_LE(sd.weight[c], s.weight[c]);
                    lost += (s.weight.x + s.weight.y + s.weight.z) -
                            (sd.weight.x + sd.weight.y + sd.weight.z);
                }
            }
            EXPECT_GT(lost, 0.0f) << "multiply_color changed nothing the kind scatters with";
        }
    }
}

}  // namespace
}  // namespace librt
