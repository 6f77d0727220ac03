#pragma once
// Images: grayscale maps read from PNG (scalp maps, masks) and RGB images written to PNG.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.hpp"

namespace wisp {

// A single-channel image with values in [0, 1]; row 0 is the top row of the file.
struct GrayImage {
    int width = 0, height = 0;
    std::vector<float> values;  // #width·height, row-major

    // Bilinear lookup at texture coordinates (u, v) in [0,1]², v = 0 at the bottom row
    // (OBJ/OpenGL convention); clamped at the edges.
    float sample(float u, float v) const;
};

// Reads an 8- or 16-bit PNG, a JPEG, a BMP or a TGA as gray; colour images are converted by
// luminance. Other formats (GIF, PSD, EXR, ...) are refused by name. Throws wisp::Error naming the
// file if it cannot.
GrayImage read_gray_image(const std::filesystem::path& path);
// The most an image file (a map or a mask) may hold.
inline constexpr uint64_t kMaxImageFileBytes = uint64_t(256) << 20;

// Reads the same files as `channels` planes (1: gray, 2: gray and alpha, 3: RGB, 4: RGBA;
// a gray file read as RGB has three equal planes, a file without alpha reads
// alpha 1). Throws wisp::Error naming the file if it cannot.
std::vector<GrayImage> read_image_planes(const std::filesystem::path& path, int channels);
// The same from the bytes of a file already in memory; `source` names it in errors.
std::vector<GrayImage> decode_image_planes(std::string_view bytes, const std::string& source,
                                           int channels);

// An 8-bit grayscale PNG of `image` (each value clamped to [0,1] and rounded to 1/255), the
// same bytes for the same image. read_gray_image of the file gives back exactly the 8-bit
// values (v/255), so a map the editor holds and the file it saves give the same hair.
std::string encode_gray_png(const GrayImage& image);

// An 8-bit RGB image.
struct RgbImage {
    int width = 0, height = 0;
    std::vector<uint8_t> rgb;  // #width·height·3, row-major, top row first
};

// The PNG file's bytes of an image (for Python's _repr_png_); throws wisp::Error if encoding
// fails.
std::string encode_png(const RgbImage& image);

// Writes a PNG atomically; throws wisp::Error if it cannot.
void write_png(const std::filesystem::path& path, const RgbImage& image);

}  // namespace wisp
