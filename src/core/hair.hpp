#pragma once
// A hairstyle as flat arrays (structure of arrays), DESIGN.md "Data layout".
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace wisp {

// Readers reject any coordinate whose magnitude exceeds this (centimetres, 1 km): hair that
// far from the head is a unit or file error, and grids sized by the hair's bounds (the
// solver's, the renderer's, the animation's) must stay small (docs/formats.md).
inline constexpr float kMaxCoordinate = 1e5f;

struct Hair {
    // points   #P control points of uniform Catmull-Rom splines (pinned ends), centimetres,
    //          head space (Y up, +Z forward), strand after strand, root first.
    std::vector<Vec3f> points;
    // offsets  #S+1, strand i owns points[offsets[i] .. offsets[i+1]); offsets[0] = 0.
    std::vector<uint32_t> offsets{0};
    // widths   #P strand diameter at each point in cm, or empty (then default_width).
    std::vector<float> widths;
    // colors   #S linear RGB in [0,1] per strand, or empty (then default_color).
    std::vector<Vec3f> colors;
    // wisp     #S wisp id per strand (-1 for none), or empty when unknown (imported hair).
    std::vector<int32_t> wisp;
    // root_uv      #S scalp UV of each strand's root (geometry/scalp.hpp: the crown at (0.5,
    //              0.5), the lowest hairline on the circle of radius 0.5 about it), or empty
    //              when unknown (imported hair).
    std::vector<Vec2f> root_uv;
    // root_normal  #S unit scalp normal at each strand's root, head space, or empty.
    std::vector<Vec3f> root_normal;
    // group        #S wisp group of each strand, >= 0: 1 + the index in Style::groups of the
    //              first constraint group (hairdressing sections expand into these) that
    //              holds the strand's wisp, 0 for wisps in none; empty when unknown.
    std::vector<int32_t> group;
    float default_width = 0.008f;  // 80 µm
    Vec3f default_color = Vec3f(0.30f, 0.20f, 0.12f);

    size_t strand_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
    size_t point_count() const { return points.size(); }
    uint32_t strand_size(size_t i) const { return offsets[i + 1] - offsets[i]; }
    std::span<const Vec3f> strand(size_t i) const {
        return {points.data() + offsets[i], strand_size(i)};
    }
    std::span<Vec3f> strand(size_t i) { return {points.data() + offsets[i], strand_size(i)}; }
    float width_at(size_t point) const { return widths.empty() ? default_width : widths[point]; }
    Vec3f color_of(size_t strand) const { return colors.empty() ? default_color : colors[strand]; }

    // Appends one strand (copies its points); for readers, not for hot loops.
    void add_strand(std::span<const Vec3f> pts) {
        points.insert(points.end(), pts.begin(), pts.end());
        offsets.push_back(static_cast<uint32_t>(points.size()));
    }
    // The box of the control points (empty when there are none), on all cores in chunks of a
    // fixed size: min and max are exact, so the box is the same at any thread count. The one
    // bounds of the points that the writers' extents and the renderer's framing use.
    Box3 bounds() const;
    // The largest of widths, or default_width when widths is empty; on all cores like bounds().
    float max_width() const;
    // Throws wisp::Error naming `what` if the arrays disagree in size, hold non-finite
    // values or a coordinate beyond ±kMaxCoordinate (called by every reader before it
    // returns, and by every writer).
    void validate(const std::string& what) const;
};

// The strands `keep` (#K indices into hair's strands, any order, repeats allowed) as a new
// Hair, with every per-point and per-strand array that hair has and its defaults. Throws
// wisp::Error for an index out of range.
Hair select_strands(const Hair& hair, std::span<const uint32_t> keep);

// n strand indices spread evenly over [0, total): index k is floor((k + 0.5)·total / n), so
// the subset is deterministic and takes strands from every part of the strand order (wisp
// after wisp). n >= total gives every index.
std::vector<uint32_t> even_subset(size_t total, size_t n);

}  // namespace wisp
