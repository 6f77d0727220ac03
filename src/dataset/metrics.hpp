#pragma once
// How close a hairstyle A (a reconstruction) is to a reference B (the ground truth), by the
// metrics of the hair-reconstruction papers (docs/dataset.md "Comparing hair"):
//
//   strands     at each pair (d, θ) of thresholds: precision, the share of A's points that
//               have a point of B within d whose strand direction differs by under θ
//               (undirected: a line's orientation), recall the same from B to A, and
//               F1 = 2PR / (P + R). NeuralHaircut (Sklyarov et al. 2023) and its successors
//               report them at (2 mm, 20°), (3 mm, 30°) and (4 mm, 40°). Points are the
//               strands' control points; a direction is the chord through the neighbours.
//   chamfer     the mean distance from each point of A to the nearest of B, and from B to A.
//   position, curvature   when A and B have the same number of strands (strand i of one is
//               strand i of the other, as a generated and a reconstructed groom of one
//               style are): both resampled to the same points per strand, evenly in arc
//               length, the mean distance between corresponding points, and the mean
//               difference of the discrete curvature (the turning angle over the mean of the
//               two segment lengths, 1/cm) at corresponding interior points.
//   orientation, silhouette   seen from each of the views (framed on B and the head as
//               `wisp render --view` frames them): the mean undirected angle between A's and
//               B's orientation maps over the pixels both masks hold (HairSale's orientation
//               error), and the masks' intersection over union.
//   occupancy   the intersection over union of the voxels (of `voxel` cm) the strands of A
//               and of B pass through, every segment sampled at a quarter voxel.
//
// Units: cm and degrees. Deterministic: the same numbers at any thread count.
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/hair.hpp"
#include "geometry/mesh.hpp"

namespace wisp {

struct CompareOptions {
    // (distance cm, angle degrees) pairs.
    std::vector<std::pair<float, float>> thresholds = {{0.2f, 20.f}, {0.3f, 30.f}, {0.4f, 40.f}};
    std::vector<std::string> views = {"front", "left", "back", "right"};
    int size = 256;            // the views' pictures, pixels a side
    float voxel = 0.5f;        // cm, the occupancy grid's cell
    int resample_points = 32;  // per strand, for position and curvature
};

struct StrandScore {
    float distance = 0, angle = 0;  // the thresholds, cm and degrees
    double precision = 0, recall = 0, f1 = 0;
};

struct CompareResult {
    size_t strands_a = 0, strands_b = 0, points_a = 0, points_b = 0;
    std::vector<StrandScore> strands;
    double chamfer_a_to_b = 0, chamfer_b_to_a = 0;  // cm
    bool corresponding = false;                     // same strand count: the next two are set
    double position_error = 0;                      // cm
    double curvature_error = 0;                     // 1/cm
    double orientation_error = 0;                   // degrees; over the pixels both masks hold
    double silhouette_iou = 0;
    double occupancy_iou = 0;
};

// Compares A with the reference B; `head`, if not null, hides the hair behind it in the views.
// Throws wisp::Error for an empty hair, a non-finite point or a bad option.
CompareResult compare_hair(const Hair& a, const Hair& b, const Mesh* head,
                           const CompareOptions& options = {});

nlohmann::json to_json(const CompareResult& result);

}  // namespace wisp
