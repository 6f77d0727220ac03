#include "io/hairsalon.hpp"

#include "core/error.hpp"
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

}  // namespace

Hair decode_hairsalon(std::string_view bytes, const std::string& name, HairSalonStats* stats) {
    io_detail::ByteReader in(bytes, name);
    return decode(in, stats);
}

Hair read_hairsalon(const std::filesystem::path& path, HairSalonStats* stats) {
    io_detail::FileReader in(path);
    return decode(in, stats);
}

}  // namespace wisp
