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

// Builds the head a style names; throws wisp::Error naming the file on bad input or an
// empty scalp.
Head load_head(const HeadSpec& spec);

}  // namespace wisp
