// BasisCurves semantics: segment counts and primvar sizes by USD's rules
// (UsdGeomBasisCurves), validity, and conversion to wisp strands.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

#include "core/error.hpp"
#include "io/usda.hpp"

namespace wisp {
namespace {

enum class Basis { kLinear, kBezier, kBspline, kCatmullRom, kUnknown };
enum class Wrap { kNonperiodic, kPeriodic, kPinned, kUnknown };

Basis basis_of(const UsdCurves& c) {
    if (c.type == "linear") return Basis::kLinear;
    if (c.type != "cubic") return Basis::kUnknown;
    if (c.basis == "bezier") return Basis::kBezier;
    if (c.basis == "bspline") return Basis::kBspline;
    if (c.basis == "catmullRom") return Basis::kCatmullRom;
    return Basis::kUnknown;
}

// Pinned only changes bspline and catmullRom curves; linear and bezier treat it as
// nonperiodic.
Wrap wrap_of(const UsdCurves& c) {
    Wrap w = c.wrap == "nonperiodic" ? Wrap::kNonperiodic
             : c.wrap == "periodic"  ? Wrap::kPeriodic
             : c.wrap == "pinned"    ? Wrap::kPinned
                                     : Wrap::kUnknown;
    const Basis b = basis_of(c);
    if (w == Wrap::kPinned && (b == Basis::kLinear || b == Basis::kBezier)) w = Wrap::kNonperiodic;
    return w;
}

int min_vertices(Basis b, Wrap w) {
    switch (b) {
        case Basis::kLinear:
            return 2;
        case Basis::kBezier:
            return w == Wrap::kPeriodic ? 3 : 4;
        case Basis::kBspline:
        case Basis::kCatmullRom:
            return w == Wrap::kPeriodic ? 3 : w == Wrap::kPinned ? 2 : 4;
        default:
            return 2;
    }
}

const char* plural(long n, const char* one, const char* many) {
    return n == 1 ? one : many;
}

size_t varying_size(const UsdCurves& c, size_t curve) {
    const size_t segs = usd_segment_count(c, curve);
    return wrap_of(c) == Wrap::kPeriodic ? segs : segs + 1;
}

// The interpolation a primvar uses: as authored, else inferred from its size.
std::string interpolation_of(const UsdCurves& c, const std::string& authored, size_t n) {
    return authored.empty() ? usd_interpolation_for_size(c, n) : authored;
}

// Checks one primvar's size against its interpolation; "" when it fits.
std::string primvar_problem(const UsdCurves& c, std::string_view what, size_t n,
                            const std::string& authored) {
    if (n == 0) return "";
    if (authored.empty()) {
        if (usd_interpolation_for_size(c, n).empty())
            return cat(what, " has ", n,
                       " values, which fits no interpolation (constant 1, uniform ",
                       usd_interpolation_size(c, "uniform"), ", varying ",
                       usd_interpolation_size(c, "varying"), ", vertex ",
                       usd_interpolation_size(c, "vertex"), ")");
        return "";
    }
    if (authored != "constant" && authored != "uniform" && authored != "varying" &&
        authored != "vertex" && authored != "faceVarying")
        return cat(what, " has unknown interpolation \"", authored, "\"");
    const size_t expected = usd_interpolation_size(c, authored);
    if (n != expected)
        return cat(what, " has ", n, " values, but interpolation \"", authored, "\" needs ",
                   expected);
    return "";
}

// Basis weights of a cubic segment at t.
void cubic_weights(Basis b, float t, float w[4]) {
    const float s = 1.f - t, t2 = t * t, t3 = t2 * t;
    switch (b) {
        case Basis::kBezier:
            w[0] = s * s * s;
            w[1] = 3.f * s * s * t;
            w[2] = 3.f * s * t2;
            w[3] = t3;
            break;
        case Basis::kBspline:
            w[0] = s * s * s / 6.f;
            w[1] = (3.f * t3 - 6.f * t2 + 4.f) / 6.f;
            w[2] = (-3.f * t3 + 3.f * t2 + 3.f * t + 1.f) / 6.f;
            w[3] = t3 / 6.f;
            break;
        default:  // catmullRom
            w[0] = 0.5f * (-t3 + 2.f * t2 - t);
            w[1] = 0.5f * (3.f * t3 - 5.f * t2 + 2.f);
            w[2] = 0.5f * (-3.f * t3 + 4.f * t2 + t);
            w[3] = 0.5f * (t3 - t2);
            break;
    }
}

// Control value j of a curve of n values, j in [-1, n]: periodic wraps around, pinned
// adds the phantom ends 2·p0 - p1 and 2·p(n-1) - p(n-2).
template <typename T>
T fetch(const T* v, long n, long j, Wrap wrap) {
    if (wrap == Wrap::kPeriodic) return v[((j % n) + n) % n];
    if (j < 0) return T(2.f * v[0] - v[1]);
    if (j >= n) return T(2.f * v[n - 1] - v[n - 2]);
    return v[j];
}

// First control index of segment k.
long segment_start(Basis b, Wrap w, long k) {
    if (b == Basis::kBezier) return 3 * k;
    return w == Wrap::kPinned ? k - 1 : k;
}

}  // namespace

size_t usd_segment_count(const UsdCurves& c, size_t curve) {
    const long n = c.counts.at(curve);
    const Basis b = basis_of(c);
    const Wrap w = wrap_of(c);
    if (b == Basis::kUnknown || w == Wrap::kUnknown || n < min_vertices(b, w)) return 0;
    const bool periodic = w == Wrap::kPeriodic;
    switch (b) {
        case Basis::kLinear:
            return periodic ? n : n - 1;
        case Basis::kBezier:
            return periodic ? n / 3 : (n - 4) / 3 + 1;
        default:
            return periodic ? n : w == Wrap::kPinned ? n - 1 : n - 3;
    }
}

size_t usd_interpolation_size(const UsdCurves& c, std::string_view interpolation) {
    if (interpolation == "constant") return 1;
    if (interpolation == "uniform") return c.counts.size();
    size_t n = 0;
    if (interpolation == "varying" || interpolation == "faceVarying") {
        for (size_t i = 0; i < c.counts.size(); ++i)
            n += varying_size(c, i);
    } else if (interpolation == "vertex") {
        for (int k : c.counts)
            n += size_t(std::max(k, 0));
    }
    return n;
}

std::string usd_interpolation_for_size(const UsdCurves& c, size_t n) {
    for (const char* i : {"constant", "uniform", "varying", "vertex"})
        if (n == usd_interpolation_size(c, i)) return i;
    return "";
}

std::string usd_curves_problem(const UsdCurves& c) {
    const Basis b = basis_of(c);
    const Wrap w = wrap_of(c);
    if (c.type != "linear" && c.type != "cubic")
        return cat("type \"", c.type, "\" is neither \"linear\" nor \"cubic\"");
    if (b == Basis::kUnknown)
        return cat("basis \"", c.basis, "\" is not supported (bezier, bspline, catmullRom)");
    if (w == Wrap::kUnknown)
        return cat("wrap \"", c.wrap, "\" is not nonperiodic, periodic or pinned");
    const std::string kind =
        b == Basis::kLinear ? cat(c.wrap, " linear") : cat(c.wrap, " ", c.basis);
    int64_t sum = 0;
    for (size_t i = 0; i < c.counts.size(); ++i) {
        const long n = c.counts[i];
        if (n < 0) return cat("curve ", i, " has a negative vertex count ", n);
        const int lo = min_vertices(b, w);
        if (n < lo)
            return cat("curve ", i, " has ", n, plural(n, " vertex", " vertices"), ", but a ", kind,
                       " curve needs at least ", lo);
        if (b == Basis::kBezier && w == Wrap::kPeriodic && n % 3 != 0)
            return cat("curve ", i, " has ", n,
                       " vertices, but a periodic bezier curve needs a "
                       "multiple of 3");
        if (b == Basis::kBezier && w != Wrap::kPeriodic && (n - 4) % 3 != 0)
            return cat("curve ", i, " has ", n, " vertices, but a ", kind,
                       " curve needs 4 + 3k (the vstep of bezier is 3)");
        sum += n;
    }
    if (sum != int64_t(c.points.size()))
        return cat("curveVertexCounts add up to ", sum, " vertices, but points has ",
                   c.points.size());
    for (size_t k = 0; k < c.points.size(); ++k)
        if (!c.points[k].allFinite()) return cat("point ", k, " is not finite");
    for (size_t k = 0; k < c.widths.size(); ++k)
        if (!std::isfinite(c.widths[k]) || c.widths[k] < 0.f)
            return cat("width ", k, " is negative or not finite");
    for (size_t k = 0; k < c.display_color.size(); ++k)
        if (!c.display_color[k].allFinite()) return cat("displayColor ", k, " is not finite");
    if (auto p = primvar_problem(c, "widths", c.widths.size(), c.widths_interpolation); !p.empty())
        return p;
    if (auto p = primvar_problem(c, "primvars:displayColor", c.display_color.size(),
                                 c.display_color_interpolation);
        !p.empty())
        return p;
    if (auto p = primvar_problem(c, "primvars:wisp_id", c.wisp_id.size(), c.wisp_id_interpolation);
        !p.empty())
        return p;
    return "";
}

Hair hair_from_usda(const UsdaLayer& layer, const std::string& name, int samples_per_segment) {
    const int K = std::max(1, samples_per_segment);
    bool any_widths = false, any_wisp = false, uniform_color = true, has_uncolored = false;
    std::optional<Vec3f> constant_color;
    // Guide curves (Unreal's groom_guide) are the simulation's, not strands to draw: they are
    // left out when the layer has render strands too.
    const bool skip_guides = std::any_of(layer.curves.begin(), layer.curves.end(),
                                         [](const UsdCurves& c) { return !c.guide; });
    for (const UsdCurves& c : layer.curves) {
        if (skip_guides && c.guide) continue;
        if (const std::string p = usd_curves_problem(c); !p.empty())
            fail(name, ":", c.line, ": prim ", excerpt(c.path, 256), ": ", p);
        any_widths |= !c.widths.empty();
        any_wisp |= !c.wisp_id.empty();
        if (c.display_color.empty()) {
            has_uncolored = true;
            continue;
        }
        const std::string ci =
            interpolation_of(c, c.display_color_interpolation, c.display_color.size());
        if (ci != "constant" || (constant_color && *constant_color != c.display_color[0]))
            uniform_color = false;
        constant_color = c.display_color[0];
    }
    // One constant color on every prim becomes the default color; anything else, colors
    // per strand (the default color for prims without displayColor).
    if (has_uncolored) uniform_color = false;
    const bool per_strand_color = constant_color && !uniform_color;

    Hair hair;
    if (constant_color && uniform_color) hair.default_color = *constant_color;
    // wisp's own metersPerUnit 0.01 gives exactly 1, so points read back bit-exact.
    const float scale = std::abs(layer.meters_per_unit - 0.01) < 1e-12
                            ? 1.f
                            : static_cast<float>(layer.meters_per_unit * 100.0);
    const bool z_up = layer.up_axis == "Z";
    auto to_wisp = [&](const Vec3f& p) {
        // Z up to Y up: (x, y, z) -> (x, z, -y), so Blender's -Y front becomes wisp's +Z.
        return Vec3f(scale * (z_up ? Vec3f(p.x(), p.z(), -p.y()) : p));
    };

    size_t expected_points = 0;
    for (const UsdCurves& c : layer.curves)
        expected_points += c.points.size() + c.counts.size();
    hair.points.reserve(expected_points);
    if (any_widths) hair.widths.reserve(expected_points);
    hair.offsets.reserve(
        1 + std::accumulate(layer.curves.begin(), layer.curves.end(), size_t(0),
                            [](size_t n, const UsdCurves& c) { return n + c.counts.size(); }));
    for (const UsdCurves& c : layer.curves) {
        if (skip_guides && c.guide) continue;
        const Basis b = basis_of(c);
        const Wrap w = wrap_of(c);
        const bool periodic = w == Wrap::kPeriodic;
        const bool direct = b == Basis::kLinear || (b == Basis::kCatmullRom && w == Wrap::kPinned);
        const std::string wi = interpolation_of(c, c.widths_interpolation, c.widths.size());
        const std::string ci =
            interpolation_of(c, c.display_color_interpolation, c.display_color.size());
        const std::string ii = interpolation_of(c, c.wisp_id_interpolation, c.wisp_id.size());
        size_t first = 0, vary_first = 0;
        for (size_t curve = 0; curve < c.counts.size(); ++curve) {
            const long n = c.counts[curve];
            const Vec3f* P = c.points.data() + first;
            const long segs = long(usd_segment_count(c, curve));
            // Width of control value j (vertex) / segment end k (varying) of this curve.
            auto width_vertex = [&](long j) -> float {
                if (wi == "vertex") return fetch(c.widths.data() + first, n, j, w);
                if (wi == "varying" || wi == "faceVarying") return c.widths[vary_first + j];
                if (wi == "uniform") return c.widths[curve];
                return c.widths[0];
            };
            auto put = [&](const Vec3f& p, float width) {
                hair.points.push_back(to_wisp(p));
                if (any_widths)
                    hair.widths.push_back(c.widths.empty() ? hair.default_width
                                                           : std::max(0.f, width * scale));
            };
            if (direct) {
                for (long j = 0; j < n; ++j)
                    put(P[j], c.widths.empty() ? 0.f : width_vertex(j));
                if (periodic) put(P[0], c.widths.empty() ? 0.f : width_vertex(0));
            } else {
                float wt[4];
                for (long k = 0; k < segs; ++k) {
                    const long j0 = segment_start(b, w, k);
                    const int last = (!periodic && k == segs - 1) ? K : K - 1;
                    for (int s = 0; s <= last; ++s) {
                        const float t = float(s) / float(K);
                        cubic_weights(b, t, wt);
                        Vec3f p = Vec3f::Zero();
                        for (int q = 0; q < 4; ++q)
                            p += wt[q] * fetch(P, n, j0 + q, w);
                        float width = 0.f;
                        if (!c.widths.empty()) {
                            if (wi == "vertex") {
                                for (int q = 0; q < 4; ++q)
                                    width += wt[q] * width_vertex(j0 + q);
                            } else if (wi == "varying" || wi == "faceVarying") {
                                const long k1 = periodic ? (k + 1) % segs : k + 1;
                                width = (1.f - t) * c.widths[vary_first + k] +
                                        t * c.widths[vary_first + k1];
                            } else {
                                width = width_vertex(0);
                            }
                        }
                        put(p, width);
                    }
                }
                if (periodic && segs > 0) {
                    const Vec3f p0 = hair.points[hair.offsets.back()];
                    hair.points.push_back(p0);
                    if (any_widths) hair.widths.push_back(hair.widths[hair.offsets.back()]);
                }
            }
            hair.offsets.push_back(static_cast<uint32_t>(hair.points.size()));
            if (per_strand_color) {
                Vec3f col = hair.default_color;
                if (!c.display_color.empty())
                    col = ci == "uniform"                            ? c.display_color[curve]
                          : ci == "vertex"                           ? c.display_color[first]
                          : (ci == "varying" || ci == "faceVarying") ? c.display_color[vary_first]
                                                                     : c.display_color[0];
                hair.colors.push_back(col);
            }
            if (any_wisp) {
                int32_t id = -1;
                if (!c.wisp_id.empty())
                    id = ii == "uniform"                            ? c.wisp_id[curve]
                         : ii == "vertex"                           ? c.wisp_id[first]
                         : (ii == "varying" || ii == "faceVarying") ? c.wisp_id[vary_first]
                                                                    : c.wisp_id[0];
                hair.wisp.push_back(id);
            }
            first += size_t(n);
            vary_first += periodic ? size_t(segs) : size_t(segs) + 1;
        }
    }
    hair.validate(name);
    return hair;
}

Hair read_usda(const std::filesystem::path& path) {
    return hair_from_usda(read_usda_layer(path), path.string());
}

}  // namespace wisp
