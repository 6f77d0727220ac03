#include "geometry/mesh.hpp"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string_view>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/hair.hpp"

namespace wisp {

Box3 Mesh::bounds() const {
    Box3 b;
    for (const Vec3f& p : vertices)
        b.extend(p);
    return b;
}

Vec3f Mesh::face_normal(size_t f) const {
    const Vec3i& t = faces[f];
    const Vec3f n = (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
    const float len = n.norm();
    return len > 0.f ? Vec3f(n / len) : Vec3f::Zero();
}

float Mesh::face_area(size_t f) const {
    const Vec3i& t = faces[f];
    return 0.5f * (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm();
}

namespace {

std::string trimmed(std::string_view s) {
    const size_t b = s.find_first_not_of(" \t\r\n");
    if (b == std::string_view::npos) return {};
    const size_t e = s.find_last_not_of(" \t\r\n");
    return std::string(s.substr(b, e - b + 1));
}

// What tinyobjloader's callbacks build up. The callback API is used (rather than LoadObj)
// because it reports `usemtl` names even when the .mtl file is missing, where LoadObj maps
// every unknown material to -1 and loses its name.
struct ObjBuilder {
    const std::filesystem::path* path;
    const std::vector<int>* face_lines;  // line number of each `f` statement, in order
    float scale = 1.f;
    Mesh mesh;
    int group = -1, material = -1;
    size_t face_statement = 0;
    bool any_uv_face = false, any_plain_face = false;
    std::string error;  // first error; callbacks cannot throw through C code

    int line_of_face() const {
        return face_statement < face_lines->size() ? (*face_lines)[face_statement] : 0;
    }

    static int intern(std::vector<std::string>& names, const std::string& name) {
        for (size_t i = 0; i < names.size(); ++i)
            if (names[i] == name) return static_cast<int>(i);
        names.push_back(name);
        return static_cast<int>(names.size() - 1);
    }

    // Resolves a raw OBJ index (1-based, negative = relative to the end, 0 = missing).
    static int resolve(int raw, size_t count) {
        if (raw > 0) return raw - 1;
        if (raw < 0) return static_cast<int>(count) + raw;
        return -1;
    }

    void face(const tinyobj::index_t* idx, int n) {
        if (!error.empty()) return;
        const int line = line_of_face();
        ++face_statement;
        if (n < 3) {
            error = cat(path->string(), ":", line, ": face has ", n, " vertices, expected >= 3");
            return;
        }
        std::vector<int> v(n), t(n);
        bool has_uv = true;
        for (int i = 0; i < n; ++i) {
            v[i] = resolve(idx[i].vertex_index, mesh.vertices.size());
            if (v[i] < 0 || v[i] >= static_cast<int>(mesh.vertices.size())) {
                error = cat(path->string(), ":", line, ": vertex index ", idx[i].vertex_index,
                            " is out of range (", mesh.vertices.size(), " vertices so far)");
                return;
            }
            if (idx[i].texcoord_index == 0) {
                has_uv = false;
                continue;
            }
            t[i] = resolve(idx[i].texcoord_index, mesh.uvs.size());
            if (t[i] < 0 || t[i] >= static_cast<int>(mesh.uvs.size())) {
                error = cat(path->string(), ":", line, ": texture index ", idx[i].texcoord_index,
                            " is out of range (", mesh.uvs.size(), " texture coordinates so far)");
                return;
            }
        }
        (has_uv ? any_uv_face : any_plain_face) = true;
        for (int i = 1; i + 1 < n; ++i) {  // fan
            mesh.faces.emplace_back(v[0], v[i], v[i + 1]);
            mesh.face_uvs.push_back(has_uv ? Vec3i(t[0], t[i], t[i + 1]) : Vec3i(-1, -1, -1));
            mesh.face_group.push_back(group);
            mesh.face_material.push_back(material);
        }
    }
};

// One pass over the text: the line number of every `f` statement, and non-finite numbers
// in `v`/`vt` lines (tinyobjloader silently reads "nan" as 0).
std::vector<int> scan_obj(const std::string& text, const std::filesystem::path& path) {
    std::vector<int> face_lines;
    int line = 0;
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        ++line;
        std::string_view s(text.data() + pos, end - pos);
        const size_t b = s.find_first_not_of(" \t");
        if (b != std::string_view::npos) {
            s.remove_prefix(b);
            if (s.size() > 1 && s[0] == 'f' && (s[1] == ' ' || s[1] == '\t')) {
                face_lines.push_back(line);
            } else if (s.size() > 1 && s[0] == 'v' && (s[1] == ' ' || s[1] == 't')) {
                if (s.find_first_of("nNiI") != std::string_view::npos)
                    fail(path.string(), ":", line, ": non-finite number in '", excerpt(trimmed(s)),
                         "'");
            }
        }
        pos = end + 1;
    }
    return face_lines;
}

}  // namespace

Mesh read_obj_mesh(const std::filesystem::path& path, float scale) {
    if (!std::isfinite(scale) || scale <= 0.f)
        fail(path.string(), ": scale ", scale, " must be a positive number");
    const std::string text = read_file(path, {kMaxObjMeshBytes, "a head OBJ file", true});
    const std::vector<int> face_lines = scan_obj(text, path);

    ObjBuilder b;
    b.path = &path;
    b.face_lines = &face_lines;
    b.scale = scale;
    tinyobj::callback_t cb;
    cb.vertex_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z,
                      tinyobj::real_t) {
        auto* s = static_cast<ObjBuilder*>(u);
        s->mesh.vertices.emplace_back(static_cast<float>(x * s->scale),
                                      static_cast<float>(y * s->scale),
                                      static_cast<float>(z * s->scale));
    };
    cb.texcoord_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t) {
        static_cast<ObjBuilder*>(u)->mesh.uvs.emplace_back(static_cast<float>(x),
                                                           static_cast<float>(y));
    };
    cb.index_cb = [](void* u, tinyobj::index_t* idx, int n) {
        static_cast<ObjBuilder*>(u)->face(idx, n);
    };
    cb.usemtl_cb = [](void* u, const char* name, int) {
        auto* s = static_cast<ObjBuilder*>(u);
        const std::string n = trimmed(name);
        s->material = n.empty() ? -1 : ObjBuilder::intern(s->mesh.material_names, n);
    };
    cb.group_cb = [](void* u, const char** names, int n) {
        auto* s = static_cast<ObjBuilder*>(u);
        const std::string g = n > 0 ? trimmed(names[0]) : std::string();
        s->group = g.empty() ? -1 : ObjBuilder::intern(s->mesh.group_names, g);
    };
    cb.object_cb = [](void* u, const char* name) {
        auto* s = static_cast<ObjBuilder*>(u);
        const std::string g = trimmed(name);
        s->group = g.empty() ? -1 : ObjBuilder::intern(s->mesh.group_names, g);
    };

    std::istringstream in(text);
    std::string warn, err;
    const bool ok = tinyobj::LoadObjWithCallback(in, cb, &b, nullptr, &warn, &err);
    if (!b.error.empty()) throw Error(b.error);
    if (!ok) fail(path.string(), ": not a valid OBJ file: ", excerpt(trimmed(err), 200));

    Mesh& m = b.mesh;
    if (m.faces.empty())
        fail(path.string(), ": no faces (", m.vertices.size(), " vertices, 0 `f` statements)");
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        const Vec3f& p = m.vertices[i];
        if (!p.allFinite())
            fail(path.string(), ": vertex ", i + 1, " is not finite after scaling by ", scale);
        // The head's grids (distance field, density, shadows) span its bounds.
        if (p.cwiseAbs().maxCoeff() > kMaxCoordinate)
            fail(path.string(), ": vertex ", i + 1, " is at (", p.x(), ", ", p.y(), ", ", p.z(),
                 ") cm after scaling by ", scale, ", farther than ", kMaxCoordinate,
                 " cm from the origin (see docs/formats.md)");
    }
    for (size_t i = 0; i < m.uvs.size(); ++i)
        if (!m.uvs[i].allFinite())
            fail(path.string(), ": texture coordinate ", i + 1, " is not finite");

    if (!b.any_uv_face) {
        m.uvs.clear();
        m.face_uvs.clear();
    } else if (b.any_plain_face) {
        // Faces without `vt` get a shared (0, 0) so that face_uvs stays one entry per face.
        const int zero = static_cast<int>(m.uvs.size());
        m.uvs.emplace_back(0.f, 0.f);
        for (Vec3i& t : m.face_uvs)
            if (t[0] < 0) t = Vec3i::Constant(zero);
    }
    if (m.group_names.empty()) m.face_group.clear();
    if (m.material_names.empty()) m.face_material.clear();
    return m;
}

void write_obj_mesh(const std::filesystem::path& path, const Mesh& mesh) {
    const size_t nf = mesh.faces.size();
    const bool uv = !mesh.uvs.empty() && mesh.face_uvs.size() == nf;
    if (!mesh.face_group.empty() && mesh.face_group.size() != nf)
        fail(path.string(), ": mesh face_group has ", mesh.face_group.size(), " entries, expected ",
             nf);
    if (!mesh.face_material.empty() && mesh.face_material.size() != nf)
        fail(path.string(), ": mesh face_material has ", mesh.face_material.size(),
             " entries, expected ", nf);
    write_file_atomic(path, [&](std::ostream& out) {
        out << "# wisp mesh: " << mesh.vertices.size() << " vertices, " << nf
            << " triangles, centimetres, Y up, +Z forward\n";
        out << std::setprecision(9);  // float round trip
        for (const Vec3f& p : mesh.vertices)
            out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
        if (uv)
            for (const Vec2f& t : mesh.uvs)
                out << "vt " << t.x() << ' ' << t.y() << '\n';
        int group = -2, material = -2;
        for (size_t f = 0; f < nf; ++f) {
            const int g = mesh.face_group.empty() ? -1 : mesh.face_group[f];
            if (g != group) {
                // `g ` without a name returns to "no group" (tinyobjloader ignores a bare `g`
                // without the space); nothing is needed before the first group.
                if (g >= 0)
                    out << "g " << mesh.group_names[g] << '\n';
                else if (group != -2)
                    out << "g \n";
                group = g;
            }
            const int m = mesh.face_material.empty() ? -1 : mesh.face_material[f];
            if (m != material && (m >= 0 || material >= 0)) {
                if (m >= 0) out << "usemtl " << mesh.material_names[m] << '\n';
                material = m;
            }
            const Vec3i& t = mesh.faces[f];
            out << 'f';
            for (int k = 0; k < 3; ++k) {
                out << ' ' << t[k] + 1;
                if (uv) out << '/' << mesh.face_uvs[f][k] + 1;
            }
            out << '\n';
        }
    });
}

namespace {

// Lists per vertex by a counting sort over the face corners: item(f, k) for corner k of face f
// goes to vertex faces[f][k].
template <typename Item>
VertexLists corner_lists(const Mesh& mesh, Item&& item) {
    VertexLists out;
    out.first.assign(mesh.vertices.size() + 1, 0);
    out.items.resize(3 * mesh.faces.size());
    for (const Vec3i& f : mesh.faces)
        for (int k = 0; k < 3; ++k)
            ++out.first[f[k] + 1];
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
        out.first[v + 1] += out.first[v];
    std::vector<uint32_t> fill(out.first.begin(), out.first.end() - 1);
    for (size_t f = 0; f < mesh.faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            out.items[fill[mesh.faces[f][k]]++] = item(f, k);
    return out;
}

}  // namespace

VertexLists vertex_edges(const Mesh& mesh) {
    return corner_lists(
        mesh, [&](size_t f, int k) { return static_cast<uint32_t>(mesh.faces[f][(k + 1) % 3]); });
}

VertexLists vertex_faces(const Mesh& mesh) {
    return corner_lists(mesh, [](size_t f, int) { return static_cast<uint32_t>(f); });
}

std::vector<std::pair<int, int>> boundary_edges(const Mesh& mesh) {
    // Half-edges a→b grouped by a, to find those without a twin b→a.
    const VertexLists edges = vertex_edges(mesh);
    const std::vector<uint32_t>& first = edges.first;
    const std::vector<uint32_t>& to = edges.items;
    auto has_edge = [&](int a, int b) {
        return std::find(to.begin() + first[a], to.begin() + first[a + 1],
                         static_cast<uint32_t>(b)) != to.begin() + first[a + 1];
    };
    std::vector<std::pair<int, int>> boundary;
    for (const Vec3i& f : mesh.faces)
        for (int k = 0; k < 3; ++k) {
            const int a = f[k], b = f[(k + 1) % 3];
            if (a != b && !has_edge(b, a)) boundary.emplace_back(a, b);
        }
    std::sort(boundary.begin(), boundary.end());
    boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());
    return boundary;
}

void close_holes(const Mesh& mesh, Mesh* closed, Mesh* caps) {
    Mesh unused;
    if (!caps) caps = &unused;
    closed->vertices = mesh.vertices;
    closed->faces = mesh.faces;
    const std::vector<std::pair<int, int>> boundary = boundary_edges(mesh);  // sorted by start

    std::vector<uint8_t> used(boundary.size(), 0);
    auto next_from = [&](int v) -> int {  // the first unused boundary edge leaving v, or -1
        auto it = std::lower_bound(boundary.begin(), boundary.end(), std::make_pair(v, INT32_MIN));
        for (; it != boundary.end() && it->first == v; ++it) {
            const auto i = static_cast<size_t>(it - boundary.begin());
            if (!used[i]) return static_cast<int>(i);
        }
        return -1;
    };
    std::vector<int> loop;
    for (size_t start = 0; start < boundary.size(); ++start) {
        if (used[start]) continue;
        loop.clear();
        for (int e = static_cast<int>(start); e >= 0; e = next_from(boundary[e].second)) {
            used[e] = 1;
            loop.push_back(e);
        }
        // The centroid of the loop as a curve (edge midpoints weighted by length), so that
        // uneven vertex spacing along the cut does not pull it aside.
        Vec3d sum = Vec3d::Zero();
        double length = 0;
        for (int e : loop) {
            const Vec3d a = mesh.vertices[boundary[e].first].cast<double>();
            const Vec3d b = mesh.vertices[boundary[e].second].cast<double>();
            sum += (b - a).norm() * 0.5 * (a + b);
            length += (b - a).norm();
        }
        if (!(length > 0)) continue;
        const Vec3f centroid = (sum / length).cast<float>();
        // The face beside the hole runs a→b, so the cap runs b→a to face outward.
        const int c = static_cast<int>(closed->vertices.size());
        closed->vertices.push_back(centroid);
        const int cc = static_cast<int>(caps->vertices.size());
        caps->vertices.push_back(centroid);
        for (int e : loop) {
            const auto [a, b] = boundary[e];
            closed->faces.emplace_back(b, a, c);
            const int k = static_cast<int>(caps->vertices.size());
            caps->vertices.push_back(mesh.vertices[b]);
            caps->vertices.push_back(mesh.vertices[a]);
            caps->faces.emplace_back(k, k + 1, cc);
        }
    }
}

void append_mesh(Mesh& mesh, const Mesh& piece, const std::string& group) {
    const int32_t first_vertex = static_cast<int32_t>(mesh.vertices.size());
    const size_t first_face = mesh.faces.size();
    if (!mesh.colors.empty() || !piece.colors.empty()) {
        mesh.colors.resize(mesh.vertices.size(), kSkinAlbedo);
        if (piece.colors.empty())
            mesh.colors.resize(mesh.vertices.size() + piece.vertices.size(), kSkinAlbedo);
        else
            mesh.colors.insert(mesh.colors.end(), piece.colors.begin(), piece.colors.end());
    }
    mesh.vertices.insert(mesh.vertices.end(), piece.vertices.begin(), piece.vertices.end());
    for (const Vec3i& f : piece.faces)
        mesh.faces.push_back(f + Vec3i::Constant(first_vertex));
    const size_t faces = mesh.faces.size();

    // Names by index into `names`, adding those not there yet.
    const auto name_index = [](std::vector<std::string>& names, const std::string& name) {
        const auto it = std::find(names.begin(), names.end(), name);
        if (it != names.end()) return static_cast<int32_t>(it - names.begin());
        names.push_back(name);
        return static_cast<int32_t>(names.size() - 1);
    };
    const auto labels = [&](std::vector<int32_t>& into, std::vector<std::string>& names,
                            const std::vector<int32_t>& from,
                            const std::vector<std::string>& from_names, const std::string& dflt) {
        if (into.empty() && from.empty() && dflt.empty()) return;
        into.resize(first_face, -1);
        const int32_t fallback = dflt.empty() ? -1 : name_index(names, dflt);
        for (size_t f = 0; f < piece.faces.size(); ++f) {
            const int32_t g = from.empty() ? -1 : from[f];
            into.push_back(g >= 0 ? name_index(names, from_names[g]) : fallback);
        }
    };
    labels(mesh.face_group, mesh.group_names, piece.face_group, piece.group_names, group);
    labels(mesh.face_material, mesh.material_names, piece.face_material, piece.material_names, {});

    if (!mesh.face_uvs.empty() || !piece.face_uvs.empty()) {
        if (mesh.face_uvs.size() < first_face || mesh.uvs.empty()) {
            // The mesh had none: one UV (0, 0) for its faces so far.
            mesh.face_uvs.assign(first_face,
                                 Vec3i::Constant(static_cast<int32_t>(mesh.uvs.size())));
            mesh.uvs.emplace_back(0.f, 0.f);
        }
        const int32_t first_uv = static_cast<int32_t>(mesh.uvs.size());
        if (piece.face_uvs.empty()) {
            mesh.uvs.emplace_back(0.f, 0.f);
            mesh.face_uvs.resize(faces, Vec3i::Constant(first_uv));
        } else {
            mesh.uvs.insert(mesh.uvs.end(), piece.uvs.begin(), piece.uvs.end());
            for (const Vec3i& f : piece.face_uvs)
                mesh.face_uvs.push_back(f + Vec3i::Constant(first_uv));
        }
    }
}

}  // namespace wisp
