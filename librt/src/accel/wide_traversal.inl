// Private, no include guard: the wide-BVH traversal shared by every instruction set.
// Each wide_<isa>.cpp includes it inside its own namespace (librt::detail::<isa>) after
// switching the compiler to that instruction set, with a policy `K` providing:
//   K::NodeRay K::prepare_nodes(const Ray&)
//   std::uint32_t K::intersect_node(const WideBvhNode&, const K::NodeRay&, float t_min,
//                                   float t_max, float* t_enter)
//       -> bit i set when child i's box is entered within [t_min, t_max]; t_enter[i] = entry
//   K::TriRay K::prepare_triangles(const Ray&)
//   bool K::intersect_block(const TriangleBlock&, const K::TriRay&, float t_min, float& t_max,
//                           std::uint32_t& lane, float& u, float& v)
//       -> true when a lane is hit in (t_min, t_max); t_max, lane, u, v become the nearest
//   bool K::occluded_block(const TriangleBlock&, const K::TriRay&, float t_min, float t_max)
// Needs <bit>, <cstdint>, librt/accel/bvh_traversal.h (is_traceable) and wide_bvh.h.

/// A deferred child: its reference and the distance at which the ray enters its box.
///   bytes 0..3  child reference (as in WideBvhNode::child)
///   bytes 4..7  entry distance
struct StackEntry {
    std::uint32_t ref;
    float t_enter;
};
static_assert(sizeof(StackEntry) == 8, "StackEntry must stay 8 bytes");

/// A node visit pushes at most eight entries and takes one back, so the stack never holds
/// more than seven per level above the current node plus eight.
inline constexpr std::uint32_t kWideStackSize = (kWideBvhWidth - 1) * kMaxWideBvhDepth + kWideBvhWidth;

/// Asks the memory system for every cache line of a deferred child's node or leaf blocks,
/// so that they are (likely) in cache when the child's turn comes while the nearer subtree
/// is walked.
inline void prefetch_child(const WideBvhNode* nodes, const TriangleBlock* blocks, std::uint32_t ref) {
    const char* p;
    std::size_t bytes;
    if (WideBvhNode::is_leaf(ref)) {
        p = reinterpret_cast<const char*>(blocks + WideBvhNode::first_block(ref));
        bytes = WideBvhNode::block_count(ref) * sizeof(TriangleBlock);
    } else {
        p = reinterpret_cast<const char*>(nodes + ref);
        bytes = sizeof(WideBvhNode);
    }
    const char* const last = p + bytes - 1;  // an unaligned run may span one more line
    for (; p <= last; p += 64) __builtin_prefetch(p);
    __builtin_prefetch(last);
}

/// Front-to-back traversal: the children a node's test hits are visited nearest first,
/// the others deferred with their entry distance and skipped when a nearer hit is known.
/// With AnyHit the walk stops at the first hit. Fills *hit (closest hit only).
template <class K, bool AnyHit>
inline bool traverse_wide(const WideBvh& bvh, const Ray& ray, PrimitiveHit* hit) {
    if (bvh.nodes.empty() || !is_traceable(ray)) return false;
    const typename K::NodeRay node_ray = K::prepare_nodes(ray);
    const typename K::TriRay tri_ray = K::prepare_triangles(ray);
    const float t_min = ray.t_min;
    float t_max = ray.t_max;
    const WideBvhNode* nodes = bvh.nodes.data();
    const TriangleBlock* blocks = bvh.blocks.data();

    StackEntry stack[kWideStackSize];
    std::uint32_t sp = 0;
    std::uint32_t current = 0;  // the root node
    std::uint32_t hit_block = 0, hit_lane = 0;
    float hit_u = 0.0f, hit_v = 0.0f;
    bool found = false;
    for (;;) {
        if (!WideBvhNode::is_leaf(current)) {
            const WideBvhNode& node = nodes[current];
            alignas(32) float t_enter[kWideBvhWidth];
            std::uint32_t mask = K::intersect_node(node, node_ray, t_min, t_max, t_enter);
            if (mask != 0) {
                const auto i0 = static_cast<std::uint32_t>(std::countr_zero(mask));
                mask &= mask - 1;
                if (mask == 0) {  // one child: go down without touching the stack
                    current = node.child[i0];
                    continue;
                }
                const auto i1 = static_cast<std::uint32_t>(std::countr_zero(mask));
                mask &= mask - 1;
                if (mask == 0) {  // two: defer the farther
                    const bool swap = t_enter[i1] < t_enter[i0];
                    const std::uint32_t near = swap ? i1 : i0, far = swap ? i0 : i1;
                    prefetch_child(nodes, blocks, node.child[far]);
                    stack[sp++] = {node.child[far], t_enter[far]};
                    current = node.child[near];
                    continue;
                }
                // Three or more: push them all, insertion-sort the new entries so the
                // nearest is on top, and take it.
                const std::uint32_t base = sp;
                stack[sp++] = {node.child[i0], t_enter[i0]};
                stack[sp++] = {node.child[i1], t_enter[i1]};
                do {
                    const auto i = static_cast<std::uint32_t>(std::countr_zero(mask));
                    mask &= mask - 1;
                    stack[sp++] = {node.child[i], t_enter[i]};
                } while (mask != 0);
                for (std::uint32_t k = base; k < sp; ++k) prefetch_child(nodes, blocks, stack[k].ref);
                for (std::uint32_t k = base + 1; k < sp; ++k) {
                    const StackEntry e = stack[k];
                    std::uint32_t j = k;
                    for (; j > base && stack[j - 1].t_enter < e.t_enter; --j) stack[j] = stack[j - 1];
                    stack[j] = e;
                }
                current = stack[--sp].ref;
                continue;
            }
        } else {
            const std::uint32_t first = WideBvhNode::first_block(current);
            const std::uint32_t end = first + WideBvhNode::block_count(current);
            for (std::uint32_t b = first; b < end; ++b) {
                if constexpr (AnyHit) {
                    if (K::occluded_block(blocks[b], tri_ray, t_min, t_max)) return true;
                } else if (K::intersect_block(blocks[b], tri_ray, t_min, t_max, hit_lane, hit_u, hit_v)) {
                    hit_block = b;
                    found = true;
                }
            }
        }
        // Take the next deferred child the ray enters before the nearest hit so far.
        for (;;) {
            if (sp == 0) {
                if (found && hit) *hit = {t_max, hit_u, hit_v, blocks[hit_block].id[hit_lane]};
                return found;
            }
            const StackEntry& e = stack[--sp];
            if (e.t_enter <= t_max) {
                current = e.ref;
                break;
            }
        }
    }
}

/// The entry points every wide_<isa>.cpp exports.
template <class K>
inline PrimitiveHit intersect_with(const WideBvh& bvh, const Ray& ray) {
    PrimitiveHit hit;
    traverse_wide<K, false>(bvh, ray, &hit);
    return hit;
}

template <class K>
inline bool occluded_with(const WideBvh& bvh, const Ray& ray) {
    return traverse_wide<K, true>(bvh, ray, nullptr);
}
