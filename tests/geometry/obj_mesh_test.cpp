#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "core/error.hpp"
#include "geometry/builtin_head.hpp"
#include "geometry/mesh.hpp"
#include "test_meshes.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

using test::kBase;
using test::kHeadNeckShoulders;

fs::path temp_dir() {
    const fs::path dir =
        fs::temp_directory_path() / ("wisp_obj_test_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

fs::path write_text(const std::string& name, const std::string& text) {
    const fs::path p = temp_dir() / name;
    std::ofstream(p) << text;
    return p;
}

// Expects read_obj_mesh(path) to throw a wisp::Error whose message names the file and
// contains `what`.
void expect_error(const fs::path& path, const std::string& what) {
    try {
        read_obj_mesh(path);
        ADD_FAILURE() << "no error for " << path;
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(path.string()), std::string::npos) << msg;
        EXPECT_NE(msg.find(what), std::string::npos) << msg;
    }
}

int group_index(const Mesh& m, const std::string& name) {
    for (size_t i = 0; i < m.group_names.size(); ++i)
        if (m.group_names[i] == name) return static_cast<int>(i);
    return -1;
}

TEST(ObjMesh, TriangulatesAndKeepsGroupsAndMaterialsWithoutMtl) {
    const fs::path p = write_text("quad.obj",
                                  "mtllib missing.mtl\n"
                                  "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
                                  "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                  "g skin\nusemtl Skin_Mat\nf 1/1 2/2 3/3 4/4\n"
                                  "o cap\nusemtl scalp\nf -5/-4 -4/-3 -1/-1\n");
    const Mesh m = read_obj_mesh(p, 2.f);
    ASSERT_EQ(m.faces.size(), 3u);
    EXPECT_EQ(m.faces[0], Vec3i(0, 1, 2));
    EXPECT_EQ(m.faces[1], Vec3i(0, 2, 3));
    EXPECT_EQ(m.faces[2], Vec3i(0, 1, 4));
    EXPECT_EQ(m.vertices[2], Vec3f(2, 2, 0));  // scaled
    ASSERT_EQ(m.group_names, (std::vector<std::string>{"skin", "cap"}));
    EXPECT_EQ(m.face_group, (std::vector<int32_t>{0, 0, 1}));
    ASSERT_EQ(m.material_names, (std::vector<std::string>{"Skin_Mat", "scalp"}));
    EXPECT_EQ(m.face_material, (std::vector<int32_t>{0, 0, 1}));
    ASSERT_EQ(m.face_uvs.size(), 3u);
    EXPECT_EQ(m.face_uvs[1], Vec3i(0, 2, 3));
    EXPECT_EQ(m.face_uvs[2], Vec3i(0, 1, 3));
    EXPECT_NEAR(m.face_area(0), 2.f, 1e-6f);
    EXPECT_NEAR(m.face_normal(0).z(), 1.f, 1e-6f);
}

TEST(ObjMesh, BadFilesNameTheFile) {
    expect_error(temp_dir() / "does_not_exist.obj", "does_not_exist.obj");
    expect_error(write_text("empty.obj", ""), "no faces");
    expect_error(write_text("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), "no faces");
    expect_error(write_text("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"), ":4:");
    expect_error(write_text("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), "out of range");
    expect_error(write_text("uvrange.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n"),
                 "texture index");
    expect_error(write_text("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), ":2:");
    expect_error(write_text("inf.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n"), "finite");
    expect_error(write_text("line.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n"), "face has 2 vertices");
    // One vertex 10 km away would size the head's grids to run out of memory.
    expect_error(
        write_text("far.obj", "v 0 0 0\nv 1e6 0 0\nv 0 1 0\nf 1 2 3\n"),
        "far.obj: vertex 2 is at (1e+06, 0, 0) cm after scaling by 1, farther than 100000");
    EXPECT_THROW(
        read_obj_mesh(write_text("far2.obj", "v 0 0 0\nv 1 0 0\nv 0 1e4 0\nf 1 2 3\n"), 30.f),
        Error);
}

// Exporters that pad a file to a block end it in NUL bytes (three.js's LeePerrySmith.obj has
// one): read as the text before them, as Blender and three.js read it. A NUL with text after
// it, or no text before it, is not padding.
TEST(ObjMesh, TrailingNulPaddingIsReadAsTheEndOfTheText) {
    const std::string tri = "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n";
    const Mesh m = read_obj_mesh(write_text("padded.obj", tri + std::string(4096, '\0')));
    EXPECT_EQ(m.faces.size(), 1u);
    expect_error(
        write_text("inner.obj", "v 0 0 0\nv 1 0 0\n" + std::string(1, '\0') + "v 0 1 0\nf 1 2 3\n"),
        "byte 16 is a NUL byte");
    expect_error(write_text("nul_first.obj", std::string(8, '\0') + tri), "byte 0 is a NUL byte");
    expect_error(write_text("long_pad.obj", tri + std::string(70000, '\0')), "is a NUL byte");
}

// Files the exporters users have write (tests/data/obj, made by the scripts beside them).
const fs::path kObjData = fs::path(WISP_SOURCE_DIR) / "tests/data/obj";

// Blender 3.4's exporter: o, s, usemtl (its .mtl not shipped), vt and vn of their own counts,
// quads and triangles; Y up and -Z forward, as wisp's head space wants.
TEST(ObjMesh, ReadsWhatBlenderWrites) {
    const Mesh m = read_obj_mesh(kObjData / "blender_sphere.obj", 10.f);
    EXPECT_EQ(m.vertices.size(), 16u * 7u + 2u);
    EXPECT_EQ(m.faces.size(), 16u * 6u * 2u + 2u * 16u);  // quads in two, the poles' triangles
    ASSERT_EQ(m.group_names, std::vector<std::string>{"Head"});
    ASSERT_EQ(m.material_names, (std::vector<std::string>{"skin", "scalp"}));
    EXPECT_FALSE(m.uvs.empty());
    EXPECT_NEAR(m.bounds().hi.y(), 10.f, 1e-4f);
    // Blender's top (its +Z, the faces given "scalp") is wisp's +Y.
    size_t scalp = 0;
    for (size_t f = 0; f < m.faces.size(); ++f) {
        if (m.face_material[f] != 1) continue;
        ++scalp;
        const Vec3i& t = m.faces[f];
        EXPECT_GT((m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]).y() / 3.f, 2.f)
            << "face " << f;
    }
    EXPECT_EQ(scalp, 16u * 2u * 2u + 16u);  // two rings of quads and the pole's triangles
}

// three.js's OBJExporter: v/vt/vn on every corner, a Unicode object name, no materials.
TEST(ObjMesh, ReadsWhatThreeJsWrites) {
    const Mesh m = read_obj_mesh(kObjData / "threejs_sphere.obj");
    EXPECT_EQ(m.vertices.size(), 17u * 9u);
    EXPECT_EQ(m.faces.size(), 16u * 8u * 2u - 2u * 16u);
    ASSERT_EQ(m.group_names, std::vector<std::string>{"T\xc3\xaate_\xe9\xa0\xad"});  // Tête_頭
    EXPECT_EQ(m.face_uvs.size(), m.faces.size());
    EXPECT_NEAR(m.bounds().hi.y(), 1.f, 1e-6f);
}

// What other exporters and hand edits put in OBJ files, all of which Blender and three.js
// read: CRLF, tabs, comments on their own lines and after data, s/l/vp/cstype-free lines
// that carry nothing for a mesh, vt with a third coordinate, more normals than vertices,
// polygons of any size, negative indices, Unicode group names, a missing .mtl.
TEST(ObjMesh, ToleratesWhatRealExportersWrite) {
    const Mesh m = read_obj_mesh(write_text("quirks.obj",
                                            "# made by hand\r\n"
                                            "mtllib nowhere.mtl\r\n"
                                            "o Kopf \xc3\xbc\r\n"
                                            "v 0 0 0\r\n"
                                            "v\t1 0 0  # a comment after data\r\n"
                                            "v 1 1 0\r\n"
                                            "v 0 1 0\r\n"
                                            "v 0.5 1.5 0 1.0\r\n"  // w, as some writers add
                                            "vt 0 0 0\r\nvt 1 0 0\r\nvt 1 1 0\r\n"
                                            "vn 0 0 1\r\nvn 0 0 1\r\nvn 0 0 1\r\nvn 0 0 1\r\n"
                                            "vn 0 0 1\r\nvn 0 0 1\r\nvn 0 0 1\r\n"
                                            "\r\n"
                                            "g scalp\r\n"
                                            "s off\r\n"
                                            "usemtl \xe5\xa4\xb4\xe7\x9a\xae\r\n"  // 头皮
                                            "# a comment between faces\r\n"
                                            "f 1/1/1 2/2/2 3/3/3 4/1/4 5/2/5\r\n"  // a pentagon
                                            "s 1\r\n"
                                            "l 1 2\r\n"
                                            "f -5//-1 -4//-2 -1//-3\r\n"));
    EXPECT_EQ(m.vertices.size(), 5u);
    ASSERT_EQ(m.faces.size(), 3u + 1u);
    EXPECT_EQ(m.faces[3], Vec3i(0, 1, 4));
    for (size_t f = 0; f < m.faces.size(); ++f)
        EXPECT_EQ(m.group_names.at(m.face_group.at(f)), "scalp") << "face " << f;
    EXPECT_EQ(m.material_names, std::vector<std::string>{"\xe5\xa4\xb4\xe7\x9a\xae"});
}

// What is not an OBJ file at all, or asks for more than any head holds: refused, naming the
// file and what is wrong.
TEST(ObjMesh, RefusesWhatIsNotAnObjFile) {
    std::string png = "\x89PNG\r\n\x1a\n";
    png += std::string("\0\0\0\rIHDR", 8) + "garbage";
    expect_error(write_text("picture.obj", png), "picture.obj");
    expect_error(write_text("index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n"),
                 "index.obj:4:");
    expect_error(write_text("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"),
                 "negative.obj:4:");
}

TEST(ObjMesh, RoundTripKeepsScalpGroupAndUvs) {
    const Mesh head = builtin_head_mesh();
    const fs::path p = temp_dir() / "head.obj";
    write_obj_mesh(p, head);
    const Mesh back = read_obj_mesh(p);
    ASSERT_EQ(back.vertices.size(), head.vertices.size());
    ASSERT_EQ(back.faces.size(), head.faces.size());
    EXPECT_TRUE(back.vertices == head.vertices);  // 9 significant digits round-trip a float
    EXPECT_TRUE(back.faces == head.faces);
    EXPECT_TRUE(back.uvs == head.uvs);
    EXPECT_TRUE(back.face_uvs == head.face_uvs);
    const int scalp = group_index(back, "scalp");
    ASSERT_GE(scalp, 0);
    const int scalp0 = group_index(head, "scalp");
    for (size_t f = 0; f < head.faces.size(); ++f)
        ASSERT_EQ(back.face_group[f] == scalp, head.face_group[f] == scalp0) << "face " << f;
    // No temporary file is left behind.
    for (const auto& e : fs::directory_iterator(temp_dir()))
        EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos) << e.path();
}

TEST(ObjMesh, MakeHumanHeadNeckShouldersHasOneOpenLoop) {
    if (!fs::exists(kHeadNeckShoulders)) GTEST_SKIP() << kHeadNeckShoulders << " not present";
    const Mesh m = read_obj_mesh(kHeadNeckShoulders, 10.f);  // decimetres -> cm
    EXPECT_EQ(m.faces.size(), 2u * 4630u);
    const Box3 b = m.bounds();
    EXPECT_NEAR(b.hi.y(), 84.9f, 0.1f);
    EXPECT_NEAR(b.lo.y(), 50.0f, 0.1f);
    EXPECT_FALSE(m.uvs.empty());
    ASSERT_EQ(m.group_names, std::vector<std::string>{"head_neck_shoulders"});
    // Boundary edges (one face) form a single loop.
    std::map<std::pair<int, int>, int> edges;
    for (const Vec3i& t : m.faces)
        for (int e = 0; e < 3; ++e) {
            const int a = t[e], c = t[(e + 1) % 3];
            ++edges[{std::min(a, c), std::max(a, c)}];
        }
    std::map<int, std::vector<int>> next;
    for (const auto& [e, n] : edges) {
        ASSERT_LE(n, 2);
        if (n == 1) {
            next[e.first].push_back(e.second);
            next[e.second].push_back(e.first);
        }
    }
    ASSERT_FALSE(next.empty());
    for (const auto& [v, ns] : next)
        ASSERT_EQ(ns.size(), 2u);
    std::set<int> seen;
    int prev = -1, cur = next.begin()->first;
    while (!seen.count(cur)) {
        seen.insert(cur);
        const int nxt = next[cur][0] != prev ? next[cur][0] : next[cur][1];
        prev = cur;
        cur = nxt;
    }
    EXPECT_EQ(seen.size(), next.size());  // one loop visits every boundary vertex
}

TEST(ObjMesh, MakeHumanBaseKeepsHelperGroups) {
    if (!fs::exists(kBase)) GTEST_SKIP() << kBase << " not present";
    const Mesh m = read_obj_mesh(kBase, 10.f);
    EXPECT_EQ(m.faces.size(), 2u * 18486u);
    EXPECT_GE(group_index(m, "body"), 0);
    const int hair = group_index(m, "helper-hair");
    ASSERT_GE(hair, 0);
    EXPECT_EQ(std::count(m.face_group.begin(), m.face_group.end(), hair), 2 * 198);
}

}  // namespace
}  // namespace wisp
