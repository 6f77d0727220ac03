#include "io/cyhair.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "io/io_util.hpp"

namespace wisp {
namespace {

constexpr size_t kHeaderSize = 128;
constexpr uint32_t kSegmentsBit = 1u << 0, kPointsBit = 1u << 1, kThicknessBit = 1u << 2,
                   kTransparencyBit = 1u << 3, kColorBit = 1u << 4;
constexpr uint32_t kMaxPointsPerStrand = 65536;  // uint16 segments + 1

struct Header {
    char signature[4];
    uint32_t strands, points, flags, d_segments;
    float d_thickness, d_transparency, d_color[3];
    char info[88];
};
static_assert(sizeof(Header) == kHeaderSize);

// Reads from a ByteReader (memory) or a FileReader (straight into the arrays).
template <typename Reader>
Hair decode(Reader& in) {
    const std::string& name = in.name();
    const size_t file_size = in.size();
    Header h;
    in.read_bytes(&h, sizeof h, "the 128-byte header");
    if (std::memcmp(h.signature, "HAIR", 4) != 0)
        in.fail_at(0, "not a cyHair file (no HAIR signature)");
    if (!(h.flags & kPointsBit))
        in.fail_at(12, "the file has no points array (flags ", h.flags, ")");
    if (h.flags >> 5) in.fail_at(12, "unknown array flags ", h.flags);

    // Expected file size from the header alone, in 64 bits: a hostile header cannot
    // overflow it, and nothing is allocated until the file is known to hold the arrays.
    const uint64_t S = h.strands, P = h.points;
    uint64_t expected = kHeaderSize;
    if (h.flags & kSegmentsBit) expected += 2 * S;
    expected += 12 * P;
    if (h.flags & kThicknessBit) expected += 4 * P;
    if (h.flags & kTransparencyBit) expected += 4 * P;
    if (h.flags & kColorBit) expected += 12 * P;
    if (expected != file_size)
        in.fail_at(file_size < expected ? file_size : expected, "header declares ", S,
                   " strands and ", P, " points (flags ", h.flags, "), which need ", expected,
                   " bytes, but the file has ", file_size);

    // Without a segments array every strand has d_segments + 1 points; check that before
    // sizing offsets by the (possibly hostile) strand count.
    if (!(h.flags & kSegmentsBit) && S * (uint64_t(h.d_segments) + 1) != P)
        in.fail_at(16, "no segments array: ", S, " strands of d_segments ", h.d_segments,
                   " + 1 points make ", S * (uint64_t(h.d_segments) + 1),
                   " points, but the header declares ", P);

    Hair hair;
    hair.offsets.resize(S + 1);
    hair.offsets[0] = 0;
    if (h.flags & kSegmentsBit) {
        const size_t at = in.offset();
        std::vector<uint16_t> segments(S);
        in.read_bytes(segments.data(), 2 * S, "segments");
        uint64_t sum = 0;
        for (size_t i = 0; i < S; ++i) {
            sum += uint64_t(segments[i]) + 1;
            if (sum > P)
                in.fail_at(at + 2 * i, "strand ", i, " ends at point ", sum,
                           " but the header declares only ", P, " points");
            hair.offsets[i + 1] = static_cast<uint32_t>(sum);
        }
        if (sum != P)
            in.fail_at(at, "segments add up to ", sum, " points but the header declares ", P);
    } else {
        for (size_t i = 0; i < S; ++i)
            hair.offsets[i + 1] = static_cast<uint32_t>((i + 1) * (uint64_t(h.d_segments) + 1));
    }

    const size_t points_at = in.offset();
    hair.points.resize(P);
    in.read_bytes(hair.points.data(), 12 * P, "points");
    for (size_t i = 0; i < P; ++i)
        if (!hair.points[i].allFinite())
            in.fail_at(points_at + 12 * i, "point ", i, " is not finite");

    if (h.flags & kThicknessBit) {
        const size_t at = in.offset();
        hair.widths.resize(P);
        in.read_bytes(hair.widths.data(), 4 * P, "thickness");
        for (size_t i = 0; i < P; ++i)
            if (!std::isfinite(hair.widths[i]) || hair.widths[i] < 0.f)
                in.fail_at(at + 4 * i, "thickness ", i, " is negative or not finite");
    } else if (std::isfinite(h.d_thickness) && h.d_thickness > 0.f) {
        hair.default_width = h.d_thickness;
    }
    if (h.flags & kTransparencyBit) in.skip(4 * P, "transparency");  // not used by wisp

    if (h.flags & kColorBit) {
        // Only each strand's first color is kept; the array is read in blocks.
        const size_t at = in.offset();
        hair.colors.resize(S);
        constexpr size_t kBlock = 1 << 16;
        std::vector<Vec3f> block(std::min<size_t>(P, kBlock));
        size_t strand = 0;
        for (size_t lo = 0; lo < P; lo += kBlock) {
            const size_t n = std::min<size_t>(kBlock, P - lo);
            in.read_bytes(block.data(), 12 * n, "color");
            for (size_t k = 0; k < n; ++k)
                if (!block[k].allFinite())
                    in.fail_at(at + 12 * (lo + k), "color ", lo + k, " is not finite");
            for (; strand < S && hair.offsets[strand] < lo + n; ++strand)
                hair.colors[strand] = block[hair.offsets[strand] - lo];
        }
    } else {
        const Vec3f c(h.d_color[0], h.d_color[1], h.d_color[2]);
        if (c.allFinite()) hair.default_color = c;
    }
    hair.validate(name);
    return hair;
}

}  // namespace

Hair decode_cyhair(std::string_view bytes, const std::string& name) {
    io_detail::ByteReader in(bytes, name);
    return decode(in);
}

Hair read_cyhair(const std::filesystem::path& path) {
    io_detail::FileReader in(path);
    return decode(in);
}

namespace {

void write_stream(std::ostream& out, const Hair& hair, const std::string& name) {
    hair.validate(name);
    const size_t S = hair.strand_count(), P = hair.point_count();
    bool uniform = true;
    for (size_t i = 0; i < S; ++i) {
        const uint32_t n = hair.strand_size(i);
        if (n == 0) fail(name, ": strand ", i, " has no points; cyHair strands have at least one");
        if (n > kMaxPointsPerStrand)
            fail(name, ": strand ", i, " has ", n, " points; cyHair stores at most ",
                 kMaxPointsPerStrand, " per strand (uint16 segment counts)");
        if (n != hair.strand_size(0)) uniform = false;
    }

    Header h{};
    std::memcpy(h.signature, "HAIR", 4);
    h.strands = static_cast<uint32_t>(S);
    h.points = static_cast<uint32_t>(P);
    h.flags = kPointsBit | (uniform ? 0u : kSegmentsBit) |
              (hair.widths.empty() ? 0u : kThicknessBit) | (hair.colors.empty() ? 0u : kColorBit);
    h.d_segments = S > 0 && uniform ? hair.strand_size(0) - 1 : 0;
    h.d_thickness = hair.default_width;
    h.d_transparency = 0.f;
    for (int k = 0; k < 3; ++k)
        h.d_color[k] = hair.default_color[k];
    std::strncpy(h.info, "wisp hair, centimetres, Y up", sizeof h.info - 1);

    auto put = [&out](const void* p, size_t n) {
        out.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
    };
    put(&h, kHeaderSize);
    if (!uniform) {
        std::vector<uint16_t> segments(S);
        for (size_t i = 0; i < S; ++i)
            segments[i] = static_cast<uint16_t>(hair.strand_size(i) - 1);
        put(segments.data(), 2 * S);
    }
    put(hair.points.data(), 12 * P);
    if (!hair.widths.empty()) put(hair.widths.data(), 4 * P);
    if (!hair.colors.empty()) {
        // Each strand's color repeated on its points, in blocks.
        std::vector<Vec3f> block;
        block.reserve(1 << 16);
        for (size_t i = 0; i < S; ++i) {
            block.insert(block.end(), hair.strand_size(i), hair.colors[i]);
            if (block.size() >= (1 << 16) || i + 1 == S) {
                put(block.data(), 12 * block.size());
                block.clear();
            }
        }
    }
}

}  // namespace

std::string encode_cyhair(const Hair& hair, const std::string& name) {
    std::ostringstream out;
    write_stream(out, hair, name);
    return std::move(out).str();
}

void write_cyhair(const std::filesystem::path& path, const Hair& hair) {
    write_file_atomic(path, [&](std::ostream& out) { write_stream(out, hair, path.string()); });
}

}  // namespace wisp
