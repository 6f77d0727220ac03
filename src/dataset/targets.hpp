#pragma once
// The training targets hair-reconstruction methods learn from, drawn for one camera:
//
//   orientation  #H×W  the undirected 2D direction θ ∈ [0, π) of the nearest strand at each
//                pixel, measured in the image from +x (right) towards up, as the orientation
//                maps of the literature (Paris et al. 2004, Chai et al. 2012, HairNet) give
//                it for photographs. Encoded in an RGB PNG as R = 255 on hair, G =
//                (1 + cos 2θ)/2, B = (1 + sin 2θ)/2 (θ and θ + π are one orientation);
//                black off the hair.
//   mask         #H×W  255 where hair in front of the head covers at least half the pixel,
//                else 0 (an 8-bit gray PNG)
//   depth        #H×W  float32 distance in cm along the camera's forward axis to the nearest
//                surface, the head or any strand drawn over the pixel (however little of it
//                the strand covers); 0 where there is neither (a .npy array)
//   strand       #H×W  the directed 2D direction of the nearest strand (root to tip), as
//                HairStep's strand map (Zheng et al. 2023): R = 255 on hair, 128 on the
//                head or body where no hair is, 0 elsewhere; G = (1 + dx)/2, B = (1 + dy)/2
//                for the unit direction (dx, dy), x right and y up; G = B = 0 off the hair
//   confidence   #H×W  float32 in [0, 1]: how well one orientation describes the hair seen in
//                the pixel, the length of the mean of e^{2iθ} over the strands there, each
//                weighted by the share of the pixel it shows (its coverage times what the
//                strands in front let through), as the confidence NeuralHaircut (Sklyarov
//                et al. 2023) weights its orientation loss with; 1 where they all agree, near
//                0 where strands cross; 0 off the hair
//   matte        #H×W  the share of the pixel that hair in front of the head covers,
//                1 − Π(1 − c) over the strands there (an alpha matte; 8-bit gray PNG)
//   strand_id    #H×W  int32 index of the nearest strand (the one depth and orientation
//                take), −1 where none is
//   depth_hairstep #H×W float32: depth as HairStep normalises it, (d − d_min)/(d_max − d_min)
//                over the hair mask (0 at the nearest hair, 1 at the farthest), 0 off it
//
// For the confidence, the strands nearest the eye in each pixel (up to kTargetLayers of them)
// are kept in depth order, a k-buffer; those behind them are merged into one layer behind
// (their coverage-weighted mean orientation), as multi-layer alpha blending (Salvi and
// Vaidyanathan 2014) merges what does not fit, and show through what the kept ones let pass.
//
// The head is rasterized as triangles at pixel centres; every strand segment between
// consecutive control points as a line (DDA, one sample per pixel on its major axis) whose
// samples in front of the head each cover the share of their pixel that the strand's
// projected width gives; a pixel is hair where they cover at least half of it, with the
// nearest strand's orientation there. Strands are drawn in order on one thread, so
// the maps are the same at any thread count.
#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/hair.hpp"
#include "core/image.hpp"
#include "geometry/mesh.hpp"
#include "render/camera.hpp"

namespace wisp {

inline constexpr int kTargetLayers = 8;

struct TargetMaps {
    int width = 0, height = 0;
    // Each #H·W, row-major, top row first.
    std::vector<float> depth;        // 0: background
    std::vector<float> orientation;  // θ in [0, π); meaningful where hair is set
    std::vector<float> direction;    // the nearest strand's, root to tip, in (−π, π], y up
    std::vector<uint8_t> hair;       // 1 where hair covers at least half the pixel
    std::vector<uint8_t> surface;    // 1 where the head (or body) mesh covers the pixel centre
    std::vector<float> coverage;     // the share of the pixel hair covers, in [0, 1]
    std::vector<float> confidence;   // in [0, 1]; 0 off the hair
    std::vector<int32_t> strand;     // the nearest strand's index; −1: none
};

// Draws the maps of hair (and head, if not null) seen by `camera`; the confidence (which
// keeps the k-buffer) only if asked for, else it is left 0.
TargetMaps draw_targets(const Hair& hair, const Mesh* head, const Camera& camera,
                        bool confidence = false);

// The hair as volumes on a grid over the box [lo, hi] (cm, head space) of dims (x, y, z)
// voxels, as HairNet (Zhou et al. 2018) and NeuralHDHair (Wu et al. 2022) train on: which
// voxels strands pass through, and the strands' mean direction (root to tip, unit; 0 where
// none pass or where directions cancel) in each. Every segment is sampled at half the
// smallest voxel side; what lies outside the box is left out. Arrays are z-major: voxel
// (x, y, z) at (z·dims.y + y)·dims.x + x, so numpy reads them with shape (z, y, x).
struct HairVolume {
    Vec3i dims = Vec3i::Zero();
    Vec3f lo = Vec3f::Zero(), hi = Vec3f::Zero();
    std::vector<uint8_t> occupancy;  // #voxels, 1 where a strand passes
    std::vector<float> orientation;  // #voxels·3
};
inline constexpr size_t kMaxVolumeVoxels = size_t{1} << 24;
// Throws wisp::Error for an empty box or dims outside [1, 1024] or past kMaxVolumeVoxels.
HairVolume hair_volume(const Hair& hair, const Vec3f& lo, const Vec3f& hi, const Vec3i& dims);

// The strands as a texture over the scalp's UV square (geometry/scalp.hpp), as DiffLocks
// (Rosu et al. 2025) and HAAR (Sklyarov et al. 2024) learn hair: texel (i, j) (row i from
// v = 1 at the top, column j from u = 0) holds the strand whose root lies nearest its centre
// among those rooted in it, resampled to `points` points evenly in arc length, as offsets
// from its root (cm, head space), with the root and the scalp's normal there; texels no root
// falls in are empty (mask 0, zeros). Needs the hair's root UVs.
struct ScalpTexture {
    int size = 0, points = 0;
    std::vector<uint8_t> mask;    // #size²
    std::vector<int32_t> strand;  // #size²: the strand's index, −1 where empty
    std::vector<float> offsets;   // #size²·points·3
    std::vector<float> roots;     // #size²·3
    std::vector<float> normals;   // #size²·3 (zeros where the hair has no root normals)
};
// Throws wisp::Error for hair without root UVs, or size outside [4, 1024], points outside
// [2, 1024] or size²·points past 2^26.
ScalpTexture scalp_texture(const Hair& hair, int size, int points);

// A camera as OpenCV has it (x right, y down, z forward): pixel = K (R p + t), pixel (i, j)
// covering [i, i+1) × [j, j+1); both row-major, K 3×3 and world_to_camera 4×4 (head space,
// cm, to camera space).
struct CameraMatrices {
    std::array<double, 9> K{};
    std::array<double, 16> world_to_camera{};
};
CameraMatrices opencv_matrices(const Camera& camera);

// The encodings above.
RgbImage orientation_image(const TargetMaps& maps);
GrayImage mask_image(const TargetMaps& maps);
RgbImage strand_map_image(const TargetMaps& maps);
GrayImage matte_image(const TargetMaps& maps);
std::vector<float> hairstep_depth(const TargetMaps& maps);

}  // namespace wisp
