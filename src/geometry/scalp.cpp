#include "geometry/scalp.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <type_traits>

#include "core/error.hpp"
#include "core/image.hpp"
#include "core/point_grid.hpp"
#include "geometry/skin_normals.hpp"

namespace wisp {
namespace {

Vec3f face_centroid(const Mesh& m, size_t f) {
    const Vec3i& t = m.faces[f];
    return (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.f;
}

std::vector<uint32_t> select_by_group(const Mesh& mesh, const ScalpSpec& spec,
                                      const std::string& source) {
    auto find = [&](const std::vector<std::string>& names) {
        for (size_t i = 0; i < names.size(); ++i)
            if (names[i] == spec.group) return static_cast<int>(i);
        return -1;
    };
    const int g = mesh.face_group.empty() ? -1 : find(mesh.group_names);
    const int m = mesh.face_material.empty() ? -1 : find(mesh.material_names);
    if (g < 0 && m < 0) {
        std::string names;
        for (const auto& n : mesh.group_names)
            names += (names.empty() ? "" : ", ") + n;
        for (const auto& n : mesh.material_names)
            names += (names.empty() ? "" : ", ") + n;
        fail(source, ": scalp by group: no face group or material named '", excerpt(spec.group),
             "' (the mesh has: ", names.empty() ? std::string("none") : excerpt(names, 200), ")");
    }
    std::vector<uint32_t> faces;
    for (size_t f = 0; f < mesh.faces.size(); ++f)
        if ((g >= 0 && mesh.face_group[f] == g) || (m >= 0 && mesh.face_material[f] == m))
            faces.push_back(static_cast<uint32_t>(f));
    return faces;
}

std::vector<uint32_t> select_by_mask(const Mesh& mesh, const ScalpSpec& spec,
                                     const std::string& source) {
    if (mesh.uvs.empty() || mesh.face_uvs.size() != mesh.faces.size())
        fail(source, ": scalp by mask ", spec.mask.string(),
             ": the mesh has no texture coordinates (vt) to look the mask up with");
    const GrayImage mask = read_gray_image(spec.mask);
    std::vector<uint32_t> faces;
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const Vec3i& t = mesh.face_uvs[f];
        const Vec2f uv = (mesh.uvs[t[0]] + mesh.uvs[t[1]] + mesh.uvs[t[2]]) / 3.f;
        if (mask.sample(uv.x(), uv.y()) > 0.5f) faces.push_back(static_cast<uint32_t>(f));
    }
    return faces;
}

// Connected components of the faces (sharing a vertex), by union-find over vertices.
struct DisjointSets {
    std::vector<uint32_t> parent;
    explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t find(uint32_t x) {
        while (parent[x] != x)
            x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

// The hairline cap, on any head with no preparation:
//  1. the head is the connected piece of largest area (skips eyes, teeth, helper shells and
//     joint markers of full-body meshes); its highest point is the top of the head;
//  2. its horizontal centre and extent come from the band 0.5..8 cm below the top (the
//     cranium, above the ears and the face);
//  3. a face is a candidate if its centroid is above the hairline (depth below the top,
//     interpolated by azimuth from front to side to back), inside the cranium's horizontal
//     ellipse grown by 8% (the ears stick out further), and its normal faces outward from the
//     head (not down, not into the head: excludes ear backs and the underside of overhangs);
//  4. the scalp is the candidates connected to the topmost one.
std::vector<uint32_t> select_by_hairline(const Mesh& mesh, const ScalpSpec& spec) {
    const size_t nv = mesh.vertices.size(), nf = mesh.faces.size();
    DisjointSets sets(nv);
    for (const Vec3i& t : mesh.faces) {
        sets.unite(t[0], t[1]);
        sets.unite(t[0], t[2]);
    }
    std::vector<double> area(nv, 0.0);
    for (size_t f = 0; f < nf; ++f)
        area[sets.find(mesh.faces[f][0])] += mesh.face_area(f);
    const uint32_t head =
        static_cast<uint32_t>(std::max_element(area.begin(), area.end()) - area.begin());
    std::vector<char> in_head(nv);
    float top = -INFINITY;
    for (size_t v = 0; v < nv; ++v) {
        in_head[v] = sets.find(static_cast<uint32_t>(v)) == head;
        if (in_head[v]) top = std::max(top, mesh.vertices[v].y());
    }

    Box3 band;
    for (size_t v = 0; v < nv; ++v) {
        const Vec3f& p = mesh.vertices[v];
        if (in_head[v] && p.y() <= top - 0.5f && p.y() >= top - 8.f) band.extend(p);
    }
    if (band.empty()) return {};
    const float cx = band.center().x(), cz = band.center().z();
    const float ax = std::max(0.5f * band.size().x(), 1e-3f) * 1.08f;
    const float az = std::max(0.5f * band.size().z(), 1e-3f) * 1.08f;
    // A centre of the cranium for "outward": on the axis, about a head radius below the top.
    const Vec3f centre(cx, top - std::max(ax, az), cz);

    auto depth = [&](float phi) {  // phi = 0 front (+Z), ±π back
        const float a = std::abs(phi);
        const float h = 0.5f * kPi;
        if (a <= h) {
            const float w = 0.5f - 0.5f * std::cos(kPi * a / h);
            return spec.hairline_front + (spec.hairline_side - spec.hairline_front) * w;
        }
        // Behind the ear the hairline drops steeply to the nape, which runs nearly level
        // across the back of the neck.
        const float w = smoothstep(h, 1.5f * h, a);
        return spec.hairline_side + (spec.hairline_back - spec.hairline_side) * w;
    };

    std::vector<char> candidate(nf, 0);
    size_t top_face = nf;
    float top_y = -INFINITY;
    for (size_t f = 0; f < nf; ++f) {
        if (!in_head[mesh.faces[f][0]]) continue;
        const Vec3f c = face_centroid(mesh, f);
        const float dx = (c.x() - cx) / ax, dz = (c.z() - cz) / az;
        if (dx * dx + dz * dz > 1.f) continue;
        if (c.y() < top - depth(std::atan2(c.x() - cx, c.z() - cz))) continue;
        candidate[f] = 3;  // within the hairline; a candidate if it faces out
        const Vec3f n = mesh.face_normal(f);
        if (n.y() < -0.5f || n.dot((c - centre).normalized()) < 0.2f) continue;
        candidate[f] = 1;
        if (c.y() > top_y) top_y = c.y(), top_face = f;
    }
    if (top_face == nf) return {};

    // Flood fill over faces sharing a vertex, from the topmost candidate.
    const VertexLists around = vertex_faces(mesh);
    const std::vector<uint32_t>& start = around.first;
    const std::vector<uint32_t>& incident = around.items;
    std::vector<uint32_t> faces, stack{static_cast<uint32_t>(top_face)};
    candidate[top_face] = 2;
    while (!stack.empty()) {
        const uint32_t f = stack.back();
        stack.pop_back();
        faces.push_back(f);
        for (int k = 0; k < 3; ++k) {
            const int v = mesh.faces[f][k];
            for (uint32_t a = start[v]; a < start[v + 1]; ++a)
                if (candidate[incident[a]] == 1) {
                    candidate[incident[a]] = 2;
                    stack.push_back(incident[a]);
                }
        }
    }
    // Close slots and pinholes: a face within the hairline whose three corners all lie on
    // selected faces is taken too, however it faces. The per-face test leaves out single faces
    // in a groove (the furrow at the nape's centre, where the normals turn down): an edge
    // inside the scalp, whose density ramp shows as a bald spot. Two passes close slots two
    // faces wide.
    std::vector<char> on_scalp(nv, 0);
    for (int pass = 0; pass < 2; ++pass) {
        for (uint32_t f : faces)
            for (int k = 0; k < 3; ++k)
                on_scalp[mesh.faces[f][k]] = 1;
        const size_t before = faces.size();
        for (size_t f = 0; f < nf; ++f) {
            const Vec3i& t = mesh.faces[f];
            if (candidate[f] != 3 && candidate[f] != 1) continue;
            if (on_scalp[t[0]] && on_scalp[t[1]] && on_scalp[t[2]]) {
                candidate[f] = 2;
                faces.push_back(static_cast<uint32_t>(f));
            }
        }
        if (faces.size() == before) break;
    }
    std::sort(faces.begin(), faces.end());
    return faces;
}

const char* kind_name(ScalpSpec::Kind k) {
    switch (k) {
        case ScalpSpec::Kind::kGroup:
            return "group";
        case ScalpSpec::Kind::kMask:
            return "mask";
        case ScalpSpec::Kind::kHairline:
            return "hairline";
    }
    return "?";
}

// Least-squares sphere through points: |p|² = 2 p·c + (r² - |c|²), solved in double around
// the points' mean. Returns false when the points are (nearly) coplanar.
bool fit_sphere(const std::vector<Vec3f>& pts, Vec3f& centre, float& radius) {
    if (pts.size() < 4) return false;
    Vec3d mean = Vec3d::Zero();
    for (const Vec3f& p : pts)
        mean += p.cast<double>();
    mean /= static_cast<double>(pts.size());
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    Eigen::Vector4d b = Eigen::Vector4d::Zero();
    for (const Vec3f& pf : pts) {
        const Vec3d p = pf.cast<double>() - mean;
        const Eigen::Vector4d row(2 * p.x(), 2 * p.y(), 2 * p.z(), 1.0);
        A += row * row.transpose();
        b += row * p.squaredNorm();
    }
    const Eigen::Vector4d x = A.ldlt().solve(b);
    const Vec3d c = x.head<3>();
    const double r2 = x[3] + c.squaredNorm();
    if (!x.allFinite() || r2 <= 0) return false;
    centre = (c + mean).cast<float>();
    radius = static_cast<float>(std::sqrt(r2));
    return true;
}

// Möller-Trumbore: distance t along the unit ray o + t·d to the triangle, or -1.
float ray_triangle(const Vec3f& o, const Vec3f& d, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const Vec3f e1 = b - a, e2 = c - a, pv = d.cross(e2);
    const float det = e1.dot(pv);
    if (std::abs(det) < 1e-12f) return -1.f;
    const Vec3f tv = o - a;
    const float u = tv.dot(pv) / det;
    if (u < 0.f || u > 1.f) return -1.f;
    const Vec3f qv = tv.cross(e1);
    const float v = d.dot(qv) / det;
    if (v < 0.f || u + v > 1.f) return -1.f;
    return e2.dot(qv) / det;
}

// edge_distance at every vertex of `faces` (kNoEdge at the others): the distance to the
// nearest of points spaced at most 0.2 cm along the scalp's edges.
std::vector<float> scalp_edge_distance(const Mesh& mesh, const std::vector<uint32_t>& faces) {
    // Vertices at one position are one: a seam in the mesh's UVs or normals is not an edge.
    std::vector<uint32_t> weld(mesh.vertices.size());
    {
        std::vector<uint32_t> order(mesh.vertices.size());
        for (uint32_t v = 0; v < order.size(); ++v)
            order[v] = v;
        const auto key = [&](uint32_t v) {
            const Vec3f& p = mesh.vertices[v];
            return std::array<float, 3>{p.x(), p.y(), p.z()};
        };
        std::stable_sort(order.begin(), order.end(),
                         [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
        for (size_t i = 0; i < order.size(); ++i)
            weld[order[i]] =
                i > 0 && key(order[i]) == key(order[i - 1]) ? weld[order[i - 1]] : order[i];
    }
    // An edge of the scalp is one that a single scalp face has (counted over welded ends);
    // edges shared with non-scalp faces count once here too.
    std::vector<std::pair<uint64_t, uint32_t>> edges;  // (welded key, a vertex of the edge)
    edges.reserve(faces.size() * 3);
    for (uint32_t f : faces) {
        const Vec3i& t = mesh.faces[f];
        for (int k = 0; k < 3; ++k) {
            uint32_t a = weld[static_cast<uint32_t>(t[k])];
            uint32_t b = weld[static_cast<uint32_t>(t[(k + 1) % 3])];
            if (a == b) continue;
            if (a > b) std::swap(a, b);
            edges.emplace_back(uint64_t{a} << 32 | b, 0u);
        }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<Vec3f> samples;
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j].first == edges[i].first)
            ++j;
        if (j - i == 1) {
            const Vec3f a = mesh.vertices[edges[i].first >> 32];
            const Vec3f b = mesh.vertices[edges[i].first & 0xffffffffu];
            const int pieces =
                std::clamp(static_cast<int>(std::ceil((b - a).norm() / 0.2f)), 1, 1000);
            for (int k = 0; k < pieces; ++k)
                samples.push_back(a +
                                  (static_cast<float>(k) / static_cast<float>(pieces)) * (b - a));
            samples.push_back(b);
        }
        i = j;
    }
    std::vector<float> out(mesh.vertices.size(), Scalp::kNoEdge);
    if (samples.empty()) return out;
    const PointGrid grid(samples, 1.f);
    for (uint32_t f : faces)
        for (int k = 0; k < 3; ++k) {
            const auto v = static_cast<size_t>(mesh.faces[f][k]);
            if (out[v] != Scalp::kNoEdge) continue;
            const int near = grid.nearest(mesh.vertices[v]);
            out[v] = (mesh.vertices[v] - samples[static_cast<size_t>(near)]).norm();
        }
    return out;
}

}  // namespace

Scalp::Scalp(const Mesh& mesh, const ScalpSpec& spec, const std::string& source, size_t head_faces)
    : mesh_(&mesh) {
    if (mesh.faces.empty()) fail(source, ": the mesh has no faces, so no scalp");
    // A body appended after the head (Head::first_body_face) never grows hair: the selection
    // sees the head's faces alone, whose indices are the whole mesh's.
    Mesh head_part;
    const Mesh* select_from = &mesh;
    if (head_faces < mesh.faces.size()) {
        const auto first = [&](const auto& v) {
            using V = std::decay_t<decltype(v)>;
            return v.size() > head_faces ? V(v.begin(), v.begin() + head_faces) : v;
        };
        head_part.vertices = mesh.vertices;
        head_part.faces = first(mesh.faces);
        head_part.uvs = mesh.uvs;
        head_part.face_uvs = first(mesh.face_uvs);
        head_part.face_group = first(mesh.face_group);
        head_part.group_names = mesh.group_names;
        head_part.face_material = first(mesh.face_material);
        head_part.material_names = mesh.material_names;
        select_from = &head_part;
    }
    switch (spec.kind) {
        case ScalpSpec::Kind::kGroup:
            faces_ = select_by_group(*select_from, spec, source);
            break;
        case ScalpSpec::Kind::kMask:
            faces_ = select_by_mask(*select_from, spec, source);
            break;
        case ScalpSpec::Kind::kHairline:
            faces_ = select_by_hairline(*select_from, spec);
            break;
    }
    // Degenerate faces can never be sampled; dropping them keeps the CDF strictly increasing.
    std::erase_if(faces_, [&](uint32_t f) { return !(mesh.face_area(f) > 0.f); });
    if (faces_.empty()) {
        std::string how = kind_name(spec.kind);
        if (spec.kind == ScalpSpec::Kind::kGroup) how += cat(" '", spec.group, "'");
        if (spec.kind == ScalpSpec::Kind::kMask) how += cat(" ", spec.mask.string());
        if (spec.kind == ScalpSpec::Kind::kHairline)
            how += cat(" (front ", spec.hairline_front, " cm, side ", spec.hairline_side,
                       " cm, back ", spec.hairline_back, " cm)");
        fail(source, ": the scalp selected by ", how, " is empty");
    }

    vertex_normals_ = skin_normals(mesh);
    edge_distance_ = scalp_edge_distance(mesh, faces_);

    double total = 0.0;
    cdf_.resize(faces_.size());
    std::vector<double> acc(faces_.size());
    for (size_t i = 0; i < faces_.size(); ++i)
        acc[i] = total += mesh.face_area(faces_[i]);
    for (size_t i = 0; i < faces_.size(); ++i)
        cdf_[i] = static_cast<float>(acc[i] / total);
    cdf_.back() = 1.f;
    area_ = static_cast<float>(total);
    // guide_[b]: the face that u = b / #buckets draws, one bucket per face.
    guide_.resize(cdf_.size() + 1);
    for (size_t b = 0; b < guide_.size(); ++b)
        guide_[b] = static_cast<uint32_t>(
            std::upper_bound(cdf_.begin(), cdf_.end(),
                             static_cast<float>(b) / static_cast<float>(cdf_.size())) -
            cdf_.begin());

    // Centre: sphere fit of the scalp's vertices; a flat or tiny patch falls back to a point
    // below its bounding box centre.
    std::vector<char> used(mesh.vertices.size(), 0);
    std::vector<Vec3f> pts;
    Box3 box;
    for (uint32_t f : faces_)
        for (int k = 0; k < 3; ++k)
            if (!used[mesh.faces[f][k]]) {
                used[mesh.faces[f][k]] = 1;
                pts.push_back(mesh.vertices[mesh.faces[f][k]]);
                box.extend(pts.back());
            }
    float radius = 0.f;
    const float extent = box.size().norm();
    if (!fit_sphere(pts, center_, radius) || radius > 2.f * extent ||
        (center_ - box.center()).norm() > extent) {
        center_ = box.center() - Vec3f(0.f, 0.5f * std::max(box.size().x(), box.size().z()), 0.f);
    }

    // Crown: where the vertical through the centre leaves the scalp (the highest hit).
    float best = -1.f;
    for (uint32_t f : faces_) {
        const Vec3i& t = mesh.faces[f];
        const float h = ray_triangle(center_, Vec3f::UnitY(), mesh.vertices[t[0]],
                                     mesh.vertices[t[1]], mesh.vertices[t[2]]);
        best = std::max(best, h);
    }
    if (best > 0.f) {
        crown_ = center_ + best * Vec3f::UnitY();
    } else {  // the vertical misses the scalp: take the vertex closest to it in angle
        float min_angle = INFINITY;
        for (const Vec3f& p : pts) {
            const Vec3f d = p - center_;
            const float a = std::atan2(std::hypot(d.x(), d.z()), d.y());
            if (a < min_angle) min_angle = a, crown_ = p;
        }
    }

    max_polar_angle_ = 1e-3f;
    for (const Vec3f& p : pts) {
        const Vec3f d = p - center_;
        max_polar_angle_ = std::max(max_polar_angle_, std::atan2(std::hypot(d.x(), d.z()), d.y()));
    }
}

size_t Scalp::face_slot(float u) const {
    // The first slot whose cumulative area exceeds u. u's bucket narrows the binary search to
    // the slots between its guides (one or two, mostly): that is the answer when the slot
    // below the range is ≤ u and the one past it > u, checked here, so that the rounding of
    // u · #buckets cannot change the face; else the whole table is searched.
    const size_t n = cdf_.size();
    const size_t b = std::min(static_cast<size_t>(u * static_cast<float>(n)), n - 1);
    const size_t lo = guide_[b], hi = guide_[b + 1];
    auto first = cdf_.begin(), last = cdf_.end();
    if ((lo == 0 || cdf_[lo - 1] <= u) && (hi >= n || cdf_[hi] > u)) {
        first = cdf_.begin() + static_cast<std::ptrdiff_t>(lo);
        last = cdf_.begin() + static_cast<std::ptrdiff_t>(std::min(hi, n));
    }
    return std::min<size_t>(std::upper_bound(first, last, u) - cdf_.begin(), n - 1);
}

SurfacePoint Scalp::sample(Rng& rng) const {
    const float u = rng.uniform();
    const size_t i = face_slot(u);
    // Uniform on the triangle: b0 = 1 - √r1, b1 = √r1 (1 - r2), b2 = √r1 r2.
    const float s = std::sqrt(rng.uniform()), r2 = rng.uniform();
    return point_on(faces_[i], Vec2f(s * (1.f - r2), s * r2));
}

SurfacePoint Scalp::point_on(uint32_t face, const Vec2f& bary) const {
    const Vec3i& t = mesh_->faces[face];
    const float b0 = 1.f - bary.x() - bary.y();
    SurfacePoint sp;
    sp.face = face;
    sp.bary = bary;
    sp.position = b0 * mesh_->vertices[t[0]] + bary.x() * mesh_->vertices[t[1]] +
                  bary.y() * mesh_->vertices[t[2]];
    const Vec3f n = b0 * vertex_normals_[t[0]] + bary.x() * vertex_normals_[t[1]] +
                    bary.y() * vertex_normals_[t[2]];
    const float len = n.norm();
    sp.normal = len > 1e-6f ? Vec3f(n / len) : mesh_->face_normal(face);
    if (sp.normal.isZero()) sp.normal = Vec3f::UnitY();
    sp.uv = uv_of(sp.position);
    return sp;
}

float Scalp::edge_distance(const SurfacePoint& p) const {
    const Vec3i& t = mesh_->faces[p.face];
    const float b0 = 1.f - p.bary.x() - p.bary.y();
    return b0 * edge_distance_[t[0]] + p.bary.x() * edge_distance_[t[1]] +
           p.bary.y() * edge_distance_[t[2]];
}

float Scalp::edge_distance(uint32_t face, const Vec3f& q) const {
    const Vec3i& t = mesh_->faces[face];
    const Vec3f a = mesh_->vertices[t[0]], e1 = mesh_->vertices[t[1]] - a,
                e2 = mesh_->vertices[t[2]] - a, d = q - a;
    const float d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2);
    const float det = d11 * d22 - d12 * d12;
    SurfacePoint p;
    p.face = face;
    if (std::abs(det) > 0.f) {
        const float b1 = std::clamp((d22 * d.dot(e1) - d12 * d.dot(e2)) / det, 0.f, 1.f);
        const float b2 = std::clamp((d11 * d.dot(e2) - d12 * d.dot(e1)) / det, 0.f, 1.f - b1);
        p.bary = Vec2f(b1, b2);
    } else {
        p.bary = Vec2f(1.f / 3, 1.f / 3);
    }
    return edge_distance(p);
}

Vec2f Scalp::uv_of(const Vec3f& p) const {
    const Vec3f d = p - center_;
    const float h = std::hypot(d.x(), d.z());
    if (h < 1e-9f) return {0.5f, d.y() >= 0.f ? 0.5f : 1.f};
    const float r = 0.5f * std::min(std::atan2(h, d.y()) / max_polar_angle_, 1.f);
    return {0.5f - r * d.x() / h, 0.5f + r * d.z() / h};
}

}  // namespace wisp
