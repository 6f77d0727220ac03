#include "groom/member.hpp"

#include <algorithm>

namespace wisp {

void grow_member_points(std::span<const Vec3f> master, std::span<const Frame> frames,
                        std::span<const float> radius, float length_u, float fuzziness, int k0,
                        int k1, Vec3f& offset, Rng& rng, std::span<Vec3f> out) {
    const int n = static_cast<int>(master.size());
    const float k_end = std::clamp(length_u, 0.f, 1.f) * static_cast<float>(n - 1);
    const int count = static_cast<int>(out.size());
    // Whole master points first; the last output point may be a fractional one.
    const int whole = static_cast<int>(k_end);
    const int last_whole = std::min(whole, count - 1);
    // In registers for the loop (`out` could alias `offset` as far as the compiler knows).
    Vec3f d = offset;
    Rng r = rng;
    const int end = std::min(k1, count);
    int k = std::max(k0, 0);
    if (k == 0 && end > 0) {
        out[0] = master[0] + frames[0].to_world(d);
        k = 1;
    }
    for (; k < std::min(end, last_whole + 1); ++k) {
        d = next_offset(d, radius[k - 1], radius[k], fuzziness, r);
        out[k] = master[k] + frames[k].to_world(d);
    }
    if (k < end) {
        // k = last_whole + 1: the tip interpolated between master points `whole` and
        // `whole + 1` (or a very short member whose whole part is 0).
        const int m = std::min(k, n - 1);
        const Vec3f d_next = next_offset(d, radius[m - 1], radius[m], fuzziness, r);
        const Vec3f a = out[last_whole];
        const Vec3f b = master[m] + frames[m].to_world(d_next);
        const float f = std::clamp(k_end - static_cast<float>(last_whole), 0.f, 1.f);
        out[k] = a + f * (b - a);
    }
    offset = d;
    rng = r;
}

void grow_member(std::span<const Vec3f> master, std::span<const Frame> frames,
                 std::span<const float> radius, const Vec3f& root_offset, float length_u,
                 float fuzziness, Rng& rng, std::span<Vec3f> out) {
    Vec3f d = root_offset;
    grow_member_points(master, frames, radius, length_u, fuzziness, 0,
                       static_cast<int>(master.size()), d, rng, out);
}

}  // namespace wisp
