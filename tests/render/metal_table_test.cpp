// The named metals' (n, k) and their reflectance at normal incidence, recomputed here
// from the published sources: Johnson & Christy, Phys. Rev. B 6, 4370 (1972), Table 1
// (Au, Ag, Cu; the rows around 650, 550 and 450 nm are copied below), and the
// Lorentz-Drude model of Rakic et al., Appl. Opt. 37, 5271 (1998), Table 1, for Al.

#include <librt/material/material.h>

#include <gtest/gtest.h>

#include <glm/vec3.hpp>

#include <array>
#include <cmath>
#include <complex>

namespace librt {
namespace {

constexpr double kHc = 1239.84193;  // eV nm (photon energy E = hc / lambda)
constexpr std::array<double, 3> kLambda{650.0, 550.0, 450.0};  // R, G, B

// Johnson & Christy 1972, Table 1: photon energy (eV), then (n, k) of Cu, Ag, Au.
struct JcRow {
    double ev;
    double cu_n, cu_k, ag_n, ag_k, au_n, au_k;
};
constexpr JcRow kJc[] = {
    {1.88, 0.22, 3.747, 0.05, 4.483, 0.14, 3.697}, {2.01, 0.30, 3.205, 0.06, 4.152, 0.21, 3.272},
    {2.13, 0.70, 2.704, 0.05, 3.858, 0.29, 2.863}, {2.26, 1.02, 2.577, 0.06, 3.586, 0.43, 2.455},
    {2.75, 1.24, 2.397, 0.04, 2.657, 1.38, 1.914}, {2.88, 1.25, 2.305, 0.04, 2.462, 1.45, 1.948},
};

// (n, k) of metal column `m` (0 Cu, 1 Ag, 2 Au) at lambda, linear in photon energy
// between the two table rows around it.
std::complex<double> johnson_christy(int m, double lambda) {
    const double e = kHc / lambda;
    for (std::size_t i = 0; i + 1 < std::size(kJc); ++i) {
        const JcRow &a = kJc[i], &b = kJc[i + 1];
        if (e < a.ev || e > b.ev) continue;
        const double f = (e - a.ev) / (b.ev - a.ev);
        const double an[] = {a.cu_n, a.ag_n, a.au_n}, ak[] = {a.cu_k, a.ag_k, a.au_k};
        const double bn[] = {b.cu_n, b.ag_n, b.au_n}, bk[] = {b.cu_k, b.ag_k, b.au_k};
        return {an[m] + f * (bn[m] - an[m]), ak[m] + f * (bk[m] - ak[m])};
    }
    ADD_FAILURE() << "no table rows around " << lambda << " nm";
    return {};
}

// Aluminium by Rakic et al. 1998's Lorentz-Drude model (their eq. 3 and Table 1):
// eps(w) = 1 - f0 wp^2 / (w (w + i G0)) + sum_j fj wp^2 / (wj^2 - w^2 - i w Gj), energies
// in eV; n + ik = sqrt(eps).
std::complex<double> rakic_aluminium(double lambda) {
    const double w = kHc / lambda, wp = 14.98, f0 = 0.523, g0 = 0.047;
    struct Osc {
        double f, gamma, w;
    };
    constexpr Osc osc[] = {
        {0.227, 0.333, 0.162}, {0.050, 0.312, 1.544}, {0.166, 1.351, 1.808}, {0.030, 3.382, 3.473}};
    using C = std::complex<double>;
    C eps = 1.0 - f0 * wp * wp / (w * C(w, g0));
    for (const Osc& o : osc) eps += o.f * wp * wp / C(o.w * o.w - w * w, -w * o.gamma);
    return std::sqrt(eps);
}

// Reflectance at normal incidence of a conductor of index n + ik in vacuum (Born & Wolf,
// Principles of Optics, section 14.4): ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2).
double normal_reflectance(std::complex<double> nk) {
    const double n = nk.real(), k = nk.imag();
    return ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
}

std::complex<double> published(Metal metal, double lambda) {
    switch (metal) {
        case Metal::Copper:
            return johnson_christy(0, lambda);
        case Metal::Silver:
            return johnson_christy(1, lambda);
        case Metal::Gold:
            return johnson_christy(2, lambda);
        case Metal::Aluminium:
            return rakic_aluminium(lambda);
    }
    return {};
}

TEST(MetalTable, IndicesMatchThePublishedData) {
    for (const Metal metal : {Metal::Gold, Metal::Silver, Metal::Copper, Metal::Aluminium}) {
        const Material m = Material::conductor(metal, 0.3f);
        for (int c = 0; c < 3; ++c) {
            const std::complex<double> p = published(metal, kLambda[std::size_t(c)]);
            // The table rounds to 3 decimals.
            EXPECT_NEAR(m.eta[c], p.real(), 1e-3) << "metal " << int(metal) << " channel " << c;
            EXPECT_NEAR(m.k[c], p.imag(), 1e-3) << "metal " << int(metal) << " channel " << c;
        }
    }
}

TEST(MetalTable, NormalIncidenceReflectanceMatchesThePublishedData) {
    for (const Metal metal : {Metal::Gold, Metal::Silver, Metal::Copper, Metal::Aluminium}) {
        const Material m = Material::conductor(metal, 0.3f);
        for (int c = 0; c < 3; ++c) {
            const double expected = normal_reflectance(published(metal, kLambda[std::size_t(c)]));
            const double f0 = normal_reflectance({double(m.eta[c]), double(m.k[c])});
            EXPECT_NEAR(f0, expected, 2e-3) << "metal " << int(metal) << " channel " << c;
        }
    }
    // What the data say about the colours: gold and copper reflect red far more than blue;
    // silver and aluminium are nearly neutral and bright (silver > 0.95, aluminium ~0.91).
    auto f0 = [](Metal metal, int c) {
        const Material m = Material::conductor(metal, 0.3f);
        return normal_reflectance({double(m.eta[c]), double(m.k[c])});
    };
    EXPECT_GT(f0(Metal::Gold, 0) - f0(Metal::Gold, 2), 0.5);
    EXPECT_GT(f0(Metal::Copper, 0) - f0(Metal::Copper, 2), 0.35);
    for (int c = 0; c < 3; ++c) {
        EXPECT_GT(f0(Metal::Silver, c), 0.95) << c;
        EXPECT_NEAR(f0(Metal::Aluminium, c), 0.915, 0.01) << c;
    }
}

}  // namespace
}  // namespace librt
