#pragma once
// The shading normals of a head or body mesh, one per vertex: what the renderer lights and
// what the editor draws, so the two show the same skin.
#include <vector>

#include "geometry/mesh.hpp"

namespace wisp {

// Area-weighted smooth vertex normals, unit (a vertex on no face of non-zero area gets +Y).
// Where a bust cut open at the chest sits on its fitted body proxy (faces in group
// kBodyProxyGroup), the two are separate surfaces meeting at a slight crease, and each side's
// smooth normals see only its own faces: the skin would change brightness in a line along the
// cut. So the normals blend into one across that seam, over two of the rim's edge lengths on
// either side, as a modeller smooths the normals of a joined mesh. Only boundary vertices
// lying on the proxy (within an edge length of one of its vertices) make the seam; other open
// edges (eyelids, a neck left open) keep their normals. Deterministic; linear in the mesh.
std::vector<Vec3f> skin_normals(const Mesh& mesh);

}  // namespace wisp
