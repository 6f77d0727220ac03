#include "dynamics/hierarchy.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>

#include "core/error.hpp"
#include "core/parallel.hpp"
#include "core/point_grid.hpp"

namespace wisp {
namespace {

// Weight of the root point in the clustering features, times √(sections − 1): the root
// counts four times as much as the rest of the curve, so clusters are neighbours on the scalp
// first and alike in shape second.
constexpr float kRootWeight = 2.f;

// The length under which a strand is short (shape_sources, build_hierarchy): a quarter of the
// median.
float short_length(const std::vector<float>& lengths) {
    if (lengths.size() < 2) return 0.f;
    std::vector<float> sorted = lengths;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    return 0.25f * sorted[sorted.size() / 2];
}

// Whose shape each strand is clustered by: its own, or for a strand under a quarter of the
// median length (a baby hair at the hairline, a trimmed strand), that of the nearest strand
// by root of at least that length. A short strand's cross-sections all lie by its root, so by
// its own shape it is closer to short strands from across the head than to its neighbours:
// it would make wisps of them, spanning the hairline. It moves with its neighbours instead.
//   samples  #strands·n cross-sections;  lengths  #strands
std::vector<uint32_t> shape_sources(const std::vector<Vec3f>& samples,
                                    const std::vector<float>& lengths, int n) {
    const size_t strands = lengths.size();
    std::vector<uint32_t> source(strands);
    for (size_t s = 0; s < strands; ++s)
        source[s] = static_cast<uint32_t>(s);
    if (strands < 2) return source;
    const float shortest = short_length(lengths);
    std::vector<Vec3f> roots;
    std::vector<uint32_t> full;
    Box3 box;
    for (size_t s = 0; s < strands; ++s)
        if (lengths[s] >= shortest && samples[s * static_cast<size_t>(n)].allFinite()) {
            full.push_back(static_cast<uint32_t>(s));
            roots.push_back(samples[s * static_cast<size_t>(n)]);
            box.extend(roots.back());
        }
    if (full.empty() || full.size() == strands) return source;
    // About the roots' spacing, for a grid of a few roots per cell.
    const Vec3f extent = box.hi - box.lo;
    const float cell =
        std::max(extent.maxCoeff() / std::sqrt(static_cast<float>(full.size())), 1e-3f);
    const PointGrid grid(roots, cell);
    parallel_for(
        strands,
        [&](size_t s) {
            // (A strand with a non-finite point keeps its own shape: it is refused elsewhere.)
            if (lengths[s] >= shortest || !std::isfinite(lengths[s]) ||
                !samples[s * static_cast<size_t>(n)].allFinite())
                return;
            const int j = grid.nearest(samples[s * static_cast<size_t>(n)]);
            if (j >= 0) source[s] = full[static_cast<size_t>(j)];
        },
        256);
    return source;
}

// Splits `items` (indices into rows of `features`, `dim` floats each) into at least `k`
// clusters of at most `max_size` items: repeatedly the largest cluster is cut in two at the
// median of its projection on its principal axis (a few power iterations). Returns the
// clusters, each in ascending item order. Deterministic: ties are broken by item index.
std::vector<std::vector<uint32_t>> bisect(const std::vector<float>& features, size_t dim,
                                          std::vector<uint32_t> items, size_t k,
                                          size_t max_size = SIZE_MAX) {
    k = std::max<size_t>(1, std::min(k, items.size()));
    max_size = std::max<size_t>(1, max_size);
    std::vector<std::vector<uint32_t>> clusters;
    clusters.push_back(std::move(items));
    // (size, −index) so the largest, then earliest, cluster splits first.
    auto larger = [&](size_t a, size_t b) {
        if (clusters[a].size() != clusters[b].size())
            return clusters[a].size() < clusters[b].size();
        return a > b;
    };
    std::priority_queue<size_t, std::vector<size_t>, decltype(larger)> queue(larger);
    queue.push(0);
    std::vector<double> mean(dim), axis(dim), next(dim);
    std::vector<std::pair<double, uint32_t>> projected;
    while (!queue.empty() && (clusters.size() < k || clusters[queue.top()].size() > max_size)) {
        const size_t c = queue.top();
        queue.pop();
        std::vector<uint32_t>& members = clusters[c];
        if (members.size() < 2) continue;
        std::fill(mean.begin(), mean.end(), 0.0);
        for (uint32_t i : members)
            for (size_t d = 0; d < dim; ++d)
                mean[d] += features[i * dim + d];
        for (double& m : mean)
            m /= static_cast<double>(members.size());
        // Start from the coordinate of largest variance, then power iterations on the
        // covariance.
        std::fill(next.begin(), next.end(), 0.0);
        for (uint32_t i : members)
            for (size_t d = 0; d < dim; ++d) {
                const double x = features[i * dim + d] - mean[d];
                next[d] += x * x;
            }
        std::fill(axis.begin(), axis.end(), 0.0);
        axis[std::max_element(next.begin(), next.end()) - next.begin()] = 1.0;
        for (int iteration = 0; iteration < 6; ++iteration) {
            std::fill(next.begin(), next.end(), 0.0);
            for (uint32_t i : members) {
                double dot = 0;
                for (size_t d = 0; d < dim; ++d)
                    dot += (features[i * dim + d] - mean[d]) * axis[d];
                for (size_t d = 0; d < dim; ++d)
                    next[d] += dot * (features[i * dim + d] - mean[d]);
            }
            double norm = 0;
            for (double x : next)
                norm += x * x;
            if (!(norm > 1e-30)) break;
            norm = std::sqrt(norm);
            for (size_t d = 0; d < dim; ++d)
                axis[d] = next[d] / norm;
        }
        projected.clear();
        for (uint32_t i : members) {
            double dot = 0;
            for (size_t d = 0; d < dim; ++d)
                dot += (features[i * dim + d] - mean[d]) * axis[d];
            projected.emplace_back(dot, i);
        }
        const size_t half = projected.size() / 2;
        std::nth_element(projected.begin(), projected.begin() + half, projected.end());
        std::vector<uint32_t> low, high;
        for (size_t j = 0; j < projected.size(); ++j)
            (j < half ? low : high).push_back(projected[j].second);
        std::sort(low.begin(), low.end());
        std::sort(high.begin(), high.end());
        clusters[c] = std::move(low);
        clusters.push_back(std::move(high));
        queue.push(c);
        queue.push(clusters.size() - 1);
    }
    // A stable order: by first item.
    std::sort(clusters.begin(), clusters.end(),
              [](const auto& a, const auto& b) { return a.front() < b.front(); });
    return clusters;
}

// A group whose wisps part ways, say over the two sides of a shoulder, is no cylinder: its
// axis runs through the gap between its wisps and its radius spans them (20 cm and more at the
// tips of long hair, against 5 to 8 cm for a group that hangs together). Such a node reads
// any small acceleration as over the split threshold (|a|·r with r three times a group's), its
// merge test (sub-nodes within its radius) passes for wisps far from where its rest shape
// has them, and its cylinder touches most of the hair at once: settled hair split and merged
// there over and over. A group is parted when, at some section, its wisps lie farther from
// its centre than this many times their roots do (the roots taken as at least
// kPartedRootSpread apart).
constexpr float kPartedSpread = 3.f;
constexpr float kPartedRootSpread = 1.f;  // cm

// Whether the rows `members` of `features` (n points each, the root's coordinates times
// `root_weight`) part ways, as above.
bool parted(const std::vector<float>& features, size_t dim, int n, float root_weight,
            const std::vector<uint32_t>& members) {
    float root = 0, worst = 0;
    for (int k = 0; k < n; ++k) {
        const auto point = [&](uint32_t i) {
            const float* f = features.data() + i * dim + 3 * static_cast<size_t>(k);
            return Vec3f(f[0], f[1], f[2]);
        };
        Vec3f centre = Vec3f::Zero();
        for (uint32_t i : members)
            centre += point(i);
        centre /= static_cast<float>(members.size());
        float spread = 0;
        for (uint32_t i : members)
            spread = std::max(spread, (point(i) - centre).norm());
        if (k == 0)
            root = std::max(kPartedRootSpread, spread / root_weight);
        else
            worst = std::max(worst, spread);
    }
    return worst > kPartedSpread * root;
}

struct Cluster {
    uint32_t parent = 0;
    std::vector<uint32_t> strands;  // ascending
};

}  // namespace

Vec3f point_at_fraction(std::span<const Vec3f> strand, float t) {
    float total = 0;
    for (size_t i = 1; i < strand.size(); ++i)
        total += (strand[i] - strand[i - 1]).norm();
    float target = std::clamp(t, 0.f, 1.f) * total;
    for (size_t i = 1; i < strand.size(); ++i) {
        const float len = (strand[i] - strand[i - 1]).norm();
        if (target <= len && len > 0)
            return strand[i - 1] + (target / len) * (strand[i] - strand[i - 1]);
        target -= len;
    }
    return strand.back();
}

std::vector<float> held_lengths(const Hair& hair, std::span<const Tie> ties) {
    for (size_t t = 0; t < ties.size(); ++t) {
        if (!ties[t].point.allFinite()) fail("dynamics: tie ", t + 1, " is not a finite point");
        if (!(ties[t].radius > 0) || !std::isfinite(ties[t].radius))
            fail("dynamics: the radius of tie ", t + 1, " must be > 0, got ", ties[t].radius);
    }
    std::vector<float> held(hair.strand_count(), 0.f);
    if (ties.empty()) return held;
    parallel_for(
        hair.strand_count(),
        [&](size_t s) {
            const auto strand = hair.strand(s);
            for (const Tie& tie : ties) {
                // The nearest approach of the polyline to the tie, and its arc length.
                float best = tie.radius * tie.radius, at = -1, walked = 0;
                for (size_t i = 0; i < strand.size(); ++i) {
                    float u = 0, length = 0;
                    Vec3f q = strand[i];
                    if (i + 1 < strand.size()) {
                        const Vec3f d = strand[i + 1] - strand[i];
                        length = d.norm();
                        const float dd = d.squaredNorm();
                        u = dd > 0 ? std::clamp((tie.point - strand[i]).dot(d) / dd, 0.f, 1.f)
                                   : 0.f;
                        q = strand[i] + u * d;
                    }
                    const float d2 = (q - tie.point).squaredNorm();
                    if (d2 <= best) {
                        best = d2;
                        at = walked + u * length;
                    }
                    walked += length;
                }
                held[s] = std::max(held[s], at);
            }
        },
        256);
    return held;
}

std::vector<float> tie_holds(const Hair& hair, std::span<const Tie> ties,
                             std::vector<size_t>* caught) {
    std::vector<float> held;
    if (caught) caught->clear();
    for (size_t t = 0; t < ties.size(); ++t) {
        const Tie& tie = ties[t];
        const std::vector<float> own = held_lengths(hair, ties.subspan(t, 1));
        const auto count = static_cast<size_t>(
            std::count_if(own.begin(), own.end(), [](float l) { return l > 0; }));
        if (count == 0) {
            const Box3 box = hair.bounds();
            fail("tie ", t + 1, " (", tie.point.x(), ",", tie.point.y(), ",", tie.point.z(),
                 ", radius ", tie.radius, " cm) passes within ", tie.radius,
                 " cm of no strand (the hair spans ", box.lo.x(), ",", box.lo.y(), ",", box.lo.z(),
                 " to ", box.hi.x(), ",", box.hi.y(), ",", box.hi.z(), ")");
        }
        if (caught) caught->push_back(count);
        if (held.empty()) held.assign(own.size(), 0.f);
        for (size_t s = 0; s < own.size(); ++s)
            held[s] = std::max(held[s], own[s]);
    }
    return held;
}

Hierarchy build_hierarchy(const Hair& hair, const HierarchyOptions& o) {
    if (o.levels < 2 || o.levels > 4) fail("dynamics: levels must be in [2, 4], got ", o.levels);
    if (o.sections < 3 || o.sections > 64)
        fail("dynamics: sections must be in [3, 64], got ", o.sections);
    if (o.sub_wisps < 2 || o.sub_wisps > 16)
        fail("dynamics: sub_wisps must be in [2, 16], got ", o.sub_wisps);
    if (o.wisps_per_group < 2 || o.wisps_per_group > 64)
        fail("dynamics: wisps_per_group must be in [2, 64], got ", o.wisps_per_group);
    if (o.strands_per_wisp < 1)
        fail("dynamics: strands_per_wisp must be ≥ 1, got ", o.strands_per_wisp);
    if (!(o.linear_density > 0) || !std::isfinite(o.linear_density))
        fail("dynamics: linear_density must be > 0, got ", o.linear_density);
    for (size_t w = 0; w < o.wisp_held.size(); ++w)
        if (!(o.wisp_held[w] >= 0) || !std::isfinite(o.wisp_held[w]))
            fail("dynamics: the held length of wisp ", w, " must be ≥ 0, got ", o.wisp_held[w]);
    const size_t strands = hair.strand_count();
    if (strands == 0) fail("dynamics: the hair has no strands");
    if (!o.strand_held.empty() && o.strand_held.size() != strands)
        fail("dynamics: ", o.strand_held.size(), " held lengths for ", strands, " strands");
    for (size_t s = 0; s < o.strand_held.size(); ++s)
        if (!(o.strand_held[s] >= 0) || !std::isfinite(o.strand_held[s]))
            fail("dynamics: the held length of strand ", s, " must be ≥ 0, got ", o.strand_held[s]);
    for (size_t s = 0; s < strands; ++s)
        if (hair.strand_size(s) < 2) fail("dynamics: strand ", s, " has fewer than 2 points");

    const int n = o.sections;
    // Cross-sections of every strand, the clustering features (root weighted), lengths.
    std::vector<Vec3f> samples(strands * n);
    std::vector<float> lengths(strands);
    parallel_for(
        strands,
        [&](size_t s) {
            const auto strand = hair.strand(s);
            float total = 0;
            for (size_t i = 1; i < strand.size(); ++i)
                total += (strand[i] - strand[i - 1]).norm();
            lengths[s] = total;
            // One walk along the strand for all n fractions.
            size_t i = 1;
            float walked = 0;
            for (int k = 0; k < n; ++k) {
                const float target = total * static_cast<float>(k) / static_cast<float>(n - 1);
                while (i + 1 < strand.size() &&
                       walked + (strand[i] - strand[i - 1]).norm() < target) {
                    walked += (strand[i] - strand[i - 1]).norm();
                    ++i;
                }
                const float len = (strand[i] - strand[i - 1]).norm();
                const float f = len > 0 ? std::clamp((target - walked) / len, 0.f, 1.f) : 0.f;
                samples[s * n + k] = strand[i - 1] + f * (strand[i] - strand[i - 1]);
            }
        },
        256);
    const size_t dim = 3 * static_cast<size_t>(n);
    const float root_weight = kRootWeight * std::sqrt(static_cast<float>(n - 1));
    const std::vector<uint32_t> shape_of = shape_sources(samples, lengths, n);
    auto strand_features = [&]() {
        std::vector<float> f(strands * dim);
        for (size_t s = 0; s < strands; ++s) {
            const size_t j = shape_of[s];
            const Vec3f shift = samples[s * n] - samples[j * n];
            for (int k = 0; k < n; ++k) {
                const Vec3f p = k == 0 ? samples[s * n] : Vec3f(samples[j * n + k] + shift);
                for (int c = 0; c < 3; ++c)
                    f[s * dim + 3 * k + c] = p[c] * (k == 0 ? root_weight : 1.f);
            }
        }
        return f;
    }();

    // The length each strand is held through: its wisp's, or its own, whichever is longer.
    bool has_ids = hair.wisp.size() == strands;
    for (size_t s = 0; has_ids && s < strands; ++s)
        has_ids = hair.wisp[s] >= 0;
    std::vector<float> held_length(strands, 0.f);
    for (size_t s = 0; s < strands; ++s) {
        if (has_ids && static_cast<size_t>(hair.wisp[s]) < o.wisp_held.size())
            held_length[s] = o.wisp_held[static_cast<size_t>(hair.wisp[s])];
        if (!o.strand_held.empty()) held_length[s] = std::max(held_length[s], o.strand_held[s]);
    }

    // Short strands (baby hairs at the hairline, in wisps that fall down the back) make wisps
    // and groups of their own. Their cross-sections lie by their roots: in a node with long
    // hair, they would stretch its radius from the nape to the tips (30 cm), and it would read
    // any small acceleration as over the split threshold and split and merge over and over on
    // settled hair.
    const float shortest = short_length(lengths);
    std::vector<uint8_t> is_short(strands);
    for (size_t s = 0; s < strands; ++s)
        is_short[s] = lengths[s] < shortest;

    // The wisp level.
    std::vector<Cluster> wisps;
    if (has_ids) {
        std::map<std::pair<int32_t, uint8_t>, uint32_t> index;
        for (size_t s = 0; s < strands; ++s)
            index.emplace(std::pair{hair.wisp[s], is_short[s]}, 0);
        uint32_t next = 0;
        for (auto& [id, i] : index)
            i = next++;
        wisps.resize(index.size());
        for (size_t s = 0; s < strands; ++s)
            wisps[index[{hair.wisp[s], is_short[s]}]].strands.push_back(static_cast<uint32_t>(s));
    } else {
        // Held and free strands make separate wisps, as do short and long.
        std::vector<uint32_t> classes[4];
        for (size_t s = 0; s < strands; ++s)
            classes[2 * (held_length[s] > 0) + is_short[s]].push_back(static_cast<uint32_t>(s));
        for (std::vector<uint32_t>& all : classes) {
            if (all.empty()) continue;
            for (auto& members : bisect(strand_features, dim, std::move(all), 1,
                                        static_cast<size_t>(o.strands_per_wisp)))
                wisps.push_back(Cluster{0, std::move(members)});
        }
    }

    // Levels of clusters, coarse to fine; parents index into the level above.
    std::vector<std::vector<Cluster>> levels;
    if (o.levels >= 3) {
        // Groups of neighbouring wisps: bisect the wisps' mean curves.
        std::vector<float> wf(wisps.size() * dim, 0.f);
        for (size_t w = 0; w < wisps.size(); ++w) {
            for (uint32_t s : wisps[w].strands)
                for (size_t d = 0; d < dim; ++d)
                    wf[w * dim + d] += strand_features[s * dim + d];
            for (size_t d = 0; d < dim; ++d)
                wf[w * dim + d] /= static_cast<float>(wisps[w].strands.size());
        }
        // Held and free wisps are grouped apart: a group is tied or loose as a whole, so the
        // coarse nodes of a ponytail are not half pinned.
        // A wisp is held when most of its strands are; short ones (above) are grouped apart.
        std::vector<uint32_t> classes[4];
        for (size_t w = 0; w < wisps.size(); ++w) {
            size_t held = 0;
            for (uint32_t s : wisps[w].strands)
                held += held_length[s] > 0;
            const bool held_wisp = 2 * held > wisps[w].strands.size();
            classes[2 * held_wisp + is_short[wisps[w].strands.front()]].push_back(
                static_cast<uint32_t>(w));
        }
        std::vector<Cluster> groups;
        for (std::vector<uint32_t>& all : classes) {
            if (all.empty()) continue;
            const size_t k = (all.size() + o.wisps_per_group - 1) / o.wisps_per_group;
            std::vector<std::vector<uint32_t>> cut = bisect(wf, dim, std::move(all), k);
            // Parted groups are cut again, until none is (at worst down to single wisps).
            for (size_t c = 0; c < cut.size(); ++c)
                while (cut[c].size() > 1 && parted(wf, dim, n, root_weight, cut[c])) {
                    std::vector<std::vector<uint32_t>> two = bisect(wf, dim, cut[c], 2);
                    cut[c] = std::move(two[0]);
                    cut.push_back(std::move(two[1]));
                }
            std::sort(cut.begin(), cut.end(),
                      [](const auto& a, const auto& b) { return a.front() < b.front(); });
            for (auto& members : cut) {
                Cluster g;
                for (uint32_t w : members) {
                    wisps[w].parent = static_cast<uint32_t>(groups.size());
                    g.strands.insert(g.strands.end(), wisps[w].strands.begin(),
                                     wisps[w].strands.end());
                }
                std::sort(g.strands.begin(), g.strands.end());
                groups.push_back(std::move(g));
            }
        }
        levels.push_back(std::move(groups));
    }
    levels.push_back(std::move(wisps));
    const int finer = o.levels - static_cast<int>(levels.size());
    for (int l = 0; l < finer; ++l) {
        const std::vector<Cluster>& above = levels.back();
        std::vector<std::vector<Cluster>> parts(above.size());
        parallel_for(above.size(), [&](size_t c) {
            for (auto& members : bisect(strand_features, dim, above[c].strands, o.sub_wisps))
                parts[c].push_back(Cluster{static_cast<uint32_t>(c), std::move(members)});
        });
        std::vector<Cluster> level;
        for (auto& p : parts)
            for (auto& c : p)
                level.push_back(std::move(c));
        levels.push_back(std::move(level));
    }

    // Order every level by parent (stable), so sub-GCs are contiguous, and renumber the
    // parents of the level below to match.
    for (size_t l = 1; l < levels.size(); ++l) {
        std::vector<uint32_t> order(levels[l].size());
        for (size_t c = 0; c < order.size(); ++c)
            order[c] = static_cast<uint32_t>(c);
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
            return levels[l][a].parent < levels[l][b].parent;
        });
        std::vector<Cluster> sorted(order.size());
        std::vector<uint32_t> new_index(order.size());
        for (size_t c = 0; c < order.size(); ++c) {
            sorted[c] = std::move(levels[l][order[c]]);
            new_index[order[c]] = static_cast<uint32_t>(c);
        }
        levels[l] = std::move(sorted);
        if (l + 1 < levels.size())
            for (Cluster& child : levels[l + 1])
                child.parent = new_index[child.parent];
    }

    Hierarchy h;
    h.levels = o.levels;
    h.sections = n;
    h.level_begin.push_back(0);
    for (const auto& level : levels)
        h.level_begin.push_back(h.level_begin.back() + static_cast<uint32_t>(level.size()));
    const size_t gcs = h.level_begin.back();
    h.level.resize(gcs);
    h.super.assign(gcs, -1);
    h.child_begin.assign(gcs, 0);
    h.child_count.assign(gcs, 0);
    h.strand_count.resize(gcs);
    h.strand_gc.resize(strands);
    for (size_t l = 0; l < levels.size(); ++l)
        for (size_t c = 0; c < levels[l].size(); ++c) {
            const uint32_t g = h.level_begin[l] + static_cast<uint32_t>(c);
            h.level[g] = static_cast<uint8_t>(l);
            h.strand_count[g] = static_cast<uint32_t>(levels[l][c].strands.size());
            if (l == 0) continue;
            const uint32_t parent = h.level_begin[l - 1] + levels[l][c].parent;
            h.super[g] = static_cast<int32_t>(parent);
            if (h.child_count[parent]++ == 0) h.child_begin[parent] = g;
        }
    const uint32_t finest = h.level_begin[o.levels - 1];
    for (size_t c = 0; c < levels.back().size(); ++c)
        for (uint32_t s : levels.back()[c].strands)
            h.strand_gc[s] = finest + static_cast<uint32_t>(c);

    // Rest nodes, radii and masses: finest from strands, coarser from their sub-nodes.
    h.rest.assign(gcs * n, Vec3f::Zero());
    h.radius.assign(gcs * n, 0.f);
    h.mass.assign(gcs * n, 0.f);
    h.held.assign(gcs * n, 0.f);
    parallel_for(levels.back().size(), [&](size_t c) {
        const uint32_t g = finest + static_cast<uint32_t>(c);
        const auto& members = levels.back()[c].strands;
        double segment_mass = 0;
        for (uint32_t s : members)
            segment_mass += lengths[s] / static_cast<double>(n - 1) * o.linear_density;
        for (int k = 0; k < n; ++k) {
            Vec3d sum = Vec3d::Zero();
            for (uint32_t s : members)
                sum += samples[s * n + k].cast<double>();
            const Vec3f centre = (sum / static_cast<double>(members.size())).cast<float>();
            // The radius holding 90% of the strands: a stray fuzzy strand does not make the
            // whole cylinder (and every collision test around it) fatter.
            std::vector<float> d;
            d.reserve(members.size());
            for (uint32_t s : members)
                d.push_back((samples[s * n + k] - centre).norm());
            const size_t q = std::min(d.size() - 1, (d.size() * 9) / 10);
            std::nth_element(d.begin(), d.begin() + q, d.end());
            const float r = std::max(0.05f, d[q]);
            h.rest[h.node(g, k)] = centre;
            h.radius[h.node(g, k)] = r;
            h.mass[h.node(g, k)] = static_cast<float>(segment_mass);
            // Held when most of its strands' cross-sections k lie within their held length,
            // to the nearest section.
            size_t held = 0;
            for (uint32_t s : members)
                held += (static_cast<float>(k) - 0.5f) / static_cast<float>(n - 1) * lengths[s] <=
                        held_length[s];
            h.held[h.node(g, k)] = 2 * held > members.size() ? 1.f : 0.f;
        }
    });
    for (int l = o.levels - 2; l >= 0; --l)
        for (uint32_t g = h.level_begin[l]; g < h.level_begin[l + 1]; ++g)
            for (int k = 0; k < n; ++k) {
                double m = 0, held = 0;
                Vec3d sum = Vec3d::Zero();
                for (uint32_t c = h.child_begin[g]; c < h.child_begin[g] + h.child_count[g]; ++c) {
                    m += h.mass[h.node(c, k)];
                    sum += h.mass[h.node(c, k)] * h.rest[h.node(c, k)].cast<double>();
                    held += h.mass[h.node(c, k)] * h.held[h.node(c, k)];
                }
                h.held[h.node(g, k)] = static_cast<float>(held / m);
                const Vec3f centre = (sum / m).cast<float>();
                float r = 0.05f;
                for (uint32_t c = h.child_begin[g]; c < h.child_begin[g] + h.child_count[g]; ++c)
                    r = std::max(r,
                                 (h.rest[h.node(c, k)] - centre).norm() + h.radius[h.node(c, k)]);
                h.rest[h.node(g, k)] = centre;
                h.radius[h.node(g, k)] = r;
                h.mass[h.node(g, k)] = static_cast<float>(m);
            }
    return h;
}

}  // namespace wisp
