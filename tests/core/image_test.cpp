#include "core/image.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace wisp {
namespace {

namespace fs = std::filesystem;

TEST(Image, PngRoundTripAsGray) {
    RgbImage rgb{2, 1, {255, 255, 255, 0, 0, 0}};
    const fs::path p = fs::temp_directory_path() / "wisp_image_test_round_trip.png";
    write_png(p, rgb);
    const GrayImage g = read_gray_image(p);
    fs::remove(p);
    ASSERT_EQ(g.width, 2);
    ASSERT_EQ(g.height, 1);
    EXPECT_NEAR(g.values[0], 1.f, 1e-6f);
    EXPECT_NEAR(g.values[1], 0.f, 1e-6f);
}

// The editor's painted maps: encode_gray_png quantizes to 8 bits, the same image gives the
// same bytes, and the bytes decode (from memory or from the file) to exactly k/255.
TEST(Image, GrayPngIsDeterministicAndDecodesToItsEightBitValues) {
    GrayImage g;
    g.width = 7;  // rows not a multiple of 4 bytes
    g.height = 3;
    for (int i = 0; i < 21; ++i)
        g.values.push_back(float(i) / 20.f);
    g.values[0] = -1.f;  // clamped
    g.values[1] = 2.f;
    g.values[2] = std::nanf("");
    const std::string bytes = encode_gray_png(g);
    EXPECT_EQ(encode_gray_png(g), bytes);
    const GrayImage d = decode_image_planes(bytes, "map", 1).front();
    ASSERT_EQ(d.width, 7);
    ASSERT_EQ(d.height, 3);
    EXPECT_EQ(d.values[0], 0.f);
    EXPECT_EQ(d.values[1], 1.f);
    EXPECT_EQ(d.values[2], 0.f);
    for (int i = 3; i < 21; ++i)
        EXPECT_EQ(d.values[i], float(std::lround(g.values[i] * 255.f)) / 255.f) << i;
    // What a generate reads from the saved file is what the editor held.
    const fs::path p = fs::temp_directory_path() / "wisp_image_test_gray.png";
    write_file_atomic(p, bytes);
    EXPECT_EQ(read_gray_image(p).values, d.values);
    fs::remove(p);
    // Re-encoding the decoded image gives the same file.
    EXPECT_EQ(encode_gray_png(d), bytes);
    EXPECT_THROW(decode_image_planes("not an image", "map", 1), Error);
    EXPECT_THROW(decode_image_planes(bytes.substr(0, 40), "map", 1), Error);
}

// Inputs the fuzzer found (fuzz/corpus/image/, docs/fuzzing.md): each is read or refused with
// wisp::Error, never a crash.
TEST(Image, FuzzFindingsReadOrFailCleanly) {
    for (const char* name :
         {"empty_idat.png", "rle_tga_claims_38_mpixel.tga", "rle_tga_claims_38_mpixel_padded.tga",
          "idat_length_2gb.png", "jpeg_huffman_table_of_510_codes.jpg"}) {
        const fs::path p = fs::path(WISP_SOURCE_DIR) / "fuzz/corpus/image" / name;
        ASSERT_TRUE(fs::exists(p)) << p;
        try {
            const GrayImage g = read_gray_image(p);
            EXPECT_EQ(g.values.size(), static_cast<size_t>(g.width) * g.height) << name;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    }
}

// A 132-byte run-length TGA whose header claims 6168 × 6168 pixels: refused before it is
// decoded (it took 26 s under the fuzzer's sanitizers and would allocate 450 MB), since no
// format packs that many pixels into so few bytes.
TEST(Image, AHeaderClaimingMorePixelsThanTheFileCanHoldIsRefused) {
    const fs::path p = fs::path(WISP_SOURCE_DIR) / "fuzz/corpus/image/rle_tga_claims_38_mpixel.tga";
    ASSERT_TRUE(fs::exists(p)) << p;
    try {
        read_gray_image(p);
        ADD_FAILURE() << "read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("6168x6168 is more than a file of 132 bytes can hold"),
                  std::string::npos)
            << e.what();
    }
    // A one-colour 2048 × 2048 PNG (16 KB or so) is far inside the bound and reads.
    GrayImage flat;
    flat.width = flat.height = 2048;
    flat.values.assign(size_t(2048) * 2048, 0.5f);
    const std::string bytes = encode_gray_png(flat);
    EXPECT_EQ(decode_image_planes(bytes, "flat", 1).front().values.size(), flat.values.size());
}

// JPEG maps decode through libjpeg-turbo: a mid-gray JPEG reads mid-gray as one plane, as gray
// with alpha 1, and as RGB; a colour one reads its colour. (Lossy: within 3/255.)
TEST(Image, JpegMapsReadInEveryChannelLayout) {
    const fs::path dir = fs::path(WISP_SOURCE_DIR) / "fuzz/corpus/image";
    const auto gray = read_image_planes(dir / "gray8.jpg", 2);
    ASSERT_EQ(gray.size(), 2u);
    EXPECT_EQ(gray[0].width, 16);
    EXPECT_EQ(gray[0].height, 8);
    for (const float v : gray[0].values)
        EXPECT_NEAR(v, 128.f / 255.f, 3.f / 255.f);
    for (const float a : gray[1].values)
        EXPECT_EQ(a, 1.f);
    const auto rgb = read_image_planes(dir / "rgb8.jpg", 4);
    ASSERT_EQ(rgb.size(), 4u);
    const float expected[] = {64.f / 255.f, 128.f / 255.f, 192.f / 255.f, 1.f};
    for (int c = 0; c < 4; ++c)
        for (const float v : rgb[size_t(c)].values)
            EXPECT_NEAR(v, expected[c], 3.f / 255.f) << c;
}

// A JPEG whose Huffman table declares 510 codes (a table holds 256): the fuzzer found that
// stb_image's decoder writes past its arrays on it. Refused with the decoder's reason.
TEST(Image, AJpegWithAnOverfullHuffmanTableIsRefused) {
    const fs::path p =
        fs::path(WISP_SOURCE_DIR) / "fuzz/corpus/image/jpeg_huffman_table_of_510_codes.jpg";
    try {
        read_gray_image(p);
        ADD_FAILURE() << "read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("jpeg_huffman_table_of_510_codes.jpg"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("Huffman"), std::string::npos) << e.what();
    }
}

// Formats wisp does not decode are named in the error, with the ones it does.
TEST(Image, OtherFormatsAreRefusedByName) {
    const std::pair<std::string, std::string> files[] = {
        {std::string("GIF89a\x01\x00\x01\x00\x00\x00\x00;", 14), "GIF"},
        {"8BPS\x00\x01", "Photoshop PSD"},
        {"#?RADIANCE\n", "Radiance HDR"},
        {"P5\n1 1\n255\n\x80", "PNM"},
        {std::string("\x76\x2F\x31\x01\x02\x00\x00\x00", 8), "OpenEXR"},
        {std::string("II*\0\x08\0\0\0", 8), "TIFF"},
        {std::string("RIFF\x10\0\0\0WEBPVP8 ", 16), "WebP"},
    };
    for (const auto& [bytes, name] : files) {
        try {
            decode_image_planes(bytes, "map.x", 1);
            ADD_FAILURE() << name;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("map.x: a " + name + " image"), std::string::npos)
                << e.what();
            EXPECT_NE(std::string(e.what()).find("PNG, JPEG, BMP or TGA"), std::string::npos)
                << e.what();
        }
    }
    EXPECT_THROW(decode_image_planes("\x89PNG", "map", 0), Error);
    EXPECT_THROW(decode_image_planes("RIFF\x01", "map", 1), Error);  // too short to say WEBP
}

}  // namespace
}  // namespace wisp
