#pragma once
// USC-HairSalon `.data` strands (Hu et al. 2015, 343 hairstyles), read and written.
// Little-endian: int32 strand count #S; per strand int32 vertex count n, then n×3 float32
// positions in metres. wisp multiplies by 100 (centimetres). Strands of 0 or 1 vertex are
// bare roots (a scalp sample with no hair): they are skipped and counted.
#include <filesystem>
#include <string>
#include <string_view>

#include "core/hair.hpp"

namespace wisp {

struct HairSalonStats {
    size_t strands_in_file = 0;  // #S of the header
    size_t bare_roots = 0;       // strands of 0 or 1 vertex, skipped
};

// Every count is checked against the bytes left before anything is allocated.
Hair decode_hairsalon(std::string_view bytes, const std::string& name,
                      HairSalonStats* stats = nullptr);
Hair read_hairsalon(const std::filesystem::path& path, HairSalonStats* stats = nullptr);

// Writing, as the data set has its strands: every strand resampled to `points_per_strand`
// points (the data set's 100) evenly spaced in arc length along wisp's curve
// (catmull_rom_resample), centimetres divided by 100 (metres). Positions only. Throws
// wisp::Error naming `name` for invalid hair, a strand without points, more than 2^31-1
// strands or points_per_strand outside [2, 4096].
inline constexpr int kHairSalonPoints = 100;
std::string encode_hairsalon(const Hair& hair, const std::string& name = "hair",
                             int points_per_strand = kHairSalonPoints);
void write_hairsalon(const std::filesystem::path& path, const Hair& hair,
                     int points_per_strand = kHairSalonPoints);

}  // namespace wisp
