#include "io/npz.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>

#include "core/catmull_rom.hpp"
#include "core/parallel.hpp"
#include "io_test_util.hpp"

namespace wisp {
namespace {

template <typename T>
T get(const std::string& s, size_t at) {
    T v;
    std::memcpy(static_cast<void*>(&v), s.data() + at, sizeof(T));
    return v;
}

// The members of a stored zip, walked through the local headers: name -> .npy bytes.
std::map<std::string, std::string> unzip(const std::string& zip) {
    std::map<std::string, std::string> out;
    size_t at = 0;
    while (get<uint32_t>(zip, at) == 0x04034b50) {
        uint64_t size = get<uint32_t>(zip, at + 18);
        const uint16_t name_len = get<uint16_t>(zip, at + 26), extra = get<uint16_t>(zip, at + 28);
        const std::string name = zip.substr(at + 30, name_len);
        if (size == 0xFFFFFFFFu) size = get<uint64_t>(zip, at + 30 + name_len + 4);
        out[name] = zip.substr(at + 30 + name_len + extra, size);
        at += 30 + name_len + extra + size;
    }
    EXPECT_EQ(get<uint32_t>(zip, at), 0x02014b50u) << "central directory after the members";
    return out;
}

// The header dictionary of a .npy file, and where its data starts.
std::string npy_dict(const std::string& npy, size_t* data_at) {
    EXPECT_EQ(npy.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    const uint16_t len = get<uint16_t>(npy, 8);
    *data_at = 10 + len;
    EXPECT_EQ(*data_at % 64, 0u);
    return npy.substr(10, len);
}

Hair sample_hair() {
    Hair h = test::random_hair(11, 40, 0, true, true, true);
    for (size_t s = 0; s < h.strand_count(); ++s) {
        h.root_uv.emplace_back(0.01f * float(s), 0.5f);
        h.root_normal.emplace_back(0.f, 1.f, 0.f);
        h.group.push_back(int32_t(s % 3));
    }
    return h;
}

TEST(Npz, ArraysAndShapes) {
    const Hair h = sample_hair();
    const std::string zip = encode_npz(h, "t.npz", NpzWriteOptions{.points_per_strand = 16});
    const auto files = unzip(zip);
    for (const char* name :
         {"positions.npy", "widths.npy", "control_points.npy", "offsets.npy", "colors.npy",
          "wisp_id.npy", "group_id.npy", "root_uv.npy", "root_normal.npy"})
        EXPECT_TRUE(files.count(name)) << name;
    size_t at = 0;
    EXPECT_EQ(npy_dict(files.at("positions.npy"), &at)
                  .find("{'descr': '<f4', 'fortran_order': False, 'shape': (40, 16, 3), }"),
              0u);
    const std::string& pts = files.at("positions.npy");
    npy_dict(pts, &at);
    ASSERT_EQ(pts.size() - at, 40u * 16 * 12);
    for (size_t s = 0; s < h.strand_count(); ++s) {
        // Root and tip are exact; the points are evenly spaced along the curve.
        const Vec3f root = get<Vec3f>(pts, at + s * 16 * 12);
        const Vec3f tip = get<Vec3f>(pts, at + (s * 16 + 15) * 12);
        EXPECT_EQ(root, h.strand(s).front());
        EXPECT_EQ(tip, h.strand(s).back());
    }
    EXPECT_NE(npy_dict(files.at("offsets.npy"), &at).find("'<i8'"), std::string::npos);
    EXPECT_NE(npy_dict(files.at("offsets.npy"), &at).find("(41,)"), std::string::npos);
    EXPECT_NE(npy_dict(files.at("root_uv.npy"), &at).find("(40, 2)"), std::string::npos);
    // Without the optional arrays, only the geometry and colours.
    const Hair bare = test::random_hair(12, 5, 4, false, false, false);
    const auto few = unzip(encode_npz(bare));
    EXPECT_EQ(few.size(), 5u);
    EXPECT_FALSE(few.count("wisp_id.npy"));
}

TEST(Npz, ResampleIsEvenInArcLength) {
    // A straight strand with uneven control points: the samples are evenly spaced.
    const std::vector<Vec3f> pts{{0, 0, 0}, {0, 1, 0}, {0, 5, 0}, {0, 6, 0}};
    const std::vector<float> w{4, 3, 2, 1};
    std::vector<Vec3f> out(7);
    std::vector<float> ow(7);
    catmull_rom_resample(pts, w, 0.f, out, ow);
    for (size_t k = 0; k < out.size(); ++k)
        EXPECT_NEAR(out[k].y(), float(k), 0.05f) << k;
    EXPECT_EQ(ow.front(), 4.f);
    EXPECT_EQ(ow.back(), 1.f);
    // One point: repeated.
    const std::vector<Vec3f> one{{1, 2, 3}};
    catmull_rom_resample(one, {}, 0.5f, out, ow);
    EXPECT_EQ(out[6], one[0]);
    EXPECT_EQ(ow[6], 0.5f);
}

TEST(Npz, SameBytesAtAnyThreadCount) {
    const Hair h = test::random_hair(13, 3000);
    std::string one, two;
    {
        const ThreadLimit limit(1);
        one = encode_npz(h);
    }
    {
        const ThreadLimit limit(2);
        two = encode_npz(h);
    }
    EXPECT_EQ(one, two);
}

TEST(Npz, BadInputFails) {
    Hair h = test::random_hair(14, 3);
    test::expect_error([&] { encode_npz(h, "x.npz", NpzWriteOptions{.points_per_strand = 1}); },
                       "x.npz: points per strand must be in [2, 4096]");
    Hair empty_strand = h;
    empty_strand.offsets.push_back(empty_strand.offsets.back());
    empty_strand.colors.push_back(Vec3f::Zero());
    empty_strand.wisp.push_back(0);
    test::expect_error([&] { encode_npz(empty_strand, "e.npz"); }, "e.npz: strand 3 has no points");
}

// numpy itself reads the file (plain and with every member as ZIP64): shapes, dtypes and
// values. Skipped where /usr/bin/python3 has no numpy.
TEST(Npz, NumpyLoadsIt) {
    if (std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "/usr/bin/python3 with numpy is not installed (python3-numpy)";
    const Hair h = sample_hair();
    for (uint64_t threshold : {uint64_t(0xFFFFFFFFu), uint64_t(0)}) {
        test::TempPath p(".npz");
        write_npz(p, h, NpzWriteOptions{.points_per_strand = 8, .zip64_threshold = threshold});
        test::TempPath script(".py");
        std::ofstream(script.path()) << R"(
import sys, numpy as np
f = np.load(sys.argv[1])
p = f['positions']; o = f['offsets']; c = f['control_points']
assert p.shape == (40, 8, 3) and p.dtype == np.float32, (p.shape, p.dtype)
assert f['widths'].shape == (40, 8)
assert o.shape == (41,) and o.dtype == np.int64 and o[0] == 0 and o[-1] == len(c)
for s in range(40):
    assert (p[s, 0] == c[o[s]]).all() and (p[s, -1] == c[o[s + 1] - 1]).all()
assert f['colors'].shape == (40, 3)
assert f['wisp_id'].dtype == np.int32 and f['wisp_id'].shape == (40,)
assert (f['group_id'] == np.arange(40) % 3).all()
assert f['root_uv'].shape == (40, 2) and abs(f['root_uv'][7, 0] - 0.07) < 1e-6
assert (f['root_normal'][:, 1] == 1).all()
print(float(c[5, 1]), int(f['wisp_id'][9]))
)";
        const std::string cmd = "/usr/bin/python3 " + script.path().string() + " " +
                                p.path().string() + " > " + script.path().string() + ".out 2>&1";
        const int rc = std::system(cmd.c_str());
        std::ifstream in(script.path().string() + ".out");
        std::string out((std::istreambuf_iterator<char>(in)), {});
        std::filesystem::remove(script.path().string() + ".out");
        ASSERT_EQ(rc, 0) << "threshold " << threshold << ": " << out;
        EXPECT_EQ(std::stof(out.substr(0, out.find(' '))), h.points[5].y());
        EXPECT_EQ(std::stoi(out.substr(out.find(' ') + 1)), h.wisp[9]);
    }
}

// Any arrays (a dataset sample's cameras): headers as numpy writes them, members in order,
// sizes checked against shapes.
TEST(Npz, ArraysOfAnyShapeAndType) {
    const std::vector<float> depth(6, 1.5f);
    const std::vector<double> k(9, 2.0);
    const std::vector<int32_t> size = {512, 256};
    const std::string npy = encode_npy(npy_array("depth", {2, 3}, std::span<const float>(depth)));
    size_t at = 0;
    const std::string dict = npy_dict(npy, &at);
    EXPECT_NE(dict.find("'descr': '<f4'"), std::string::npos) << dict;
    EXPECT_NE(dict.find("'shape': (2, 3)"), std::string::npos) << dict;
    EXPECT_EQ(dict.back(), '\n');
    EXPECT_EQ(npy.size(), at + 6 * sizeof(float));
    EXPECT_EQ(get<float>(npy, at + 20), 1.5f);

    const NpyArray arrays[] = {npy_array("K", {1, 3, 3}, std::span<const double>(k)),
                               npy_array("image_size", {1, 2}, std::span<const int32_t>(size))};
    const std::string zip = encode_npz(arrays);
    const auto members = unzip(zip);
    ASSERT_EQ(members.size(), 2u);
    EXPECT_NE(npy_dict(members.at("K.npy"), &at)
                  .find("'<f8', 'fortran_order': False, "
                        "'shape': (1, 3, 3)"),
              std::string::npos);
    EXPECT_NE(npy_dict(members.at("image_size.npy"), &at).find("'shape': (1, 2)"),
              std::string::npos);
    EXPECT_EQ(get<int32_t>(members.at("image_size.npy"), at + 4), 256);
    EXPECT_EQ(encode_npz(arrays), zip);

    NpyArray wrong = arrays[0];
    wrong.shape = {2, 3, 3};
    test::expect_error([&] { encode_npy(wrong); }, "K: 72 bytes of data for 18 elements of <f8");
    const NpyArray twice[] = {arrays[0], arrays[0]};
    test::expect_error([&] { encode_npz(twice); }, "npz: two arrays named 'K'");
}

}  // namespace
}  // namespace wisp
