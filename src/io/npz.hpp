#pragma once
// numpy's `.npz` for research code (write only): a zip archive of `.npy` arrays, stored
// uncompressed (so `numpy.load(path, mmap_mode=...)` style readers and any zip tool read it),
// little-endian, C order. `numpy.load("hair.npz")` gives:
//
//   positions       float32 #S×N×3  every strand resampled to N points evenly spaced in arc
//                                   length along wisp's pinned Catmull-Rom curve, root first;
//                                   centimetres, head space (Y up, +Z forward)
//   widths          float32 #S×N    diameter at those points, cm
//   control_points  float32 #P×3    wisp's own control points, strand after strand
//   offsets         int64   #S+1    strand i owns control_points[offsets[i]:offsets[i+1]]
//   colors          float32 #S×3    linear RGB (the default colour repeated when the hair has none)
//   wisp_id         int32   #S      (only when known)
//   group_id        int32   #S      (only when known; Hair::group)
//   root_uv         float32 #S×2    scalp UV of the root (only when known)
//   root_normal     float32 #S×3    unit scalp normal at the root (only when known)
//
// Archive members over 4 GiB, or starting past 4 GiB, are written with ZIP64 extra fields
// and a ZIP64 end record, which Python's zipfile (numpy.load) reads. Every member has the
// fixed date 1980-01-01 00:00, so the bytes depend only on the hair (and N).
#include <cstdint>
#include <filesystem>
#include <string>

#include "core/hair.hpp"

namespace wisp {

struct NpzWriteOptions {
    int points_per_strand = 32;  // N, in [2, 4096]
    // Members whose size or offset reaches this are written as ZIP64; lower only to test.
    uint64_t zip64_threshold = 0xFFFFFFFFu;
};

// The archive's bytes. Throws wisp::Error naming `name` for invalid hair, a strand without
// points, or N out of range.
std::string encode_npz(const Hair& hair, const std::string& name = "hair",
                       const NpzWriteOptions& options = {});
void write_npz(const std::filesystem::path& path, const Hair& hair,
               const NpzWriteOptions& options = {});

}  // namespace wisp
