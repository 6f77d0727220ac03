#include "io/obj_curves.hpp"

#include <gtest/gtest.h>

#include "io_test_util.hpp"

namespace wisp {
namespace {

using test::expect_error;

TEST(ObjCurves, RoundTripBothFormsIsBitExact) {
    Hair h = test::random_hair(5, 200, 0, false, false, false);
    // Include 2-point strands next to each other: they must not be joined.
    h.add_strand(std::vector<Vec3f>{{1, 2, 3}, {4, 5, 6}});
    h.add_strand(std::vector<Vec3f>{{4, 5, 6}, {7, 8, 9}});
    h.add_strand(std::vector<Vec3f>{{0, 0, 0}});
    for (bool segments : {false, true}) {
        SCOPED_TRACE(segments ? "segments" : "polylines");
        test::TempPath p(".obj");
        write_obj_curves(p, h, segments);
        const Hair r = read_obj_curves(p);
        test::expect_same_geometry(h, r);
        EXPECT_TRUE(r.widths.empty());
        EXPECT_TRUE(r.colors.empty());
    }
    const std::string seg = encode_obj_curves(h, true);
    EXPECT_NE(seg.find("\nl 1 2\nl 2 3\n"), std::string::npos);
}

TEST(ObjCurves, RelativeIndicesAndOtherStatements) {
    const char* text =
        "# a comment\n"
        "mtllib hair.mtl\n"
        "o hair\n"
        "g strands\n"
        "v 0 0 0\r\n"
        "v 0 1 0 1.0\n"          // w is ignored
        "v 0 2 0 0.5 0.5 0.5\n"  // vertex colors are ignored
        "vt 0 0\n"
        "vn 0 1 0\n"
        "f 1 2 3\n"
        "l -3 -2 -1\n"
        "v 5 5 5\n"
        "v 6 6 6\n"
        "l 4/1 5/2\n";
    const Hair h = decode_obj_curves(text, "rel.obj");
    ASSERT_EQ(h.strand_count(), 2u);
    EXPECT_EQ(h.strand_size(0), 3u);
    EXPECT_EQ(h.strand(0)[2], Vec3f(0, 2, 0));
    EXPECT_EQ(h.strand(1)[1], Vec3f(6, 6, 6));
}

TEST(ObjCurves, ErrorsNameFileAndLine) {
    expect_error([] { decode_obj_curves("v 0 0 0\nl 1 2\n", "a.obj"); },
                 "a.obj:2: vertex index 2 is out of range (1 vertices defined so far)");
    expect_error([] { decode_obj_curves("v 0 0\n", "b.obj"); }, "b.obj:1: `v` needs 3 coordinates");
    expect_error([] { decode_obj_curves("v 0 x 0\n", "c.obj"); }, "c.obj:1: `x` is not a number");
    expect_error([] { decode_obj_curves("v 0 0 0\n\nl 0 1\n", "d.obj"); },
                 "d.obj:3: vertex index 0");
    expect_error([] { decode_obj_curves("v 0 nan 0\n", "e.obj"); },
                 "e.obj:1: vertex coordinate `nan` is not finite");
    expect_error([] { decode_obj_curves("v 0 0 0\nl\n", "f.obj"); },
                 "f.obj:2: `l` without vertex indices");
    expect_error([] { decode_obj_curves("v 0 0 0\nl -2\n", "g.obj"); }, "g.obj:2: vertex index -2");
}

// Hair beyond kMaxCoordinate (1 km) would size the renderer's and solver's grids to hours of
// work: every reader rejects it through Hair::validate, naming the strand and point.
TEST(ObjCurves, FarOffCoordinatesFail) {
    expect_error(
        [] {
            decode_obj_curves("v 0 0 0\nv 0 1 0\nv 0 0 0\nv 0 2e8 0\nl 1 2\nl 3 4\n", "far.obj");
        },
        "far.obj: point 3 (strand 1, its point 1) is at (0, 2e+08, 0), farther than 100000 cm");
    const Hair h = decode_obj_curves("v 0 0 0\nv 0 -1e5 0\nl 1 2\n", "edge.obj");
    EXPECT_EQ(h.points[1].y(), -1e5f);
}

TEST(ObjCurves, TruncatedFilesNeverCrash) {
    // Text cut after a whole line is a valid shorter file; every cut must either read or
    // throw wisp::Error, and never read more points than the whole file has.
    const Hair h = test::random_hair(8, 5, 4, false, false, false);
    const std::string text = encode_obj_curves(h, true);
    for (size_t cut = 0; cut < text.size(); ++cut) {
        try {
            const Hair r = decode_obj_curves(std::string_view(text).substr(0, cut), "cut.obj");
            EXPECT_LE(r.point_count(), h.point_count());
        } catch (const Error&) {
        }
    }
}

}  // namespace
}  // namespace wisp
