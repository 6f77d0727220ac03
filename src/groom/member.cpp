#include "groom/member.hpp"

#include <algorithm>

namespace wisp {

void grow_member_points(std::span<const Vec3f> master, std::span<const Frame> frames,
                        std::span<const float> radius, float length_u, float fuzziness, int k0,
                        int k1, Vec3f& offset, Rng& rng, std::span<Vec3f> out) {
    grow_member_points(master, frames, radius, length_u, fuzziness, k0, k1, offset, rng, out,
                       [](int, const Vec3f& p) { return p; });
}

void grow_member(std::span<const Vec3f> master, std::span<const Frame> frames,
                 std::span<const float> radius, const Vec3f& root_offset, float length_u,
                 float fuzziness, Rng& rng, std::span<Vec3f> out) {
    Vec3f d = root_offset;
    grow_member_points(master, frames, radius, length_u, fuzziness, 0,
                       static_cast<int>(master.size()), d, rng, out);
}

}  // namespace wisp
