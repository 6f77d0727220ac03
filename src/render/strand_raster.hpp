#pragma once
// Coverage rasterization of one thin strand piece: a straight segment of the image plane
// with a width at each end, as thin as a fraction of a pixel. The segment is walked one
// pixel column (or row, whichever axis it spans more of) at a time; across it, its extent
// h = width / cos(slope) is spread over the pixels it overlaps. Pieces thinner than a pixel
// are widened to one pixel with their intensity scaled by h, i.e. a tent filter across the
// strand (Wu's antialiased lines), so that a strand's summed coverage equals its area in
// pixels whatever its position or width. Columns are sampled at their centres with a
// half-open rule (centre in [start, end)), so consecutive pieces of a strand neither
// overlap nor leave gaps.
#include <algorithm>
#include <cmath>

namespace wisp {

// ⌊x⌋ and ⌈x⌉ as ints, for x within the int range: std::floor and std::ceil are a libm call or
// a long sequence on the baseline x86-64 this is built for (no SSE4.1 round), and the tiles
// take several per piece and one per pixel column.
inline int floor_to_int(float x) {
    const int i = static_cast<int>(x);  // toward zero
    return i - (static_cast<float>(i) > x);
}
inline int ceil_to_int(float x) {
    const int i = static_cast<int>(x);
    return i + (static_cast<float>(i) < x);
}

// Calls fragment(x, y, t, coverage) for each pixel (x, y) of the clip rectangle
// [clip_x0, clip_x1) × [clip_y0, clip_y1) that the segment from (x0, y0) with width w0 to
// (x1, y1) with width w1 (pixels) covers: t in [0, 1] is the position along the segment,
// coverage in (0, 1] the fraction of the pixel covered.
template <typename Fragment>
void rasterize_strand_piece(float x0, float y0, float w0, float x1, float y1, float w1, int clip_x0,
                            int clip_y0, int clip_x1, int clip_y1, Fragment&& fragment) {
    const float dx = x1 - x0, dy = y1 - y0;
    const bool x_major = std::abs(dx) >= std::abs(dy);
    // Work in (a, b) = (major, minor) coordinates.
    const float a0 = x_major ? x0 : y0, b0 = x_major ? y0 : x0;
    const float da = x_major ? dx : dy, db = x_major ? dy : dx;
    if (da == 0.f) return;
    const int lo_a = x_major ? clip_x0 : clip_y0, hi_a = x_major ? clip_x1 : clip_y1;
    const int lo_b = x_major ? clip_y0 : clip_x0, hi_b = x_major ? clip_y1 : clip_x1;
    const float a_min = std::min(a0, a0 + da), a_max = std::max(a0, a0 + da);
    const int first = std::max(lo_a, ceil_to_int(a_min - 0.5f));
    const int last = std::min(hi_a, ceil_to_int(a_max - 0.5f));  // exclusive
    if (first >= last) return;
    const float inv_da = 1.f / da, slope = db * inv_da;
    const float stretch = std::sqrt(1.f + slope * slope);  // 1 / cos of the angle to the axis
    for (int i = first; i < last; ++i) {
        const float t = std::clamp((static_cast<float>(i) + 0.5f - a0) * inv_da, 0.f, 1.f);
        const float b = b0 + db * t;
        const float h = (w0 + (w1 - w0) * t) * stretch;
        if (!(h > 0.f)) continue;
        if (h <= 1.f) {  // the common case: two rows weighted by a tent, as below
            const float c = b - 0.5f;
            const int j = floor_to_int(c);
            const float f = c - static_cast<float>(j);
            if (j >= lo_b && j < hi_b && f < 1.f) {
                if (x_major)
                    fragment(i, j, t, (1.f - f) * h);
                else
                    fragment(j, i, t, (1.f - f) * h);
            }
            if (j + 1 >= lo_b && j + 1 < hi_b && f > 0.f) {
                if (x_major)
                    fragment(i, j + 1, t, f * h);
                else
                    fragment(j + 1, i, t, f * h);
            }
            continue;
        }
        const float half = 0.5f * h;
        const float gain = 1.f;
        const float lo = b - half, hi = b + half;
        const int j0 = std::max(lo_b, floor_to_int(lo));
        const int j1 = std::min(hi_b - 1, floor_to_int(hi));
        for (int j = j0; j <= j1; ++j) {
            const float overlap =
                std::min(hi, static_cast<float>(j + 1)) - std::max(lo, static_cast<float>(j));
            if (overlap <= 0.f) continue;
            const float coverage = std::min(1.f, overlap * gain);
            if (x_major)
                fragment(i, j, t, coverage);
            else
                fragment(j, i, t, coverage);
        }
    }
}

}  // namespace wisp
