#include "core/hair.hpp"

#include <cmath>

#include "core/error.hpp"

namespace wisp {

void Hair::validate(const std::string& what) const {
    if (offsets.empty() || offsets.front() != 0) fail(what, ": offsets must start with 0");
    for (size_t i = 0; i + 1 < offsets.size(); ++i)
        if (offsets[i + 1] < offsets[i]) fail(what, ": strand ", i, " has negative point count");
    if (offsets.back() != points.size())
        fail(what, ": offsets end at ", offsets.back(), " but there are ", points.size(),
             " points");
    const size_t s = strand_count();
    if (!widths.empty() && widths.size() != points.size())
        fail(what, ": widths has ", widths.size(), " values, expected ", points.size());
    if (!colors.empty() && colors.size() != s)
        fail(what, ": colors has ", colors.size(), " values, expected ", s);
    if (!wisp.empty() && wisp.size() != s)
        fail(what, ": wisp has ", wisp.size(), " values, expected ", s);
    for (size_t st = 0; st < s; ++st)
        for (uint32_t i = offsets[st]; i < offsets[st + 1]; ++i) {
            const Vec3f& p = points[i];
            if (!p.allFinite())
                fail(what, ": point ", i, " is not finite (strand ", st, ", its point ",
                     i - offsets[st], ")");
            if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
                fail(what, ": point ", i, " (strand ", st, ", its point ", i - offsets[st],
                     ") is at (", p.x(), ", ", p.y(), ", ", p.z(), "), farther than ",
                     kMaxCoordinate, " cm from the origin on an axis (see docs/formats.md)");
        }
    for (size_t i = 0; i < widths.size(); ++i)
        if (!std::isfinite(widths[i]) || widths[i] < 0.f)
            fail(what, ": width ", i, " is negative or not finite");
    for (size_t i = 0; i < colors.size(); ++i)
        if (!colors[i].allFinite()) fail(what, ": color ", i, " is not finite");
}

}  // namespace wisp
