#include "geometry/builtin_head.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/parallel.hpp"

namespace wisp {
namespace {

// ---- The implicit head: a smooth union of ellipsoids and capsules. Values are approximate
// signed distances in cm (negative inside), accurate near the surface.

float smin(float a, float b, float k) {  // polynomial smooth minimum, blend width k
    const float h = std::max(k - std::abs(a - b), 0.f) / k;
    return std::min(a, b) - h * h * k * 0.25f;
}
float smax(float a, float b, float k) {
    return -smin(-a, -b, k);
}

// Ellipsoid bound (Quilez): exact on the surface, good nearby.
float ellipsoid(const Vec3f& p, const Vec3f& c, const Vec3f& r) {
    const Vec3f q = p - c;
    const float k0 = q.cwiseQuotient(r).norm();
    const float k1 = q.cwiseQuotient(r.cwiseProduct(r)).norm();
    return k1 > 1e-12f ? k0 * (k0 - 1.f) / k1 : -r.minCoeff();
}

const Vec3f kEarCentre(7.3f, -0.2f, -0.9f);
const Vec3f kEarRadii(0.9f, 2.9f, 1.8f);

float capsule(const Vec3f& p, const Vec3f& a, const Vec3f& b, float r) {
    const Vec3f pa = p - a, ba = b - a;
    const float h = std::clamp(pa.dot(ba) / ba.squaredNorm(), 0.f, 1.f);
    return (pa - h * ba).norm() - r;
}

// Head space: origin between the ears (ear-canal height, mid-depth), Y up, +Z forward.
// Each part is blended in only where it can change the result: a part whose bounding sphere
// is further than the blend width from the current value is skipped, which keeps the field
// cheap away from its own parts (the union is exact there, smin(a, b, k) = a for b >= a + k).
float head_field(const Vec3f& p) {
    const Vec3f m(std::abs(p.x()), p.y(), p.z());  // mirror: the head is symmetric in x
    auto near = [](const Vec3f& q, const Vec3f& c, float radius, float bound) {
        return (q - c).squaredNorm() < (radius + bound) * (radius + bound);
    };
    float d = 1e3f;
    auto add = [&](const Vec3f& q, const Vec3f& c, float radius, float k, auto&& part) {
        if (d > 1e2f || near(q, c, radius, d + k + 0.5f)) d = smin(d, part(), k);
    };
    auto carve = [&](const Vec3f& q, const Vec3f& c, float radius, float k, auto&& part) {
        if (near(q, c, radius, k - d + 0.5f)) d = smax(d, -part(), k);
    };

    // Chest and back, cut flat at the bottom.
    add(p, {0.f, -32.f, -0.6f}, 16.f, 5.f, [&] {
        return smax(ellipsoid(p, {0.f, -32.f, -0.6f}, {16.f, 11.5f, 10.f}), -38.f - p.y(), 1.5f);
    });
    // Shoulders' trapezius slope and the neck, slightly forward-leaning.
    add(m, {8.f, -23.75f, -1.5f}, 11.5f, 5.f, [&] {
        return capsule(m, {1.5f, -22.5f, -1.5f}, {14.5f, -25.0f, -1.5f}, 4.8f);
    });
    add(p, {0.f, -12.5f, -1.2f}, 14.f, 2.f, [&] {
        return capsule(p, {0.f, -4.f, -1.6f}, {0.f, -21.f, -0.8f}, 5.6f);
    });
    // Cranium: longer than wide, fuller at the back (occiput) than at the forehead.
    add(p, {0.f, 2.6f, -1.0f}, 9.4f, 2.f, [&] {
        return ellipsoid(p, {0.f, 2.6f, -1.0f}, {7.5f, 9.4f, 9.3f});
    });
    add(p, {0.f, 1.6f, -3.6f}, 8.f, 2.f, [&] {
        return ellipsoid(p, {0.f, 1.6f, -3.6f}, {7.3f, 8.0f, 7.3f});
    });
    // Face: forehead down to the jaw, narrowing toward the chin.
    add(p, {0.f, -1.4f, 2.6f}, 8.2f, 2.5f, [&] {
        const float taper = 1.f + 0.45f * std::clamp((-p.y() - 1.f) / 9.f, 0.f, 1.f);
        const Vec3f pf(p.x() * taper, p.y(), p.z());
        return ellipsoid(pf, {0.f, -1.4f, 2.6f}, {6.6f, 8.2f, 6.2f});
    });
    // Chin and jaw angles.
    add(p, {0.f, -8.3f, 6.2f}, 2.7f, 1.5f, [&] {
        return ellipsoid(p, {0.f, -8.3f, 6.2f}, {2.7f, 1.9f, 2.3f});
    });
    add(m, {4.6f, -5.6f, 1.2f}, 3.2f, 2.f, [&] {
        return ellipsoid(m, {4.6f, -5.6f, 1.2f}, {1.7f, 2.2f, 3.2f});
    });
    // Cheekbones and brow.
    add(m, {4.3f, -0.8f, 5.6f}, 2.f, 1.5f, [&] {
        return ellipsoid(m, {4.3f, -0.8f, 5.6f}, {2.0f, 1.4f, 2.0f});
    });
    add(p, {0.f, 2.6f, 7.6f}, 5.2f, 1.5f, [&] {
        return ellipsoid(p, {0.f, 2.6f, 7.6f}, {5.2f, 1.4f, 1.5f});
    });
    // Eye sockets, shallow so the surface stays a sphere topologically.
    carve(m, {3.1f, 1.1f, 9.5f}, 1.5f, 1.f, [&] {
        return ellipsoid(m, {3.1f, 1.1f, 9.5f}, {1.5f, 1.0f, 1.2f});
    });
    // Nose: bridge and tip with nostrils.
    add(p, {0.f, -0.3f, 9.6f}, 3.0f, 1.2f, [&] {
        return capsule(p, {0.f, 1.6f, 8.6f}, {0.f, -2.2f, 10.6f}, 0.75f);
    });
    add(p, {0.f, -2.5f, 9.7f}, 1.6f, 0.8f, [&] {
        return ellipsoid(p, {0.f, -2.5f, 9.7f}, {1.6f, 0.9f, 1.2f});
    });
    // Lips.
    add(p, {0.f, -5.0f, 8.4f}, 2.4f, 0.8f, [&] {
        return ellipsoid(p, {0.f, -5.0f, 8.4f}, {2.4f, 1.1f, 1.0f});
    });
    // Ears.
    add(m, kEarCentre, kEarRadii.maxCoeff(), 0.8f,
        [&] { return ellipsoid(m, kEarCentre, kEarRadii); });
    return d;
}

Vec3f field_gradient(const Vec3f& p, float f0) {
    constexpr float h = 0.02f;
    return Vec3f(head_field(p + Vec3f(h, 0, 0)) - f0, head_field(p + Vec3f(0, h, 0)) - f0,
                 head_field(p + Vec3f(0, 0, h)) - f0) /
           h;
}

// Moves p onto the zero set with Newton steps along the gradient.
Vec3f project_to_surface(Vec3f p) {
    for (int it = 0; it < 1; ++it) {
        const float f = head_field(p);
        const Vec3f g = field_gradient(p, f);
        const float g2 = g.squaredNorm();
        if (g2 < 1e-8f) break;
        p -= (f / g2) * g;
    }
    return p;
}

// ---- Marching tetrahedra on the Freudenthal (Kuhn) split of the grid: every cube is cut into
// six tetrahedra along its main diagonal, consistently across neighbours, so the piecewise
// linear zero set is a closed 2-manifold whenever no node value is exactly zero (no table
// ambiguities, unlike marching cubes).

constexpr float kCell = 0.75f;                     // cm
const Vec3f kLo(-30 * kCell, -40.f, -18 * kCell);  // x symmetric about the midline
const Vec3f kHi(30 * kCell, 13.5f, 18 * kCell);

// Corner c of a cube: bit 0 = +x, bit 1 = +y, bit 2 = +z. Tetrahedra 0-a-b-7.
constexpr int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                             {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

Mesh polygonize() {
    const Vec3i dims = ((kHi - kLo) / kCell).array().ceil().cast<int>() + 1;
    const int nx = dims.x(), ny = dims.y(), nz = dims.z();
    const size_t nodes = static_cast<size_t>(nx) * ny * nz;
    std::vector<float> value(nodes);
    parallel_for(static_cast<size_t>(nz), [&](size_t k) {
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i) {
                float f = head_field(kLo + kCell * Vec3f(i, j, static_cast<float>(k)));
                if (f == 0.f) f = 1e-6f;  // keep the zero set off the nodes
                value[(k * ny + j) * nx + i] = f;
            }
    });
    auto node = [&](int i, int j, int k) { return (static_cast<size_t>(k) * ny + j) * nx + i; };

    Mesh mesh;
    std::vector<int32_t> edge_vertex(nodes * 8, -1);  // (node, direction bits) -> vertex
    const size_t corner_offset[8] = {0,
                                     1,
                                     static_cast<size_t>(nx),
                                     static_cast<size_t>(nx) + 1,
                                     static_cast<size_t>(nx) * ny,
                                     static_cast<size_t>(nx) * ny + 1,
                                     static_cast<size_t>(nx) * ny + nx,
                                     static_cast<size_t>(nx) * ny + nx + 1};
    auto edge_point = [&](size_t base, int cu, int cv) -> int32_t {
        // cu ⊂ cv bitwise, so the edge runs from node base+off[cu] in direction cv ^ cu.
        const size_t a = base + corner_offset[cu], b = base + corner_offset[cv];
        int32_t& slot = edge_vertex[a * 8 + (cv ^ cu)];
        if (slot < 0) {
            const float fa = value[a], fb = value[b];
            const float t = fa / (fa - fb);
            auto pos = [&](size_t n) {
                const size_t i = n % nx, j = (n / nx) % ny, k = n / (static_cast<size_t>(nx) * ny);
                return Vec3f(kLo + kCell * Vec3f(i, j, k));
            };
            slot = static_cast<int32_t>(mesh.vertices.size());
            mesh.vertices.push_back(pos(a) + t * (pos(b) - pos(a)));
        }
        return slot;
    };
    auto emit = [&](int32_t a, int32_t b, int32_t c, const Vec3f& outward) {
        const Vec3f n =
            (mesh.vertices[b] - mesh.vertices[a]).cross(mesh.vertices[c] - mesh.vertices[a]);
        if (n.dot(outward) >= 0.f)
            mesh.faces.emplace_back(a, b, c);
        else
            mesh.faces.emplace_back(a, c, b);
    };

    for (int k = 0; k + 1 < nz; ++k)
        for (int j = 0; j + 1 < ny; ++j)
            for (int i = 0; i + 1 < nx; ++i) {
                const size_t base = node(i, j, k);
                float v[8];
                int inside = 0;
                for (int c = 0; c < 8; ++c) {
                    v[c] = value[base + corner_offset[c]];
                    inside += v[c] < 0.f;
                }
                if (inside == 0 || inside == 8) continue;
                const Vec3f origin = kLo + kCell * Vec3f(i, j, k);
                auto corner_pos = [&](int c) {
                    return Vec3f(origin + kCell * Vec3f(c & 1, (c >> 1) & 1, (c >> 2) & 1));
                };
                for (const auto& tet : kTets) {
                    int in[4], out[4], ni = 0, no = 0;
                    for (int c : tet)
                        (v[c] < 0.f ? in[ni++] : out[no++]) = c;
                    if (ni == 0 || ni == 4) continue;
                    Vec3f cin = Vec3f::Zero(), cout = Vec3f::Zero();
                    for (int q = 0; q < ni; ++q)
                        cin += corner_pos(in[q]) / ni;
                    for (int q = 0; q < no; ++q)
                        cout += corner_pos(out[q]) / no;
                    const Vec3f outward = cout - cin;
                    auto ep = [&](int c0, int c1) {
                        return c0 < c1 ? edge_point(base, c0, c1) : edge_point(base, c1, c0);
                    };
                    if (ni == 1 || no == 1) {
                        const int apex = ni == 1 ? in[0] : out[0];
                        const int* rest = ni == 1 ? out : in;
                        emit(ep(apex, rest[0]), ep(apex, rest[1]), ep(apex, rest[2]), outward);
                    } else {  // a quad across the tetrahedron: in0-out0, in0-out1, in1-out1,
                              // in1-out0
                        const int32_t q0 = ep(in[0], out[0]), q1 = ep(in[0], out[1]),
                                      q2 = ep(in[1], out[1]), q3 = ep(in[1], out[0]);
                        emit(q0, q1, q2, outward);
                        emit(q0, q2, q3, outward);
                    }
                }
            }
    return mesh;
}

// Uniform Laplacian smoothing followed by projection back onto the implicit surface: evens out
// the slivers of marching tetrahedra without changing the connectivity.
void relax(Mesh& mesh, int iterations) {
    const size_t nv = mesh.vertices.size();
    // Vertex neighbours in CSR form from the (directed) triangle edges; each undirected edge
    // appears once per direction in a closed manifold, so neighbours are listed once.
    std::vector<uint32_t> start(nv + 1, 0), adj(mesh.faces.size() * 3);
    for (const Vec3i& t : mesh.faces)
        for (int e = 0; e < 3; ++e)
            ++start[t[e] + 1];
    for (size_t i = 0; i < nv; ++i)
        start[i + 1] += start[i];
    std::vector<uint32_t> fill(start.begin(), start.end() - 1);
    for (const Vec3i& t : mesh.faces)
        for (int e = 0; e < 3; ++e)
            adj[fill[t[e]]++] = t[(e + 1) % 3];

    std::vector<Vec3f> next(nv);
    for (int it = 0; it < iterations; ++it) {
        parallel_for(
            nv,
            [&](size_t v) {
                Vec3f c = Vec3f::Zero();
                for (uint32_t a = start[v]; a < start[v + 1]; ++a)
                    c += mesh.vertices[adj[a]];
                const uint32_t n = start[v + 1] - start[v];
                const Vec3f p =
                    n ? Vec3f(0.5f * mesh.vertices[v] + 0.5f * c / n) : mesh.vertices[v];
                next[v] = project_to_surface(p);
            },
            256);
        mesh.vertices.swap(next);
    }
}

// The hairline of the built-in head: the height (y, cm) of the hairline at azimuth phi around
// the head (0 = front, ±π = back), as a periodic smooth curve through key points. It dips at the
// sideburns, rises over the ears and falls to the nape.
float hairline_height(float phi) {
    struct Key {
        float deg, y;
    };
    static constexpr Key kKeys[] = {{0.f, 5.4f},    {30.f, 5.0f},  {50.f, 3.6f},  {62.f, -0.6f},
                                    {72.f, 1.6f},   {90.f, 3.0f},  {108.f, 1.6f}, {125.f, -1.8f},
                                    {150.f, -3.6f}, {180.f, -4.2f}};
    const float a = std::min(std::abs(phi) * 180.f / kPi, 180.f);
    for (size_t i = 0; i + 1 < std::size(kKeys); ++i) {
        if (a <= kKeys[i + 1].deg) {
            const float t = (a - kKeys[i].deg) / (kKeys[i + 1].deg - kKeys[i].deg);
            const float s = t * t * (3.f - 2.f * t);
            return kKeys[i].y + (kKeys[i + 1].y - kKeys[i].y) * s;
        }
    }
    return kKeys[std::size(kKeys) - 1].y;
}

}  // namespace

Mesh builtin_head_mesh() {
    Mesh mesh = polygonize();
    relax(mesh, 2);

    // Groups: the scalp is above the hairline and off the ears.
    mesh.group_names = {"scalp", "body"};
    mesh.face_group.resize(mesh.faces.size());
    const Vec3f axis(0.f, 0.f, -1.0f);  // the vertical axis of the cranium passes (x, z) = (0, -1)
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const Vec3i& t = mesh.faces[f];
        const Vec3f c = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]) / 3.f;
        const float phi = std::atan2(c.x() - axis.x(), c.z() - axis.z());
        const Vec3f m(std::abs(c.x()), c.y(), c.z());
        const bool ear = ellipsoid(m, kEarCentre, kEarRadii) < 0.5f;
        const bool scalp = c.y() > hairline_height(phi) && !ear && c.y() > -8.f;
        mesh.face_group[f] = scalp ? 0 : 1;
    }

    // UVs: the polar map around the cranium centre (crown at (0.5, 0.5), front toward v = 1,
    // +X toward u = 1, radius = polar angle / π · 0.5), one UV per vertex.
    const Vec3f centre(0.f, 2.f, -1.f);
    mesh.uvs.resize(mesh.vertices.size());
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
        const Vec3f d = mesh.vertices[v] - centre;
        const float h = std::hypot(d.x(), d.z());
        const float r = 0.5f * std::atan2(h, d.y()) / kPi;
        mesh.uvs[v] = h > 1e-6f ? Vec2f(0.5f + r * d.x() / h, 0.5f + r * d.z() / h)
                                : Vec2f(0.5f, d.y() > 0 ? 0.5f : 1.f);
    }
    mesh.face_uvs = mesh.faces;
    // The few faces around the map's pole (straight down, under the chest) span every azimuth,
    // so their UV centroid would land near the crown; they get one UV on the rim instead.
    const int pole = static_cast<int>(mesh.uvs.size());
    mesh.uvs.emplace_back(0.5f, 0.f);
    const Vec2f mid(0.5f, 0.5f);
    for (Vec3i& t : mesh.face_uvs) {
        const Vec2f c = (mesh.uvs[t[0]] + mesh.uvs[t[1]] + mesh.uvs[t[2]]) / 3.f;
        float r = INFINITY;
        for (int k = 0; k < 3; ++k)
            r = std::min(r, (mesh.uvs[t[k]] - mid).norm());
        if ((c - mid).norm() < 0.5f * r) t = Vec3i::Constant(pole);
    }
    return mesh;
}

}  // namespace wisp
