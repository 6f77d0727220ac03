#pragma once
// The built-in procedural head, neck and shoulders: smooth, closed, about 22 cm from chin
// to crown, in centimetres, Y up, facing +Z, so that no file is needed for the default run.
#include "geometry/mesh.hpp"

namespace wisp {

// Builds the built-in mesh: a closed, manifold, genus-0 triangle mesh (~29k vertices, ~58k
// triangles, counter-clockwise seen from outside) with face groups "scalp" (the hair-bearing
// cap above a hairline: ~6.5 cm below the crown at the forehead, above the ears, down to the
// nape ~16 cm below the crown) and "body" for the rest, and UVs (the polar map about the
// cranium centre (0, 2, -1): crown at (0.5, 0.5), +Z toward v = 1, +X toward u = 1, radius
// = polar angle / 2π). Deterministic; about 50 ms.
//
// Head space, centimetres, Y up, facing +Z (the nose points along +Z), symmetric in x. The
// origin is the centre of the head between the ears at ear-canal height:
//   crown (top of the head)   y ≈ +12       chin               y ≈ -10
//   brow / occiput            z ≈ +9.3 / -11.1 (≈20 cm deep, 15.5 cm wide above the ears)
//   nose tip                  (0, -2.4, 11.4)
//   neck, 11.2 cm wide        y ≈ -8 … -17  neck base (trapezius) y ≈ -18
//   shoulders, 38.6 cm wide   y ≈ -25       flat bottom of the chest y = -38
Mesh builtin_head_mesh();

}  // namespace wisp
