#pragma once
// Triangle meshes: heads, necks and shoulders in head space (centimetres, Y up, +Z forward).
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "core/math.hpp"

namespace wisp {

// The albedo of skin where a mesh gives none (linear RGB).
inline const Vec3f kSkinAlbedo(0.62f, 0.42f, 0.32f);

struct Mesh {
    std::vector<Vec3f> vertices;      // #V positions, cm
    std::vector<Vec3i> faces;         // #F triangles, indices into vertices, counter-clockwise
                                      // seen from outside
    std::vector<Vec2f> uvs;           // #UV texture coordinates, or empty
    std::vector<Vec3i> face_uvs;      // #F indices into uvs per corner, or empty
    std::vector<int32_t> face_group;  // #F index into group_names (-1 none), or empty
    std::vector<std::string> group_names;
    std::vector<int32_t> face_material;  // #F index into material_names (-1 none), or empty
    std::vector<std::string> material_names;
    // #V linear RGB albedo per vertex (the eyes and lips of the built-in face), or empty:
    // the renderer's skin albedo everywhere.
    std::vector<Vec3f> colors;

    Box3 bounds() const;
    Vec3f face_normal(size_t f) const;  // unit, zero for degenerate faces
    float face_area(size_t f) const;
};

// Reads an OBJ (tinyobjloader; polygons are triangulated; `g`/`o` groups and `usemtl`
// materials kept). Positions are multiplied by `scale` to reach centimetres. Throws
// wisp::Error naming the file on any malformed, empty or non-finite content.
Mesh read_obj_mesh(const std::filesystem::path& path, float scale = 1.f);
// The most a head OBJ may hold (docs/formats.md): scanned heads of a few million triangles fit.
inline constexpr uint64_t kMaxObjMeshBytes = uint64_t(1) << 30;

// Writes an OBJ atomically with `g NAME` blocks per face group and `vt` when present.
void write_obj_mesh(const std::filesystem::path& path, const Mesh& mesh);

// Appends `piece` to `mesh`: its vertices, its faces (renumbered), its groups by name (faces
// without a group get `group` when it is not empty) and its UVs, so a mesh with UVs keeps one
// per corner (a piece without UVs gets the UV (0, 0)); materials likewise; vertex colours
// likewise (kSkinAlbedo for a piece without them).
void append_mesh(Mesh& mesh, const Mesh& piece, const std::string& group = {});

// Per-vertex lists in CSR form: vertex v's entries are items[first[v]] … items[first[v+1]−1].
struct VertexLists {
    std::vector<uint32_t> first;  // #vertices + 1
    std::vector<uint32_t> items;
};
// For each vertex, the far end of every directed triangle edge leaving it (in a closed
// manifold, each neighbour once).
VertexLists vertex_edges(const Mesh& mesh);
// For each vertex, the faces that use it.
VertexLists vertex_faces(const Mesh& mesh);

// The half-edges a→b of `mesh` without a twin b→a (its open boundary), sorted by a, then b.
std::vector<std::pair<int, int>> boundary_edges(const Mesh& mesh);

// `mesh` with every boundary loop closed by a fan about the loop's centroid (the loop as a
// curve: edge midpoints weighted by length), into `closed`; the fans alone into `caps` (may
// be null). A head mesh cut open at the neck or chest encloses its inside only once closed:
// its winding number is ambiguous near the cut, and its distance ignores it.
void close_holes(const Mesh& mesh, Mesh* closed, Mesh* caps = nullptr);

}  // namespace wisp
