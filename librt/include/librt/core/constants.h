#pragma once

#include <numbers>

// The library's one pi, in core so that every area (geometry's sphere parameterisation as
// well as sampling's warps) uses the same constants.

namespace librt {

inline constexpr float kPi = std::numbers::pi_v<float>;
/// pi for arithmetic in double (the sphere-light cuts, whose walls are radius 1e5).
inline constexpr double kPiDouble = std::numbers::pi;
inline constexpr float kInvPi = std::numbers::inv_pi_v<float>;

}  // namespace librt
