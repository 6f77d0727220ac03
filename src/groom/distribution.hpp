#pragma once
// Drawing from a style's scalar distributions (length distribution l(u) of Choe & Ko §2.1,
// the HSV channels of §5).
#include "core/rng.hpp"
#include "groom/style.hpp"

namespace wisp {

// One draw. kNormal is truncated to [min, max] by resampling (at most 64 tries, then the
// mean clamped into range); kTable is the histogram over [min, max].
float sample(const Distribution& d, Rng& rng);

}  // namespace wisp
