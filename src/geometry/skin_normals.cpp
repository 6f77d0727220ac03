#include "geometry/skin_normals.hpp"

#include <algorithm>
#include <cmath>

#include "core/parallel.hpp"
#include "core/point_grid.hpp"
#include "geometry/body_proxy.hpp"

namespace wisp {
namespace {

void blend_seam_normals(const Mesh& mesh, std::vector<Vec3f>& normals) {
    const auto& groups = mesh.group_names;
    const auto it = std::find(groups.begin(), groups.end(), kBodyProxyGroup);
    if (it == groups.end() || mesh.face_group.size() != mesh.faces.size()) return;
    const int32_t proxy = static_cast<int32_t>(it - groups.begin());
    const size_t nv = mesh.vertices.size();
    std::vector<char> on_proxy(nv, 0);
    for (size_t f = 0; f < mesh.faces.size(); ++f)
        if (mesh.face_group[f] == proxy)
            for (int k = 0; k < 3; ++k)
                on_proxy[static_cast<size_t>(mesh.faces[f][k])] = 1;
    std::vector<char> rim(nv, 0);
    double edge_sum = 0;
    size_t edges = 0;
    for (const auto& [a, b] : boundary_edges(mesh)) {
        if (on_proxy[size_t(a)] || on_proxy[size_t(b)]) continue;
        rim[size_t(a)] = rim[size_t(b)] = 1;
        edge_sum += (mesh.vertices[size_t(a)] - mesh.vertices[size_t(b)]).norm();
        ++edges;
    }
    if (edges == 0) return;
    const float edge = static_cast<float>(edge_sum / double(edges));
    // The seam: each rim vertex on the proxy, with the normal both sides will share there.
    std::vector<Vec3f> proxy_at;
    std::vector<uint32_t> proxy_index;
    for (size_t v = 0; v < nv; ++v)
        if (on_proxy[v]) proxy_at.push_back(mesh.vertices[v]), proxy_index.push_back(uint32_t(v));
    const PointGrid proxy_grid(proxy_at, edge);
    std::vector<Vec3f> seam_at, seam_normal;
    for (size_t v = 0; v < nv; ++v) {
        if (!rim[v]) continue;
        const int q = proxy_grid.nearest(mesh.vertices[v]);
        if (q < 0 || (proxy_at[size_t(q)] - mesh.vertices[v]).squaredNorm() > edge * edge) continue;
        const Vec3f shared = normals[v] + normals[proxy_index[size_t(q)]];
        if (shared.squaredNorm() < 1e-12f) continue;
        seam_at.push_back(mesh.vertices[v]);
        seam_normal.push_back(shared.normalized());
    }
    if (seam_at.empty()) return;
    const float radius = 2.f * edge;
    const PointGrid seam_grid(seam_at, radius);
    parallel_for(
        nv,
        [&](size_t v) {
            const int s = seam_grid.nearest(mesh.vertices[v]);
            const float d = (seam_at[size_t(s)] - mesh.vertices[v]).norm();
            if (d >= radius) return;
            const float w = 1.f - smoothstep(0.f, radius, d);
            const Vec3f n = (1.f - w) * normals[v] + w * seam_normal[size_t(s)];
            if (n.squaredNorm() > 1e-12f) normals[v] = n.normalized();
        },
        1024);
}

}  // namespace

std::vector<Vec3f> skin_normals(const Mesh& mesh) {
    std::vector<Vec3f> normals(mesh.vertices.size(), Vec3f::Zero());
    for (const Vec3i& t : mesh.faces) {
        const Vec3f n = (mesh.vertices[size_t(t[1])] - mesh.vertices[size_t(t[0])])
                            .cross(mesh.vertices[size_t(t[2])] - mesh.vertices[size_t(t[0])]);
        for (int k = 0; k < 3; ++k)
            normals[size_t(t[k])] += n;  // 2·area·n: area-weighted
    }
    for (Vec3f& n : normals)
        n = n.norm() > 0 ? Vec3f(n.normalized()) : Vec3f::UnitY();
    blend_seam_normals(mesh, normals);
    return normals;
}

}  // namespace wisp
