#include "geometry/mesh_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/error.hpp"

namespace wisp {
namespace {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection §5.1.5).
Vec3f closest_on_triangle(const Vec3f& p, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const Vec3f ab = b - a, ac = c - a, ap = p - a;
    const float d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0.f && d2 <= 0.f) return a;
    const Vec3f bp = p - b;
    const float d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0.f && d4 <= d3) return b;
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.f && d1 >= 0.f && d3 <= 0.f) return a + (d1 / (d1 - d3)) * ab;
    const Vec3f cp = p - c;
    const float d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0.f && d5 <= d6) return c;
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.f && d2 >= 0.f && d6 <= 0.f) return a + (d2 / (d2 - d6)) * ac;
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.f && (d4 - d3) >= 0.f && (d5 - d6) >= 0.f)
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    const float denom = 1.f / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

// Signed solid angle of triangle abc seen from p (Van Oosterom & Strackee 1983), positive when
// p is behind the triangle (on the side its counter-clockwise normal points away from).
float solid_angle(const Vec3f& p, const Vec3f& a0, const Vec3f& b0, const Vec3f& c0) {
    const Vec3f a = a0 - p, b = b0 - p, c = c0 - p;
    const float la = a.norm(), lb = b.norm(), lc = c.norm();
    const float det = a.dot(b.cross(c));
    const float den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    return 2.f * std::atan2(det, den);
}

float box_distance2(const Vec3f& p, const Vec3f& lo, const Vec3f& hi) {
    const Vec3f d = (lo - p).cwiseMax(p - hi).cwiseMax(0.f);
    return d.squaredNorm();
}

constexpr int kLeafSize = 4;
// Below this depth splits are SAH; deeper ones are median splits, so the depth stays below
// kMaxSahDepth + log2(#F) and the traversal stacks (one slot per level plus one) cannot overflow.
constexpr int kMaxSahDepth = 48;
constexpr int kStackSize = 128;
constexpr int kBins = 12;
constexpr float kFarField = 2.f;  // β of Barill et al. 2018: dipole when |q - c| > β r
constexpr float kInv4Pi = 0.25f / kPi;

}  // namespace

// A bounding volume hierarchy in flat arrays. Internal node i has children left and left + 1;
// a leaf owns triangles [first, first + count) of the reordered arrays. Every node also keeps
// the first-order far-field expansion of its triangles for the winding number (Barill et al.
// 2018, "Fast winding numbers for soups and clouds"): the sum of area-weighted normals placed
// at the area-weighted centroid, valid beyond β times the node's radius about that centroid.
struct MeshDistance::Impl {
    struct Node {
        Vec3f lo = Vec3f::Zero(), hi = Vec3f::Zero();
        uint32_t index = 0;  // leaf: first triangle; internal: left child
        uint32_t count = 0;  // 0 for internal nodes
    };
    struct Dipole {
        Vec3f centre;       // p̃ = Σ a_t x_t / Σ a_t, x_t the triangle centroids
        Vec3f normal_area;  // N = Σ a_t n_t = Σ ½ (b - a) × (c - a)
        Mat3f moment;       // C = Σ a_t (x_t - p̃) n_tᵀ, the second-order term
        float radius2;      // squared radius about p̃, times β²
    };
    std::vector<Node> nodes;
    std::vector<Dipole> dipoles;
    std::vector<std::array<Vec3f, 3>> tris;  // in leaf order
    std::vector<uint32_t> tri_face;          // original face index of each tri

    explicit Impl(const Mesh& mesh) {
        const size_t n = mesh.faces.size();
        if (n == 0) fail("MeshDistance: the mesh has no faces");
        std::vector<uint32_t> order(n);
        std::vector<Vec3f> centroid(n);
        std::vector<std::array<Vec3f, 3>> all(n);
        for (size_t f = 0; f < n; ++f) {
            for (int k = 0; k < 3; ++k) {
                const int v = mesh.faces[f][k];
                if (v < 0 || static_cast<size_t>(v) >= mesh.vertices.size())
                    fail("MeshDistance: face ", f, " has vertex index ", v, " out of range (",
                         mesh.vertices.size(), " vertices)");
                all[f][k] = mesh.vertices[v];
            }
            centroid[f] = (all[f][0] + all[f][1] + all[f][2]) / 3.f;
            order[f] = static_cast<uint32_t>(f);
        }
        nodes.reserve(2 * n / kLeafSize + 2);
        nodes.push_back({});
        build(0, 0, static_cast<uint32_t>(n), order, centroid, all);
        tris.resize(n);
        tri_face = order;
        for (size_t i = 0; i < n; ++i)
            tris[i] = all[order[i]];
        dipoles.resize(nodes.size());
        fill_dipoles(0);
    }

    Box3 bounds_of(uint32_t first, uint32_t count, const std::vector<uint32_t>& order,
                   const std::vector<std::array<Vec3f, 3>>& all) const {
        Box3 b;
        for (uint32_t i = first; i < first + count; ++i)
            for (const Vec3f& p : all[order[i]])
                b.extend(p);
        return b;
    }

    // Binned surface-area-heuristic split over centroids; recursion depth is logarithmic.
    void build(uint32_t node, uint32_t first, uint32_t count, std::vector<uint32_t>& order,
               const std::vector<Vec3f>& centroid, const std::vector<std::array<Vec3f, 3>>& all,
               int depth = 0) {
        const Box3 box = bounds_of(first, count, order, all);
        nodes[node].lo = box.lo;
        nodes[node].hi = box.hi;
        auto make_leaf = [&] {
            nodes[node].index = first;
            nodes[node].count = count;
        };
        if (count <= kLeafSize) return make_leaf();
        Box3 cbox;
        for (uint32_t i = first; i < first + count; ++i)
            cbox.extend(centroid[order[i]]);
        int axis = 0;
        cbox.size().maxCoeff(&axis);
        const float lo = cbox.lo[axis], extent = cbox.size()[axis];
        if (!(extent > 0.f)) return make_leaf();

        auto bin_of = [&](uint32_t t) {
            return std::min(kBins - 1, static_cast<int>(kBins * (centroid[t][axis] - lo) / extent));
        };
        Box3 bin_box[kBins];
        int bin_count[kBins] = {};
        for (uint32_t i = first; i < first + count; ++i) {
            const int b = bin_of(order[i]);
            ++bin_count[b];
            for (const Vec3f& p : all[order[i]])
                bin_box[b].extend(p);
        }
        auto half_area = [](const Box3& b) {
            if (b.empty()) return 0.f;
            const Vec3f s = b.size();
            return s.x() * s.y() + s.y() * s.z() + s.z() * s.x();
        };
        float right_cost[kBins] = {};
        Box3 acc;
        int acc_n = 0;
        for (int b = kBins - 1; b > 0; --b) {
            acc.extend(bin_box[b]);
            acc_n += bin_count[b];
            right_cost[b] = half_area(acc) * acc_n;
        }
        float best = INFINITY;
        int split = -1;
        acc = Box3();
        acc_n = 0;
        for (int b = 0; b + 1 < kBins; ++b) {
            acc.extend(bin_box[b]);
            acc_n += bin_count[b];
            if (acc_n == 0 || acc_n == static_cast<int>(count) || depth >= kMaxSahDepth) continue;
            const float cost = half_area(acc) * acc_n + right_cost[b + 1];
            if (cost < best) best = cost, split = b;
        }
        uint32_t mid;
        if (split < 0) {  // all centroids in one bin: split the order in half
            mid = first + count / 2;
            std::nth_element(
                order.begin() + first, order.begin() + mid, order.begin() + first + count,
                [&](uint32_t a, uint32_t b) { return centroid[a][axis] < centroid[b][axis]; });
        } else {
            mid = static_cast<uint32_t>(
                std::partition(order.begin() + first, order.begin() + first + count,
                               [&](uint32_t t) { return bin_of(t) <= split; }) -
                order.begin());
        }
        const uint32_t left = static_cast<uint32_t>(nodes.size());
        nodes.push_back({});
        nodes.push_back({});
        nodes[node].index = left;
        nodes[node].count = 0;
        build(left, first, mid - first, order, centroid, all, depth + 1);
        build(left + 1, mid, first + count - mid, order, centroid, all, depth + 1);
    }

    // Fills the far-field expansion bottom-up; returns Σ area and writes the node's dipole.
    float fill_dipoles(uint32_t node) {
        const Node& nd = nodes[node];
        Dipole& d = dipoles[node];
        float area = 0.f;
        Vec3f weighted = Vec3f::Zero(), na = Vec3f::Zero();
        if (nd.count > 0) {
            for (uint32_t i = nd.index; i < nd.index + nd.count; ++i) {
                const auto& t = tris[i];
                const Vec3f n = 0.5f * (t[1] - t[0]).cross(t[2] - t[0]);
                const float a = n.norm();
                area += a;
                weighted += a * (t[0] + t[1] + t[2]) / 3.f;
                na += n;
            }
            d.centre = area > 0.f ? Vec3f(weighted / area) : Vec3f(0.5f * (nd.lo + nd.hi));
            d.moment.setZero();
            for (uint32_t i = nd.index; i < nd.index + nd.count; ++i) {
                const auto& t = tris[i];
                const Vec3f n = 0.5f * (t[1] - t[0]).cross(t[2] - t[0]);
                d.moment += ((t[0] + t[1] + t[2]) / 3.f - d.centre) * n.transpose();
            }
        } else {
            const float a0 = fill_dipoles(nd.index), a1 = fill_dipoles(nd.index + 1);
            const Dipole &d0 = dipoles[nd.index], &d1 = dipoles[nd.index + 1];
            area = a0 + a1;
            weighted = a0 * d0.centre + a1 * d1.centre;
            na = d0.normal_area + d1.normal_area;
            d.centre = area > 0.f ? Vec3f(weighted / area) : Vec3f(0.5f * (nd.lo + nd.hi));
            // Moments move to the parent's centre: C = Σ_c C_c + (p̃_c - p̃) N_cᵀ.
            d.moment = d0.moment + (d0.centre - d.centre) * d0.normal_area.transpose() + d1.moment +
                       (d1.centre - d.centre) * d1.normal_area.transpose();
        }
        d.normal_area = na;
        // The radius about the centre bounds every triangle: the furthest box corner.
        const Vec3f far = (d.centre - nd.lo).cwiseAbs().cwiseMax((nd.hi - d.centre).cwiseAbs());
        d.radius2 = kFarField * kFarField * far.squaredNorm();
        return area;
    }

    // Closest point within sqrt(best) of p; best_point is left alone if there is none.
    uint32_t closest(const Vec3f& p, Vec3f& best_point, float best = INFINITY) const {
        uint32_t best_tri = 0;
        uint32_t stack[kStackSize];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& nd = nodes[stack[--top]];
            if (box_distance2(p, nd.lo, nd.hi) >= best) continue;
            if (nd.count > 0) {
                for (uint32_t i = nd.index; i < nd.index + nd.count; ++i) {
                    const auto& t = tris[i];
                    const Vec3f q = closest_on_triangle(p, t[0], t[1], t[2]);
                    const float d2 = (q - p).squaredNorm();
                    if (d2 < best) best = d2, best_point = q, best_tri = i;
                }
                continue;
            }
            const uint32_t a = nd.index, b = nd.index + 1;
            const float da = box_distance2(p, nodes[a].lo, nodes[a].hi);
            const float db = box_distance2(p, nodes[b].lo, nodes[b].hi);
            // Push the farther child first so the nearer one is searched first.
            if (da < db) {
                if (db < best) stack[top++] = b;
                if (da < best) stack[top++] = a;
            } else {
                if (da < best) stack[top++] = a;
                if (db < best) stack[top++] = b;
            }
        }
        return tri_face[best_tri];
    }

    float winding_number(const Vec3f& p) const {
        float w = 0.f;
        uint32_t stack[kStackSize];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const uint32_t i = stack[--top];
            const Node& nd = nodes[i];
            const Dipole& d = dipoles[i];
            const Vec3f r = d.centre - p;
            const float r2 = r.squaredNorm();
            if (r2 > d.radius2) {
                // Σ a_t n_t · f(x_t) with f(x) = (x - q) / |x - q|³, Taylor-expanded about p̃
                // to second order: f(p̃)·N + tr(J C), J = ∇f = I/|r|³ - 3 r rᵀ/|r|⁵.
                const float inv_r = 1.f / std::sqrt(r2);
                const float inv_r3 = inv_r * inv_r * inv_r;
                const float inv_r5 = inv_r3 * inv_r * inv_r;
                w += r.dot(d.normal_area) * inv_r3 + d.moment.trace() * inv_r3 -
                     3.f * inv_r5 * r.dot(d.moment * r);
                continue;
            }
            if (nd.count > 0) {
                for (uint32_t t = nd.index; t < nd.index + nd.count; ++t)
                    w += solid_angle(p, tris[t][0], tris[t][1], tris[t][2]);
                continue;
            }
            stack[top++] = nd.index;
            stack[top++] = nd.index + 1;
        }
        return w * kInv4Pi;
    }
};

MeshDistance::MeshDistance(const Mesh& mesh) : impl_(std::make_unique<Impl>(mesh)) {}
MeshDistance::~MeshDistance() = default;
MeshDistance::MeshDistance(MeshDistance&&) noexcept = default;
MeshDistance& MeshDistance::operator=(MeshDistance&&) noexcept = default;

Vec3f MeshDistance::closest_point(const Vec3f& p, uint32_t* face) const {
    Vec3f q = p;
    const uint32_t f = impl_->closest(p, q);
    if (face) *face = f;
    return q;
}

float MeshDistance::unsigned_distance(const Vec3f& p) const {
    Vec3f q = p;
    impl_->closest(p, q);
    return (q - p).norm();
}

float MeshDistance::unsigned_distance(const Vec3f& p, float max_distance) const {
    Vec3f q = Vec3f::Constant(NAN);  // stays NaN when nothing is within max_distance
    impl_->closest(p, q, max_distance * max_distance);
    return q.allFinite() ? std::min((q - p).norm(), max_distance) : max_distance;
}

float MeshDistance::winding_number(const Vec3f& p) const {
    return impl_->winding_number(p);
}

bool MeshDistance::inside(const Vec3f& p) const {
    return impl_->winding_number(p) > 0.5f;
}

float MeshDistance::signed_distance(const Vec3f& p) const {
    const float d = unsigned_distance(p);
    return inside(p) ? -d : d;
}

size_t MeshDistance::face_count() const {
    return impl_->tris.size();
}

}  // namespace wisp
