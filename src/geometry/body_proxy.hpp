#pragma once
// A body for head-only meshes: the built-in figure's shoulders, chest, back, waist and arms
// (builtin_torso_mesh) fitted under a head that ends at the neck, so that long hair has
// shoulders to rest on and a back and chest to fall along, as on the built-in figure.
//
// The torso is scaled by the head's height (chin to crown) against the built-in head's
// 22.8 cm, turned to face where the face looks, hung from the chin at the built-in figure's
// proportions and centred under the neck. Its neck column rises into the mesh's own neck, of
// the neck's narrowest radius, so the two overlap there and nothing of the column shows
// beside the neck; the solver's head field is the union of the two (HeadField).
#include "geometry/landmarks.hpp"
#include "geometry/mesh.hpp"

namespace wisp {

// The group every face of a fitted body proxy carries (never scalp: no hair grows on it).
inline constexpr const char* kBodyProxyGroup = "body_proxy";

// The proxy for a head with these landmarks (cm, the head's space): a closed, oriented
// triangle mesh with every face in group kBodyProxyGroup. With the head's `mesh`, a bust whose
// shoulders are broader or deeper than the proxy's gets a proxy widened to hold them (by at
// most 40%). Deterministic.
Mesh fit_body_proxy(const Landmarks& head, const Mesh* mesh = nullptr);

}  // namespace wisp
