#pragma once
// Shared helpers of the io tests: seeded random hair, unique temporary paths, bit-exact
// comparison.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/hair.hpp"

namespace wisp::test {

// A unique path under the temporary folder, removed when the object dies.
class TempPath {
  public:
    explicit TempPath(const std::string& ext) {
        static std::atomic<int> counter{0};
        path_ =
            std::filesystem::temp_directory_path() /
            ("wisp_io_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ext);
    }
    ~TempPath() {
        std::error_code ec;
        std::filesystem::remove(path_, ec);
    }
    const std::filesystem::path& path() const { return path_; }
    operator const std::filesystem::path&() const { return path_; }

  private:
    std::filesystem::path path_;
};

inline void write_bytes(const std::filesystem::path& p, std::string_view bytes) {
    write_file_atomic(p, bytes);
}

// Random strands with full-mantissa coordinates (round trips must be bit-exact).
// points_per_strand 0 = random counts in [2, 40].
inline Hair random_hair(uint32_t seed, size_t strands, uint32_t points_per_strand = 0,
                        bool widths = true, bool colors = true, bool wisp = true) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> coord(-30.f, 30.f), unit(0.f, 1.f), width(0.001f, 0.02f);
    std::uniform_int_distribution<uint32_t> count(2, 40);
    std::uniform_int_distribution<int32_t> id(-1, 500);
    Hair h;
    for (size_t s = 0; s < strands; ++s) {
        const uint32_t n = points_per_strand ? points_per_strand : count(rng);
        for (uint32_t i = 0; i < n; ++i) {
            h.points.emplace_back(coord(rng), coord(rng), coord(rng));
            if (widths) h.widths.push_back(width(rng));
        }
        h.offsets.push_back(static_cast<uint32_t>(h.points.size()));
        if (colors) h.colors.emplace_back(unit(rng), unit(rng), unit(rng));
        if (wisp) h.wisp.push_back(id(rng));
    }
    // A few awkward values: tiny, the largest allowed (kMaxCoordinate), negative zero, many
    // digits.
    if (h.points.size() > 4) {
        h.points[0] = Vec3f(1e-30f, -kMaxCoordinate, -0.f);
        h.points[1] = Vec3f(0.1f, 1.f / 3.f, 99999.992f);
    }
    return h;
}

inline bool same_bits(const void* a, const void* b, size_t n) {
    return std::memcmp(a, b, n) == 0;
}

// Points and offsets bit-exact.
inline void expect_same_geometry(const Hair& a, const Hair& b) {
    ASSERT_EQ(a.offsets, b.offsets);
    ASSERT_EQ(a.points.size(), b.points.size());
    EXPECT_TRUE(same_bits(a.points.data(), b.points.data(), a.points.size() * sizeof(Vec3f)));
}

// Effective widths (array or default) bit-exact.
inline void expect_same_widths(const Hair& a, const Hair& b) {
    ASSERT_EQ(a.point_count(), b.point_count());
    for (size_t i = 0; i < a.point_count(); ++i) {
        const float wa = a.width_at(i), wb = b.width_at(i);
        ASSERT_TRUE(same_bits(&wa, &wb, 4)) << "width " << i << ": " << wa << " vs " << wb;
    }
}

inline void expect_same_colors(const Hair& a, const Hair& b) {
    ASSERT_EQ(a.strand_count(), b.strand_count());
    for (size_t s = 0; s < a.strand_count(); ++s) {
        const Vec3f ca = a.color_of(s), cb = b.color_of(s);
        ASSERT_TRUE(same_bits(ca.data(), cb.data(), 12)) << "color " << s;
    }
}

// Runs f and expects a wisp::Error whose message contains `part`.
template <typename F>
void expect_error(F&& f, const std::string& part) {
    try {
        f();
        ADD_FAILURE() << "expected wisp::Error containing \"" << part << "\"";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(part), std::string::npos)
            << "message: " << e.what() << "\nexpected to contain: " << part;
    }
}

}  // namespace wisp::test

namespace wisp::test {
inline std::string read_file_text(const std::filesystem::path& p) {
    return read_file(p);
}
}  // namespace wisp::test
