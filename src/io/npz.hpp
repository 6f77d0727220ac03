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
#include <span>
#include <string>
#include <type_traits>
#include <vector>

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

// One array of any other archive (a dataset sample's cameras, a depth map): the member's name
// without ".npy", numpy's dtype ("<f4", "<f8", "<i4", "<i8", "<u4", "|u1"), the shape, and
// the data in C order, little-endian: product(shape) elements of the dtype's size.
struct NpyArray {
    std::string name;
    std::string dtype;
    std::vector<size_t> shape;
    const void* data = nullptr;
    size_t bytes = 0;
};

// numpy's dtype of an arithmetic type.
template <typename T>
constexpr const char* npy_dtype() {
    static_assert(std::is_arithmetic_v<T>, "npy_dtype: an arithmetic type");
    if constexpr (std::is_floating_point_v<T>)
        return sizeof(T) == 4 ? "<f4" : "<f8";
    else if constexpr (sizeof(T) == 1)
        return std::is_signed_v<T> ? "|i1" : "|u1";
    else if constexpr (std::is_signed_v<T>)
        return sizeof(T) == 2 ? "<i2" : sizeof(T) == 4 ? "<i4" : "<i8";
    else
        return sizeof(T) == 2 ? "<u2" : sizeof(T) == 4 ? "<u4" : "<u8";
}

// An NpyArray viewing `values` (which must outlive it) with the given shape.
template <typename T>
NpyArray npy_array(std::string name, std::vector<size_t> shape, std::span<const T> values) {
    return {std::move(name), npy_dtype<T>(), std::move(shape), values.data(),
            values.size() * sizeof(T)};
}

// The `.npy` bytes of one array (version 1.0, the header padded so that the data starts at a
// multiple of 64 bytes, as numpy writes it). Throws wisp::Error naming the array if its bytes
// do not match its shape and dtype.
std::string encode_npy(const NpyArray& array);

// An archive of the arrays, in order, as the hair's (stored, fixed dates): the bytes depend
// only on the arrays. Throws wisp::Error as encode_npy, or for two arrays of one name.
std::string encode_npz(std::span<const NpyArray> arrays);
void write_npz(const std::filesystem::path& path, std::span<const NpyArray> arrays);

}  // namespace wisp
