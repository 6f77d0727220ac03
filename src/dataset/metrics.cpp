#include "dataset/metrics.hpp"

#include <nanoflann.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "core/catmull_rom.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "dataset/targets.hpp"
#include "render/render.hpp"

namespace wisp {
namespace {

// A hair's control points with their strands' unit directions (the chord through the
// neighbours; one-sided at the ends), as nanoflann's dataset.
struct Cloud {
    std::span<const Vec3f> points;  // the hair's own
    std::vector<Vec3f> directions;
    size_t kdtree_get_point_count() const { return points.size(); }
    float kdtree_get_pt(size_t i, size_t dim) const { return points[i][static_cast<int>(dim)]; }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;
    }
};

Cloud cloud_of(const Hair& hair) {
    Cloud c;
    c.points = hair.points;  // a view: the hair outlives the comparison
    c.directions.resize(hair.points.size(), Vec3f::Zero());
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const std::span<const Vec3f> p = hair.strand(s);
        const size_t base = hair.offsets[s];
        for (size_t i = 0; i < p.size(); ++i) {
            const Vec3f d = p[std::min(i + 1, p.size() - 1)] - p[i > 0 ? i - 1 : 0];
            const float n = d.norm();
            c.directions[base + i] = n > 0.f ? Vec3f(d / n) : Vec3f::Zero();
        }
    }
    return c;
}

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud,
                                                 3, uint32_t>;

// nanoflann's result set for one query: which thresholds some point within reach matches
// (near enough, and of a direction close enough), without storing the points.
class ThresholdMatches {
  public:
    ThresholdMatches(const Cloud& cloud, const Vec3f& direction,
                     const std::vector<std::pair<float, float>>& limits)
        : cloud_(cloud), direction_(direction), limits_(limits) {
        for (const auto& [d, cos_angle] : limits)
            reach_ = std::max(reach_, d);
        all_ = (1u << limits.size()) - 1u;
    }
    void init() {}
    size_t size() const { return 0; }
    bool full() const { return true; }
    float worstDist() const { return reach_; }
    // dist: squared distance. Returns false (stop) once every threshold is matched.
    bool addPoint(float dist, uint32_t index) {
        const float cos_angle = std::abs(direction_.dot(cloud_.directions[index]));
        for (size_t k = 0; k < limits_.size(); ++k)
            if (dist < limits_[k].first && cos_angle > limits_[k].second) matched |= 1u << k;
        return matched != all_;
    }
    uint32_t matched = 0;

  private:
    const Cloud& cloud_;
    Vec3f direction_;
    const std::vector<std::pair<float, float>>& limits_;  // (distance², cos angle)
    float reach_ = 0.f;
    uint32_t all_ = 0;
};

// For each point of `from`: the thresholds it matches in `to` (bits), and its distance to the
// nearest point of `to`.
void match(const Cloud& from, const Cloud& to, const Tree& tree,
           const std::vector<std::pair<float, float>>& limits, std::vector<uint32_t>& bits,
           std::vector<float>& nearest) {
    bits.assign(from.points.size(), 0);
    nearest.assign(from.points.size(), 0.f);
    parallel_for(
        from.points.size(),
        [&](size_t i) {
            ThresholdMatches m(to, from.directions[i], limits);
            tree.radiusSearchCustomCallback(from.points[i].data(), m, nanoflann::SearchParams());
            bits[i] = m.matched;
            uint32_t index = 0;
            float d2 = 0.f;
            tree.knnSearch(from.points[i].data(), 1, &index, &d2);
            nearest[i] = std::sqrt(d2);
        },
        1024);
}

// Both hairs' strands resampled to n points: the mean distance between corresponding points
// and the mean curvature difference at corresponding interior points.
std::pair<double, double> corresponding_errors(const Hair& a, const Hair& b, int n) {
    std::vector<double> position(a.strand_count()), curvature(a.strand_count());
    parallel_for(a.strand_count(), [&](size_t s) {
        thread_local std::vector<Vec3f> pa, pb;
        thread_local std::vector<float> wa, wb;
        pa.resize(n);
        pb.resize(n);
        wa.resize(n);
        wb.resize(n);
        catmull_rom_resample(a.strand(s), {}, 0.f, pa, wa);
        catmull_rom_resample(b.strand(s), {}, 0.f, pb, wb);
        double dp = 0, dk = 0;
        auto kappa = [](const std::vector<Vec3f>& p, int i) {
            const Vec3f u = p[i] - p[i - 1], v = p[i + 1] - p[i];
            const float lu = u.norm(), lv = v.norm();
            if (!(lu > 0.f && lv > 0.f)) return 0.f;
            const float c = std::clamp(u.dot(v) / (lu * lv), -1.f, 1.f);
            return std::acos(c) / (0.5f * (lu + lv));
        };
        for (int i = 0; i < n; ++i) {
            dp += (pa[i] - pb[i]).norm();
            if (i > 0 && i + 1 < n) dk += std::abs(kappa(pa, i) - kappa(pb, i));
        }
        position[s] = dp / n;
        curvature[s] = n > 2 ? dk / (n - 2) : 0.0;
    });
    double p = 0, k = 0;
    for (size_t s = 0; s < position.size(); ++s) {
        p += position[s];
        k += curvature[s];
    }
    const double count = static_cast<double>(std::max<size_t>(1, position.size()));
    return {p / count, k / count};
}

// The voxels (of `voxel` cm, on a grid over `box`) the strands pass through, as bits.
std::vector<uint64_t> occupancy(const Hair& hair, const Box3& box, float voxel, const Vec3i& dims) {
    const size_t cells = static_cast<size_t>(dims.x()) * dims.y() * dims.z();
    std::vector<uint64_t> bits((cells + 63) / 64, 0);
    auto mark = [&](const Vec3f& p) {
        const Vec3f q = (p - box.lo) / voxel;
        const int x = std::clamp(static_cast<int>(q.x()), 0, dims.x() - 1);
        const int y = std::clamp(static_cast<int>(q.y()), 0, dims.y() - 1);
        const int z = std::clamp(static_cast<int>(q.z()), 0, dims.z() - 1);
        const size_t c = (static_cast<size_t>(z) * dims.y() + y) * dims.x() + x;
        bits[c / 64] |= uint64_t{1} << (c % 64);
    };
    for (size_t s = 0; s < hair.strand_count(); ++s) {
        const std::span<const Vec3f> p = hair.strand(s);
        if (p.empty()) continue;
        mark(p[0]);
        for (size_t i = 0; i + 1 < p.size(); ++i) {
            const float len = (p[i + 1] - p[i]).norm();
            const int steps = std::max(1, static_cast<int>(std::ceil(len / (0.25f * voxel))));
            for (int k = 1; k <= steps; ++k)
                mark(p[i] + (p[i + 1] - p[i]) * (static_cast<float>(k) / steps));
        }
    }
    return bits;
}

}  // namespace

CompareResult compare_hair(const Hair& a, const Hair& b, const Mesh* head,
                           const CompareOptions& options) {
    a.validate("compare: hair A");
    b.validate("compare: hair B");
    if (a.point_count() == 0 || b.point_count() == 0)
        fail("compare: hair ", a.point_count() == 0 ? "A" : "B", " has no points");
    if (options.thresholds.empty() || options.thresholds.size() > 16)
        fail("compare: 1 to 16 thresholds, got ", options.thresholds.size());
    for (const auto& [d, angle] : options.thresholds)
        if (!(d > 0.f && d < 100.f) || !(angle > 0.f && angle <= 90.f))
            fail(
                "compare: a threshold is a distance in (0, 100) cm and an angle in (0, 90] "
                "degrees, got ",
                d, " cm, ", angle, "°");
    if (!(options.voxel >= 0.01f && options.voxel <= 100.f))
        fail("compare: voxel must be in [0.01, 100] cm, got ", options.voxel);
    if (options.resample_points < 2 || options.resample_points > 4096)
        fail("compare: resample_points must be in [2, 4096], got ", options.resample_points);

    CompareResult r;
    r.strands_a = a.strand_count();
    r.strands_b = b.strand_count();
    r.points_a = a.point_count();
    r.points_b = b.point_count();

    // Strands: precision from A to B, recall from B to A.
    std::vector<std::pair<float, float>> limits;
    for (const auto& [d, angle] : options.thresholds)
        limits.emplace_back(d * d, std::cos(angle * kPi / 180.f));
    const Cloud ca = cloud_of(a), cb = cloud_of(b);
    const Tree ta(3, ca, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    const Tree tb(3, cb, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    std::vector<uint32_t> bits_a, bits_b;
    std::vector<float> near_a, near_b;
    match(ca, cb, tb, limits, bits_a, near_a);
    match(cb, ca, ta, limits, bits_b, near_b);
    for (size_t k = 0; k < limits.size(); ++k) {
        StrandScore score;
        score.distance = options.thresholds[k].first;
        score.angle = options.thresholds[k].second;
        size_t hit_a = 0, hit_b = 0;
        for (uint32_t m : bits_a)
            hit_a += m >> k & 1u;
        for (uint32_t m : bits_b)
            hit_b += m >> k & 1u;
        score.precision = static_cast<double>(hit_a) / bits_a.size();
        score.recall = static_cast<double>(hit_b) / bits_b.size();
        const double sum = score.precision + score.recall;
        score.f1 = sum > 0 ? 2 * score.precision * score.recall / sum : 0;
        r.strands.push_back(score);
    }
    double sa = 0, sb = 0;
    for (float d : near_a)
        sa += d;
    for (float d : near_b)
        sb += d;
    r.chamfer_a_to_b = sa / near_a.size();
    r.chamfer_b_to_a = sb / near_b.size();

    if (r.strands_a == r.strands_b) {
        r.corresponding = true;
        std::tie(r.position_error, r.curvature_error) =
            corresponding_errors(a, b, options.resample_points);
    }

    // The views: orientation error over both masks, silhouette IoU.
    double angle_sum = 0;
    size_t both = 0, either = 0;
    for (const std::string& view : options.views) {
        RenderOptions ro;
        ro.width = ro.height = options.size;
        ro.view = view;
        const Camera cam = render_camera(b, head, ro);
        const TargetMaps ma = draw_targets(a, head, cam), mb = draw_targets(b, head, cam);
        for (size_t i = 0; i < ma.hair.size(); ++i) {
            either += ma.hair[i] || mb.hair[i];
            if (!(ma.hair[i] && mb.hair[i])) continue;
            ++both;
            const float d = std::abs(ma.orientation[i] - mb.orientation[i]);
            angle_sum += std::min(d, kPi - d) * (180.0 / kPi);
        }
    }
    r.orientation_error = both ? angle_sum / both : 0;
    r.silhouette_iou = either ? static_cast<double>(both) / either : 0;

    // Occupancy over the box of both.
    Box3 box;
    for (const Vec3f& p : a.points)
        box.extend(p);
    for (const Vec3f& p : b.points)
        box.extend(p);
    const Vec3f extent = (box.hi - box.lo) / options.voxel;
    const double cells =
        (std::floor(extent.x()) + 1) * (std::floor(extent.y()) + 1) * (std::floor(extent.z()) + 1);
    constexpr double kMaxCells = 1 << 28;
    if (!(cells <= kMaxCells))
        fail("compare: an occupancy grid of ", options.voxel, " cm over the hairs' ",
             box.hi.x() - box.lo.x(), " x ", box.hi.y() - box.lo.y(), " x ",
             box.hi.z() - box.lo.z(), " cm would have ", cells, " voxels (at most ", kMaxCells,
             "): give a larger voxel");
    const Vec3i dims(static_cast<int>(extent.x()) + 1, static_cast<int>(extent.y()) + 1,
                     static_cast<int>(extent.z()) + 1);
    const std::vector<uint64_t> oa = occupancy(a, box, options.voxel, dims);
    const std::vector<uint64_t> ob = occupancy(b, box, options.voxel, dims);
    size_t inter = 0, uni = 0;
    for (size_t i = 0; i < oa.size(); ++i) {
        inter += std::popcount(oa[i] & ob[i]);
        uni += std::popcount(oa[i] | ob[i]);
    }
    r.occupancy_iou = uni ? static_cast<double>(inter) / uni : 0;
    return r;
}

nlohmann::json to_json(const CompareResult& r) {
    nlohmann::json strands = nlohmann::json::array();
    for (const StrandScore& s : r.strands)
        // The thresholds as given (0.2, not the float's 0.20000000298…).
        strands.push_back({{"distance_cm", std::round(s.distance * 1e4) / 1e4},
                           {"angle_degrees", std::round(s.angle * 1e4) / 1e4},
                           {"precision", s.precision},
                           {"recall", s.recall},
                           {"f1", s.f1}});
    nlohmann::json j = {{"strands_a", r.strands_a},
                        {"strands_b", r.strands_b},
                        {"points_a", r.points_a},
                        {"points_b", r.points_b},
                        {"strands", strands},
                        {"chamfer_a_to_b_cm", r.chamfer_a_to_b},
                        {"chamfer_b_to_a_cm", r.chamfer_b_to_a},
                        {"orientation_error_degrees", r.orientation_error},
                        {"silhouette_iou", r.silhouette_iou},
                        {"occupancy_iou", r.occupancy_iou}};
    if (r.corresponding) {
        j["position_error_cm"] = r.position_error;
        j["curvature_error_per_cm"] = r.curvature_error;
    }
    return j;
}

}  // namespace wisp
