#include "groom/member.hpp"

#include <algorithm>

namespace wisp {

void grow_member(std::span<const Vec3f> master, std::span<const Frame> frames,
                 std::span<const float> radius, const Vec3f& root_offset, float length_u,
                 float fuzziness, Rng& rng, std::span<Vec3f> out) {
    const int n = static_cast<int>(master.size());
    const float k_end = std::clamp(length_u, 0.f, 1.f) * static_cast<float>(n - 1);
    const size_t count = out.size();
    Vec3f d = root_offset;
    out[0] = master[0] + frames[0].to_world(d);
    // Whole master points first; the last output point may be a fractional one.
    const int whole = static_cast<int>(k_end);
    const int last_whole = std::min<int>(whole, static_cast<int>(count) - 1);
    for (int k = 1; k <= last_whole; ++k) {
        d = next_offset(d, radius[k - 1], radius[k], fuzziness, rng);
        out[k] = master[k] + frames[k].to_world(d);
    }
    if (static_cast<size_t>(last_whole + 1) < count) {
        // Interpolated tip between master points `whole` and `whole + 1` (or a very short
        // member whose whole part is 0).
        const int k = std::min(last_whole + 1, n - 1);
        const Vec3f d_next = next_offset(d, radius[k - 1], radius[k], fuzziness, rng);
        const Vec3f a = out[last_whole];
        const Vec3f b = master[k] + frames[k].to_world(d_next);
        const float f = std::clamp(k_end - static_cast<float>(last_whole), 0.f, 1.f);
        out[last_whole + 1] = a + f * (b - a);
    }
}

}  // namespace wisp
