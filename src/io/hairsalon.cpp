#include "io/hairsalon.hpp"

#include <cstring>
#include <vector>

#include "core/atomic_file.hpp"
#include "core/catmull_rom.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"
#include "io/io_util.hpp"

namespace wisp {

namespace {

template <typename Reader>
int32_t read_int32(Reader& in, std::string_view what) {
    int32_t v;
    in.read_bytes(&v, sizeof v, what);
    return v;
}

// Reads from a ByteReader (memory) or a FileReader (straight into the arrays: its size is
// taken once at open, so an endless file such as /dev/zero, which reports 0, fails at once).
template <typename Reader>
Hair decode(Reader& in, HairSalonStats* stats) {
    const int32_t count = read_int32(in, "the strand count");
    if (count < 0) in.fail_at(0, "negative strand count ", count);
    // Each strand needs at least its 4-byte vertex count.
    if (uint64_t(count) * 4 > in.remaining())
        in.fail_at(0, "header declares ", count, " strands, which need at least ",
                   uint64_t(count) * 4, " more bytes, but the file has ", in.remaining());
    HairSalonStats st;
    st.strands_in_file = size_t(count);
    Hair hair;
    hair.offsets.reserve(size_t(count) + 1);
    constexpr float kCentimetresPerMetre = 100.f;
    for (int32_t s = 0; s < count; ++s) {
        const size_t at = in.offset();
        const int32_t n = read_int32(in, "a strand's vertex count");
        if (n < 0) in.fail_at(at, "strand ", s, " has a negative vertex count ", n);
        in.require(uint64_t(n) * 12, cat("strand ", s, "'s ", n, " vertices"));
        if (n <= 1) {
            in.skip(size_t(n) * 12, "a bare root");
            ++st.bare_roots;
            continue;
        }
        const size_t first = hair.points.size();
        hair.points.resize(first + size_t(n));
        const size_t data_at = in.offset();
        in.read_bytes(hair.points.data() + first, size_t(n) * 12, "vertices");
        for (size_t k = first; k < hair.points.size(); ++k) {
            if (!hair.points[k].allFinite())
                in.fail_at(data_at + 12 * (k - first), "strand ", s, " vertex ", k - first,
                           " is not finite");
            hair.points[k] *= kCentimetresPerMetre;
        }
        if (hair.points.size() > UINT32_MAX) in.fail_at(at, "more than 2^32 points");
        hair.offsets.push_back(static_cast<uint32_t>(hair.points.size()));
    }
    if (in.remaining() != 0)
        in.fail_at(in.offset(), in.remaining(), " unexpected bytes after the last strand");
    hair.validate(in.name());
    if (stats) *stats = st;
    return hair;
}

void check_writable_hair(const Hair& hair, const std::string& name, int points_per_strand) {
    hair.validate(name);
    if (points_per_strand < 2 || points_per_strand > 4096)
        fail(name, ": points per strand must be in [2, 4096], not ", points_per_strand);
    if (hair.strand_count() > size_t(INT32_MAX))
        fail(name, ": ", hair.strand_count(), " strands, more than a .data file can count");
    for (size_t s = 0; s < hair.strand_count(); ++s)
        if (hair.strand_size(s) == 0) fail(name, ": strand ", s, " has no points");
}

// Strands are resampled and converted in parallel, each into its own bytes, in blocks so
// that a large file is never held whole; the bytes never depend on the thread count.
template <typename Sink>
void encode(const Hair& hair, int points_per_strand, Sink&& sink) {
    const size_t S = hair.strand_count(), N = size_t(points_per_strand);
    const size_t record = 4 + N * 12;
    std::string buf;
    const int32_t count = static_cast<int32_t>(S);
    buf.append(reinterpret_cast<const char*>(&count), 4);
    sink(buf);
    constexpr size_t kBlock = 16384;
    for (size_t first = 0; first < S; first += kBlock) {
        const size_t last = std::min(S, first + kBlock);
        buf.resize((last - first) * record);
        parallel_for(
            last - first,
            [&](size_t i) {
                const size_t s = first + i;
                static thread_local std::vector<Vec3f> pts;
                static thread_local std::vector<float> widths;
                pts.resize(N);
                widths.resize(N);
                catmull_rom_resample(hair.strand(s), {}, 0.f, pts, widths);
                // Centimetres to metres. The curve can overshoot a strand's control points:
                // clamped to ±kMaxCoordinate, so that what is written always reads back.
                for (Vec3f& p : pts)
                    p = p.cwiseMax(-kMaxCoordinate).cwiseMin(kMaxCoordinate) / 100.f;
                char* out = buf.data() + i * record;
                const int32_t n = static_cast<int32_t>(N);
                std::memcpy(out, &n, 4);
                std::memcpy(out + 4, pts.data(), N * 12);
            },
            256);
        sink(buf);
    }
}

}  // namespace

std::string encode_hairsalon(const Hair& hair, const std::string& name, int points_per_strand) {
    check_writable_hair(hair, name, points_per_strand);
    std::string out;
    encode(hair, points_per_strand, [&](const std::string& b) { out += b; });
    return out;
}

void write_hairsalon(const std::filesystem::path& path, const Hair& hair, int points_per_strand) {
    check_writable_hair(hair, path.string(), points_per_strand);
    write_file_atomic(path, [&](std::ostream& os) {
        encode(hair, points_per_strand, [&](const std::string& b) {
            os.write(b.data(), static_cast<std::streamsize>(b.size()));
        });
    });
}

Hair decode_hairsalon(std::string_view bytes, const std::string& name, HairSalonStats* stats) {
    io_detail::ByteReader in(bytes, name);
    return decode(in, stats);
}

Hair read_hairsalon(const std::filesystem::path& path, HairSalonStats* stats) {
    io_detail::FileReader in(path);
    return decode(in, stats);
}

}  // namespace wisp
