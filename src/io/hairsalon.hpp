#pragma once
// USC-HairSalon `.data` strands (Hu et al. 2015, 343 hairstyles), read only.
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

}  // namespace wisp
