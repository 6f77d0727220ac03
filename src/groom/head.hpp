#pragma once
// The head a style grows hair on: its mesh (built-in or the user's OBJ) and its scalp.
#include <memory>
#include <string>

#include "geometry/mesh.hpp"
#include "geometry/scalp.hpp"
#include "groom/style.hpp"

namespace wisp {

struct Head {
    std::string source;          // "built-in head" or the OBJ path, for messages
    std::unique_ptr<Mesh> mesh;  // stable address: the scalp refers to it
    std::unique_ptr<Scalp> scalp;
};

// The most a head mesh may span on any axis after head.scale (cm): a head with its bust,
// with room to spare. The solver's head field is a grid over it (docs/style.md).
inline constexpr float kMaxHeadSpan = 300.f;

// Builds the head a style names; throws wisp::Error naming the file on bad input, a mesh
// wider than kMaxHeadSpan, or an empty scalp.
Head load_head(const HeadSpec& spec);

}  // namespace wisp
