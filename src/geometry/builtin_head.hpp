#pragma once
// The built-in procedural figure: a smooth mannequin of an adult's head and upper body, 22.8 cm
// from chin to crown, with ears, eyes in their sockets, nose, lips, jaw and chin, a
// forward-leaning neck, trapezius, shoulders, chest, back, the waist and arms hanging beside
// it, cut flat through the top of the hips like a display mannequin; in centimetres, Y up,
// facing +Z, so that no file is needed for the default run. Long hair rests on its shoulders,
// chest and back.
#include "geometry/mesh.hpp"

namespace wisp {

// Builds the built-in mesh: a closed, manifold, genus-0 triangle mesh (~25k vertices, ~50k
// triangles, counter-clockwise seen from outside) with face groups "scalp" (the hair-bearing
// cap above a hairline: 6.3 cm below the crown at the forehead, receding at the temples,
// sideburns in front of the ears down to about the ear canal, around and above the ears,
// never on them, down to the nape 18 cm below the crown) and "body" for the rest, and UVs (the
// polar map about the cranium centre (0, 3, -0.7): crown at (0.5, 0.5), +Z toward v = 1, +X
// toward u = 1, radius = polar angle / 2π). Deterministic; about 110 ms on two cores.
//
// It is the zero set of a signed distance field (a smooth union of ellipsoids, capsules and a
// few shaped parts), polygonized by marching tetrahedra on a 0.35 cm grid over the head and a
// 0.8 cm grid over the bust, joined under the chin, then thinned of short edges where the
// surface is flat and relaxed onto the field; around the eyes, the nose's tip and the lips,
// whose forms are finer than that grid, edges are split down to 2–2.5 mm onto the field.
//
// Head space, centimetres, Y up, facing +Z (the nose points along +Z), symmetric in x. The
// origin is the centre of the head between the ears at ear-canal height. Landmarks, measured:
//   crown (top of the head)      y = 12.5          chin (lowest point)   y = -10.3
//   brow (glabella)              (0, 3.2, 9.1)     back of the head      z = -10.1
//     (19.2 cm from brow to back; 14.9 cm wide above the ears)
//   eyes, 6.3 cm apart           centres (±3.15, 1.3, 6.8), fronts at z ≈ 7.95
//   nose tip                     (0, -1.45, 11.45) mouth line           y ≈ -4.95, z ≈ 9.4
//   ears, 6.1 cm tall            y = -2.5 … 3.5, out to |x| = 9.0, z ≈ -3.3 … 0
//   neck, 11.2 cm wide           y ≈ -10 … -17     shoulders, 41 cm wide y ≈ -19 … -28
//   chest (nipple line)          y ≈ -33           waist, 25 cm wide      y ≈ -52
//   elbows                       y ≈ -51, |x| ≈ 18 flat bottom (top of the hips) y = -62
Mesh builtin_head_mesh();

// The same figure's torso and arms below a neck column that rises from inside the shoulders
// to a flat top at y = neck_top (clamped to −16 … −6 cm) of radius neck_radius (2 … 8 cm),
// without head or face: a closed, oriented mesh in the built-in head's space. The body proxy
// fitted under a head-only mesh is this torso moved, turned and scaled (body_proxy.hpp).
Mesh builtin_torso_mesh(float neck_top, float neck_radius);

}  // namespace wisp
