#include "geometry/landmarks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "core/error.hpp"
#include "core/point_grid.hpp"

namespace wisp {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
// The eye sockets, in head heights: how far above and below a hollow its rims are looked for,
// the depth beyond which a hollow counts no more (an opening to the inside of the head counts
// as much as a socket), and how far behind the filled surface the eye's centre lies.
constexpr float kSocketReach = 0.06f, kSocketCap = 0.02f, kEyeDepth = 0.07f;

// ---- The head's piece.

struct Piece {
    std::vector<uint32_t> faces;     // indices into mesh.faces
    std::vector<uint32_t> vertices;  // the piece's vertices, ascending
    std::vector<float> vertex_area;  // #V: a third of the area of the piece's faces at each vertex
    std::vector<Vec3f> vertex_normal;  // #V: unit, the area-weighted mean of those faces' normals
    float top = -kInf, bottom = kInf;
};

// The connected piece (faces sharing a vertex) of largest area, as the scalp's hairline
// selection takes it: full-body meshes carry eyes, teeth and helper shells beside the body.
Piece largest_piece(const Mesh& mesh) {
    const size_t nv = mesh.vertices.size(), nf = mesh.faces.size();
    std::vector<uint32_t> parent(nv);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t x) {
        while (parent[x] != x)
            x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const Vec3i& t : mesh.faces) {
        parent[find(t[0])] = find(t[1]);
        parent[find(t[1])] = find(t[2]);
    }
    std::vector<float> face_area(nf);
    std::vector<double> area(nv, 0.0);
    for (size_t f = 0; f < nf; ++f) {
        face_area[f] = mesh.face_area(f);
        area[find(mesh.faces[f][0])] += face_area[f];
    }
    const uint32_t root =
        static_cast<uint32_t>(std::max_element(area.begin(), area.end()) - area.begin());
    Piece piece;
    piece.vertex_area.assign(nv, 0.f);
    piece.vertex_normal.assign(nv, Vec3f::Zero());
    for (size_t f = 0; f < nf; ++f) {
        const Vec3i& t = mesh.faces[f];
        if (find(t[0]) != root) continue;
        piece.faces.push_back(static_cast<uint32_t>(f));
        const Vec3f& a = mesh.vertices[t[0]];
        const Vec3f twice_area = (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a);
        for (int k = 0; k < 3; ++k) {
            piece.vertex_area[t[k]] += face_area[f] / 3.f;
            piece.vertex_normal[t[k]] += twice_area;
        }
    }
    for (Vec3f& n : piece.vertex_normal)
        n.normalize();  // Eigen leaves a zero vector as it is
    for (size_t v = 0; v < nv; ++v)
        if (find(static_cast<uint32_t>(v)) == root) {
            piece.vertices.push_back(static_cast<uint32_t>(v));
            piece.top = std::max(piece.top, mesh.vertices[v].y());
            piece.bottom = std::min(piece.bottom, mesh.vertices[v].y());
        }
    return piece;
}

// ---- Cutting triangles by planes.

// Where the plane s = 0 cuts the triangle (p[0], p[1], p[2]) with values s[0..2]: from the
// crossing of the edge that goes from s >= 0 to s < 0 (start) to the one coming back (end), in
// the triangle's winding. A vertex at s = 0 counts as s >= 0, so the two triangles of an edge
// agree on it and sections close into loops, oriented alike when the faces are.
bool cut(const Vec3f* p, const float* s, Vec3f& start, Vec3f& end) {
    int found = 0;
    for (int i = 0; i < 3; ++i) {
        const int j = i == 2 ? 0 : i + 1;
        const bool above_i = s[i] >= 0.f, above_j = s[j] >= 0.f;
        if (above_i == above_j) continue;
        const Vec3f x = p[i] + (s[i] / (s[i] - s[j])) * (p[j] - p[i]);
        (above_i ? start : end) = x;
        ++found;
    }
    return found == 2;
}

// Levels y_k = y0 - (k + 1)·h, k in [0, count), from the top down.
struct Levels {
    float y0 = 0, h = 1;
    int count = 0;
    float y(int k) const { return y0 - static_cast<float>(k + 1) * h; }
    // The levels in (lo, hi]: those that cut a triangle spanning lo … hi by cut()'s rule.
    void range(float lo, float hi, int& first, int& last) const {
        first = std::max(0, static_cast<int>(std::floor((y0 - hi) / h)) - 1);
        last = std::min(count - 1, static_cast<int>(std::ceil((y0 - lo) / h)));
        while (first <= last && y(first) > hi)
            ++first;
        while (last >= first && y(last) <= lo)
            --last;
    }
};

// Horizontal sections of the piece at each level: radius √(|area| / π) (0 where the level
// misses the piece) and area centroid (x, z). Area and centroid are taken about the section's
// own mean point (of its edges, by length), so that an open chain (a hole in the mesh) adds a
// bounded error; one pass gathers the sums that let them be moved there afterwards.
struct Sections {
    Levels levels;
    std::vector<float> radius;  // #levels
    std::vector<Vec2f> centre;  // #levels
    // #levels: the section is not closed (its edges' ends are more than 5% of its length apart,
    // where it crosses a hole or the mesh's open end); its area is then only partly there.
    std::vector<char> open;
};

Sections horizontal_sections(const Mesh& mesh, const Piece& piece, const Levels& levels,
                             const Vec2f& reference) {
    // Per level, for segments a → b (x, z about `reference`) with d = b - a and c = a × b:
    // Σ|d|, Σ|d|(a + b)/2, Σd, Σc, Σ(a + b)c, Σ(a + b)d_x, Σ(a + b)d_z.
    struct Sums {
        double length = 0, mid_x = 0, mid_z = 0, d_x = 0, d_z = 0, c = 0, abc_x = 0, abc_z = 0;
        double abdx_x = 0, abdx_z = 0, abdz_x = 0, abdz_z = 0;
    };
    std::vector<Sums> sums(levels.count);
    for (uint32_t f : piece.faces) {
        const Vec3i& t = mesh.faces[f];
        const Vec3f p[3] = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
        int first, last;
        levels.range(std::min({p[0].y(), p[1].y(), p[2].y()}),
                     std::max({p[0].y(), p[1].y(), p[2].y()}), first, last);
        for (int k = first; k <= last; ++k) {
            const float y = levels.y(k);
            const float s[3] = {p[0].y() - y, p[1].y() - y, p[2].y() - y};
            Vec3f a3, b3;
            if (!cut(p, s, a3, b3)) continue;
            const double ax = a3.x() - reference.x(), az = a3.z() - reference.y();
            const double bx = b3.x() - reference.x(), bz = b3.z() - reference.y();
            const double dx = bx - ax, dz = bz - az, sx = ax + bx, sz = az + bz;
            const double l = std::sqrt(dx * dx + dz * dz), c = ax * bz - az * bx;
            Sums& m = sums[k];
            m.length += l;
            m.mid_x += 0.5 * l * sx;
            m.mid_z += 0.5 * l * sz;
            m.d_x += dx;
            m.d_z += dz;
            m.c += c;
            m.abc_x += sx * c;
            m.abc_z += sz * c;
            m.abdx_x += sx * dx;
            m.abdx_z += sz * dx;
            m.abdz_x += sx * dz;
            m.abdz_z += sz * dz;
        }
    }
    Sections sections;
    sections.levels = levels;
    sections.radius.assign(levels.count, 0.f);
    sections.centre.assign(levels.count, reference);
    sections.open.assign(levels.count, 0);
    for (int k = 0; k < levels.count; ++k) {
        const Sums& m = sums[k];
        if (!(m.length > 0)) continue;
        sections.open[k] = std::hypot(m.d_x, m.d_z) > 0.05 * m.length;
        // About o: cross(a - o, b - o) = c - o × d, and the centroid's moment
        // Σ(a + b - 2o)(c - o × d) expands into the sums above.
        const double ox = m.mid_x / m.length, oz = m.mid_z / m.length;
        const double area2 = m.c - (ox * m.d_z - oz * m.d_x);
        const double o_cross_x = ox * m.abdz_x - oz * m.abdx_x;  // Σ(a + b)_x (o × d)
        const double o_cross_z = ox * m.abdz_z - oz * m.abdx_z;
        const double moment_x = m.abc_x - o_cross_x - 2 * ox * area2;
        const double moment_z = m.abc_z - o_cross_z - 2 * oz * area2;
        sections.radius[k] = static_cast<float>(std::sqrt(std::abs(0.5 * area2) / kPi));
        Vec2f c(static_cast<float>(ox), static_cast<float>(oz));
        if (std::abs(area2) > 1e-9 * m.length * m.length)
            c = Vec2f(static_cast<float>(ox + moment_x / (3 * area2)),
                      static_cast<float>(oz + moment_z / (3 * area2)));
        sections.centre[k] = c + reference;
    }
    return sections;
}

// The neck in a profile of section radii from the top down: the narrowest section after the
// profile has narrowed to 85% of the widest above it, taken when the profile widens again to
// 1.3 times it (the shoulders) or ends; -1 when it never narrows so (a box, a cylinder).
int narrowest_below_widest(const std::vector<float>& radius) {
    float widest = 0.f, narrowest = kInf;
    int at = -1;
    for (size_t k = 0; k < radius.size(); ++k) {
        const float r = radius[k];
        if (!(r > 0.f)) continue;  // a level between pieces of the mesh
        if (narrowest < 0.85f * widest && r > 1.3f * narrowest) return at;
        if (r > widest) {
            widest = narrowest = r;
            at = static_cast<int>(k);
        } else if (r < narrowest) {
            narrowest = r;
            at = static_cast<int>(k);
        }
    }
    return narrowest < 0.85f * widest ? at : -1;
}

// ---- The plane of mirror symmetry.

struct MirrorPlane {
    Vec3f normal = Vec3f::UnitX();  // horizontal, unit
    Vec3f point = Vec3f::Zero();
    Vec3f mirror(const Vec3f& p) const { return p - 2.f * normal.dot(p - point) * normal; }
};

// The head's vertices (above the mouth) with their unit normals and areas.
struct HeadPoints {
    std::vector<Vec3f> points, normals;
    std::vector<float> weights;
};

// The weighted mean of min(d², cap²) over every stride-th head vertex, d the distance from its
// mirror image to the nearest head vertex, or (along_normal) that distance along the nearest
// vertex's normal: the error of a smooth surface then varies smoothly with the plane, not in
// steps of the vertex spacing, and what still slides along the surface is held by the nose,
// the ears and the chin.
float mirror_error(const HeadPoints& head, const PointGrid& grid, size_t stride,
                   const MirrorPlane& plane, float cap, bool along_normal) {
    double sum = 0, total = 0;
    for (size_t i = 0; i < head.points.size(); i += stride) {
        const Vec3f image = plane.mirror(head.points[i]);
        const int j = grid.nearest(image);
        const Vec3f d = head.points[j] - image;
        const float d2 =
            along_normal ? Eigen::numext::abs2(d.dot(head.normals[j])) : d.squaredNorm();
        sum += head.weights[i] * std::min(d2, cap * cap);
        total += head.weights[i];
    }
    return total > 0 ? static_cast<float>(sum / total) : 0.f;
}

// The vertical plane that best mirrors the head onto itself: a sweep over normals every 10°
// through the head's centroid (nearest-vertex distances, 250 probes), then the angle refined by
// halving steps from 4° to 1/8° (distances along the normals, 1000 probes), then the plane's
// offset by iterating closest points (the mean of the midpoints of vertices and the vertices
// nearest their images).
MirrorPlane symmetry_plane(const HeadPoints& head, float scale) {
    const size_t n = head.points.size();
    double total = 0;
    Vec3d centroid = Vec3d::Zero();
    for (size_t i = 0; i < n; ++i) {
        centroid += head.weights[i] * head.points[i].cast<double>();
        total += head.weights[i];
    }
    if (!(total > 0)) fail("find_landmarks: no head: the faces above the mouth have no area");
    centroid /= total;
    const float spacing = std::sqrt(static_cast<float>(2 * total / n));
    const PointGrid grid(head.points, std::max(spacing, 0.005f * scale));
    const float cap = 0.1f * scale;

    MirrorPlane plane;
    plane.point = Vec3f(static_cast<float>(centroid.x()), 0.f, static_cast<float>(centroid.z()));
    auto at = [&](float angle) {
        MirrorPlane p = plane;
        p.normal = Vec3f(std::cos(angle), 0.f, std::sin(angle));
        return p;
    };
    constexpr int kSteps = 18;
    const size_t coarse = std::max<size_t>(1, n / 250);
    int best = 0;
    float best_error = kInf;
    for (int i = 0; i < kSteps; ++i) {
        const float e = mirror_error(head, grid, coarse, at(kPi * i / kSteps), cap, false);
        if (e < best_error) best_error = e, best = i;
    }
    const size_t fine = std::max<size_t>(1, n / 1000);
    float angle = kPi * best / kSteps;
    float error = mirror_error(head, grid, fine, at(angle), cap, true);
    for (float step = 4.f * kPi / 180.f; step > 0.1f * kPi / 180.f; step *= 0.5f) {
        const float below = mirror_error(head, grid, fine, at(angle - step), cap, true);
        const float above = mirror_error(head, grid, fine, at(angle + step), cap, true);
        if (below < error && below <= above) {
            angle -= step;
            error = below;
        } else if (above < error) {
            angle += step;
            error = above;
        }
    }
    plane = at(angle);
    for (int iteration = 0; iteration < 4; ++iteration) {
        double offset = 0, w = 0;
        for (size_t i = 0; i < n; i += fine) {
            const Vec3f& p = head.points[i];
            const Vec3f image = plane.mirror(p);
            const Vec3f& q = head.points[grid.nearest(image)];
            if ((q - image).squaredNorm() > cap * cap) continue;
            offset += head.weights[i] * plane.normal.dot(0.5f * (p + q) - plane.point);
            w += head.weights[i];
        }
        if (!(w > 0)) break;
        const float shift = static_cast<float>(offset / w);
        plane.point += shift * plane.normal;
        if (std::abs(shift) < 1e-4f * scale) break;
    }
    return plane;
}

// ---- The midline profile.

// The head cut by its symmetry plane, in the plane's coordinates: u along `forward` from the
// plane's point, y up. Per level, the frontmost and backmost u of the cut (NaN where the level
// misses it).
struct Profile {
    Levels levels;
    std::vector<float> front, back;  // #levels
    std::vector<Vec2f> points;       // (u, y): the cut's segment ends, two per segment

    // The level nearest to height y (clamped to the levels).
    int level_of(float y) const {
        return std::clamp(static_cast<int>(std::lround((levels.y0 - y) / levels.h - 1.f)), 0,
                          levels.count - 1);
    }
    // The front at height y, linearly between levels (NaN outside them).
    float front_at(float y) const {
        const float x = (levels.y0 - y) / levels.h - 1.f;
        const int k = static_cast<int>(std::floor(x));
        if (k < 0 || k + 1 >= levels.count) return NAN;
        const float w = x - static_cast<float>(k);
        return (1.f - w) * front[k] + w * front[k + 1];
    }
    // The same profile seen with u the other way (forward reversed).
    void turn_around() {
        for (size_t k = 0; k < front.size(); ++k) {
            const float old_front = front[k];
            front[k] = -back[k];
            back[k] = -old_front;
        }
        for (Vec2f& p : points)
            p.x() = -p.x();
    }
};

Profile midline_profile(const Mesh& mesh, const Piece& piece, const MirrorPlane& plane,
                        const Vec3f& forward, const Levels& levels, float lowest) {
    Profile profile;
    profile.levels = levels;
    profile.front.assign(levels.count, -kInf);
    profile.back.assign(levels.count, kInf);
    for (uint32_t f : piece.faces) {
        const Vec3i& t = mesh.faces[f];
        const Vec3f p[3] = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
        if (std::max({p[0].y(), p[1].y(), p[2].y()}) < lowest) continue;
        const float s[3] = {plane.normal.dot(p[0] - plane.point),
                            plane.normal.dot(p[1] - plane.point),
                            plane.normal.dot(p[2] - plane.point)};
        Vec3f a3, b3;
        if (!cut(p, s, a3, b3)) continue;
        const Vec2f a(forward.dot(a3 - plane.point), a3.y()),
            b(forward.dot(b3 - plane.point), b3.y());
        profile.points.push_back(a);
        profile.points.push_back(b);
        int first, last;
        levels.range(std::min(a.y(), b.y()), std::max(a.y(), b.y()), first, last);
        for (int k = first; k <= last; ++k) {
            const float y = levels.y(k);
            const float dy = b.y() - a.y();
            const float u = dy != 0.f ? a.x() + (y - a.y()) / dy * (b.x() - a.x()) : a.x();
            profile.front[k] = std::max(profile.front[k], u);
            profile.back[k] = std::min(profile.back[k], u);
        }
    }
    for (int k = 0; k < levels.count; ++k)
        if (profile.front[k] == -kInf) profile.front[k] = profile.back[k] = NAN;
    return profile;
}

// The largest bump of a profile side: max over levels of v(k) - (v(k - q) + v(k + q)) / 2,
// for v = sign · (front or back), over levels in [first, last].
float sharpest_bump(const std::vector<float>& side, float sign, int q, int first, int last) {
    float best = 0.f;
    for (int k = std::max(first, q); k <= last && k + q < static_cast<int>(side.size()); ++k) {
        const float bump = sign * (side[k] - 0.5f * (side[k - q] + side[k + q]));
        if (std::isfinite(bump)) best = std::max(best, bump);
    }
    return best;
}

// The offset in [-0.5, 0.5] of the extremum of the parabola through (-1, a), (0, b), (1, c).
float parabola_peak(float a, float b, float c) {
    const float curvature = a - 2.f * b + c;
    if (!(std::abs(curvature) > 0.f) || !std::isfinite(curvature)) return 0.f;
    return std::clamp(0.5f * (a - c) / curvature, -0.5f, 0.5f);
}

// The head's axes: origin on the symmetry plane at y = 0, forward and left horizontal.
struct HeadAxes {
    Vec3f origin = Vec3f::Zero(), forward = Vec3f::UnitZ(), left = Vec3f::UnitX();
    // The point `s` to the left, at height y, `u` forward.
    Vec3f at(float s, float y, float u) const {
        return origin + s * left + y * Vec3f::UnitY() + u * forward;
    }
};

// ---- The face seen from the front.

// Depth (u, along forward) of the frontmost surface over a grid of lateral offset s (along
// left) and height y, from the plane's point.
struct DepthMap {
    float s0 = 0, y0 = 0, h = 1;
    int ns = 0, ny = 0;
    std::vector<float> depth;  // #ny × #ns, row-major (rows of equal y)
    float& at(int i, int j) { return depth[static_cast<size_t>(j) * ns + i]; }
    float at(int i, int j) const { return depth[static_cast<size_t>(j) * ns + i]; }
    float s(int i) const { return s0 + static_cast<float>(i) * h; }
    float y(int j) const { return y0 + static_cast<float>(j) * h; }
};

DepthMap face_depth(const Mesh& mesh, const Piece& piece, const HeadAxes& axes, float s_half,
                    float y_lo, float y_hi, float h) {
    DepthMap map;
    map.h = h;
    // Columns mirrored about s = 0, so that both eyes are looked for on the same samples.
    const int half = static_cast<int>(std::ceil(s_half / h));
    map.ns = 2 * half + 1;
    map.ny = static_cast<int>(std::ceil((y_hi - y_lo) / h)) + 1;
    map.s0 = -static_cast<float>(half) * h;
    map.y0 = y_lo;
    map.depth.assign(static_cast<size_t>(map.ns) * map.ny, -kInf);
    for (uint32_t f : piece.faces) {
        const Vec3i& t = mesh.faces[f];
        Vec3f q[3];  // (s, y, u)
        for (int k = 0; k < 3; ++k) {
            const Vec3f d = mesh.vertices[t[k]] - axes.origin;
            q[k] = Vec3f(axes.left.dot(d), mesh.vertices[t[k]].y(), axes.forward.dot(d));
        }
        const float smin = std::min({q[0].x(), q[1].x(), q[2].x()});
        const float smax = std::max({q[0].x(), q[1].x(), q[2].x()});
        const float ymin = std::min({q[0].y(), q[1].y(), q[2].y()});
        const float ymax = std::max({q[0].y(), q[1].y(), q[2].y()});
        const int i0 = std::max(0, static_cast<int>(std::ceil((smin - map.s0) / h)));
        const int i1 = std::min(map.ns - 1, static_cast<int>(std::floor((smax - map.s0) / h)));
        const int j0 = std::max(0, static_cast<int>(std::ceil((ymin - map.y0) / h)));
        const int j1 = std::min(map.ny - 1, static_cast<int>(std::floor((ymax - map.y0) / h)));
        if (i0 > i1 || j0 > j1) continue;
        const Vec3f &a = q[0], &b = q[1], &c = q[2];
        const float det = (b.y() - c.y()) * (a.x() - c.x()) + (c.x() - b.x()) * (a.y() - c.y());
        if (!(std::abs(det) > 0.f)) continue;
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                const float x = map.s(i), y = map.y(j);
                const float l0 =
                    ((b.y() - c.y()) * (x - c.x()) + (c.x() - b.x()) * (y - c.y())) / det;
                const float l1 =
                    ((c.y() - a.y()) * (x - c.x()) + (a.x() - c.x()) * (y - c.y())) / det;
                const float l2 = 1.f - l0 - l1;
                if (l0 < 0.f || l1 < 0.f || l2 < 0.f) continue;
                float& d = map.at(i, j);
                d = std::max(d, l0 * a.z() + l1 * b.z() + l2 * c.z());
            }
    }
    return map;
}

// Grey-scale closing (dilation, then erosion) of each column of the map by a vertical segment
// of r cells either way: the surface with every hollow between a ridge above and one below
// filled (the eye sockets between brow and cheek), but not the slope beside the nose, which
// falls away sideways. Cells that see no surface count as the lowest depth seen.
DepthMap close_columns(const DepthMap& map, int r) {
    float lowest = kInf;
    for (float d : map.depth)
        if (d > -kInf) lowest = std::min(lowest, d);
    DepthMap out = map;
    for (float& d : out.depth)
        if (d == -kInf) d = lowest;
    std::vector<float> column(map.ny), dilated(map.ny);
    for (int i = 0; i < map.ns; ++i) {
        for (int j = 0; j < map.ny; ++j)
            column[j] = out.at(i, j);
        for (int j = 0; j < map.ny; ++j) {
            float v = -kInf;
            for (int k = std::max(0, j - r); k <= std::min(map.ny - 1, j + r); ++k)
                v = std::max(v, column[k]);
            dilated[j] = v;
        }
        for (int j = 0; j < map.ny; ++j) {
            float v = kInf;
            for (int k = std::max(0, j - r); k <= std::min(map.ny - 1, j + r); ++k)
                v = std::min(v, dilated[k]);
            out.at(i, j) = v;
        }
    }
    return out;
}

// ---- The stages.

// Stage 1: the head's reach from horizontal sections. A coarse pass over the whole piece finds
// the neck roughly, which sets the scale (the top to that neck, about a head's height) of a
// fine pass over 3.2 such heights from the top.
struct HeadReach {
    float neck_guess = 0;  // y of the coarse neck
    float scale = 0;       // top - neck_guess
    Sections sections;     // the fine pass
};

HeadReach head_reach(const Mesh& mesh, const Piece& piece) {
    Box3 box;
    for (uint32_t v : piece.vertices)
        box.extend(mesh.vertices[v]);
    const Vec2f reference(box.center().x(), box.center().z());
    const float extent = piece.top - piece.bottom;
    const Levels coarse{piece.top, extent / 257.f, 256};
    const int neck =
        narrowest_below_widest(horizontal_sections(mesh, piece, coarse, reference).radius);
    if (neck < 0)
        fail(
            "find_landmarks: no head: no horizontal section of the mesh narrows below a wider "
            "one (a head narrows to its neck)");
    HeadReach reach;
    reach.neck_guess = coarse.y(neck);
    reach.scale = piece.top - reach.neck_guess;
    Levels fine;
    fine.y0 = piece.top;
    fine.h = reach.scale / 160.f;
    fine.count = static_cast<int>(std::min(extent, 3.2f * reach.scale) / fine.h) - 1;
    reach.sections = horizontal_sections(mesh, piece, fine, reference);
    return reach;
}

// Stages 2 and 3a: the symmetry plane, and which of its sides the face is on (the profile is
// turned to have its front there).
HeadAxes face_axes(const Mesh& mesh, const Piece& piece, const HeadReach& reach, Profile& profile) {
    HeadPoints head;
    const float head_low = reach.neck_guess + 0.3f * reach.scale;
    for (uint32_t v : piece.vertices)
        if (mesh.vertices[v].y() >= head_low) {
            head.points.push_back(mesh.vertices[v]);
            head.normals.push_back(piece.vertex_normal[v]);
            head.weights.push_back(piece.vertex_area[v]);
        }
    if (head.points.size() < 16)
        fail("find_landmarks: no head: ", head.points.size(),
             " vertices above the neck guessed at y = ", reach.neck_guess);
    const MirrorPlane plane = symmetry_plane(head, reach.scale);

    HeadAxes axes;
    axes.origin = Vec3f(plane.point.x(), 0.f, plane.point.z());
    axes.forward = Vec3f(-plane.normal.z(), 0.f, plane.normal.x());
    const Levels& levels = reach.sections.levels;
    profile = midline_profile(mesh, piece, plane, axes.forward, levels,
                              reach.neck_guess - 0.2f * reach.scale);
    const int first = profile.level_of(piece.top - 0.2f * reach.scale);
    const int last = profile.level_of(reach.neck_guess + 0.15f * reach.scale);
    const int q = std::max(2, static_cast<int>(std::lround(0.08f * reach.scale / levels.h)));
    const float front = sharpest_bump(profile.front, 1.f, q, first, last);
    const float back = sharpest_bump(profile.back, -1.f, q, first, last);
    if (std::max(front, back) < 0.015f * reach.scale ||
        std::max(front, back) < 1.5f * std::min(front, back))
        fail(
            "find_landmarks: no face: neither side of the head's midline has a bump like a "
            "nose (the sharpest: ",
            front, " and ", back, " for a head ", reach.scale, " tall)");
    if (back > front) {
        axes.forward = -axes.forward;
        profile.turn_around();
    }
    axes.left = Vec3f::UnitY().cross(axes.forward);
    return axes;
}

// Stage 3b: nose tip, crown, chin and height from the midline profile.
void read_midline(const Profile& profile, const HeadReach& reach, const Piece& piece,
                  const HeadAxes& axes, Landmarks& l) {
    const Levels& levels = profile.levels;
    const float scale = reach.scale;
    const int first = profile.level_of(piece.top - 0.2f * scale);
    const int last = profile.level_of(reach.neck_guess + 0.15f * scale);

    // The nose tip: the profile's most forward point.
    int nose = -1;
    for (int k = first; k <= last; ++k)
        if (std::isfinite(profile.front[k]) && (nose < 0 || profile.front[k] > profile.front[nose]))
            nose = k;
    if (nose < 0) fail("find_landmarks: no face: the midline profile is empty");
    const float a = nose > 0 ? profile.front[nose - 1] : NAN;
    const float c = nose + 1 < levels.count ? profile.front[nose + 1] : NAN;
    const float b = profile.front[nose];
    const float d = std::isfinite(a) && std::isfinite(c) ? parabola_peak(a, b, c) : 0.f;
    const float nose_u = d != 0.f ? b - 0.25f * (a - c) * d : b;
    l.nose_tip = axes.at(0.f, levels.y(nose) - d * levels.h, nose_u);

    // The crown: the profile's top, at the middle of its chord 0.02 scale below.
    float top = -kInf;
    for (const Vec2f& p : profile.points)
        top = std::max(top, p.y());
    const float chord = top - 0.02f * scale;
    float lo = kInf, hi = -kInf;
    for (size_t i = 0; i < profile.points.size(); i += 2) {
        const Vec2f &p = profile.points[i], &q = profile.points[i + 1];
        if ((p.y() >= chord) == (q.y() >= chord)) continue;
        const float u = p.x() + (chord - p.y()) / (q.y() - p.y()) * (q.x() - p.x());
        lo = std::min(lo, u);
        hi = std::max(hi, u);
    }
    l.crown = axes.at(0.f, top, hi >= lo ? 0.5f * (lo + hi) : 0.f);

    // The chin: on the face's outline below the nose, down to where the profile falls back to
    // the throat (behind 72% of the way from the back of the head to the nose tip, or by 0.1
    // scale from one level to the next under a chin that rises toward the throat, as on a head
    // tilted back), the extreme 10° forward of straight down.
    float back = kInf;
    for (int k = first; k <= last; ++k)
        if (std::isfinite(profile.back[k])) back = std::min(back, profile.back[k]);
    const float u_min = back + 0.72f * (nose_u - back);
    const float y_max = l.nose_tip.y() - 0.05f * scale;
    int throat = nose + 1;
    for (; throat < levels.count; ++throat) {
        const float u = profile.front[throat];
        if (u < u_min) break;
        if (levels.y(throat) < y_max && u < profile.front[throat - 1] - 0.1f * scale) break;
    }
    const float y_min = levels.y(std::min(throat + 1, levels.count - 1));
    const float cs = std::cos(10.f * kPi / 180.f), sn = std::sin(10.f * kPi / 180.f);
    float best = -kInf;
    for (const Vec2f& p : profile.points) {
        if (p.x() < u_min || p.y() > y_max || p.y() < y_min) continue;
        if (-cs * p.y() + sn * p.x() > best) {
            best = -cs * p.y() + sn * p.x();
            l.chin = axes.at(0.f, p.y(), p.x());
        }
    }
    if (best == -kInf)
        fail(
            "find_landmarks: no chin: the midline has no point below the nose in front of "
            "the throat");
    l.height = l.crown.y() - l.chin.y();
    if (!(l.height > 0.f)) fail("find_landmarks: no head: the chin is not below the crown");
}

// Stage 3c: the neck, the narrowest closed section (smoothed over ±0.02 height) 0.02-0.8
// height below the chin, or, on a mesh that ends sooner, the narrowest closed one below the
// chin; and whether the mesh is a head only.
void find_neck(const Sections& sections, const Piece& piece, Landmarks& l) {
    const Levels& levels = sections.levels;
    const float height = l.height;
    const int w = std::max(1, static_cast<int>(std::lround(0.02f * height / levels.h)));
    auto narrowest = [&](float y_hi, float y_lo) {
        int best = -1;
        float best_r = kInf;
        for (int k = 0; k < levels.count; ++k) {
            const float y = levels.y(k);
            if (y > y_hi || y < y_lo || sections.open[k] || !(sections.radius[k] > 0.f)) continue;
            float sum = 0.f;
            int n = 0;
            for (int i = std::max(0, k - w); i <= std::min(levels.count - 1, k + w); ++i)
                if (!sections.open[i] && sections.radius[i] > 0.f) sum += sections.radius[i], ++n;
            if (sum / n < best_r) best_r = sum / n, best = k;
        }
        return best;
    };
    int neck = narrowest(l.chin.y() - 0.02f * height, l.chin.y() - 0.8f * height);
    if (neck < 0) neck = narrowest(l.chin.y(), l.chin.y() - 0.8f * height);
    if (neck < 0)
        fail(
            "find_landmarks: no neck: the mesh has no closed horizontal section below the "
            "chin (y = ",
            l.chin.y(), ")");
    const Vec2f& c = sections.centre[neck];
    l.neck = Vec3f(c.x(), levels.y(neck), c.y());
    l.neck_radius = sections.radius[neck];
    // Head only: the mesh ends within 1.5 heights below the chin, never as wide as shoulders
    // (1.5 times the neck) on the way.
    l.head_only = piece.bottom > l.chin.y() - 1.5f * height;
    for (int k = neck; k < levels.count && l.head_only; ++k)
        if (!sections.open[k] && sections.radius[k] > 1.5f * l.neck_radius) l.head_only = false;
    l.neck_bottom = l.head_only ? piece.bottom : NAN;
}

// Stage 4: the eyes and the brow from the face's depth map.
void find_eyes_and_brow(const Mesh& mesh, const Piece& piece, const HeadAxes& axes,
                        const Profile& profile, Landmarks& l) {
    const float height = l.height, h = 0.01f * height;
    const float nose_y = l.nose_tip.y();
    const DepthMap map = face_depth(mesh, piece, axes, 0.32f * height, nose_y - 0.1f * height,
                                    nose_y + 0.55f * height, h);
    const DepthMap closed =
        close_columns(map, static_cast<int>(std::lround(kSocketReach * height / h)));
    const float cap = kSocketCap * height;
    float eye_s[2], eye_y[2];
    for (int side = 0; side < 2; ++side) {
        // The centroid of the hollows beside the nose bridge, weighted by their depth.
        const float sign = side == 0 ? 1.f : -1.f;
        double sum = 0, sum_s = 0, sum_y = 0;
        for (int j = 0; j < map.ny; ++j) {
            const float y = map.y(j);
            if (y < nose_y + 0.06f * height || y > nose_y + 0.3f * height) continue;
            for (int i = 0; i < map.ns; ++i) {
                const float out = sign * map.s(i);
                if (out < 0.04f * height || out > 0.22f * height) continue;
                const float d = map.at(i, j) == -kInf
                                    ? cap
                                    : std::clamp(closed.at(i, j) - map.at(i, j), 0.f, cap);
                sum += d;
                sum_s += d * map.s(i);
                sum_y += d * y;
            }
        }
        if (sum > 0) {
            eye_s[side] = static_cast<float>(sum_s / sum);
            eye_y[side] = static_cast<float>(sum_y / sum);
        } else {  // a face with no hollows at all: the usual proportions
            eye_s[side] = sign * 0.14f * height;
            eye_y[side] = nose_y + 0.12f * height;
        }
        const int i =
            std::clamp(static_cast<int>(std::lround((eye_s[side] - map.s0) / h)), 0, map.ns - 1);
        const int j =
            std::clamp(static_cast<int>(std::lround((eye_y[side] - map.y0) / h)), 0, map.ny - 1);
        const Vec3f eye = axes.at(eye_s[side], eye_y[side], closed.at(i, j) - kEyeDepth * height);
        (side == 0 ? l.eye_left : l.eye_right) = eye;
    }

    // The brow: the most forward row (mean depth between the eyes) above the eyes.
    const float eyes_y = 0.5f * (eye_y[0] + eye_y[1]);
    const float half = 0.5f * (eye_s[0] - eye_s[1]);
    std::vector<float> row(map.ny, -kInf);
    int best = -1;
    for (int j = 0; j < map.ny; ++j) {
        const float y = map.y(j);
        if (y < eyes_y || y > eyes_y + 0.2f * height) continue;
        double sum = 0;
        int n = 0;
        for (int i = 0; i < map.ns; ++i)
            if (std::abs(map.s(i)) <= half && map.at(i, j) > -kInf) sum += map.at(i, j), ++n;
        if (n == 0) continue;
        row[j] = static_cast<float>(sum / n);
        if (best < 0 || row[j] > row[best]) best = j;
    }
    float brow_y = best >= 0 ? map.y(best) : eyes_y + 0.08f * height;
    if (best > 0 && best + 1 < map.ny && row[best - 1] > -kInf && row[best + 1] > -kInf)
        brow_y += h * parabola_peak(row[best - 1], row[best], row[best + 1]);
    float brow_u = profile.front_at(brow_y);
    if (!std::isfinite(brow_u)) brow_u = axes.forward.dot(l.nose_tip - axes.origin);
    l.brow = axes.at(0.f, brow_y, brow_u);
}

// Stage 5: the ears, the lateral extremes from the bottom of the nose to 0.1 height above the
// eye line (the ears stay where they are on a head tilted about them, the face does not), as
// the centroid of the vertices within 0.02 height of each.
void find_ears(const Mesh& mesh, const Piece& piece, const HeadAxes& axes, Landmarks& l) {
    const float y_lo = l.nose_tip.y() - 0.06f * l.height;
    const float y_hi = 0.5f * (l.eye_left.y() + l.eye_right.y()) + 0.1f * l.height;
    for (int side = 0; side < 2; ++side) {
        const float sign = side == 0 ? 1.f : -1.f;
        float extreme = -kInf;
        for (uint32_t v : piece.vertices) {
            const Vec3f& p = mesh.vertices[v];
            if (p.y() >= y_lo && p.y() <= y_hi)
                extreme = std::max(extreme, sign * axes.left.dot(p - axes.origin));
        }
        Vec3d sum = Vec3d::Zero();
        double total = 0;
        for (uint32_t v : piece.vertices) {
            const Vec3f& p = mesh.vertices[v];
            if (p.y() < y_lo || p.y() > y_hi ||
                sign * axes.left.dot(p - axes.origin) < extreme - 0.02f * l.height)
                continue;
            const double w = std::max(piece.vertex_area[v], 1e-12f);
            sum += w * p.cast<double>();
            total += w;
        }
        if (!(total > 0))
            fail("find_landmarks: no ears: the head has no vertex between the nose and the eyes");
        (side == 0 ? l.ear_left : l.ear_right) = (sum / total).cast<float>();
    }
    l.center = 0.5f * (l.ear_left + l.ear_right);
}

}  // namespace

Landmarks find_landmarks(const Mesh& mesh) {
    const size_t nv = mesh.vertices.size();
    if (mesh.faces.empty()) fail("find_landmarks: the mesh has no faces");
    for (size_t v = 0; v < nv; ++v)
        if (!mesh.vertices[v].allFinite())
            fail("find_landmarks: vertex ", v, " is not finite (", mesh.vertices[v].transpose(),
                 ")");
    for (size_t f = 0; f < mesh.faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            if (mesh.faces[f][k] < 0 || static_cast<size_t>(mesh.faces[f][k]) >= nv)
                fail("find_landmarks: face ", f, " uses vertex ", mesh.faces[f][k], " of ", nv);
    const Piece piece = largest_piece(mesh);
    if (!(piece.top > piece.bottom))
        fail("find_landmarks: the mesh's largest piece is flat (no height to find a head in)");

    const HeadReach reach = head_reach(mesh, piece);
    Profile profile;
    const HeadAxes axes = face_axes(mesh, piece, reach, profile);
    Landmarks l;
    l.forward = axes.forward;
    read_midline(profile, reach, piece, axes, l);
    find_neck(reach.sections, piece, l);
    find_eyes_and_brow(mesh, piece, axes, profile, l);
    find_ears(mesh, piece, axes, l);
    return l;
}

}  // namespace wisp
