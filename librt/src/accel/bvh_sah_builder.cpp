// build_sah_bvh: the parallel binned SAH builder. Its own file, ~590 lines, over the usual
// 400: it is one class (SahBuilder) whose binning, SIMD sweep, partition and task queue
// share its state and its SIMD helpers (V4, Box4, Box3x); the median builder shares only
// the input check (bvh_build_input.h).

#include "accel/bvh_build_input.h"
#include "core/parallel.h"

#include <librt/accel/bvh_builder.h>
#include <librt/core/error.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <string>
#include <thread>
#include <vector>

namespace librt {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Four floats handled as one SIMD register where the compiler can (GCC/Clang vector
/// extension: SSE on x86-64, NEON on aarch64); lane 3 is unused padding.
using V4 = float __attribute__((vector_size(16)));
using V4i = std::int32_t __attribute__((vector_size(16)));
using V4u = std::uint32_t __attribute__((vector_size(16)));

inline V4 vmin(V4 a, V4 b) { return a < b ? a : b; }
inline V4 vmax(V4 a, V4 b) { return a > b ? a : b; }
inline V4 splat(float x) { return V4{x, x, x, x}; }
inline V4 load3(const glm::vec3& v) { return V4{v.x, v.y, v.z, 0.0f}; }

/// An axis-aligned box as two V4s (lane 3 unused).
struct Box4 {
    V4 lo = splat(kInf);
    V4 hi = splat(-kInf);

    void grow(V4 l, V4 h) {
        lo = vmin(lo, l);
        hi = vmax(hi, h);
    }
    void grow(const Box4& b) { grow(b.lo, b.hi); }
    /// Half the surface area, dx dy + dy dz + dz dx: the SAH only uses ratios of areas.
    [[nodiscard]] float half_area() const {
        const V4 d = hi - lo;
        if (d[0] < 0.0f || d[1] < 0.0f || d[2] < 0.0f) return 0.0f;
        return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
    }
    [[nodiscard]] BBox to_bbox() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }
};

/// out[k] = {x[k], y[k], z[k], 0} for k = 0, 1, 2: a 4 x 4 transpose in six shuffles.
inline void transpose3(V4 x, V4 y, V4 z, V4 out[3]) {
    const V4 w = splat(0.0f);
    const V4 xy01 = __builtin_shufflevector(x, y, 0, 4, 1, 5);  // x0 y0 x1 y1
    const V4 xy23 = __builtin_shufflevector(x, y, 2, 6, 3, 7);  // x2 y2 x3 y3
    const V4 zw01 = __builtin_shufflevector(z, w, 0, 4, 1, 5);  // z0 0 z1 0
    const V4 zw23 = __builtin_shufflevector(z, w, 2, 6, 3, 7);  // z2 0 z3 0
    out[0] = __builtin_shufflevector(xy01, zw01, 0, 1, 4, 5);
    out[1] = __builtin_shufflevector(xy01, zw01, 2, 3, 6, 7);
    out[2] = __builtin_shufflevector(xy23, zw23, 0, 1, 4, 5);
}

/// Three boxes transposed, box a in lane a: lo[k], hi[k] hold coordinate k of each (lane 3
/// unused), so that growing them and taking their areas are plain SIMD operations.
struct Box3x {
    V4 lo[3] = {splat(kInf), splat(kInf), splat(kInf)};
    V4 hi[3] = {splat(-kInf), splat(-kInf), splat(-kInf)};

    void grow(const Box3x& b) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = vmin(lo[k], b.lo[k]);
            hi[k] = vmax(hi[k], b.hi[k]);
        }
    }
    /// Box4::half_area of each box, by the same operations (+inf for an empty box).
    [[nodiscard]] V4 half_areas() const {
        const V4 dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
        return dx * dy + dy * dz + dz * dx;
    }
};

/// A bin: the box of its primitives and their number, on a cache line of its own (the
/// binning loop's address arithmetic is then a shift).
struct alignas(64) Bin {
    Box4 box;
    std::uint32_t count = 0;
};
static_assert(sizeof(Bin) == 64);

/// A primitive as the SAH builder sees it; the array of them is partitioned in place,
/// so each level streams contiguous memory:
///   bytes  0..15  box lo.xyz, padding
///   bytes 16..31  box hi.xyz, padding
///   bytes 32..47  centre.xyz (what is binned), padding
/// (the primitive index lives in a parallel array, swapped along).
struct BuildRef {
    Box4 box;
    V4 c;
};
static_assert(sizeof(BuildRef) == 48, "BuildRef must stay 48 bytes");

/// A node under construction (trivially default-constructible, so the buffer of them is
/// allocated untouched):
///   bytes  0..31  box (Box4: lo.xyz + padding, hi.xyz + padding)
///   bytes 32..35  first slot (leaf) or first child (interior)
///   bytes 36..39  primitive count (leaf) or 0 (interior)
///   bytes 40..47  padding to Box4's 16-byte alignment
struct RawNode {
    Box4 box;
    std::uint32_t index;
    std::uint32_t count;
};
static_assert(sizeof(RawNode) == 48, "RawNode must stay 48 bytes");

/// A node whose primitives are refs_[begin, end), with the bounds of their centres.
struct SahTask {
    std::uint32_t node = 0;
    std::uint32_t begin = 0;
    std::uint32_t end = 0;
    std::uint32_t depth = 0;
    Box4 centroid_bounds;
};

/// Parallel binned SAH builder. Workers take subtrees from a shared queue; a subtree
/// of at least kGrain primitives is offered back to the queue, smaller ones are built
/// on the worker's own stack. Node slots come from an atomic counter and are renumbered
/// depth first at the end, so the result does not depend on scheduling.
class SahBuilder {
public:
    SahBuilder(std::span<const BBox> boxes, std::span<const glm::vec3> centers,
               const SahConfig& config)
        : boxes_(boxes), centers_(centers), config_(config) {
        bin_count_ = std::clamp(config.bin_count, 2u, 256u);
        max_leaf_ = std::max(config.max_leaf_size, 1u);
        block_ = std::max(config.leaf_block_size, 1u);
        leaf_wins_one_block_ =
            config.traversal_cost >= config.intersection_cost && config.intersection_cost >= 0.0f;
        threads_ = config.thread_count ? config.thread_count
                                       : std::max(1u, std::thread::hardware_concurrency());
        // B(n) for every n a node can hold is looked up, not divided, in the sweep.
        blocks_.resize(boxes.size() + 1);
        for (std::size_t k = 0; k < blocks_.size(); ++k)
            blocks_[k] = static_cast<float>((k + block_ - 1) / block_);
    }

    Bvh run() {
        const auto n = static_cast<std::uint32_t>(boxes_.size());
        if (n == 0) return {};
        refs_ = detail::make_large_buffer<BuildRef>(n);
        ids_ = detail::make_large_buffer<std::uint32_t>(n);
        nodes_ = detail::make_large_buffer<RawNode>(2 * std::size_t{n} - 1);
        // The references and the root's bounds, in parallel parts merged in part order.
        const unsigned parts = std::min(threads_, detail::threads_for(n));
        std::vector<Box4> part_boxes(parts), part_centroids(parts);
        // Each part also checks its primitives (check_build_input's test, in SIMD: c - c is
        // 0 for a finite c, NaN otherwise; x == x fails for NaN) and keeps its first bad one.
        std::vector<std::size_t> part_bad(parts, n);
        detail::parallel_parts(n, parts, [&](unsigned p, std::size_t begin, std::size_t end) {
            Box4 box, centroids;
            V4i valid = V4i{} - 1;
            for (std::size_t i = begin; i < end; ++i) {
                BuildRef& r = refs_[i];
                r.box = Box4{load3(boxes_[i].lo), load3(boxes_[i].hi)};
                r.c = load3(centers_[i]);
                ids_[i] = static_cast<std::uint32_t>(i);
                box.grow(r.box);
                centroids.grow(r.c, r.c);
                valid &= (r.c - r.c == 0.0f) & (r.box.lo == r.box.lo) & (r.box.hi == r.box.hi);
            }
            part_boxes[p] = box;
            part_centroids[p] = centroids;
            if (valid[0] & valid[1] & valid[2]) return;
            for (std::size_t i = begin; i < end; ++i) {
                if (!detail::primitive_is_valid(boxes_[i], centers_[i])) {
                    part_bad[p] = i;
                    return;
                }
            }
        });
        for (unsigned p = 0; p < parts; ++p)
            if (part_bad[p] < n) detail::throw_bad_primitive(part_bad[p], centers_[part_bad[p]]);
        SahTask root{0, 0, n, 0, {}};
        Box4 root_box;
        for (unsigned p = 0; p < parts; ++p) {
            root_box.grow(part_boxes[p]);
            root.centroid_bounds.grow(part_centroids[p]);
        }
        nodes_[0].box = root_box;
        next_node_ = 1;
        queue_.push_back(root);
        pending_ = 1;

        const unsigned threads = n >= 2 * kGrain ? threads_ : 1u;
        std::vector<std::thread> helpers;
        // Under a memory limit a helper may not start (its stack) or a worker may fail to
        // allocate: the build then ends with that exception here, never std::terminate.
        try {
            helpers.reserve(threads - 1);
            for (unsigned t = 1; t < threads; ++t) helpers.emplace_back([this] { worker(); });
        } catch (const std::exception&) {
            // Fewer helpers (none if the reserve failed: a reallocation must not destroy a
            // running thread); the workers that run take every task.
        }
        worker();
        for (std::thread& t : helpers) t.join();
        if (error_) std::rethrow_exception(error_);
        return finish(n);
    }

private:
    static constexpr std::uint32_t kGrain = 4096;
    /// Nodes of at least this many primitives are partitioned by a threshold on the centre.
    static constexpr std::uint32_t kThresholdNodeSize = 128;

    /// The least float t in (lo, hi] with bin_of(t) >= bin, for a bin_of that is monotonic
    /// in its argument with bin_of(lo) < bin <= bin_of(hi): bisection on the floats taken in
    /// order (their bit patterns, negative ones mirrored, are then ordered integers).
    template <class BinOf>
    static float first_of_bin(BinOf bin_of, float lo, float hi, std::int32_t bin) {
        constexpr std::int64_t kSign = std::numeric_limits<std::int32_t>::min();
        auto key = [](float f) {
            const auto i = static_cast<std::int64_t>(std::bit_cast<std::int32_t>(f));
            return i >= 0 ? i : kSign - i;
        };
        auto value = [](std::int64_t k) {
            return std::bit_cast<float>(static_cast<std::int32_t>(k >= 0 ? k : kSign - k));
        };
        std::int64_t below = key(lo), at = key(hi);
        while (at - below > 1) {
            const std::int64_t mid = below + (at - below) / 2;
            (bin_of(value(mid)) >= bin ? at : below) = mid;
        }
        return value(at);
    }

    /// Per-worker scratch space.
    struct Scratch {
        std::vector<Bin> bins;       // 3 axes x bin_count_
        std::vector<Box3x> axes;     // the bins transposed for the sweep
        std::vector<V4> right_cost;  // per bin, lane = axis: A_R B(N_R) right of its left plane
        std::vector<SahTask> stack;
    };

    /// Takes tasks until none are left; the first exception of any worker is kept in
    /// error_ and stops them all.
    void worker() noexcept {
        try {
            take_tasks();
        } catch (...) {
            const std::lock_guard lock(mutex_);
            if (!error_) error_ = std::current_exception();
            ready_.notify_all();
        }
    }

    void take_tasks() {
        Scratch s;
        s.bins.resize(3 * std::size_t{bin_count_});
        s.axes.resize(bin_count_);
        s.right_cost.resize(bin_count_);
        for (;;) {
            SahTask task;
            {
                std::unique_lock lock(mutex_);
                ready_.wait(lock, [&] { return error_ || !queue_.empty() || pending_ == 0; });
                if (error_ || queue_.empty()) return;
                task = queue_.back();
                queue_.pop_back();
            }
            run_subtree(task, s);
            const std::lock_guard lock(mutex_);
            if (--pending_ == 0) ready_.notify_all();
        }
    }

    void run_subtree(const SahTask& root, Scratch& s) {
        s.stack.clear();
        s.stack.push_back(root);
        while (!s.stack.empty()) {
            const SahTask task = s.stack.back();
            s.stack.pop_back();
            SahTask children[2];
            if (!split(task, s, children)) continue;
            for (const SahTask& child : children) {
                if (threads_ > 1 && child.end - child.begin >= kGrain) {
                    const std::lock_guard lock(mutex_);
                    queue_.push_back(child);
                    ++pending_;
                    ready_.notify_one();
                } else {
                    s.stack.push_back(child);
                }
            }
        }
    }

    /// Evaluates every bin plane (bins and counts from s) and keeps the cheapest
    /// A_L B(N_L) + A_R B(N_R) in best_*. The three axes go through one SIMD sweep, lane a
    /// for axis a, on the bins transposed once (s.axes[b]: coordinate k of the three axes'
    /// bin-b boxes in lo[k], hi[k]), with the same float operations per axis as a scalar
    /// sweep and the first of equal costs in (axis, bin) order: the choice is the scalar one.
    /// A plane with nothing on one side needs no test: that side's box is empty (area +inf)
    /// and B(0) = 0, so its cost is inf * 0 = NaN, which never compares less. An axis whose
    /// centres coincide has them all in bin 0, so each of its planes is such a plane.
    void sweep(Scratch& s, std::uint32_t bin_count, float& best_cost, int& best_axis,
               std::int32_t& best_bin) const {
        const Bin* bins0 = s.bins.data();
        const Bin* bins1 = bins0 + bin_count;
        const Bin* bins2 = bins0 + 2 * bin_count;
        const float* blocks = blocks_.data();
        Box3x* axes = s.axes.data();
        for (std::uint32_t b = 0; b < bin_count; ++b) {
            transpose3(bins0[b].box.lo, bins1[b].box.lo, bins2[b].box.lo, axes[b].lo);
            transpose3(bins0[b].box.hi, bins1[b].box.hi, bins2[b].box.hi, axes[b].hi);
        }
        // Sweep from the right for A_R B(N_R) right of each plane...
        Box3x acc;
        std::uint32_t n0 = 0, n1 = 0, n2 = 0;
        for (std::uint32_t b = bin_count - 1; b > 0; --b) {
            acc.grow(axes[b]);
            n0 += bins0[b].count;
            n1 += bins1[b].count;
            n2 += bins2[b].count;
            s.right_cost[b] = acc.half_areas() * V4{blocks[n0], blocks[n1], blocks[n2], 0.0f};
        }
        // ...then from the left, evaluating A_L B(N_L) + A_R B(N_R) at each plane; each lane
        // keeps its first minimum.
        acc = Box3x{};
        n0 = n1 = n2 = 0;
        V4 best = splat(kInf);
        V4i best_b{}, plane{};
        for (std::uint32_t b = 0; b + 1 < bin_count; ++b) {
            acc.grow(axes[b]);
            n0 += bins0[b].count;
            n1 += bins1[b].count;
            n2 += bins2[b].count;
            plane += 1;
            const V4 cost = acc.half_areas() * V4{blocks[n0], blocks[n1], blocks[n2], 0.0f} +
                            s.right_cost[b + 1];
            const V4i better = cost < best;
            best = better ? cost : best;
            best_b = better ? plane : best_b;
        }
        for (int a = 0; a < 3; ++a) {
            if (best[a] < best_cost) {
                best_cost = best[a];
                best_axis = a;
                best_bin = best_b[a];
            }
        }
    }

    /// Two-pointer partition of the task's references, those for which goes_left holds
    /// first, gathering each side's centroid bounds; returns where the right side starts.
    template <class GoesLeft>
    std::uint32_t partition(const SahTask& task, GoesLeft goes_left, Box4& left_cb,
                            Box4& right_cb) {
        // Locals, not members or references: the swaps' stores could alias those, which
        // would keep the bounds in memory and reload the arrays' addresses every step.
        BuildRef* const refs = refs_.get();
        std::uint32_t* const ids = ids_.get();
        Box4 left, right;
        std::uint32_t i = task.begin, j = task.end;
        for (;;) {
            while (i < j && goes_left(refs[i])) {
                left.grow(refs[i].c, refs[i].c);
                ++i;
            }
            while (i < j && !goes_left(refs[j - 1])) {
                --j;
                right.grow(refs[j].c, refs[j].c);
            }
            if (i >= j) break;
            std::swap(refs[i], refs[j - 1]);
            std::swap(ids[i], ids[j - 1]);
        }
        left_cb = left;
        right_cb = right;
        return i;
    }

    /// The bin of centre coordinate c on an axis whose centroid bounds start at lo: the same
    /// operations as split()'s bins_of, one lane, so both put a centre in one bin.
    static std::int32_t bin_index(float c, float lo, float scale, float last_bin) {
        float f = (c - lo) * scale;
        f = f > 0.0f ? f : 0.0f;
        f = f < last_bin ? f : last_bin;
        return static_cast<std::int32_t>(f);
    }

    /// Splits one node, or makes it a leaf (returns false).
    bool split(const SahTask& task, Scratch& s, SahTask children[2]) {
        RawNode& node = nodes_[task.node];
        const std::uint32_t n = task.end - task.begin;
        auto make_leaf = [&] {
            node.index = task.begin;
            node.count = n;
            return false;
        };
        if (n <= 1 || task.depth >= kMaxBvhDepth) return make_leaf();
        const float node_area = node.box.half_area();
        // A node of one block: a split costs T + I (A_L + A_R) / A >= T, the leaf I, so with
        // T >= I the leaf wins whatever the binning would find (skipping it keeps the tree).
        if (n <= block_ && n <= max_leaf_ && node_area > 0.0f && leaf_wins_one_block_)
            return make_leaf();

        // Fewer bins for small nodes: binning a few primitives into 32 bins mostly
        // sweeps empty ones.
        const std::uint32_t bin_count = std::min(bin_count_, std::max(4u, n));
        const Box4& cb = task.centroid_bounds;
        // Bin of a centre on an axis: (c - lo) * bins / extent, clamped to [0, bins - 1]
        // while still a float, so the float -> int conversion is always in range. The scale
        // comes from the extent in double, where it cannot overflow (lo, hi of +-3e38) nor
        // underflow; a tiny positive extent (denormal centroids, 1e-40 apart) gives an
        // infinite scale: then c == lo makes 0 * inf = NaN, which the clamp sends to bin 0,
        // and every other centre goes to the last bin. The bin stays monotonic in c, which
        // the partition below relies on.
        bool usable[3];
        V4 scale = splat(0.0f);
        for (int a = 0; a < 3; ++a) {
            const double extent = double(cb.hi[a]) - double(cb.lo[a]);
            usable[a] = extent > 0.0;
            if (!usable[a]) continue;
            const double axis_scale = double(bin_count) / extent;
            scale[a] = axis_scale <= double(std::numeric_limits<float>::max())
                           ? static_cast<float>(axis_scale)
                           : kInf;
        }
        const float last_bin = static_cast<float>(bin_count - 1);
        const V4 zero = splat(0.0f), last = splat(last_bin);
        auto bins_of = [&](const BuildRef& r) {
            V4 f = (r.c - cb.lo) * scale;
            f = f > zero ? f : zero;  // NaN fails the comparison: bin 0
            f = f < last ? f : last;
            return __builtin_convertvector(f, V4i);
        };
        auto bin_at = [&](float c, int a) { return bin_index(c, cb.lo[a], scale[a], last_bin); };

        float best_cost = kInf;
        int best_axis = -1;
        std::int32_t best_bin = 0;
        if (usable[0] || usable[1] || usable[2]) {
            Bin* bins = s.bins.data();
            std::fill(bins, bins + 3 * bin_count, Bin{});
            // Byte offsets of each axis' bin, computed in SIMD (axis a's bins start at
            // a * bin_count): the loop then needs no per-axis address arithmetic.
            const auto stride = static_cast<std::uint32_t>(bin_count);
            const V4u first = {0, stride, 2 * stride, 0};
            auto* base = reinterpret_cast<unsigned char*>(bins);
            for (std::uint32_t i = task.begin; i < task.end; ++i) {
                const BuildRef& r = refs_[i];
                const V4u offset = (__builtin_convertvector(bins_of(r), V4u) + first)
                                   << static_cast<std::uint32_t>(std::countr_zero(sizeof(Bin)));
                for (int a = 0; a < 3; ++a) {
                    Bin& bin = *reinterpret_cast<Bin*>(base + offset[a]);
                    bin.box.grow(r.box);
                    ++bin.count;
                }
            }
            sweep(s, bin_count, best_cost, best_axis, best_bin);
        }

        if (best_axis >= 0 && node_area > 0.0f) {
            // Full SAH cost of splitting against the cost of a leaf.
            const float split_cost =
                config_.traversal_cost + config_.intersection_cost * best_cost / node_area;
            const float leaf_cost = config_.intersection_cost * blocks_[n];
            if (split_cost >= leaf_cost && n <= max_leaf_) return make_leaf();
        } else if (best_axis < 0 && n <= max_leaf_) {
            return make_leaf();
        }
        // (A flat node, of zero area, takes any valid split.)

        std::uint32_t mid;
        Box4 left_box, right_box, left_cb, right_cb;
        if (best_axis < 0) {
            // All centroids coincide: split the range in half so leaves stay small.
            mid = task.begin + n / 2;
            for (std::uint32_t i = task.begin; i < task.end; ++i) {
                const BuildRef& r = refs_[i];
                (i < mid ? left_box : right_box).grow(r.box);
                (i < mid ? left_cb : right_cb).grow(r.c, r.c);
            }
        } else {
            const Bin* axis_bins = s.bins.data() + best_axis * bin_count;
            for (std::int32_t b = 0; b < std::int32_t(bin_count); ++b)
                (b < best_bin ? left_box : right_box).grow(axis_bins[b].box);
            // Two-pointer partition by bin, gathering each side's centroid bounds. The bin
            // is monotonic in the centre, so "bin < best_bin" is "c < t" for the least float
            // t of bin best_bin (found by bisection, ~32 bin evaluations: for large nodes
            // only, where it saves more than it costs).
            // (The predicates hold copies, which stay in registers through the swaps.)
            const int a = best_axis;
            if (n >= kThresholdNodeSize) {
                const float t = first_of_bin([&](float c) { return bin_at(c, a); }, cb.lo[a],
                                             cb.hi[a], best_bin);
                mid = partition(
                    task, [a, t](const BuildRef& r) { return r.c[a] < t; }, left_cb, right_cb);
            } else {
                const float lo = cb.lo[a], axis_scale = scale[a];
                mid = partition(
                    task,
                    [=](const BuildRef& r) {
                        return bin_index(r.c[a], lo, axis_scale, last_bin) < best_bin;
                    },
                    left_cb, right_cb);
            }
        }

        const std::uint32_t left = next_node_.fetch_add(2, std::memory_order_relaxed);
        nodes_[left].box = left_box;
        nodes_[left + 1].box = right_box;
        node.index = left;
        node.count = 0;
        children[0] = {left, task.begin, mid, task.depth + 1, left_cb};
        children[1] = {left + 1, mid, task.end, task.depth + 1, right_cb};
        return true;
    }

    /// Renumbers the nodes depth first (siblings stay adjacent) into a Bvh.
    Bvh finish(std::uint32_t n) {
        Bvh bvh;
        bvh.nodes.resize(next_node_.load());
        bvh.prim_indices.assign(ids_.get(), ids_.get() + n);
        struct Item {
            std::uint32_t raw, out, depth;
        };
        std::vector<Item> stack{{0, 0, 0}};
        std::uint32_t next = 1;
        while (!stack.empty()) {
            const Item item = stack.back();
            stack.pop_back();
            const RawNode& raw = nodes_[item.raw];
            BvhNode& out = bvh.nodes[item.out];
            out.bounds = raw.box.to_bbox();
            bvh.depth = std::max(bvh.depth, item.depth);
            if (raw.count != 0) {
                out.index = raw.index;
                out.prim_count = raw.count;
                continue;
            }
            out.index = next;
            out.prim_count = 0;
            next += 2;
            stack.push_back({raw.index + 1, out.index + 1, item.depth + 1});
            stack.push_back({raw.index, out.index, item.depth + 1});
        }
        return bvh;
    }

    std::span<const BBox> boxes_;
    std::span<const glm::vec3> centers_;
    SahConfig config_;
    std::uint32_t bin_count_, max_leaf_, block_;
    unsigned threads_;
    bool leaf_wins_one_block_ = false;  // T >= I >= 0: a node of one block is always a leaf
    std::vector<float> blocks_;         // B(n) = ceil(n / block_)

    detail::LargeBuffer<BuildRef> refs_;
    detail::LargeBuffer<std::uint32_t> ids_;  // primitive index of each ref
    detail::LargeBuffer<RawNode> nodes_;
    std::atomic<std::uint32_t> next_node_{0};

    std::mutex mutex_;  // guards queue_ and pending_
    std::condition_variable ready_;
    std::vector<SahTask> queue_;
    std::size_t pending_ = 0;   // tasks queued or running
    std::exception_ptr error_;  // the first exception a worker threw, guarded by mutex_
};

}  // namespace

Bvh build_sah_bvh(std::span<const BBox> boxes, std::span<const glm::vec3> centers,
                  const SahConfig& config) {
    detail::check_build_sizes(boxes, centers);
    SahBuilder builder(boxes, centers, config);
    return builder.run();
}

}  // namespace librt
