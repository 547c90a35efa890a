#pragma once

#include <array>
#include <cstdint>

// Sobol' points (Sobol' 1967) in base 2 and hash-based Owen scrambling (Burley 2020,
// "Practical Hash-based Owen Scrambling", JCGT 9(4)). Everything is constexpr bit
// arithmetic on 32-bit fractions: a value x stands for x * 2^-32 in [0, 1).

namespace librt {

/// Reverses the order of the 32 bits of x (bit 0 becomes bit 31).
[[nodiscard]] constexpr std::uint32_t reverse_bits(std::uint32_t x) {
    x = ((x >> 1u) & 0x55555555u) | ((x & 0x55555555u) << 1u);
    x = ((x >> 2u) & 0x33333333u) | ((x & 0x33333333u) << 2u);
    x = ((x >> 4u) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4u);
    x = ((x >> 8u) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8u);
    return (x >> 16u) | (x << 16u);
}

/// How many Sobol' dimensions sobol_u32 has a generator matrix for.
inline constexpr int k_sobol_dimensions = 4;

/// Implementation details of sobol_u32; not part of the API.
namespace detail {

/// Primitive-polynomial parameters of one Sobol' dimension, as Joe and Kuo tabulate them.
struct SobolPolynomial {
    int degree;            ///< s, the polynomial's degree
    std::uint32_t coeffs;  ///< a: the inner coefficients, most significant first
    std::array<int, 3> m;  ///< initial direction numbers m_1..m_s (odd, m_k < 2^k)
};

/// Dimensions 2..4 of S. Joe and F. Y. Kuo, "Constructing Sobol sequences with better
/// two-dimensional projections", SIAM J. Sci. Comput. 30 (2008), file new-joe-kuo-6.21201
/// (rows "d s a m_i": "2 1 0 1", "3 2 1 1 3", "4 3 1 1 3 1"). Dimension 1 is the van der
/// Corput sequence (the identity matrix after bit reversal) and needs no polynomial.
inline constexpr std::array<SobolPolynomial, k_sobol_dimensions - 1> k_joe_kuo{{
    {1, 0u, {1, 0, 0}},
    {2, 1u, {1, 3, 0}},
    {3, 1u, {1, 3, 1}},
}};

/// The 32 direction numbers of each dimension.
using SobolMatrices = std::array<std::array<std::uint32_t, 32>, k_sobol_dimensions>;

/// The direction numbers V_k = m_k 2^(32-k) of every dimension; for k > s Bratley and Fox's
/// recurrence V_k = V_{k-s} ^ (V_{k-s} >> s) ^ XOR_{j=1}^{s-1} a_j V_{k-j}.
constexpr SobolMatrices make_sobol_matrices() {
    SobolMatrices v{};
    for (int k = 0; k < 32; ++k) v[0][k] = 1u << (31 - k);  // van der Corput
    for (int d = 1; d < k_sobol_dimensions; ++d) {
        const SobolPolynomial& p = k_joe_kuo[d - 1];
        const int s = p.degree;
        for (int k = 0; k < 32; ++k) {
            if (k < s) {
                v[d][k] = static_cast<std::uint32_t>(p.m[k]) << (31 - k);
                continue;
            }
            std::uint32_t x = v[d][k - s] ^ (v[d][k - s] >> s);
            for (int j = 1; j < s; ++j) {
                if ((p.coeffs >> (s - 1 - j)) & 1u) x ^= v[d][k - j];
            }
            v[d][k] = x;
        }
    }
    return v;
}

/// The generator matrices, built at compile time.
inline constexpr SobolMatrices k_sobol_matrices = make_sobol_matrices();

}  // namespace detail

/// Component `dimension` (in [0, k_sobol_dimensions)) of Sobol' point `index`, unscrambled,
/// as a 32-bit fraction: the XOR of the direction numbers selected by the index's bits.
[[nodiscard]] constexpr std::uint32_t sobol_u32(std::uint32_t index, int dimension) {
    if (dimension == 0) return reverse_bits(index);  // van der Corput, without the loop
    const auto& v = detail::k_sobol_matrices[static_cast<unsigned>(dimension)];
    std::uint32_t x = 0;
    for (int k = 0; index != 0; ++k, index >>= 1u) {
        if (index & 1u) x ^= v[static_cast<unsigned>(k)];
    }
    return x;
}

/// Laine and Karras's permutation with Burley 2020's improved constants (section 4): every
/// output bit is its input bit XOR a function of the less significant bits only (adding
/// and multiplying by even constants never carry downwards), so on bit-reversed values it
/// is a nested uniform (Owen) scramble, which keeps every elementary interval's count.
[[nodiscard]] constexpr std::uint32_t laine_karras_permutation(std::uint32_t x,
                                                               std::uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/// Owen scrambling of a 32-bit fraction (Burley 2020, nested_uniform_scramble): each bit is
/// flipped by a hash of the more significant bits above it. Applied to a sample index it is
/// Burley's shuffle: the first 2^k indices map onto one aligned block of 2^k indices.
[[nodiscard]] constexpr std::uint32_t owen_scramble(std::uint32_t x, std::uint32_t seed) {
    return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

}  // namespace librt
