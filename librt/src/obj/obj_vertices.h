#pragma once

// Private: vertex unification for load_obj, one mesh vertex per distinct (v, vt, vn)
// corner of the OBJ.

#include <librt/core/error.h>

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

namespace librt::detail {

/// tinyobjloader's "no vt / vn" index.
inline constexpr std::int32_t kAbsent = -1;

/// One face corner as OBJ indexes it, after tinyobjloader made the indices 0-based.
struct Corner {
    std::int32_t v, vt, vn;
    bool operator==(const Corner&) const = default;
};

struct CornerHash {
    std::size_t operator()(const Corner& c) const noexcept {
        // splitmix64 finaliser over the packed indices: cheap and well mixed.
        std::uint64_t h = (std::uint64_t(std::uint32_t(c.v)) << 32) ^ std::uint32_t(c.vt);
        h ^= std::uint64_t(std::uint32_t(c.vn)) * 0x9E3779B97F4A7C15ull;
        h ^= h >> 30;
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 27;
        h *= 0x94D049BB133111EBull;
        h ^= h >> 31;
        return static_cast<std::size_t>(h);
    }
};

/// Maps (v, vt, vn) corners to mesh vertices. Vertex i is OBJ position i with the first
/// (vt, vn) it is used with, so positions-only files need no hashing and keep their order;
/// every further distinct pair for a position gets a new vertex, found again by hash.
class VertexUnifier {
public:
    /// positions holds the OBJ's positions; vertices for further (vt, vn) pairs are appended.
    explicit VertexUnifier(std::vector<glm::vec3>& positions)
        : positions_(positions),
          vt_(positions.size(), kAbsent),
          vn_(positions.size(), kAbsent),
          claimed_(positions.size(), 0) {}

    /// The vertex for a corner whose indices were checked.
    std::uint32_t vertex(const Corner& c) {
        const auto v = static_cast<std::size_t>(c.v);
        if (!claimed_[v]) {
            claimed_[v] = 1;
            vt_[v] = c.vt;
            vn_[v] = c.vn;
            return static_cast<std::uint32_t>(v);
        }
        if (vt_[v] == c.vt && vn_[v] == c.vn) return static_cast<std::uint32_t>(v);
        const auto [it, inserted] =
            extra_.try_emplace(c, static_cast<std::uint32_t>(positions_.size()));
        if (inserted) {
            if (positions_.size() >= std::numeric_limits<std::uint32_t>::max()) {
                throw Error("more than 2^32 - 1 vertices");
            }
            positions_.push_back(positions_[v]);
            vt_.push_back(c.vt);
            vn_.push_back(c.vn);
        }
        return it->second;
    }

    /// Per vertex: the vt index, or kAbsent.
    [[nodiscard]] const std::vector<std::int32_t>& vt() const { return vt_; }
    /// Per vertex: the vn index, or kAbsent.
    [[nodiscard]] const std::vector<std::int32_t>& vn() const { return vn_; }

private:
    std::vector<glm::vec3>& positions_;
    std::vector<std::int32_t> vt_, vn_;
    std::vector<std::uint8_t> claimed_;
    std::unordered_map<Corner, std::uint32_t, CornerHash> extra_;
};

}  // namespace librt::detail
