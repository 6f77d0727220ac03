#pragma once
// The built-in procedural head, neck and shoulders: smooth, closed, about 22 cm from chin
// to crown, in centimetres, Y up, facing +Z, so that no file is needed for the default run.
#include "geometry/mesh.hpp"

namespace wisp {

// Builds the built-in mesh: a closed, manifold triangle mesh with a face group named
// "scalp" (the hair-bearing cap) and "body" for the rest, and UVs. Deterministic.
Mesh builtin_head_mesh();

}  // namespace wisp
