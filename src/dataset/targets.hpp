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
//
// The head is rasterized as triangles at pixel centres; every strand segment between
// consecutive control points as a line (DDA, one sample per pixel on its major axis) whose
// samples in front of the head each cover the share of their pixel that the strand's
// projected width gives; a pixel is hair where they cover at least half of it, with the
// nearest strand's orientation there. Strands are drawn in order on one thread, so
// the maps are the same at any thread count.
#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/hair.hpp"
#include "core/image.hpp"
#include "geometry/mesh.hpp"
#include "render/camera.hpp"

namespace wisp {

struct TargetMaps {
    int width = 0, height = 0;
    std::vector<float> depth;        // #H·W, row-major, top row first; 0: background
    std::vector<float> orientation;  // #H·W, θ in [0, π); meaningful where hair is set
    std::vector<uint8_t> hair;       // #H·W, 1 where hair covers at least half the pixel
};

// Draws the maps of hair (and head, if not null) seen by `camera`.
TargetMaps draw_targets(const Hair& hair, const Mesh* head, const Camera& camera);

// The encodings above.
RgbImage orientation_image(const TargetMaps& maps);
GrayImage mask_image(const TargetMaps& maps);

}  // namespace wisp
