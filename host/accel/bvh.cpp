#include "accel/bvh.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <future>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <thread>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace ray {

// ---------------------------------------------------------------------------------------
// Boxes

void BoundingBox::expand(const BoundingBox& b) {
    for (int a = 0; a < 3; ++a) {
        min[a] = std::min(min[a], b.min[a]);
        max[a] = std::max(max[a], b.max[a]);
    }
}

float BoundingBox::surfaceArea() const {
    if (empty()) return 0;
    float dx = max[0] - min[0], dy = max[1] - min[1], dz = max[2] - min[2];
    return 2 * (dx * dy + dy * dz + dz * dx);
}

namespace {

// The lanes of a node's bounds row: 0 left.min, 1 right.min, 2 left.max, 3 right.max.
float& lane(gpu::float4& v, int i) {
    switch (i) {
        case 0: return v.x;
        case 1: return v.y;
        case 2: return v.z;
        default: return v.w;
    }
}

float lane(const gpu::float4& v, int i) {
    switch (i) {
        case 0: return v.x;
        case 1: return v.y;
        case 2: return v.z;
        default: return v.w;
    }
}

// The largest float ≤ v, then one float step further down. The extra step covers the
// rounding of the double arithmetic that produced v (a few double ulps, far below one
// float ulp), so the float bound holds the exact primitive and not only its double box.
float floatBelow(double v) {
    float f = static_cast<float>(v);
    if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    return std::nextafter(f, -std::numeric_limits<float>::infinity());
}

float floatAbove(double v) {
    float f = static_cast<float>(v);
    if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
    return std::nextafter(f, std::numeric_limits<float>::infinity());
}

// Half-extents of the object-space box around the primitive (SPEC §2): the unit cube's,
// the torus's [−.5,.5]×[−.125,.125]×[−.5,.5], a mesh's own bounds
// (PrimitiveInstance::objectLo/objectHi, set by the loader).
Vec3 objectHalfExtents(const PrimitiveInstance& primitive) { return (primitive.objectHi - primitive.objectLo) * 0.5; }

Vec3 objectCentre(const PrimitiveInstance& primitive) { return (primitive.objectHi + primitive.objectLo) * 0.5; }

// Half-extent along world axis `row` of the transformed primitive.
double worldHalfExtent(const PrimitiveInstance& primitive, int row) {
    const double* m = primitive.objectToWorld.m[row];
    if (primitive.type == PrimitiveType::Sphere) {
        // Exact for a sphere: the support of an ellipsoid M·(ball of radius r) along e_i
        // is r·‖Mᵀe_i‖, and Mᵀe_i is row i of the linear part.
        return 0.5 * std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    }
    // The box around the 8 transformed corners of the object box (±h): each world
    // coordinate is Σ_j m_ij·(±h_j), largest when every sign matches m_ij's.
    Vec3 h = objectHalfExtents(primitive);
    return std::abs(m[0]) * h.x + std::abs(m[1]) * h.y + std::abs(m[2]) * h.z;
}

}  // namespace

BoundingBox worldBounds(const PrimitiveInstance& primitive) {
    BoundingBox box;
    for (int i = 0; i < 3; ++i) {
        double centre = primitive.objectToWorld.transformPoint(objectCentre(primitive))[i];
        double half = worldHalfExtent(primitive, i);
        // A moving instance (motion blur) is swept linearly from its place at t = 0 to
        // that plus its motion at t = 1: the union of the two boxes holds it at every time.
        double moved = primitive.motion[i];
        box.min[i] = floatBelow(centre - half + std::min(0.0, moved));
        box.max[i] = floatAbove(centre + half + std::max(0.0, moved));
    }
    return box;
}

// ---------------------------------------------------------------------------------------
// Building

namespace {

// SAH costs, relative: visiting an inner node (two box tests against one fetched node)
// against testing one primitive (a transform plus a quadric or box test).
constexpr double kNodeVisitCost = 1.0;
constexpr double kPrimitiveTestCost = 1.0;

// Nodes of at most this many primitives are split by the exact SAH (every position of a
// sort along each axis) rather than by binning.
constexpr uint32_t kExactSahMaxCount = 4;

// Below this many primitives a range is never split across threads: a thread's start
// costs more than it saves.
constexpr size_t kParallelBuildThreshold = 65536;

// Ranges of at least this many primitives are binned on every core (the top of the tree,
// where the forks below have not yet spread the work): in blocks of kBinningBlock
// primitives, each into bins of its own, merged in block order. Both are fixed, not drawn
// from the thread count, and the merge is in order, so the bins, and the tree, are those
// of one pass over the range, whatever the number of threads: a box's min and max keep
// the same one of equal values (0 and -0) as the pass does, and counts add exactly.
constexpr uint32_t kParallelBinningThreshold = uint32_t(1) << 18;
constexpr uint32_t kBinningBlock = uint32_t(1) << 15;

// The threads a build may use: options.threads, or one a core.
int buildThreads(const BvhBuildOptions& options) {
    return options.threads > 0 ? options.threads : int(std::max(1u, std::thread::hardware_concurrency()));
}

// Four float lanes (x, y, z and a spare that is kept 0): the builder's inner loops work on
// whole boxes at once, with SSE where the compiler offers it (every x86-64) and plain
// loops elsewhere. Both give the same IEEE results lane by lane.
#if defined(__SSE2__)
struct Float4 {
    __m128 v;

    static Float4 load(const float* p) { return {_mm_loadu_ps(p)}; }
    static Float4 broadcast(float f) { return {_mm_set1_ps(f)}; }
    static Float4 of(float x, float y, float z, float w) { return {_mm_setr_ps(x, y, z, w)}; }
    void store(float* p) const { _mm_storeu_ps(p, v); }
    Float4 withoutLastLane() const {
        return {_mm_and_ps(v, _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0)))};
    }
    // Truncates each lane to an integer (toward zero).
    std::array<int32_t, 4> truncate() const {
        std::array<int32_t, 4> r;
        _mm_storeu_si128(reinterpret_cast<__m128i*>(r.data()), _mm_cvttps_epi32(v));
        return r;
    }
    friend Float4 operator+(Float4 a, Float4 b) { return {_mm_add_ps(a.v, b.v)}; }
    friend Float4 operator-(Float4 a, Float4 b) { return {_mm_sub_ps(a.v, b.v)}; }
    friend Float4 operator*(Float4 a, Float4 b) { return {_mm_mul_ps(a.v, b.v)}; }
    friend Float4 min(Float4 a, Float4 b) { return {_mm_min_ps(a.v, b.v)}; }
    friend Float4 max(Float4 a, Float4 b) { return {_mm_max_ps(a.v, b.v)}; }
};
#else
struct Float4 {
    std::array<float, 4> v;

    static Float4 load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
    static Float4 broadcast(float f) { return {{f, f, f, f}}; }
    static Float4 of(float x, float y, float z, float w) { return {{x, y, z, w}}; }
    void store(float* p) const { std::copy(v.begin(), v.end(), p); }
    Float4 withoutLastLane() const { return {{v[0], v[1], v[2], 0.0f}}; }
    std::array<int32_t, 4> truncate() const {
        return {int32_t(v[0]), int32_t(v[1]), int32_t(v[2]), int32_t(v[3])};
    }
    template <class Op>
    static Float4 lanes(Float4 a, Float4 b, Op op) {
        return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1]), op(a.v[2], b.v[2]), op(a.v[3], b.v[3])}};
    }
    friend Float4 operator+(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return x + y; }); }
    friend Float4 operator-(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return x - y; }); }
    friend Float4 operator*(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return x * y; }); }
    friend Float4 min(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return y < x ? y : x; }); }
    friend Float4 max(Float4 a, Float4 b) { return lanes(a, b, [](float x, float y) { return y > x ? y : x; }); }
};
#endif

// A box in lanes; the default one is empty, as BoundingBox's.
struct Box4 {
    Float4 lo = Float4::broadcast(1e30f);
    Float4 hi = Float4::broadcast(-1e30f);

    void expand(Float4 boxLo, Float4 boxHi) {
        lo = min(lo, boxLo);
        hi = max(hi, boxHi);
    }
    void expand(const Box4& b) { expand(b.lo, b.hi); }
    void expand(Float4 point) { expand(point, point); }

    BoundingBox toBox() const {
        float l[4], h[4];
        lo.store(l);
        hi.store(h);
        BoundingBox b;
        for (int a = 0; a < 3; ++a) b.min[a] = l[a], b.max[a] = h[a];
        return b;
    }
};

// A primitive as the builder moves it around: its box and input index in 32 bytes, so the
// in-place partitions stream through memory instead of chasing an index array. Each row
// loads as four lanes; the index rides in the max row's spare lane and is masked off
// before any arithmetic (as a float its bits would be a denormal, slow on some CPUs).
struct alignas(16) BuildPrimitive {
    float min[4];  // x, y, z, 0
    float max[3];
    uint32_t index;

    Float4 lo() const { return Float4::load(min); }
    Float4 hi() const { return Float4::load(max).withoutLastLane(); }
    Float4 centroid() const { return (lo() + hi()) * Float4::broadcast(0.5f); }
    float centroid(int axis) const { return 0.5f * (min[axis] + max[axis]); }
};
static_assert(sizeof(BuildPrimitive) == 32);

// Half the surface area (0 for an empty box): only ratios of areas matter to the SAH. In
// double: the product of two float extents overflows float for scenes past 1e19.
double halfArea(const Box4& b) {
    BoundingBox box = b.toBox();
    if (box.empty()) return 0;
    double dx = double(box.max[0]) - box.min[0], dy = double(box.max[1]) - box.min[1],
           dz = double(box.max[2]) - box.min[2];
    return dx * dy + dy * dz + dz * dx;
}

int ceilLog2(uint32_t n) {
    int bits = 0;
    while ((uint64_t(1) << bits) < n) ++bits;
    return bits;
}

// Primitives [begin, end) of the build array with the bounds of their boxes and of their
// centroids (the centroids' bounds drive the binning).
struct Range {
    uint32_t begin = 0, end = 0;
    Box4 bounds;
    Box4 centroids;

    uint32_t count() const { return end - begin; }
};

// A child as BinaryBvhNode::links stores it: (node index, 0) or (first primitive, count).
struct Link {
    int32_t index = -1;
    int32_t count = 0;
};

// Maps centroids to one of `bins` equal slices of the node's centroid bounds, on all three
// axes at once (binsOf) or on one (binOnAxis). An axis along which the centroids do not
// spread gets scale 0: all of its primitives land in bin 0 and it offers no split.
//
// The binning pass uses binsOf and the partition binOnAxis; they must agree on every
// primitive, and do: a lane of binsOf and binOnAxis perform the same IEEE operations on
// the same floats (the centroid (min + max)·0.5, then (c − origin)·scale, truncated), with
// nothing to fuse into an FMA.
struct Binning {
    Float4 origin = Float4::broadcast(0);
    Float4 scale = Float4::broadcast(0);
    float axisOrigin[3] = {0, 0, 0};
    float axisScale[3] = {0, 0, 0};
    int bins = 2;

    Binning(const Box4& centroids, int binCount) : bins(binCount) {
        BoundingBox c = centroids.toBox();
        for (int a = 0; a < 3; ++a) {
            float extent = c.max[a] - c.min[a];
            float s = float(bins) / extent;
            axisOrigin[a] = c.min[a];
            axisScale[a] = extent > 0 && std::isfinite(s) ? s : 0;
        }
        origin = Float4::of(axisOrigin[0], axisOrigin[1], axisOrigin[2], 0);
        scale = Float4::of(axisScale[0], axisScale[1], axisScale[2], 0);
    }

    bool splits(int axis) const { return axisScale[axis] != 0; }
    bool splitsAny() const { return splits(0) || splits(1) || splits(2); }

    std::array<int32_t, 4> binsOf(Float4 centroid) const {
        std::array<int32_t, 4> k = ((centroid - origin) * scale).truncate();
        for (int a = 0; a < 3; ++a) k[size_t(a)] = std::min(k[size_t(a)], bins - 1);
        return k;
    }

    int binOnAxis(float centroid, int axis) const {
        return std::min(int32_t((centroid - axisOrigin[axis]) * axisScale[axis]), bins - 1);
    }
};

// What one bin collects: the bounds of its primitives' boxes and of their centroids (so
// that a child's centroid bounds are the union of its bins', with no extra pass).
struct Bin {
    Box4 bounds;
    Box4 centroids;
};

struct SahSplit {
    int axis = 0;
    int bins = 0;  // how many the node was binned into
    int bin = 0;   // bins [0, bin) go left
    uint32_t leftCount = 0;
    double cost = 0;  // Σ halfArea(child)·count(child), without the node's own cost
};

void setChildBounds(BinaryBvhNode& node, int child, const BoundingBox& b) {
    // Lanes: (left.min, right.min, left.max, right.max); see cl/shared_types.h.
    gpu::float4* rows[3] = {&node.xBounds, &node.yBounds, &node.zBounds};
    for (int a = 0; a < 3; ++a) {
        lane(*rows[a], child) = b.min[a];
        lane(*rows[a], child + 2) = b.max[a];
    }
}

void setLinks(BinaryBvhNode& node, Link left, Link right) {
    node.links = {left.index, left.count, right.index, right.count};
}

// A node with both children absent: empty bounds, index −1.
BinaryBvhNode emptyNode() {
    BinaryBvhNode node;
    setChildBounds(node, 0, BoundingBox{});
    setChildBounds(node, 1, BoundingBox{});
    setLinks(node, Link{}, Link{});
    return node;
}

// Builds one subtree top-down into its own node array (its root at index 0), partitioning
// its slice of the shared primitive array in place. Builders on different threads work on
// disjoint slices. The bin arrays are allocated once per builder, never per node.
class SubtreeBuilder {
public:
    SubtreeBuilder(std::span<BuildPrimitive> primitives, const BvhBuildOptions& options)
        : primitives_(primitives),
          maxLeafSize_(uint32_t(std::max(options.maxLeafSize, 1))),
          leafBlock_(uint32_t(std::max(options.leafBlock, 1))),
          maxDepth_(std::clamp(options.maxDepth, 1, kBvhMaxDepth)),
          maxBins_(std::clamp(options.bins, 2, 256)),
          threads_(buildThreads(options)),
          bins_(size_t(3 * maxBins_)),
          binCounts_(size_t(3 * maxBins_)),
          rightHalfArea_(size_t(maxBins_)),
          rightCount_(size_t(maxBins_)) {}

    // Emits the subtree for `range` (whose first inner node, if any, sits at `depth`, the
    // root being 1) in depth-first order, and returns the link its parent stores.
    Link build(const Range& range, int depth) {
        Range left, right;
        if (!split(range, depth, &left, &right)) return {int32_t(range.begin), int32_t(range.count())};
        int32_t self = int32_t(nodes.size());
        nodes.emplace_back();
        setChildBounds(nodes[size_t(self)], 0, left.bounds.toBox());
        setChildBounds(nodes[size_t(self)], 1, right.bounds.toBox());
        // The left subtree comes right after its parent, the right one after that.
        Link leftLink = build(left, depth + 1);
        Link rightLink = build(right, depth + 1);
        setLinks(nodes[size_t(self)], leftLink, rightLink);
        return {self, 0};
    }

    // Decides whether `range` becomes a leaf (false) or an inner node at `depth`; for an
    // inner node, partitions the range and describes the two halves.
    //
    // Depth guard: a median split halves the count, so the median subtree under a node of
    // n primitives has at most ceilLog2(n) inner levels. SAH is allowed only while
    // depth + ceilLog2(n) ≤ maxDepth, which keeps that fallback within the limit for every
    // child, however lopsided the SAH split.
    bool split(const Range& range, int depth, Range* left, Range* right) {
        uint32_t count = range.count();
        if (count <= 1) return false;
        bool sahAllowed = depth + ceilLog2(count) <= maxDepth_;
        if (sahAllowed && count <= kExactSahMaxCount) {
            SahSplit best = findExactSplit(range);
            if (count <= maxLeafSize_ && !splittingPays(range, best)) return false;
            applyExactSplit(range, best, left, right);
            return true;
        }
        if (sahAllowed) {
            SahSplit best;
            bool found = findSahSplit(range, &best);
            if (count <= maxLeafSize_ && (!found || !splittingPays(range, best))) return false;
            if (found) {
                partitionAtBin(range, best, left, right);
                return true;
            }
        } else if (count <= maxLeafSize_) {
            return false;
        }
        // Above the leaf size with no SAH split (all centroids within one float), or near
        // the depth limit.
        medianSplit(range, left, right);
        return true;
    }

    std::vector<BinaryBvhNode> nodes;

private:
    // The tests a leaf of n primitives costs: one a block of leafBlock_ (BvhBuildOptions).
    double blocks(uint32_t n) const { return double((n + leafBlock_ - 1) / leafBlock_); }

    bool splittingPays(const Range& range, const SahSplit& split) const {
        // Both sides multiplied by the node's area, so that a node of zero area (all
        // boxes degenerate to one point or segment) compares without dividing by 0.
        double area = halfArea(range.bounds);
        double leafCost = kPrimitiveTestCost * blocks(range.count()) * area;
        double splitCost = kNodeVisitCost * area + kPrimitiveTestCost * split.cost;
        return splitCost < leafCost;
    }

    // Nodes not much larger than the bin count get fewer bins: the per-node cost of clearing
    // and sweeping 16 bins per axis would otherwise dominate the lower levels of the tree.
    int binsFor(uint32_t count) const { return int(std::clamp<uint32_t>(count, 2, uint32_t(maxBins_))); }

    // The positions of the range's primitives (0 … n − 1) sorted by centroid along an axis:
    // an insertion sort, stable, so that the evaluation and the application of an exact
    // split see the very same order.
    void sortByCentroid(const Range& range, int axis, std::array<uint8_t, kExactSahMaxCount>& order) const {
        uint32_t n = range.count();
        float keys[kExactSahMaxCount];
        for (uint32_t i = 0; i < n; ++i) {
            keys[i] = primitives_[range.begin + i].centroid(axis);
            uint32_t j = i;
            for (; j > 0 && keys[order[j - 1]] > keys[i]; --j) order[j] = order[j - 1];
            order[j] = uint8_t(i);
        }
    }

    // Small nodes: the exact SAH over every split position of the centroid order on each
    // axis. Cheaper than binning at this size, better, and it splits even coincident
    // centroids (by position), so no median fallback is needed below kExactSahMaxCount.
    SahSplit findExactSplit(const Range& range) const {
        uint32_t n = range.count();
        if (n == 2) {  // the most common node by far, and its one split needs no sort
            const BuildPrimitive* p = &primitives_[range.begin];
            Box4 a, b;
            a.expand(p[0].lo(), p[0].hi());
            b.expand(p[1].lo(), p[1].hi());
            return {0, 0, 1, 1, halfArea(a) + halfArea(b)};
        }
        std::array<uint8_t, kExactSahMaxCount> order;
        double rightHalfArea[kExactSahMaxCount];
        SahSplit best;
        bool found = false;  // the first candidate is taken whatever its cost
        for (int axis = 0; axis < 3; ++axis) {
            sortByCentroid(range, axis, order);
            Box4 accumulated;
            for (uint32_t k = n - 1; k >= 1; --k) {
                const BuildPrimitive& p = primitives_[range.begin + order[k]];
                accumulated.expand(p.lo(), p.hi());
                rightHalfArea[k] = halfArea(accumulated);
            }
            accumulated = Box4{};
            for (uint32_t k = 1; k < n; ++k) {
                const BuildPrimitive& p = primitives_[range.begin + order[k - 1]];
                accumulated.expand(p.lo(), p.hi());
                double cost = halfArea(accumulated) * blocks(k) + rightHalfArea[k] * blocks(n - k);
                if (!found || cost < best.cost) best = {axis, 0, int(k), k, cost};
                found = true;
            }
        }
        return best;
    }

    void applyExactSplit(const Range& range, const SahSplit& split, Range* left, Range* right) {
        uint32_t n = range.count();
        if (n == 2) {
            *left = describe(range.begin, range.begin + 1);
            *right = describe(range.begin + 1, range.end);
            return;
        }
        std::array<uint8_t, kExactSahMaxCount> order;
        sortByCentroid(range, split.axis, order);
        BuildPrimitive sorted[kExactSahMaxCount];
        for (uint32_t i = 0; i < n; ++i) sorted[i] = primitives_[range.begin + order[i]];
        std::copy(sorted, sorted + n, primitives_.begin() + range.begin);
        *left = describe(range.begin, range.begin + split.leftCount);
        *right = describe(range.begin + split.leftCount, range.end);
    }

    // Bins the range along all three axes and returns the cheapest bin boundary by SAH.
    bool findSahSplit(const Range& range, SahSplit* best) {
        Binning binning(range.centroids, binsFor(range.count()));
        if (!binning.splitsAny()) return false;
        if (threads_ > 1 && range.count() >= kParallelBinningThreshold) {
            binInBlocks(range, binning);
        } else {
            clearBins(bins_.data(), binCounts_.data(), binning.bins);
            binRange(range.begin, range.end, binning, bins_.data(), binCounts_.data());
        }
        bool found = false;
        for (int a = 0; a < 3; ++a) {
            if (binning.splits(a)) found |= sweepAxis(a, binning.bins, best, found);
        }
        return found;
    }

    void clearBins(Bin* bins, uint32_t* counts, int binCount) const {
        for (int a = 0; a < 3; ++a) {
            std::fill_n(bins + a * maxBins_, binCount, Bin{});
            std::fill_n(counts + a * maxBins_, binCount, 0u);
        }
    }

    // Adds primitives [begin, end) to the bins, in order. Raw pointers: the compiler cannot
    // tell that the bins do not alias the primitives through members, and would reload
    // them every iteration.
    void binRange(uint32_t begin, uint32_t end, const Binning& binning, Bin* bins, uint32_t* counts) const {
        const BuildPrimitive* last = primitives_.data() + end;
        for (const BuildPrimitive* p = primitives_.data() + begin; p < last; ++p) {
            Float4 lo = p->lo(), hi = p->hi();
            Float4 c = (lo + hi) * Float4::broadcast(0.5f);
            std::array<int32_t, 4> k = binning.binsOf(c);
            for (int a = 0; a < 3; ++a) {
                size_t slot = size_t(a * maxBins_ + k[size_t(a)]);
                bins[slot].bounds.expand(lo, hi);
                bins[slot].centroids.expand(c);
                ++counts[slot];
            }
        }
    }

    // binRange over the whole range on every thread: block b into bins of its own, the
    // blocks then merged in order (kParallelBinningThreshold says why that is the same).
    void binInBlocks(const Range& range, const Binning& binning) {
        const uint32_t blocks = (range.count() + kBinningBlock - 1) / kBinningBlock;
        const size_t slots = size_t(3 * maxBins_);
        std::vector<Bin> blockBins(blocks * slots);
        std::vector<uint32_t> blockCounts(blocks * slots);
        auto work = [&](uint32_t thread, uint32_t threads) {
            for (uint32_t b = thread; b < blocks; b += threads) {
                Bin* bins = &blockBins[b * slots];
                uint32_t* counts = &blockCounts[b * slots];
                clearBins(bins, counts, binning.bins);
                const uint32_t begin = range.begin + b * kBinningBlock;
                binRange(begin, std::min(range.end, begin + kBinningBlock), binning, bins, counts);
            }
        };
        const uint32_t threads = std::min(uint32_t(threads_), blocks);
        std::vector<std::future<void>> others;
        for (uint32_t t = 1; t < threads; ++t) others.push_back(std::async(std::launch::async, work, t, threads));
        work(0, threads);
        for (std::future<void>& f : others) f.get();
        clearBins(bins_.data(), binCounts_.data(), binning.bins);
        for (uint32_t b = 0; b < blocks; ++b)
            for (int a = 0; a < 3; ++a)
                for (int k = 0; k < binning.bins; ++k) {
                    const size_t slot = size_t(a * maxBins_ + k);
                    bins_[slot].bounds.expand(blockBins[b * slots + slot].bounds);
                    bins_[slot].centroids.expand(blockBins[b * slots + slot].centroids);
                    binCounts_[slot] += blockCounts[b * slots + slot];
                }
    }

    // Evaluates the binCount − 1 boundaries along one axis; true if one beat *best.
    bool sweepAxis(int axis, int binCount, SahSplit* best, bool haveBest) {
        const Bin* bins = &bins_[size_t(axis * maxBins_)];
        const uint32_t* counts = &binCounts_[size_t(axis * maxBins_)];
        Box4 accumulated;
        uint32_t accumulatedCount = 0;
        for (int k = binCount - 1; k >= 1; --k) {
            accumulated.expand(bins[k].bounds);
            accumulatedCount += counts[k];
            rightHalfArea_[size_t(k)] = halfArea(accumulated);
            rightCount_[size_t(k)] = accumulatedCount;
        }
        bool improved = false;
        accumulated = Box4{};
        accumulatedCount = 0;
        for (int k = 1; k < binCount; ++k) {
            accumulated.expand(bins[k - 1].bounds);
            accumulatedCount += counts[k - 1];
            if (accumulatedCount == 0 || rightCount_[size_t(k)] == 0) continue;
            double cost = halfArea(accumulated) * blocks(accumulatedCount) +
                          rightHalfArea_[size_t(k)] * blocks(rightCount_[size_t(k)]);
            if (!haveBest || cost < best->cost) {
                *best = {axis, binCount, k, accumulatedCount, cost};
                haveBest = improved = true;
            }
        }
        return improved;
    }

    // Partitions the range so bins [0, split.bin) come first; the sides' bounds are the
    // unions of their bins'.
    void partitionAtBin(const Range& range, const SahSplit& split, Range* left, Range* right) {
        Binning binning(range.centroids, split.bins);
        int axis = split.axis;
        auto goesLeft = [&](const BuildPrimitive& p) { return binning.binOnAxis(p.centroid(axis), axis) < split.bin; };
        // A branch-free Lomuto partition: [begin, boundary) holds those that go left and
        // [boundary, i) those that go right. Every step swaps (often an element with
        // itself, or two that both go right) and moves the boundary by 0 or 1, so the
        // random left/right sequence costs no mispredicted branches.
        BuildPrimitive* boundary = primitives_.data() + range.begin;
        BuildPrimitive* last = primitives_.data() + range.end;
        for (BuildPrimitive* i = boundary; i < last; ++i) {
            bool toLeft = goesLeft(*i);
            BuildPrimitive moved = *i;
            *i = *boundary;
            *boundary = moved;
            boundary += toLeft;
        }
        uint32_t middle = uint32_t(boundary - primitives_.data());
        assert(middle - range.begin == split.leftCount);
        *left = Range{range.begin, middle, {}, {}};
        *right = Range{middle, range.end, {}, {}};
        const Bin* bins = &bins_[size_t(axis * maxBins_)];
        for (int k = 0; k < split.bins; ++k) {
            Range* side = k < split.bin ? left : right;
            side->bounds.expand(bins[k].bounds);
            side->centroids.expand(bins[k].centroids);
        }
    }

    // Splits at the median centroid along the widest centroid axis; when every centroid
    // coincides, simply in half (any order is as good as any other).
    void medianSplit(const Range& range, Range* left, Range* right) {
        BoundingBox c = range.centroids.toBox();
        int axis = 0;
        for (int a = 1; a < 3; ++a) {
            if (c.max[a] - c.min[a] > c.max[axis] - c.min[axis]) axis = a;
        }
        uint32_t middle = range.begin + range.count() / 2;
        BuildPrimitive* base = primitives_.data();
        if (c.max[axis] > c.min[axis]) {
            std::nth_element(base + range.begin, base + middle, base + range.end,
                             [axis](const BuildPrimitive& a, const BuildPrimitive& b) {
                                 return a.centroid(axis) < b.centroid(axis);
                             });
        }
        *left = describe(range.begin, middle);
        *right = describe(middle, range.end);
    }

    Range describe(uint32_t begin, uint32_t end) const {
        Range r{begin, end, {}, {}};
        for (uint32_t i = begin; i < end; ++i) {
            const BuildPrimitive& p = primitives_[i];
            r.bounds.expand(p.lo(), p.hi());
            r.centroids.expand(p.centroid());
        }
        return r;
    }

    std::span<BuildPrimitive> primitives_;
    uint32_t maxLeafSize_;
    uint32_t leafBlock_;
    int maxDepth_;
    int maxBins_;
    int threads_;
    std::vector<Bin> bins_;  // [axis · maxBins_ + bin]
    std::vector<uint32_t> binCounts_;
    std::vector<double> rightHalfArea_;
    std::vector<uint32_t> rightCount_;
};

// Copies boxes [begin, end) into build records and returns their range. A box with a NaN
// coordinate becomes empty (never hit); other coordinates are clamped to ±kCoordinateLimit
// (infinities included). Both keep the binning arithmetic finite: centroid spreads, their
// reciprocals and (c − origin)·scale all stay far from float overflow, so no NaN can reach
// the float-to-int conversion of a bin index. No primitive reaches that far in a scene a
// float renderer can draw.
constexpr float kCoordinateLimit = 1e30f;

Range fillBuildPrimitives(const std::vector<BoundingBox>& boxes, uint32_t begin, uint32_t end,
                          BuildPrimitive* primitives) {
    Range range{begin, end, {}, {}};
    for (uint32_t i = begin; i < end; ++i) {
        BoundingBox b = boxes[i];
        bool hasNaN = false;
        for (int a = 0; a < 3; ++a) {
            hasNaN = hasNaN || std::isnan(b.min[a]) || std::isnan(b.max[a]);
            b.min[a] = std::clamp(b.min[a], -kCoordinateLimit, kCoordinateLimit);
            b.max[a] = std::clamp(b.max[a], -kCoordinateLimit, kCoordinateLimit);
        }
        if (hasNaN) b = BoundingBox{};
        BuildPrimitive& p = primitives[i];
        p = {{b.min[0], b.min[1], b.min[2], 0}, {b.max[0], b.max[1], b.max[2]}, i};
        range.bounds.expand(p.lo(), p.hi());
        range.centroids.expand(p.centroid());
    }
    return range;
}

// The tree as the parallel top of the build leaves it: either a piece built by one
// SubtreeBuilder (its nodes numbered from 0, and the link its parent stores), or a fork,
// an inner node split on its own whose two children were built concurrently. There are
// a few dozen parts at most, so their heap allocations do not matter.
struct Part {
    bool isFork = false;
    // A fork:
    BinaryBvhNode node = emptyNode();
    std::unique_ptr<Part> left, right;
    // A piece:
    std::vector<BinaryBvhNode> nodes;
    Link link;
};

// Ranges of at least forkSize primitives are split on their own and their two halves
// built on two threads. forkSize is a fraction of the scene (kForkFraction), so pieces
// stay small against the whole whatever the shape of the tree: where the top splits are
// lopsided, the large side keeps forking instead of leaving one thread with most of the
// work (with three fixed levels of forks, one of recursiveSpheres10's eight pieces held
// over a third of the scene and the build took 30% longer). More threads than cores
// is deliberate: the operating system hands the cores to whichever pieces remain, which
// balances the load without a task queue.
constexpr size_t kForkFraction = 16;

Part buildPart(std::span<BuildPrimitive> primitives, const Range& range, int depth, size_t forkSize,
               const BvhBuildOptions& options) {
    SubtreeBuilder builder(primitives, options);
    Range left, right;
    if (range.count() >= forkSize && builder.split(range, depth, &left, &right)) {
        Part fork;
        fork.isFork = true;
        setChildBounds(fork.node, 0, left.bounds.toBox());
        setChildBounds(fork.node, 1, right.bounds.toBox());
        std::future<Part> leftPart =
            std::async(std::launch::async, [&] { return buildPart(primitives, left, depth + 1, forkSize, options); });
        fork.right = std::make_unique<Part>(buildPart(primitives, right, depth + 1, forkSize, options));
        fork.left = std::make_unique<Part>(leftPart.get());
        return fork;
    }
    Part piece;
    // A subtree over n primitives has at most n − 1 inner nodes. Reserving that up front
    // spares the regrowth copies; pages the tree does not reach are never touched.
    builder.nodes.reserve(range.count());
    piece.link = builder.build(range, depth);
    piece.nodes = std::move(builder.nodes);
    return piece;
}

size_t countNodes(const Part& part) {
    return part.isFork ? 1 + countNodes(*part.left) + countNodes(*part.right) : part.nodes.size();
}

Link relocate(Link link, int32_t offset) {
    if (link.count == 0 && link.index >= 0) link.index += offset;
    return link;
}

// Appends the part depth-first (a fork, then its left part, then its right), shifting each
// piece's inner-node links by where it lands; returns the link to the part.
Link assemble(const Part& part, std::vector<BinaryBvhNode>& nodes) {
    if (part.isFork) {
        int32_t self = int32_t(nodes.size());
        nodes.push_back(part.node);
        Link left = assemble(*part.left, nodes);
        Link right = assemble(*part.right, nodes);
        setLinks(nodes[size_t(self)], left, right);
        return {self, 0};
    }
    int32_t offset = int32_t(nodes.size());
    for (BinaryBvhNode node : part.nodes) {
        if (node.links.y == 0 && node.links.x >= 0) node.links.x += offset;
        if (node.links.w == 0 && node.links.z >= 0) node.links.z += offset;
        nodes.push_back(node);
    }
    return relocate(part.link, offset);
}

}  // namespace

FlatBvh buildBvh(const std::vector<BoundingBox>& primitiveBounds, const BvhBuildOptions& options) {
    FlatBvh bvh;
    if (primitiveBounds.size() > size_t(std::numeric_limits<int32_t>::max()))
        throw std::length_error("too many primitives for a BVH with 32-bit links");
    if (primitiveBounds.empty()) {
        bvh.nodes.push_back(emptyNode());
        return bvh;
    }

    // Not a std::vector: its zero-filling would touch all of the memory on this thread
    // first; here the two halves are written (and first touched) in parallel.
    uint32_t count = uint32_t(primitiveBounds.size());
    auto storage = std::make_unique_for_overwrite<BuildPrimitive[]>(count);
    std::span<BuildPrimitive> primitives(storage.get(), count);
    bool parallel = count >= kParallelBuildThreshold && buildThreads(options) >= 2;
    std::future<Range> firstHalf = std::async(parallel ? std::launch::async : std::launch::deferred, [&] {
        return fillBuildPrimitives(primitiveBounds, 0, count / 2, storage.get());
    });
    Range all = fillBuildPrimitives(primitiveBounds, count / 2, count, storage.get());
    Range first = firstHalf.get();
    all.begin = 0;
    all.bounds.expand(first.bounds);
    all.centroids.expand(first.centroids);

    size_t forkSize = parallel ? std::max(kParallelBuildThreshold, primitives.size() / kForkFraction)
                               : std::numeric_limits<size_t>::max();
    Part tree = buildPart(primitives, all, 1, forkSize, options);
    if (!tree.isFork && tree.link.count > 0) {
        // The whole scene is one leaf: the root's left child, its right one absent.
        BinaryBvhNode root = emptyNode();
        setChildBounds(root, 0, all.bounds.toBox());
        setLinks(root, tree.link, Link{});
        bvh.nodes.push_back(root);
    } else {
        bvh.nodes.reserve(countNodes(tree));
        assemble(tree, bvh.nodes);  // the root lands at 0
    }

    bvh.primitiveOrder.resize(primitives.size());
    for (size_t i = 0; i < primitives.size(); ++i) bvh.primitiveOrder[i] = primitives[i].index;
    return bvh;
}

// ---------------------------------------------------------------------------------------
// Traversal
//
// The walk the kernel mirrors:
//
//  1. The ray's reciprocal direction is taken once. A direction component smaller in
//     magnitude than kTinyDirection (zero included) is replaced by ±kTinyDirection, keeping
//     its sign: with 1/0 = ∞, a ray starting exactly on a slab plane would compute 0·∞ =
//     NaN; with 1/1e-30 = 1e30 it gets 0 there and an enormous distance elsewhere, which is
//     what the slab test wants. 1e-30 (and 1e30) are representable in float, so the kernel
//     uses the same constant.
//  2. A slab test picks each axis's entering plane by the direction's sign (min for
//     positive, max for negative) instead of swapping t0 and t1: an absent child's empty
//     box (min > max) then yields entry > exit on every axis and is never hit. The
//     interval starts as [0, best] — best is the closest hit so far (tMax initially) —
//     so boxes beyond the current hit are pruned at once; a hit is entry ≤ exit.
//  3. The current item is a link (index, count, entry distance). An inner node tests both
//     children: both hit → push the farther onto the stack and continue with the nearer
//     (ties go left); one hit → continue with it; none → pop. A leaf tests its primitives
//     in order; each accepted hit (t < best) lowers best (any-hit returns at once).
//  4. Popping discards entries whose entry distance now exceeds best. Each inner node on
//     the current path pushes at most once, so the stack never holds more than the tree's
//     depth, at most kBvhMaxDepth.

namespace {

constexpr double kTinyDirection = 1e-30;

struct SlabRay {
    double origin[3];
    double inverseDirection[3];
    bool negative[3];  // the ray enters through the max plane along this axis
};

SlabRay makeSlabRay(const Vec3& origin, const Vec3& direction) {
    SlabRay ray;
    for (int a = 0; a < 3; ++a) {
        double d = direction[a];
        if (std::abs(d) < kTinyDirection) d = std::copysign(kTinyDirection, d);
        ray.origin[a] = origin[a];
        ray.inverseDirection[a] = 1.0 / d;
        ray.negative[a] = d < 0;
    }
    return ray;
}

// Whether the ray meets child `child` (0 left, 1 right) of the node within [0, tLimit];
// *entry receives the distance at which it enters.
bool hitChild(const BinaryBvhNode& node, int child, const SlabRay& ray, double tLimit, double* entry) {
    const gpu::float4* rows[3] = {&node.xBounds, &node.yBounds, &node.zBounds};
    double enter = 0, exit = tLimit;
    for (int a = 0; a < 3; ++a) {
        double lo = lane(*rows[a], child), hi = lane(*rows[a], child + 2);
        double nearPlane = ray.negative[a] ? hi : lo;
        double farPlane = ray.negative[a] ? lo : hi;
        enter = std::max(enter, (nearPlane - ray.origin[a]) * ray.inverseDirection[a]);
        exit = std::min(exit, (farPlane - ray.origin[a]) * ray.inverseDirection[a]);
    }
    *entry = enter;
    return enter <= exit;
}

struct Pending {
    int32_t index = 0;
    int32_t count = 0;  // 0: inner node; > 0: leaf
    double entry = 0;
};

template <bool kStopAtFirstHit>
int64_t traverse(const FlatBvh& bvh, const Vec3& origin, const Vec3& direction, double tMax,
                 const PrimitiveTest& intersect, double* tHit) {
    double best = tMax;
    int64_t bestPosition = -1;
    if (tHit) *tHit = tMax;
    if (bvh.nodes.empty()) return -1;
    SlabRay ray = makeSlabRay(origin, direction);
    std::array<Pending, kBvhMaxDepth> stack;
    int stackSize = 0;
    Pending current{0, 0, 0.0};  // node 0, the root, is always an inner node
    for (;;) {
        if (current.count > 0) {
            for (int32_t p = current.index; p < current.index + current.count; ++p) {
                double t = intersect(uint32_t(p), best);
                if (t >= 0 && t < best) {
                    best = t;
                    bestPosition = p;
                    if constexpr (kStopAtFirstHit) break;
                }
            }
            if (kStopAtFirstHit && bestPosition >= 0) break;
        } else {
            const BinaryBvhNode& node = bvh.nodes[size_t(current.index)];
            Pending left{node.links.x, node.links.y, 0}, right{node.links.z, node.links.w, 0};
            bool hitLeft = left.index >= 0 && hitChild(node, 0, ray, best, &left.entry);
            bool hitRight = right.index >= 0 && hitChild(node, 1, ray, best, &right.entry);
            if (hitLeft && hitRight) {
                bool rightFirst = right.entry < left.entry;
                if (stackSize == kBvhMaxDepth) throw std::logic_error("BVH deeper than kBvhMaxDepth");
                stack[size_t(stackSize++)] = rightFirst ? left : right;
                current = rightFirst ? right : left;
                continue;
            }
            if (hitLeft || hitRight) {
                current = hitLeft ? left : right;
                continue;
            }
        }
        bool resumed = false;
        while (stackSize > 0 && !resumed) {
            current = stack[size_t(--stackSize)];
            resumed = current.entry <= best;
        }
        if (!resumed) break;
    }
    if (tHit && bestPosition >= 0) *tHit = best;
    return bestPosition;
}

}  // namespace

int64_t bvhClosestHit(const FlatBvh& bvh, const Vec3& origin, const Vec3& direction, double tMax,
                      const PrimitiveTest& intersect, double* tHit) {
    return traverse<false>(bvh, origin, direction, tMax, intersect, tHit);
}

bool bvhAnyHit(const FlatBvh& bvh, const Vec3& origin, const Vec3& direction, double tMax,
               const PrimitiveTest& intersect) {
    return traverse<true>(bvh, origin, direction, tMax, intersect, nullptr) >= 0;
}

}  // namespace ray
