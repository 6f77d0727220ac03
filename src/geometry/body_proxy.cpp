#include "geometry/body_proxy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/SparseCholesky>

#include "geometry/builtin_head.hpp"
#include "geometry/mesh_distance.hpp"

namespace wisp {
namespace {

// The built-in head, whose torso the proxy is: its height from chin to crown, its chin and the
// point of its neck's axis that the proxy centres under the mesh's neck (cm, its space).
constexpr float kBuiltinHeight = 22.8f;
constexpr float kBuiltinChinY = -10.3f;
constexpr float kBuiltinNeckZ = -2.f;

// Where a bust is cut open below the shoulders, the proxy takes the bust's surface on, so the
// cut's ragged rim lies on the proxy instead of standing out of it as a ledge. The proxy's
// vertices that the bust covers (whose nearest point on the bust is inside its surface, not on
// the rim, facing the same way and within `reach`) move onto the bust, a millimetre inside at
// the rim and 5 mm inside further up; those within `blend` of the rim below it follow them by
// a biharmonic blend of the moves, fading to nothing further away; the proxy's vertex nearest
// each of the rim's vertices goes onto it.
void meet_bust_rim(Mesh& proxy, const Mesh& bust, const Landmarks& head) {
    // The bust's open edges below the face (not a scan's eye sockets or nostrils).
    const std::vector<std::pair<int, int>> open = boundary_edges(bust);
    const auto is_open = [&](int a, int b) {
        return std::binary_search(open.begin(), open.end(), std::make_pair(a, b));
    };
    const float below = head.chin.y() - 0.2f * head.height;
    std::vector<uint8_t> rim(bust.vertices.size(), 0);
    std::vector<Vec3f> rim_points;
    for (const auto& [a, b] : open) {
        if (bust.vertices[a].y() > below || bust.vertices[b].y() > below) continue;
        for (int v : {a, b})
            if (!rim[v]) rim[v] = 1, rim_points.push_back(bust.vertices[v]);
    }
    if (rim_points.empty()) return;

    const float reach = 0.15f * head.height, blend = 0.35f * head.height;
    const float inset = 0.1f * head.height / kBuiltinHeight;  // a millimetre at the built-in's
    const float sink = 0.4f * head.height / kBuiltinHeight;
    const size_t n = proxy.vertices.size();
    std::vector<Vec3f> normal(n, Vec3f::Zero());
    for (const Vec3i& t : proxy.faces) {
        const Vec3f& a = proxy.vertices[t[0]];
        const Vec3f area = (proxy.vertices[t[1]] - a).cross(proxy.vertices[t[2]] - a);
        for (int k = 0; k < 3; ++k)
            normal[t[k]] += area;
    }
    const VertexLists around = vertex_edges(proxy);  // the proxy is closed: each neighbour once

    const MeshDistance distance(bust);
    enum : uint8_t { kFree, kOnBust, kStill };
    std::vector<uint8_t> kind(n, kFree);
    std::vector<Vec3f> move(n, Vec3f::Zero());
    const float on_rim = 1e-3f * head.height;
    for (size_t i = 0; i < n; ++i) {
        const Vec3f& v = proxy.vertices[i];
        uint32_t f = 0;
        const Vec3f c = distance.closest_point(v, &f);
        const Vec3f nb = bust.face_normal(f);
        bool at_rim = false;
        for (int k = 0; k < 3; ++k)
            at_rim |=
                rim[bust.faces[f][k]] && (bust.vertices[bust.faces[f][k]] - c).norm() < on_rim;
        for (int e = 0; e < 3 && !at_rim; ++e) {
            const int a = bust.faces[f][e], b = bust.faces[f][(e + 1) % 3];
            if (!rim[a] || !rim[b] || !is_open(a, b)) continue;
            const Vec3f ab = bust.vertices[b] - bust.vertices[a];
            const float t = std::clamp((c - bust.vertices[a]).dot(ab) / ab.squaredNorm(), 0.f, 1.f);
            at_rim = (bust.vertices[a] + t * ab - c).norm() < on_rim;
        }
        const float nn = normal[i].norm();
        if (!at_rim && (c - v).norm() < reach && nn > 0.f && nb.dot(normal[i] / nn) > 0.5f &&
            v.y() < head.neck.y()) {
            // Deeper away from the rim (not near it, where the proxy must leave the bust at
            // the bust's slope): a proxy edge spanning a hollow of the bust (the collarbones,
            // the notch above the breastbone) sags out of it otherwise, in ragged patches.
            float from_rim = INFINITY;
            for (const Vec3f& r : rim_points)
                from_rim = std::min(from_rim, (r - c).squaredNorm());
            const float depth = inset + sink * smoothstep(0.1f * head.height, 0.25f * head.height,
                                                          std::sqrt(from_rim));
            kind[i] = kOnBust;
            move[i] = c - depth * nb - v;
            continue;
        }
        float nearest = INFINITY;
        for (const Vec3f& r : rim_points)
            nearest = std::min(nearest, (r - v).squaredNorm());
        if (nearest > blend * blend) kind[i] = kStill;
    }
    // The rim itself: each of its vertices pins the proxy's vertex nearest to it (where the
    // rim's teeth stand out between the covered vertices and the free ones below).
    std::vector<Vec3f> pinned(n, Vec3f::Zero());
    std::vector<uint32_t> pins(n, 0);
    for (const Vec3f& r : rim_points) {
        size_t best = 0;
        float closest = INFINITY;
        for (size_t i = 0; i < n; ++i)
            if (const float d = (proxy.vertices[i] - r).squaredNorm(); d < closest)
                closest = d, best = i;
        if (closest > reach * reach) continue;
        pinned[best] += r;
        ++pins[best];
    }
    for (size_t i = 0; i < n; ++i)
        if (pins[i]) {
            kind[i] = kOnBust;
            move[i] = pinned[i] / float(pins[i]) - proxy.vertices[i];
        }
    // The band below the rim follows by a biharmonic blend of the moves (Σ|Δ move|² least over
    // the free vertices, the umbrella Laplacian), not a harmonic one: a harmonic blend meets
    // the covered vertices at a kink, a crease of 14° on the MakeHuman bust that shading drew
    // as a line across the chest and back; the biharmonic one meets them at the same slope.
    std::vector<int> unknown(n, -1);
    int free_count = 0;
    for (size_t i = 0; i < n; ++i)
        if (kind[i] == kFree) unknown[i] = free_count++;
    if (free_count > 0) {
        // Rows of Δ for every vertex with a free vertex in its umbrella: (Δu)_i = mean of the
        // neighbours' u − u_i. The free columns form A; the fixed ones move the right side.
        using Sparse = Eigen::SparseMatrix<double>;
        std::vector<Eigen::Triplet<double>> entries;
        std::vector<Eigen::Vector3d> fixed_part;
        int rows = 0;
        for (size_t i = 0; i < n; ++i) {
            const uint32_t lo = around.first[i], hi = around.first[i + 1];
            if (hi == lo) continue;
            bool touches = unknown[i] >= 0;
            for (uint32_t k = lo; k < hi && !touches; ++k)
                touches = unknown[around.items[k]] >= 0;
            if (!touches) continue;
            const double w = 1.0 / double(hi - lo);
            Eigen::Vector3d known = Eigen::Vector3d::Zero();
            const auto add = [&](uint32_t j, double weight) {
                if (unknown[j] >= 0)
                    entries.emplace_back(rows, unknown[j], weight);
                else
                    known += weight * move[j].cast<double>();
            };
            for (uint32_t k = lo; k < hi; ++k)
                add(around.items[k], w);
            add(static_cast<uint32_t>(i), -1.0);
            fixed_part.push_back(known);
            ++rows;
        }
        Sparse laplacian(rows, free_count);
        laplacian.setFromTriplets(entries.begin(), entries.end());
        Eigen::MatrixXd rhs(rows, 3);
        for (int r = 0; r < rows; ++r)
            rhs.row(r) = -fixed_part[r].transpose();
        const Sparse normal_matrix = laplacian.transpose() * laplacian;
        const Eigen::SimplicialLDLT<Sparse> solver(normal_matrix);
        if (solver.info() == Eigen::Success) {
            const Eigen::MatrixXd x = solver.solve(laplacian.transpose() * rhs);
            for (size_t i = 0; i < n; ++i)
                if (unknown[i] >= 0) move[i] = x.row(unknown[i]).transpose().cast<float>();
        }
    }
    for (size_t i = 0; i < n; ++i)
        proxy.vertices[i] += move[i];
}

}  // namespace

Mesh fit_body_proxy(const Landmarks& head, const Mesh* mesh) {
    const float s = head.height / kBuiltinHeight;
    // The neck column goes up into the mesh's neck, 2 head-scaled cm above where the mesh
    // ends, or to the narrowest section if that is higher, never above 1 cm under the chin;
    // thinner than the narrowest section, it stays inside the neck everywhere between.
    const float bottom = std::isfinite(head.neck_bottom) ? head.neck_bottom : head.neck.y();
    const float top = std::min(std::max(head.neck.y(), bottom + 2.f * s), head.chin.y() - 1.f * s);
    const auto to_builtin_y = [&](float y) { return kBuiltinChinY + (y - head.chin.y()) / s; };
    // The radius is the circle's of the section's area: necks are wider than deep, so 0.8 of
    // it stays inside front and back.
    Mesh torso = builtin_torso_mesh(to_builtin_y(top), 0.8f * head.neck_radius / s);

    // p = T + s·R·(q − A): A the built-in's chin level on its neck's axis, T the mesh's chin
    // level on its neck's centre; R turns +Z to the face's direction about +Y.
    const float yaw = std::atan2(head.forward.x(), head.forward.z());
    const float c = std::cos(yaw), sn = std::sin(yaw);
    const Vec3f a(0.f, kBuiltinChinY, kBuiltinNeckZ);
    const Vec3f t(head.neck.x(), head.chin.y(), head.neck.z());
    // A bust's own shoulders, where it has them, may be broader or deeper than the built-in
    // figure's at this head size: the proxy is widened (never narrowed) to hold them, so their
    // cut edge does not stand out of it. Measured in the face's frame across the shoulders,
    // a little above where the mesh ends (or 0.45 heights below the chin).
    Vec3f stretch = Vec3f::Ones();
    if (mesh) {
        const float level =
            std::max(head.chin.y() - 0.45f * head.height, mesh->bounds().lo.y() + 1.5f * s);
        if (level < head.chin.y() - 0.3f * head.height) {
            const auto extent = [&](const std::vector<Vec3f>& points, bool builtin) {
                Vec3f lo = Vec3f::Constant(INFINITY), hi = Vec3f::Constant(-INFINITY);
                for (const Vec3f& v : points) {
                    // Across (character's left) and forward in the face's frame: the built-in
                    // torso faces +Z already, the mesh turns by the yaw.
                    const Vec3f d = builtin ? Vec3f(s * (v - a)) : Vec3f(v - t);
                    if (std::abs(d.y() + t.y() - level) > 1.f * s) continue;
                    const Vec3f f =
                        builtin ? Vec3f(d.x(), 0.f, d.z())
                                : Vec3f(c * d.x() - sn * d.z(), 0.f, sn * d.x() + c * d.z());
                    lo = lo.cwiseMin(f);
                    hi = hi.cwiseMax(f);
                }
                return Vec3f(hi - lo);
            };
            const Vec3f theirs = extent(mesh->vertices, false), ours = extent(torso.vertices, true);
            for (int axis : {0, 2})
                if (ours[axis] > 0.f && std::isfinite(theirs[axis]))
                    stretch[axis] = std::clamp(1.02f * theirs[axis] / ours[axis], 1.f, 1.4f);
        }
    }
    for (Vec3f& v : torso.vertices) {
        const Vec3f q = s * (v - a).cwiseProduct(stretch);
        v = t + Vec3f(c * q.x() + sn * q.z(), q.y(), -sn * q.x() + c * q.z());
    }
    if (mesh) meet_bust_rim(torso, *mesh, head);
    torso.group_names = {kBodyProxyGroup};
    torso.face_group.assign(torso.faces.size(), 0);
    return torso;
}

}  // namespace wisp
