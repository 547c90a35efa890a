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
    // The bytes' order by one instruction (bswap) where the last two swaps took eight.
    return __builtin_bswap32(x);
}

/// How many Sobol' dimensions sobol_u32 has a generator matrix for.
inline constexpr int kSobolDimensions = 4;

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
inline constexpr std::array<SobolPolynomial, kSobolDimensions - 1> kJoeKuo{{
    {1, 0u, {1, 0, 0}},
    {2, 1u, {1, 3, 0}},
    {3, 1u, {1, 3, 1}},
}};

/// The 32 direction numbers of each dimension.
using SobolMatrices = std::array<std::array<std::uint32_t, 32>, kSobolDimensions>;

/// The direction numbers V_k = m_k 2^(32-k) of every dimension; for k > s Bratley and Fox's
/// recurrence V_k = V_{k-s} ^ (V_{k-s} >> s) ^ XOR_{j=1}^{s-1} a_j V_{k-j}.
constexpr SobolMatrices make_sobol_matrices() {
    SobolMatrices v{};
    for (int k = 0; k < 32; ++k) v[0][k] = 1u << (31 - k);  // van der Corput
    for (int d = 1; d < kSobolDimensions; ++d) {
        const SobolPolynomial& p = kJoeKuo[d - 1];
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
inline constexpr SobolMatrices kSobolMatrices = make_sobol_matrices();

/// For each dimension and each byte of the index, the XOR of the direction numbers that
/// byte's 256 values select: 4 table lookups per point instead of a loop over 32 bits
/// whose branches on random index bits the CPU cannot predict (4 KiB per dimension).
using SobolByteTables = std::array<std::array<std::array<std::uint32_t, 256>, 4>, kSobolDimensions>;

/// Builds SobolByteTables from kSobolMatrices.
constexpr SobolByteTables make_sobol_byte_tables() {
    SobolByteTables t{};
    for (int d = 0; d < kSobolDimensions; ++d) {
        for (int b = 0; b < 4; ++b) {
            for (std::uint32_t v = 0; v < 256; ++v) {
                std::uint32_t x = 0;
                for (int k = 0; k < 8; ++k) {
                    if ((v >> k) & 1u) x ^= kSobolMatrices[d][8 * b + k];
                }
                t[d][b][v] = x;
            }
        }
    }
    return t;
}

/// The byte tables, built at compile time.
inline constexpr SobolByteTables kSobolByteTables = make_sobol_byte_tables();

/// The byte tables with every entry bit-reversed: bit reversal is linear over XOR, so
/// their XOR is reverse_bits(sobol_u32(index, d)), the form Owen scrambling works on.
constexpr SobolByteTables make_sobol_reversed_byte_tables() {
    SobolByteTables t = make_sobol_byte_tables();
    for (auto& dim : t)
        for (auto& byte : dim)
            for (auto& v : byte) v = reverse_bits(v);
    return t;
}

/// The bit-reversed byte tables, built at compile time.
inline constexpr SobolByteTables kSobolReversedByteTables = make_sobol_reversed_byte_tables();

/// The pair (reverse_bits(sobol_u32(i, 0)), reverse_bits(sobol_u32(i, 1))) as a function
/// of r = reverse_bits(i), packed low and high in 64 bits, per byte of r: both components
/// are linear over XOR in r, so the XOR of a byte's four entries gives the pair. A padded
/// 2D draw then reads its two values from the scrambled index r directly: no reversal
/// of r back to the index, and one lookup per byte for both dimensions (8 KiB).
using SobolPairTables = std::array<std::array<std::uint64_t, 256>, 4>;

/// Builds SobolPairTables from the reversed byte tables.
constexpr SobolPairTables make_sobol_pair_tables() {
    SobolPairTables t{};
    const SobolByteTables& rev = kSobolReversedByteTables;
    for (int b = 0; b < 4; ++b) {
        for (std::uint32_t v = 0; v < 256; ++v) {
            // i = reverse_bits(v << 8b): r's byte b is i's byte 3 - b with its bits reversed.
            const std::uint32_t i = reverse_bits(v << (8u * static_cast<unsigned>(b)));
            std::uint32_t d1 = 0;
            for (int k = 0; k < 4; ++k)
                d1 ^= rev[1][k][(i >> (8u * static_cast<unsigned>(k))) & 0xffu];
            t[b][v] = std::uint64_t{i} | (std::uint64_t{d1} << 32u);  // dim 0 reversed is i
        }
    }
    return t;
}

/// The pair tables, built at compile time.
inline constexpr SobolPairTables kSobolPairTables = make_sobol_pair_tables();

}  // namespace detail

/// Component `dimension` (in [0, kSobolDimensions)) of Sobol' point `index`, unscrambled,
/// as a 32-bit fraction: the XOR of the direction numbers selected by the index's bits.
/// The Sobol' tests check it against the bit loop over detail::kSobolMatrices.
[[nodiscard]] constexpr std::uint32_t sobol_u32(std::uint32_t index, int dimension) {
    if (dimension == 0) return reverse_bits(index);  // van der Corput, without tables
    const auto& t = detail::kSobolByteTables[static_cast<unsigned>(dimension)];
    return t[0][index & 0xffu] ^ t[1][(index >> 8u) & 0xffu] ^ t[2][(index >> 16u) & 0xffu] ^
           t[3][index >> 24u];
}

/// reverse_bits(sobol_u32(index, dimension)) by four lookups, without reversing: what
/// owen_scramble reverses first, so a scrambled Sobol' value costs one reversal, not two.
[[nodiscard]] constexpr std::uint32_t sobol_reversed_u32(std::uint32_t index, int dimension) {
    if (dimension == 0) return index;  // van der Corput reversed is the index itself
    const auto& t = detail::kSobolReversedByteTables[static_cast<unsigned>(dimension)];
    return t[0][index & 0xffu] ^ t[1][(index >> 8u) & 0xffu] ^ t[2][(index >> 16u) & 0xffu] ^
           t[3][index >> 24u];
}

/// Sobol' dimensions 0 and 1 of point i, each bit-reversed, from r = reverse_bits(i):
/// sobol_reversed_u32(i, 0) in the low 32 bits, sobol_reversed_u32(i, 1) in the high 32.
[[nodiscard]] constexpr std::uint64_t sobol_reversed_pair(std::uint32_t r) {
    const auto& t = detail::kSobolPairTables;
    return t[0][r & 0xffu] ^ t[1][(r >> 8u) & 0xffu] ^ t[2][(r >> 16u) & 0xffu] ^ t[3][r >> 24u];
}

/// reverse_bits of each 32-bit half of x, the halves exchanged: reverse_bits(high) in the
/// low half, reverse_bits(low) in the high half. Two reversals for about the price of one:
/// the swaps inside bytes act on both halves at once, and one 64-bit byte swap ends both.
[[nodiscard]] constexpr std::uint64_t reverse_bits_halves(std::uint64_t x) {
    x = ((x >> 1u) & 0x5555555555555555ULL) | ((x & 0x5555555555555555ULL) << 1u);
    x = ((x >> 2u) & 0x3333333333333333ULL) | ((x & 0x3333333333333333ULL) << 2u);
    x = ((x >> 4u) & 0x0f0f0f0f0f0f0f0fULL) | ((x & 0x0f0f0f0f0f0f0f0fULL) << 4u);
    return __builtin_bswap64(x);
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
