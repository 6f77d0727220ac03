#include "core/image.hpp"

#include <stb_image.h>
#include <stb_image_write.h>
#include <turbojpeg.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/atomic_file.hpp"
#include "core/error.hpp"

namespace wisp {

float GrayImage::sample(float u, float v) const {
    if (width == 0 || height == 0) return 0.f;
    const float x = std::clamp(u, 0.f, 1.f) * static_cast<float>(width - 1);
    const float y = (1.f - std::clamp(v, 0.f, 1.f)) * static_cast<float>(height - 1);
    const int x0 = std::min(static_cast<int>(x), std::max(width - 2, 0));
    const int y0 = std::min(static_cast<int>(y), std::max(height - 2, 0));
    const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
    const float fx = x - x0, fy = y - y0;
    auto at = [&](int i, int j) { return values[static_cast<size_t>(j) * width + i]; };
    return (at(x0, y0) * (1 - fx) + at(x1, y0) * fx) * (1 - fy) +
           (at(x0, y1) * (1 - fx) + at(x1, y1) * fx) * fy;
}

namespace {

// The most pixels a byte of the file can hold in its format at its best compression: a header
// claiming more (beyond a megapixel) is truncated or corrupt, and a few bytes would otherwise
// decode to 64 Mpixel. PNG: deflate's 1,032 to 1 on 1-bit pixels; JPEG: an empty 8×8 block in
// 2 bits; BMP: runs of 255 in 2 bytes; TGA (no signature): runs of 128 in 2 bytes.
int64_t most_pixels_per_byte(std::string_view b) {
    const auto starts = [&](std::string_view magic) { return b.substr(0, magic.size()) == magic; };
    if (starts("\x89PNG")) return 8400;
    if (starts("\xFF\xD8")) return 256;
    if (starts("BM")) return 128;
    return 64;
}

// A PNG's chunks each fit in the file: stb_image grows its buffer to a chunk's declared length
// before reading it, so a corrupt length would have it ask for gigabytes.
void check_png_chunks(std::string_view b, const std::string& source) {
    size_t pos = 8;
    while (pos + 8 <= b.size()) {
        const auto byte = [&](size_t i) { return uint32_t(static_cast<uint8_t>(b[pos + i])); };
        const uint32_t length = byte(0) << 24 | byte(1) << 16 | byte(2) << 8 | byte(3);
        if (length > b.size() - pos - 8)
            fail(source, ": PNG chunk '", b.substr(pos + 4, 4), "' at byte ", pos, " declares ",
                 length, " bytes, more than the file holds (truncated or corrupt)");
        if (b.substr(pos + 4, 4) == "IEND") return;
        pos += size_t(length) + 12;
    }
}

}  // namespace

std::vector<GrayImage> read_image_planes(const std::filesystem::path& path, int channels) {
    const std::string bytes = read_file(path, {kMaxImageFileBytes, "an image file"});
    return decode_image_planes(bytes, path.string(), channels);
}

namespace {

// Formats some tools write and wisp does not read, known by their first bytes, so that the
// error names what the file is. (stb_impl.cpp says why GIF, PSD, PIC, HDR and PNM are not
// decoded.)
std::string_view refused_format(std::string_view b) {
    const auto starts = [&](std::string_view magic) { return b.substr(0, magic.size()) == magic; };
    if (starts("GIF8")) return "GIF";
    if (starts("8BPS")) return "Photoshop PSD";
    if (starts("\x53\x80\xF6\x34")) return "Softimage PIC";
    if (starts("#?")) return "Radiance HDR";
    if (b.size() >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '7') return "PNM";
    if (starts("\x76\x2F\x31\x01")) return "OpenEXR";
    if (starts(std::string_view("II*\0", 4)) || starts(std::string_view("MM\0*", 4))) return "TIFF";
    if (starts("RIFF") && b.size() >= 12 && b.substr(8, 4) == "WEBP") return "WebP";
    return {};
}

// A size that is out of range, or more pixels than the file's bytes can hold, is refused
// before anything is decoded.
void check_image_size(int w, int h, std::string_view bytes, const std::string& source) {
    if (w <= 0 || h <= 0 || static_cast<int64_t>(w) * h > (int64_t{1} << 26))
        fail(source, ": image size ", w, "x", h, " is out of range (at most 64 Mpixel)");
    if (static_cast<int64_t>(w) * h >
        std::max<int64_t>(int64_t{1} << 20,
                          most_pixels_per_byte(bytes) * static_cast<int64_t>(bytes.size())))
        fail(source, ": image size ", w, "x", h, " is more than a file of ", bytes.size(),
             " bytes can hold (truncated or corrupt)");
}

// `channels` planes of interleaved pixels whose full scale is `scale`.
template <typename T>
std::vector<GrayImage> split_planes(const T* pixels, int w, int h, int stride, int channels,
                                    float scale) {
    std::vector<GrayImage> planes(static_cast<size_t>(channels));
    const size_t count = static_cast<size_t>(w) * h;
    for (int c = 0; c < channels; ++c) {
        GrayImage& img = planes[static_cast<size_t>(c)];
        img.width = w;
        img.height = h;
        img.values.resize(count);
        // A plane the file does not have (alpha, or colour of a gray decode) is filled as
        // stb fills it: alpha 1, gray repeated.
        const int from = std::min(c, stride - 1);
        const bool opaque = c == channels - 1 && (channels == 2 || channels == 4) && c >= stride;
        for (size_t i = 0; i < count; ++i)
            img.values[i] = opaque ? 1.f : float(pixels[i * stride + from]) / scale;
    }
    return planes;
}

// JPEG through libjpeg-turbo (TurboJPEG), which is fuzzed upstream. Its warnings (a few
// stray bytes before a marker, a file cut short) decode as other tools decode them; errors
// are refused.
std::vector<GrayImage> decode_jpeg(std::string_view bytes, const std::string& source,
                                   int channels) {
    tjhandle tj = tjInitDecompress();
    if (!tj) fail(source, ": cannot start the JPEG decoder");
    struct Destroy {
        tjhandle h;
        ~Destroy() { tjDestroy(h); }
    } destroy{tj};
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    const auto len = static_cast<unsigned long>(bytes.size());
    int w = 0, h = 0, subsampling = 0, colorspace = 0;
    if (tjDecompressHeader3(tj, data, len, &w, &h, &subsampling, &colorspace) != 0)
        fail(source, ": not a readable JPEG (", tjGetErrorStr2(tj), ")");
    check_image_size(w, h, bytes, source);
    // Gray and gray-with-alpha decode to luminance, as stb converts colour to gray.
    const int format = channels <= 2 ? TJPF_GRAY : TJPF_RGB;
    const int stride = tjPixelSize[format];
    std::vector<unsigned char> pixels(static_cast<size_t>(w) * h * stride);
    // A progressive file of thousands of scans would take minutes: at most 500, as
    // libjpeg-turbo's own tools allow.
    if (tjDecompress2(tj, data, len, pixels.data(), w, 0, h, format,
                      TJFLAG_LIMITSCANS | TJFLAG_ACCURATEDCT) != 0 &&
        tjGetErrorCode(tj) != TJERR_WARNING)
        fail(source, ": cannot decode JPEG (", tjGetErrorStr2(tj), ")");
    return split_planes(pixels.data(), w, h, stride, channels, 255.f);
}

}  // namespace

std::vector<GrayImage> decode_image_planes(std::string_view bytes, const std::string& source,
                                           int channels) {
    if (channels < 1 || channels > 4)
        fail(source, ": ", channels, " channels asked of an image (1 to 4)");
    if (bytes.size() > kMaxImageFileBytes)
        fail(source, ": image of ", bytes.size(), " bytes is over the limit of ",
             kMaxImageFileBytes);
    if (const std::string_view name = refused_format(bytes); !name.empty())
        fail(source, ": a ", name, " image; wisp reads maps and masks as PNG, JPEG, BMP or TGA");
    if (bytes.size() >= 2 && static_cast<uint8_t>(bytes[0]) == 0xFF &&
        static_cast<uint8_t>(bytes[1]) == 0xD8)
        return decode_jpeg(bytes, source, channels);
    if (bytes.substr(0, 4) == "\x89PNG") check_png_chunks(bytes, source);
    int w = 0, h = 0, file_channels = 0;
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int len = static_cast<int>(bytes.size());
    if (!stbi_info_from_memory(data, len, &w, &h, &file_channels))
        fail(source, ": not a readable image (", stbi_failure_reason(),
             "; wisp reads PNG, JPEG, BMP and TGA)");
    check_image_size(w, h, bytes, source);
    stbi_us* pixels = stbi_load_16_from_memory(data, len, &w, &h, &file_channels, channels);
    if (!pixels) fail(source, ": cannot decode image (", stbi_failure_reason(), ")");
    std::vector<GrayImage> planes = split_planes(pixels, w, h, channels, channels, 65535.f);
    stbi_image_free(pixels);
    return planes;
}

GrayImage read_gray_image(const std::filesystem::path& path) {
    return std::move(read_image_planes(path, 1).front());
}

namespace {

// The PNG file's bytes of 8-bit pixels, `channels` per pixel, rows packed.
std::string png_bytes(int width, int height, int channels, const uint8_t* pixels) {
    std::string bytes;
    auto sink = [](void* ctx, void* data, int size) {
        static_cast<std::string*>(ctx)->append(static_cast<const char*>(data), size);
    };
    if (!stbi_write_png_to_func(sink, &bytes, width, height, channels, pixels, width * channels))
        fail("PNG encoding of a ", width, "×", height, " image failed");
    return bytes;
}

}  // namespace

std::string encode_gray_png(const GrayImage& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.values.size() != static_cast<size_t>(image.width) * image.height)
        fail("encode_gray_png: image ", image.width, "x", image.height, " holds ",
             image.values.size(), " values");
    std::vector<uint8_t> gray(image.values.size());
    for (size_t i = 0; i < gray.size(); ++i) {
        const float v = image.values[i];
        gray[i] = static_cast<uint8_t>(std::lround((v > 0.f ? std::min(v, 1.f) : 0.f) * 255.f));
    }
    return png_bytes(image.width, image.height, 1, gray.data());
}

std::string encode_png(const RgbImage& image) {
    return png_bytes(image.width, image.height, 3, image.rgb.data());
}

void write_png(const std::filesystem::path& path, const RgbImage& image) {
    std::string bytes;
    try {
        bytes = encode_png(image);
    } catch (const Error&) {
        fail(path.string(), ": PNG encoding failed");
    }
    write_file_atomic(path, bytes);
}

}  // namespace wisp
