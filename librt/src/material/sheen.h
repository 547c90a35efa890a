#pragma once

// The sheen lobe of KHR_materials_sheen: the "Charlie" distribution of Estevez & Kulla 2017
// ("Production Friendly Microfacet Sheen BRDF"), D(h) = (2 + 1/a) sin(theta_h)^(1/a) / (2 pi)
// with a = sheenRoughness^2, and the visibility term of Neubelt & Pettineo 2013 ("Crafting a
// Next-Gen Material Pipeline for The Order: 1886"), V = 1 / (4 (cos_i + cos_o - cos_i cos_o)),
// the cheaper of the two the extension's specification names; f = sheen colour D V.
// Its directional albedo E(cos_o, roughness) (colour 1), which scales the layer below it,
// is tabulated once per process by quadrature of this f (the table is ours, not a fit).

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace librt::microfacet {

/// Charlie's a is clamped from below: sin^(1/a) of a smaller one underflows everywhere.
inline constexpr float kMinSheenAlpha = 1e-3f;

/// The Charlie distribution at a half vector's cosine with the normal.
[[nodiscard]] inline float charlie_d(float cos_h, float alpha) {
    const float inv = 1.0f / std::max(alpha, kMinSheenAlpha);
    const float sin2 = std::max(0.0f, 1.0f - cos_h * cos_h);
    return (2.0f + inv) * std::pow(sin2, 0.5f * inv) * (0.5f / std::numbers::pi_v<float>);
}

/// The sheen BRDF (colour 1) for directions above the surface (local z up).
[[nodiscard]] inline float sheen_f(float cos_o, float cos_i, float cos_h, float alpha) {
    const float v = 1.0f / (4.0f * (cos_i + cos_o - cos_i * cos_o));
    return charlie_d(cos_h, alpha) * v;
}

/// Table of E(cos_o, roughness), kSheenN x kSheenN samples on [0, 1]^2, by a midpoint
/// quadrature in (cos_i, phi) over the hemisphere.
inline constexpr int kSheenN = 32;

[[nodiscard]] inline const std::array<float, kSheenN * kSheenN>& sheen_albedo_table() {
    static const std::array<float, kSheenN* kSheenN> table = [] {
        std::array<float, kSheenN * kSheenN> t{};
        constexpr int n_cos = 96, n_phi = 64;
        for (int r = 0; r < kSheenN; ++r) {
            const float rough = float(r) / float(kSheenN - 1);
            const float alpha = rough * rough;
            for (int c = 0; c < kSheenN; ++c) {
                // cos_o from 1e-3 (not 0: V has 1/cos_i there) to 1.
                const float co = std::max(1e-3f, float(c) / float(kSheenN - 1));
                const float so = std::sqrt(1.0f - co * co);
                double sum = 0.0;
                for (int i = 0; i < n_cos; ++i) {
                    const float ci = (float(i) + 0.5f) / float(n_cos);
                    const float si = std::sqrt(1.0f - ci * ci);
                    for (int j = 0; j < n_phi; ++j) {
                        const float phi =
                            2.0f * std::numbers::pi_v<float> * (float(j) + 0.5f) / float(n_phi);
                        // h = normalize(wo + wi), wo at azimuth 0.
                        const float hx = so + si * std::cos(phi), hy = si * std::sin(phi);
                        const float hz = co + ci;
                        const float ch = hz / std::sqrt(hx * hx + hy * hy + hz * hz);
                        sum += double(sheen_f(co, ci, ch, alpha) * ci);
                    }
                }
                t[std::size_t(r * kSheenN + c)] =
                    float(sum * (2.0 * std::numbers::pi / (n_cos * n_phi)));
            }
        }
        return t;
    }();
    return table;
}

/// E(cos_o, roughness) bilinearly from the table.
[[nodiscard]] inline float sheen_albedo(float cos_o, float roughness) {
    const auto& t = sheen_albedo_table();
    const float x = std::clamp(cos_o, 0.0f, 1.0f) * float(kSheenN - 1);
    const float y = std::clamp(roughness, 0.0f, 1.0f) * float(kSheenN - 1);
    const int x0 = std::min(int(x), kSheenN - 2), y0 = std::min(int(y), kSheenN - 2);
    const float fx = x - float(x0), fy = y - float(y0);
    const auto at = [&](int r, int c) { return t[std::size_t(r * kSheenN + c)]; };
    return (1.0f - fy) * ((1.0f - fx) * at(y0, x0) + fx * at(y0, x0 + 1)) +
           fy * ((1.0f - fx) * at(y0 + 1, x0) + fx * at(y0 + 1, x0 + 1));
}

}  // namespace librt::microfacet
