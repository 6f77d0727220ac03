// The npz writer: each array is built in memory (strands resampled in parallel, each into
// its own rows, so the bytes never depend on the thread count), then stored in the zip with
// its CRC-32 (zlib).
#include "io/npz.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <ostream>
#include <sstream>
#include <vector>

#include "core/atomic_file.hpp"
#include "core/catmull_rom.hpp"
#include "core/error.hpp"
#include "core/parallel.hpp"

namespace wisp {

namespace {

size_t dtype_size(const std::string& dtype) {
    if (dtype.size() == 3 && (dtype[0] == '<' || dtype[0] == '|') &&
        (dtype[1] == 'f' || dtype[1] == 'i' || dtype[1] == 'u') &&
        (dtype[2] == '1' || dtype[2] == '2' || dtype[2] == '4' || dtype[2] == '8'))
        return static_cast<size_t>(dtype[2] - '0');
    return 0;
}

// The version 1.0 header of one `.npy` file, padded with spaces so that the data starts at
// a multiple of 64 bytes, as numpy writes it; checks the data's size against the shape.
std::string npy_header(const NpyArray& a) {
    const size_t item = dtype_size(a.dtype);
    if (item == 0) fail(a.name, ": unsupported dtype '", excerpt(a.dtype), "'");
    size_t count = 1;
    for (size_t d : a.shape)
        count *= d;
    if (count * item != a.bytes)
        fail(a.name, ": ", a.bytes, " bytes of data for ", count, " elements of ", a.dtype);
    std::ostringstream dict;
    dict << "{'descr': '" << a.dtype << "', 'fortran_order': False, 'shape': (";
    size_t i = 0;
    for (size_t d : a.shape)
        dict << (i++ ? ", " : "") << d;
    dict << (a.shape.size() == 1 ? ",), }" : "), }");
    std::string h = dict.str();
    const size_t total = 10 + h.size() + 1;
    h.append((64 - total % 64) % 64, ' ');
    h += '\n';
    std::string out("\x93NUMPY\x01\x00", 8);
    const uint16_t len = static_cast<uint16_t>(h.size());
    out += static_cast<char>(len & 0xff);
    out += static_cast<char>(len >> 8);
    out += h;
    return out;
}

template <typename T>
void put(std::string& out, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out.append(b, sizeof(T));
}

// A zip archive of stored (uncompressed) members, written in order to a stream.
class ZipWriter {
  public:
    ZipWriter(std::ostream& out, uint64_t zip64_threshold)
        : out_(out), threshold_(zip64_threshold) {}

    void add(const std::string& name, const std::string& header, const void* data, size_t bytes) {
        Entry e;
        e.name = name;
        e.size = header.size() + bytes;
        e.offset = offset_;
        uLong crc = crc32_z(0L, reinterpret_cast<const Bytef*>(header.data()), header.size());
        crc = crc32_z(crc, static_cast<const Bytef*>(data), bytes);
        e.crc = static_cast<uint32_t>(crc);
        e.zip64 = e.size >= threshold_ || e.offset >= threshold_;
        std::string h;
        put<uint32_t>(h, 0x04034b50);
        put<uint16_t>(h, e.zip64 ? 45 : 20);  // version needed: 4.5 for ZIP64
        put<uint16_t>(h, 0);                  // flags
        put<uint16_t>(h, 0);                  // stored
        put<uint16_t>(h, 0);                  // time 00:00
        put<uint16_t>(h, 0x21);               // date 1980-01-01
        put<uint32_t>(h, e.crc);
        put<uint32_t>(h, e.zip64 ? 0xFFFFFFFFu : static_cast<uint32_t>(e.size));
        put<uint32_t>(h, e.zip64 ? 0xFFFFFFFFu : static_cast<uint32_t>(e.size));
        put<uint16_t>(h, static_cast<uint16_t>(name.size()));
        put<uint16_t>(h, e.zip64 ? 20 : 0);
        h += name;
        if (e.zip64) {
            put<uint16_t>(h, 0x0001);
            put<uint16_t>(h, 16);
            put<uint64_t>(h, e.size);
            put<uint64_t>(h, e.size);
        }
        write(h.data(), h.size());
        write(header.data(), header.size());
        write(data, bytes);
        entries_.push_back(std::move(e));
    }

    void finish() {
        const uint64_t cd_offset = offset_;
        std::string cd;
        for (const Entry& e : entries_) {
            put<uint32_t>(cd, 0x02014b50);
            put<uint16_t>(cd, e.zip64 ? 45 : 20);  // made by (MS-DOS attributes)
            put<uint16_t>(cd, e.zip64 ? 45 : 20);
            put<uint16_t>(cd, 0);
            put<uint16_t>(cd, 0);
            put<uint16_t>(cd, 0);
            put<uint16_t>(cd, 0x21);
            put<uint32_t>(cd, e.crc);
            put<uint32_t>(cd, e.zip64 ? 0xFFFFFFFFu : static_cast<uint32_t>(e.size));
            put<uint32_t>(cd, e.zip64 ? 0xFFFFFFFFu : static_cast<uint32_t>(e.size));
            put<uint16_t>(cd, static_cast<uint16_t>(e.name.size()));
            put<uint16_t>(cd, e.zip64 ? 28 : 0);
            put<uint16_t>(cd, 0);  // comment
            put<uint16_t>(cd, 0);  // disk
            put<uint16_t>(cd, 0);  // internal attributes
            put<uint32_t>(cd, 0);  // external attributes
            put<uint32_t>(cd, e.zip64 ? 0xFFFFFFFFu : static_cast<uint32_t>(e.offset));
            cd += e.name;
            if (e.zip64) {  // the three fields set to 0xFFFFFFFF above, in this order
                put<uint16_t>(cd, 0x0001);
                put<uint16_t>(cd, 24);
                put<uint64_t>(cd, e.size);
                put<uint64_t>(cd, e.size);
                put<uint64_t>(cd, e.offset);
            }
        }
        write(cd.data(), cd.size());
        const uint64_t cd_size = cd.size(), count = entries_.size();
        const bool zip64 =
            cd_offset >= threshold_ || cd_size >= threshold_ || count >= 0xFFFF ||
            std::any_of(entries_.begin(), entries_.end(), [](const Entry& e) { return e.zip64; });
        std::string end;
        if (zip64) {
            const uint64_t record = offset_;
            put<uint32_t>(end, 0x06064b50);
            put<uint64_t>(end, 44);  // size of the rest of the record
            put<uint16_t>(end, 45);
            put<uint16_t>(end, 45);
            put<uint32_t>(end, 0);
            put<uint32_t>(end, 0);
            put<uint64_t>(end, count);
            put<uint64_t>(end, count);
            put<uint64_t>(end, cd_size);
            put<uint64_t>(end, cd_offset);
            put<uint32_t>(end, 0x07064b50);  // the locator
            put<uint32_t>(end, 0);
            put<uint64_t>(end, record);
            put<uint32_t>(end, 1);
        }
        put<uint32_t>(end, 0x06054b50);
        put<uint16_t>(end, 0);
        put<uint16_t>(end, 0);
        put<uint16_t>(end, zip64 ? 0xFFFF : static_cast<uint16_t>(count));
        put<uint16_t>(end, zip64 ? 0xFFFF : static_cast<uint16_t>(count));
        put<uint32_t>(end, zip64 ? 0xFFFFFFFFu : static_cast<uint32_t>(cd_size));
        put<uint32_t>(end, zip64 ? 0xFFFFFFFFu : static_cast<uint32_t>(cd_offset));
        put<uint16_t>(end, 0);
        write(end.data(), end.size());
    }

  private:
    struct Entry {
        std::string name;
        uint64_t size = 0, offset = 0;
        uint32_t crc = 0;
        bool zip64 = false;
    };
    void write(const void* p, size_t n) {
        out_.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
        offset_ += n;
    }
    std::ostream& out_;
    uint64_t threshold_;
    uint64_t offset_ = 0;
    std::vector<Entry> entries_;
};

void check(const Hair& hair, const std::string& name, const NpzWriteOptions& options) {
    hair.validate(name);
    if (options.points_per_strand < 2 || options.points_per_strand > 4096)
        fail(name, ": points per strand must be in [2, 4096], not ", options.points_per_strand);
    for (size_t s = 0; s < hair.strand_count(); ++s)
        if (hair.strand_size(s) == 0) fail(name, ": strand ", s, " has no points");
}

void add_array(ZipWriter& zip, const NpyArray& a) {
    zip.add(a.name + ".npy", npy_header(a), a.data, a.bytes);
}

template <typename T>
requires(!std::is_arithmetic_v<T>)  // Eigen vectors: packed scalars
    void add_array(ZipWriter& zip, const char* name, std::vector<size_t> shape,
                   const std::vector<T>& v) {
    using Scalar = std::remove_cv_t<std::remove_reference_t<decltype(*v.data()->data())>>;
    add_array(zip, npy_array(name, std::move(shape),
                             std::span<const Scalar>(v.empty() ? nullptr : v.data()->data(),
                                                     v.size() * sizeof(T) / sizeof(Scalar))));
}

template <typename T>
requires std::is_arithmetic_v<T>
void add_array(ZipWriter& zip, const char* name, std::vector<size_t> shape,
               const std::vector<T>& v) {
    add_array(zip, npy_array(name, std::move(shape), std::span<const T>(v)));
}

void write_archive(std::ostream& os, const Hair& hair, const NpzWriteOptions& options) {
    static_assert(sizeof(Vec3f) == 12 && sizeof(Vec2f) == 8, "Eigen vectors are packed floats");
    ZipWriter zip(os, options.zip64_threshold);
    const size_t S = hair.strand_count(), N = static_cast<size_t>(options.points_per_strand);
    {
        std::vector<Vec3f> points(S * N);
        std::vector<float> widths(S * N);
        parallel_for(
            S,
            [&](size_t s) {
                const std::span<const float> w =
                    hair.widths.empty()
                        ? std::span<const float>()
                        : std::span<const float>(hair.widths.data() + hair.offsets[s],
                                                 hair.strand_size(s));
                catmull_rom_resample(hair.strand(s), w, hair.default_width,
                                     {points.data() + s * N, N}, {widths.data() + s * N, N});
            },
            256);
        add_array(zip, "positions", {S, N, 3}, points);
        add_array(zip, "widths", {S, N}, widths);
    }
    add_array(zip, "control_points", {hair.point_count(), 3}, hair.points);
    const std::vector<int64_t> offsets(hair.offsets.begin(), hair.offsets.end());
    add_array(zip, "offsets", {offsets.size()}, offsets);
    if (hair.colors.empty())
        add_array(zip, "colors", {S, 3}, std::vector<Vec3f>(S, hair.default_color));
    else
        add_array(zip, "colors", {S, 3}, hair.colors);
    if (!hair.wisp.empty()) add_array(zip, "wisp_id", {S}, hair.wisp);
    if (!hair.group.empty()) add_array(zip, "group_id", {S}, hair.group);
    if (!hair.root_uv.empty()) add_array(zip, "root_uv", {S, 2}, hair.root_uv);
    if (!hair.root_normal.empty()) add_array(zip, "root_normal", {S, 3}, hair.root_normal);
    zip.finish();
}

}  // namespace

std::string encode_npz(const Hair& hair, const std::string& name, const NpzWriteOptions& options) {
    check(hair, name, options);
    std::ostringstream os;
    write_archive(os, hair, options);
    return std::move(os).str();
}

void write_npz(const std::filesystem::path& path, const Hair& hair,
               const NpzWriteOptions& options) {
    check(hair, path.string(), options);
    write_file_atomic(path, [&](std::ostream& os) { write_archive(os, hair, options); });
}

std::string encode_npy(const NpyArray& array) {
    std::string out = npy_header(array);
    out.append(static_cast<const char*>(array.data), array.bytes);
    return out;
}

namespace {

void write_arrays(std::ostream& os, std::span<const NpyArray> arrays) {
    ZipWriter zip(os, 0xFFFFFFFFu);
    for (const NpyArray& a : arrays)
        add_array(zip, a);
    zip.finish();
}

void check_arrays(std::span<const NpyArray> arrays, const std::string& where) {
    for (size_t i = 0; i < arrays.size(); ++i) {
        npy_header(arrays[i]);
        for (size_t j = 0; j < i; ++j)
            if (arrays[j].name == arrays[i].name)
                fail(where, ": two arrays named '", excerpt(arrays[i].name), "'");
    }
}

}  // namespace

std::string encode_npz(std::span<const NpyArray> arrays) {
    check_arrays(arrays, "npz");
    std::ostringstream os;
    write_arrays(os, arrays);
    return std::move(os).str();
}

void write_npz(const std::filesystem::path& path, std::span<const NpyArray> arrays) {
    check_arrays(arrays, path.string());
    write_file_atomic(path, [&](std::ostream& os) { write_arrays(os, arrays); });
}

}  // namespace wisp
