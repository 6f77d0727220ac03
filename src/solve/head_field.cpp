#include "solve/head_field.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/parallel.hpp"
#include "geometry/mesh_distance.hpp"

namespace wisp {

namespace {
// The grid covers the mesh's bounding box grown by this many cells on every side.
constexpr float kPadCells = 3.f;

// The signed distance of the closed `mesh` at every node of `grid`: exact within 1.5 cells of
// the skin, beyond it the sign of the region and the distance walked from the band.
void signed_distance_on_grid(const Mesh& mesh, Grid3<float>& grid) {
    const Vec3i dims = grid.dims();
    const Vec3f lo = grid.origin();
    const float cell = grid.cell();
    const MeshDistance distance(mesh);
    const float band = 1.5f * cell;
    const size_t n = grid.size();
    std::vector<float>& d = grid.data();
    // 1. Unsigned distance capped at the band; exact sign inside the band. Blocks of 4³
    // nodes whose centre is further than the band plus the block's half-diagonal are far as
    // a whole, which spares most queries.
    std::fill(d.begin(), d.end(), NAN);  // NaN: far, sign unknown
    constexpr int kBlock = 4;
    const Vec3i blocks((dims.x() + kBlock - 1) / kBlock, (dims.y() + kBlock - 1) / kBlock,
                       (dims.z() + kBlock - 1) / kBlock);
    const size_t block_count = static_cast<size_t>(blocks.x()) * blocks.y() * blocks.z();
    const float half_diag = 0.5f * std::sqrt(3.f) * cell * (kBlock - 1);
    parallel_for(
        block_count,
        [&](size_t b) {
            const int bx = static_cast<int>(b % blocks.x());
            const int by = static_cast<int>((b / blocks.x()) % blocks.y());
            const int bz = static_cast<int>(b / (static_cast<size_t>(blocks.x()) * blocks.y()));
            const Vec3f centre =
                lo + cell * (kBlock * Vec3f(bx, by, bz) + Vec3f::Constant(0.5f * (kBlock - 1)));
            if (distance.unsigned_distance(centre, band + half_diag + cell) >= band + half_diag)
                return;
            for (int z = bz * kBlock; z < std::min((bz + 1) * kBlock, dims.z()); ++z)
                for (int y = by * kBlock; y < std::min((by + 1) * kBlock, dims.y()); ++y)
                    for (int x = bx * kBlock; x < std::min((bx + 1) * kBlock, dims.x()); ++x) {
                        const Vec3f p = grid.node(x, y, z);
                        if (distance.unsigned_distance(p, band) >= band) continue;
                        uint32_t face = 0;
                        const Vec3f c = distance.closest_point(p, &face);
                        const Vec3f v = p - c;
                        const float u = v.norm();
                        // The face normal decides when p lies squarely in front of or behind the
                        // closest face; near edges and vertices the winding number does.
                        const float facing = u > 0.f ? v.dot(mesh.face_normal(face)) / u : 0.f;
                        const bool in = std::abs(facing) > 0.5f ? facing < 0.f : distance.inside(p);
                        d[grid.index(x, y, z)] = in ? -u : u;
                    }
        },
        4);
    // 2. Far nodes: connected regions (6-neighbourhood) share a sign, classified once by
    // the winding number of their first node; their distance grows by one cell per step of
    // a breadth-first walk away from the band, so the gradient points out of the head
    // everywhere.
    std::vector<int32_t> region(n, -1);
    std::vector<float> sign_of;
    std::vector<size_t> frontier, next;
    auto decode = [&](size_t i, int& x, int& y, int& z) {
        x = static_cast<int>(i % dims.x());
        y = static_cast<int>((i / dims.x()) % dims.y());
        z = static_cast<int>(i / (static_cast<size_t>(dims.x()) * dims.y()));
    };
    auto for_neighbours = [&](size_t i, auto&& f) {
        int x, y, z;
        decode(i, x, y, z);
        if (x > 0) f(grid.index(x - 1, y, z));
        if (x + 1 < dims.x()) f(grid.index(x + 1, y, z));
        if (y > 0) f(grid.index(x, y - 1, z));
        if (y + 1 < dims.y()) f(grid.index(x, y + 1, z));
        if (z > 0) f(grid.index(x, y, z - 1));
        if (z + 1 < dims.z()) f(grid.index(x, y, z + 1));
    };
    for (size_t seed = 0; seed < n; ++seed) {
        if (!std::isnan(d[seed]) || region[seed] >= 0) continue;
        int x0, y0, z0;
        decode(seed, x0, y0, z0);
        const int id = static_cast<int32_t>(sign_of.size());
        sign_of.push_back(distance.inside(grid.node(x0, y0, z0)) ? -1.f : 1.f);
        region[seed] = id;
        std::vector<size_t> stack{seed};
        while (!stack.empty()) {
            const size_t i = stack.back();
            stack.pop_back();
            for_neighbours(i, [&](size_t j) {
                if (std::isnan(d[j]) && region[j] < 0) {
                    region[j] = id;
                    stack.push_back(j);
                }
            });
        }
    }
    // Breadth-first distance from the band, in steps.
    for (size_t i = 0; i < n; ++i) {
        if (!std::isnan(d[i])) continue;
        bool touches = false;
        for_neighbours(i, [&](size_t j) { touches |= !std::isnan(d[j]); });
        if (touches) frontier.push_back(i);
    }
    for (size_t i : frontier)
        d[i] = sign_of[region[i]] * band;
    for (float step = 1.f; !frontier.empty(); step += 1.f) {
        next.clear();
        for (size_t i : frontier)
            for_neighbours(i, [&](size_t j) {
                if (std::isnan(d[j])) {
                    d[j] = sign_of[region[j]] * (band + step * cell);
                    next.push_back(j);
                }
            });
        frontier.swap(next);
    }
}

}  // namespace

double HeadField::node_count(const Box3& mesh_bounds, float cell) {
    return grid_nodes(mesh_bounds.size() + Vec3f::Constant(2.f * kPadCells * cell), cell);
}

HeadField::HeadField(const Mesh& open_mesh, float cell, size_t first_body_face, float bridge) {
    // A head cut open at the neck or chest (most head meshes) encloses its inside only once
    // closed: otherwise the inside far from the skin is one region with the outside, through
    // the cut, and takes its sign, so hair that crossed the skin's band could pass through
    // the head.
    const bool two = first_body_face < open_mesh.faces.size();
    Mesh head, body;
    if (two) {
        // The head and the body overlap at the neck: each is closed and measured on its own,
        // and the field is their union (the smaller distance), which a single mesh's faces
        // inside the other would break (a node just outside the head's neck, deep in the body,
        // would be "outside").
        Mesh part;
        part.vertices = open_mesh.vertices;
        part.faces.assign(open_mesh.faces.begin(), open_mesh.faces.begin() + first_body_face);
        close_holes(part, &head);
        part.faces.assign(open_mesh.faces.begin() + first_body_face, open_mesh.faces.end());
        close_holes(part, &body);
    } else {
        close_holes(open_mesh, &head);
    }
    const Box3 b = open_mesh.bounds();
    const Vec3f pad = Vec3f::Constant(kPadCells * cell);
    const Vec3f lo = b.lo - pad;
    const Vec3f size = b.size() + 2.f * pad;
    Vec3i dims;
    for (int a = 0; a < 3; ++a)
        dims[a] = std::max(2, static_cast<int>(std::ceil(size[a] / cell)) + 1);
    grid_ = Grid3<float>(lo, cell, dims, 0.f);
    box_.lo = lo;
    box_.hi = lo + cell * Vec3f(dims.x() - 1, dims.y() - 1, dims.z() - 1);
    signed_distance_on_grid(head, grid_);
    if (two) {
        Grid3<float> other(lo, cell, dims, 0.f);
        signed_distance_on_grid(body, other);
        std::vector<float>& d = grid_.data();
        const std::vector<float>& e = other.data();
        for (size_t i = 0; i < d.size(); ++i)
            d[i] = std::min(d[i], e[i]);
    }
    find_cell_minima();
    if (bridge > 0.f) {
        // The closing, node by node: the ball of the bridge radius that touches the skin at
        // a node's nearest skin point from outside (its centre o a bridge radius out along the
        // normal) reaches into skin beyond by bridge − sdf(o) where the skin folds back within
        // its diameter; the node is that much deeper in the closed head. On open skin the ball
        // is free and the distance stays; inside the head nothing changes.
        auto closed = std::make_shared<HeadField>();
        closed->grid_ = grid_;
        closed->box_ = box_;
        std::vector<float>& out = closed->grid_.data();
        parallel_for(
            static_cast<size_t>(dims.z()),
            [&](size_t zi) {
                const int z = static_cast<int>(zi);
                for (int y = 0; y < dims.y(); ++y)
                    for (int x = 0; x < dims.x(); ++x) {
                        const float d = grid_.at(x, y, z);
                        if (!(d >= 0.f && d < bridge)) continue;
                        const Vec3f p = grid_.node(x, y, z);
                        const Vec3f g = gradient(p);
                        const float gn = g.norm();
                        if (!(gn > 1e-6f)) continue;
                        const float reach = bridge - sdf(p + (bridge - d) / gn * g);
                        if (reach > 0.f) out[grid_.index(x, y, z)] = d - reach;
                    }
            },
            1);
        closed->find_cell_minima();
        bridged_ = std::move(closed);
    }
}

void HeadField::find_cell_minima() {
    // The smallest distance at each cell's nodes, for beyond().
    const Vec3i dims = grid_.dims();
    const Vec3i cells = dims - Vec3i::Ones();
    cell_min_.resize(static_cast<size_t>(cells.x()) * cells.y() * cells.z());
    parallel_for(
        static_cast<size_t>(cells.z()),
        [&](size_t zi) {
            const int z = static_cast<int>(zi);
            for (int y = 0; y < cells.y(); ++y)
                for (int x = 0; x < cells.x(); ++x) {
                    float m = INFINITY;
                    for (int c = 0; c < 8; ++c)
                        m = std::min(m, grid_.at(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2)));
                    cell_min_[(static_cast<size_t>(z) * cells.y() + y) * cells.x() + x] = m;
                }
        },
        1);
}

Vec3f HeadField::gradient(const Vec3f& p) const {
    const float h = 0.5f * grid_.cell();
    Vec3f g;
    for (int a = 0; a < 3; ++a) {
        Vec3f e = Vec3f::Zero();
        e[a] = h;
        const float f1 = sdf(p + e), f0 = sdf(p - e);
        g[a] = (f1 > 1e5f || f0 > 1e5f) ? 0.f : (f1 - f0) / (2.f * h);
    }
    return g;
}

}  // namespace wisp
