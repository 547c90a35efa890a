#include "wide_bvh.h"

#include <librt/core/error.h>

#include <algorithm>
#include <array>
#include <limits>
#include <optional>
#include <string>
#include <utility>

namespace librt::detail {
namespace {

/// Four floats as one SIMD register where the compiler can (GCC/Clang vector extension).
using V4 = float __attribute__((vector_size(16)));
constexpr float kInf = std::numeric_limits<float>::infinity();
inline V4 vmin(V4 a, V4 b) { return a < b ? a : b; }
inline V4 vmax(V4 a, V4 b) { return a > b ? a : b; }
inline V4 splat(float x) { return V4{x, x, x, x}; }

/// Writes child slot i of a wide node.
void set_child(WideBvhNode& node, std::uint32_t i, const BBox& box, std::uint32_t ref) {
    node.bounds[0][i] = box.lo.x;
    node.bounds[1][i] = box.hi.x;
    node.bounds[2][i] = box.lo.y;
    node.bounds[3][i] = box.hi.y;
    node.bounds[4][i] = box.lo.z;
    node.bounds[5][i] = box.hi.z;
    node.child[i] = ref;
}

WideBvhNode empty_node() {
    WideBvhNode node;
    for (std::uint32_t i = 0; i < kWideBvhWidth; ++i)
        set_child(node, i, BBox{}, WideBvhNode::kEmptyChild);
    return node;
}

class Collapser {
public:
    Collapser(const Bvh& bvh, std::span<const Triangle> triangles, std::span<const BBox> boxes,
              WideBvh& out)
        : bvh_(bvh), triangles_(triangles), boxes_(boxes), out_(out) {}

    void run() {
        // Reserve once (exact for blocks, a bound for nodes: each wide node but the
        // root and the leaf-splitting ones consumes a binary interior node), so the big
        // arrays are not copied while growing.
        std::size_t blocks = 0, split_nodes = 0, interior = 0;
        for (const BvhNode& n : bvh_.nodes) {
            if (n.is_leaf())
                count_leaf(n.prim_count, blocks, split_nodes);
            else
                ++interior;
        }
        out_.nodes.reserve(interior + split_nodes + 1);
        out_.blocks.reserve(blocks);
        out_.nodes.push_back(empty_node());
        fill(0, 0, 0);
    }

private:
    /// Fills wide node `wide` with the children reached by opening binary node `binary`.
    void fill(std::uint32_t wide, std::uint32_t binary, std::uint32_t depth) {
        check_depth(depth);
        std::uint32_t open[kWideBvhWidth];
        std::uint32_t count = 0;
        const BvhNode& root = bvh_.nodes[binary];
        if (root.is_leaf()) {
            open[count++] = binary;
        } else {
            open[count++] = root.index;
            open[count++] = root.index + 1;
        }
        // Greedy: open the interior child of largest area until there are eight.
        while (count < kWideBvhWidth) {
            int best = -1;
            float best_area = -1.0f;
            for (std::uint32_t i = 0; i < count; ++i) {
                const BvhNode& n = bvh_.nodes[open[i]];
                if (n.is_leaf()) continue;
                const float area = n.bounds.surface_area();
                if (area > best_area) {
                    best_area = area;
                    best = static_cast<int>(i);
                }
            }
            if (best < 0) break;
            const BvhNode& n = bvh_.nodes[open[best]];
            open[best] = n.index;
            open[count++] = n.index + 1;
        }
        // Free slots go to the binary leaves of two blocks (5..8 triangles), each split into
        // two one-block leaves where that saves work (Embree fills the eight slots with
        // leaves of at most four): fewer block tests per ray without more nodes.
        // (Planned only for a node with free slots: most nodes have none.)
        std::optional<std::array<LeafPieces, kWideBvhWidth>> pieces;  // pieces[i]: open[i]'s
        if (count < kWideBvhWidth) {
            pieces.emplace();
            for (std::uint32_t i = 0; i < count; ++i) {
                const BvhNode& n = bvh_.nodes[open[i]];
                if (n.is_leaf() && n.prim_count > kTriangleBlockSize &&
                    n.prim_count <= kSplitLeafMax)
                    plan_split(n.index, n.prim_count, n.bounds, (*pieces)[i]);
            }
            for (std::uint32_t free = kWideBvhWidth - count; free > 0; --free) {
                LeafPieces* best = nullptr;
                for (LeafPieces& p : *pieces)
                    if (!p.split && p.saving > 0.0f && (!best || p.saving > best->saving))
                        best = &p;
                if (!best) break;
                best->split = true;
            }
        }
        // Leaves first, so a node's blocks sit together; then the interior children.
        std::uint32_t pending_binary[kWideBvhWidth];
        std::uint32_t pending_wide[kWideBvhWidth];
        std::uint32_t pending = 0;
        std::uint32_t slot = 0;
        for (std::uint32_t i = 0; i < count; ++i) {
            const BvhNode& n = bvh_.nodes[open[i]];
            if (n.is_leaf()) {
                if (!pieces || !(*pieces)[i].split) {
                    set_child(out_.nodes[wide], slot++, n.bounds,
                              leaf(n.index, n.prim_count, depth));
                    continue;
                }
                const LeafPieces& p = (*pieces)[i];
                const std::span<const std::uint32_t> slots(p.slots, n.prim_count);
                set_child(out_.nodes[wide], slot++, slots_bounds(slots.first(p.cut)),
                          emit_blocks(slots.first(p.cut)));
                set_child(out_.nodes[wide], slot++, slots_bounds(slots.subspan(p.cut)),
                          emit_blocks(slots.subspan(p.cut)));
                continue;
            }
            const std::uint32_t ref = new_node();
            pending_binary[pending] = open[i];
            pending_wide[pending++] = ref;
            set_child(out_.nodes[wide], slot++, n.bounds, ref);
        }
        for (std::uint32_t k = 0; k < pending; ++k)
            fill(pending_wide[k], pending_binary[k], depth + 1);
    }

    /// Largest binary leaf fill() may split into two one-block leaves.
    static constexpr std::uint32_t kSplitLeafMax = 2 * kTriangleBlockSize;

    /// Cost of entering a leaf relative to testing one block of four (callgrind: ~60
    /// instructions against ~85 on the AVX2 path, docs/benchmarks.md).
    static constexpr float kLeafEntryCost = 0.7f;

    /// How fill() would split a binary leaf into two one-block leaves: its slots (in
    /// prim_indices) in the order of the cut, the first part's size, and the expected
    /// saving, in block tests per ray through the leaf's box, of splitting it.
    struct LeafPieces {
        std::uint32_t slots[kSplitLeafMax];
        std::uint32_t cut = 0;  ///< triangles of the first part
        float saving = 0.0f;    ///< > 0 when splitting pays
        bool split = false;     ///< chosen for a free slot
    };

    /// Plans the split of the leaf of 5..8 triangles at slots [begin, begin + count), box
    /// `box`: sorted by box centre along the centres' longest extent, cut where the two
    /// boxes' areas sum least. By surface area (a ray through the leaf's box enters a part's
    /// box with probability area ratio), the leaf costs entry + 2 blocks and the parts
    /// (A + B) / P (entry + 1 block); the saving is the difference.
    void plan_split(std::uint32_t begin, std::uint32_t count, const BBox& box,
                    LeafPieces& p) const {
        // In SIMD registers (lane 3 unused), with BBox's operations per lane: the same plan.
        V4 lo[kSplitLeafMax], hi[kSplitLeafMax];
        V4 centres_lo = splat(kInf), centres_hi = splat(-kInf);
        for (std::uint32_t k = 0; k < count; ++k) {
            const BBox& b = box_at(begin + k);
            lo[k] = V4{b.lo.x, b.lo.y, b.lo.z, 0.0f};
            hi[k] = V4{b.hi.x, b.hi.y, b.hi.z, 0.0f};
            const V4 twice = lo[k] + hi[k];  // twice the centre: the order is the same
            centres_lo = vmin(centres_lo, twice);
            centres_hi = vmax(centres_hi, twice);
        }
        const V4 extent = centres_hi - centres_lo;
        const int axis = extent[0] >= extent[1] ? (extent[0] >= extent[2] ? 0 : 2)
                                                : (extent[1] >= extent[2] ? 1 : 2);
        std::uint32_t order[kSplitLeafMax];
        float keys[kSplitLeafMax];
        for (std::uint32_t k = 0; k < count; ++k) {
            // Insertion sort, stable.
            const float key = lo[k][axis] + hi[k][axis];
            std::uint32_t j = k;
            for (; j > 0 && key < keys[j - 1]; --j) {
                keys[j] = keys[j - 1];
                order[j] = order[j - 1];
            }
            keys[j] = key;
            order[j] = k;
        }
        // BBox::surface_area of a box that is not empty.
        auto area = [](V4 l, V4 h) {
            const V4 d = h - l;
            return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
        };
        float prefix[kSplitLeafMax], suffix[kSplitLeafMax];
        V4 run_lo = splat(kInf), run_hi = splat(-kInf);
        for (std::uint32_t k = 0; k < count; ++k) {
            run_lo = vmin(run_lo, lo[order[k]]);
            run_hi = vmax(run_hi, hi[order[k]]);
            prefix[k] = area(run_lo, run_hi);
        }
        run_lo = splat(kInf);
        run_hi = splat(-kInf);
        for (std::uint32_t k = count; k-- > 0;) {
            run_lo = vmin(run_lo, lo[order[k]]);
            run_hi = vmax(run_hi, hi[order[k]]);
            suffix[k] = area(run_lo, run_hi);
        }
        float best = std::numeric_limits<float>::infinity();
        for (std::uint32_t k = count - kTriangleBlockSize; k <= kTriangleBlockSize; ++k) {
            if (prefix[k - 1] + suffix[k] < best) {
                best = prefix[k - 1] + suffix[k];
                p.cut = k;
            }
        }
        for (std::uint32_t k = 0; k < count; ++k) p.slots[k] = begin + order[k];
        const float whole = box.surface_area();
        p.saving =
            whole > 0.0f ? (kLeafEntryCost + 2.0f) - best / whole * (kLeafEntryCost + 1.0f) : 0.0f;
    }

    /// Box of the triangles at the given slots.
    [[nodiscard]] BBox slots_bounds(std::span<const std::uint32_t> slots) const {
        BBox b;
        for (const std::uint32_t slot : slots) b.extend(box_at(slot));
        return b;
    }

    /// Blocks and extra nodes leaf() will make for a leaf of `count` triangles.
    static void count_leaf(std::uint32_t count, std::size_t& blocks, std::size_t& nodes) {
        if (count <= kMaxLeafBlocks * kTriangleBlockSize) {
            blocks += (count + kTriangleBlockSize - 1) / kTriangleBlockSize;
            return;
        }
        ++nodes;
        const std::uint32_t chunk = (count + kWideBvhWidth - 1) / kWideBvhWidth;
        for (std::uint32_t s = 0; s < count; s += chunk)
            count_leaf(std::min(chunk, count - s), blocks, nodes);
    }

    /// A leaf reference for slots [begin, begin + count), or a node splitting them when
    /// they need more than kMaxLeafBlocks blocks.
    std::uint32_t leaf(std::uint32_t begin, std::uint32_t count, std::uint32_t depth) {
        if (count <= kMaxLeafBlocks * kTriangleBlockSize) return emit_blocks(begin, count);
        check_depth(depth + 1);
        const std::uint32_t node = new_node();
        const std::uint32_t chunk = (count + kWideBvhWidth - 1) / kWideBvhWidth;
        std::uint32_t i = 0;
        for (std::uint32_t s = begin; s < begin + count; s += chunk, ++i) {
            const std::uint32_t n = std::min(chunk, begin + count - s);
            BBox box;
            for (std::uint32_t k = s; k < s + n; ++k) box.extend(bounds(triangle_at(k)));
            const std::uint32_t ref = leaf(s, n, depth + 1);
            set_child(out_.nodes[node], i, box, ref);
        }
        return node;
    }

    /// Blocks for slots [begin, begin + count) of prim_indices.
    std::uint32_t emit_blocks(std::uint32_t begin, std::uint32_t count) {
        return emit_blocks(count, [begin](std::uint32_t k) { return begin + k; });
    }

    /// Blocks for the given slots of prim_indices, in that order.
    std::uint32_t emit_blocks(std::span<const std::uint32_t> slots) {
        return emit_blocks(static_cast<std::uint32_t>(slots.size()),
                           [slots](std::uint32_t k) { return slots[k]; });
    }

    /// Blocks for `count` slots of prim_indices, the k-th being slot_at(k).
    template <class SlotAt>
    std::uint32_t emit_blocks(std::uint32_t count, SlotAt slot_at) {
        const auto first = static_cast<std::uint32_t>(out_.blocks.size());
        const std::uint32_t block_count = (count + kTriangleBlockSize - 1) / kTriangleBlockSize;
        if (first + block_count - 1 > WideBvhNode::kMaxFirstBlock)
            throw Error("wide BVH: too many triangle blocks (" +
                        std::to_string(first + block_count) + ")");
        out_.blocks.resize(first + block_count);
        for (std::uint32_t b = 0; b < block_count; ++b) {
            TriangleBlock& block = out_.blocks[first + b];
            for (std::uint32_t lane = 0; lane < kTriangleBlockSize; ++lane) {
                const std::uint32_t k = b * kTriangleBlockSize + lane;
                // The triangles are gathered in leaf order: ask for one a few slots ahead.
                const bool real = k < count;
                const std::uint32_t slot = real ? slot_at(k) : 0;
                if (real && slot + 8 < bvh_.prim_indices.size())
                    __builtin_prefetch(&triangle_at(slot + 8));
                const Triangle& t = real ? triangle_at(slot) : kPadding;
                const float corners[3][3] = {
                    {t.p0.x, t.p0.y, t.p0.z}, {t.p1.x, t.p1.y, t.p1.z}, {t.p2.x, t.p2.y, t.p2.z}};
                for (int c = 0; c < 3; ++c)
                    for (int a = 0; a < 3; ++a) block.p[c][a][lane] = corners[c][a];
                block.id[lane] = real ? bvh_.prim_indices[slot] : kInvalidId;
            }
        }
        return WideBvhNode::make_leaf(first, block_count);
    }

    [[nodiscard]] const Triangle& triangle_at(std::uint32_t slot) const {
        return triangles_[bvh_.prim_indices[slot]];
    }

    /// The box of the triangle in a slot (the builder's, bounds() of the triangle).
    [[nodiscard]] const BBox& box_at(std::uint32_t slot) const {
        return boxes_[bvh_.prim_indices[slot]];
    }

    std::uint32_t new_node() {
        const auto index = static_cast<std::uint32_t>(out_.nodes.size());
        if (index >= WideBvhNode::kLeafBit) throw Error("wide BVH: too many nodes");
        out_.nodes.push_back(empty_node());
        return index;
    }

    void check_depth(std::uint32_t depth) {
        if (depth > kMaxWideBvhDepth) throw Error("wide BVH: deeper than kMaxWideBvhDepth");
        out_.depth = std::max(out_.depth, depth);
    }

    static constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    static constexpr Triangle kPadding{glm::vec3(kNaN), glm::vec3(kNaN), glm::vec3(kNaN)};
    const Bvh& bvh_;
    std::span<const Triangle> triangles_;
    std::span<const BBox> boxes_;
    WideBvh& out_;
};

}  // namespace

WideBvh collapse_to_wide(const Bvh& bvh, std::span<const Triangle> triangles,
                         std::span<const BBox> boxes) {
    if (boxes.size() != triangles.size())
        throw Error("collapse_to_wide: " + std::to_string(boxes.size()) + " boxes for " +
                    std::to_string(triangles.size()) + " triangles");
    WideBvh out;
    out.triangle_count = bvh.prim_indices.size();
    if (bvh.empty()) return out;
    for (const std::uint32_t id : bvh.prim_indices)
        if (id >= triangles.size())
            throw Error("collapse_to_wide: primitive " + std::to_string(id) + " but only " +
                        std::to_string(triangles.size()) + " triangles");
    out.bounds = bvh.bounds();
    Collapser(bvh, triangles, boxes, out).run();
    return out;
}

BvhStats wide_bvh_stats(const WideBvh& wide) {
    BvhStats s;
    s.node_count = wide.nodes.size();
    s.depth = wide.depth;
    s.bytes = wide.memory_bytes();
    const float root_area = wide.bounds.surface_area();
    // Area of a child's box relative to the root's (0 for a flat scene, whose SAH is moot).
    auto relative = [&](const WideBvhNode& node, std::uint32_t i) {
        return root_area > 0.0f ? double(node.child_bounds(i).surface_area()) / root_area : 0.0;
    };
    if (!wide.empty()) s.node_sah = 1.0;  // the root, whose box is the bounds
    for (const WideBvhNode& node : wide.nodes) {
        for (std::uint32_t i = 0; i < kWideBvhWidth; ++i) {
            const std::uint32_t ref = node.child[i];
            if (ref == WideBvhNode::kEmptyChild) continue;
            if (!WideBvhNode::is_leaf(ref)) {
                s.node_sah += relative(node, i);
                continue;
            }
            ++s.leaf_count;
            s.leaf_sah += relative(node, i) * WideBvhNode::block_count(ref);
            std::uint32_t size = 0;
            const std::uint32_t first = WideBvhNode::first_block(ref);
            for (std::uint32_t b = first; b < first + WideBvhNode::block_count(ref); ++b)
                for (const std::uint32_t id : wide.blocks[b].id) size += id != kInvalidId;
            s.max_leaf_size = std::max(s.max_leaf_size, size);
        }
    }
    return s;
}

}  // namespace librt::detail
