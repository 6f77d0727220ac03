#pragma once
// The head a style grows hair on: its mesh (built-in or the user's OBJ) and its scalp.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "geometry/landmarks.hpp"
#include "geometry/mesh.hpp"
#include "geometry/scalp.hpp"
#include "groom/style.hpp"

namespace wisp {

struct Head {
    std::string source;  // "built-in head" or the OBJ path, for messages
    // The head, then what hair rests on below it when that is a second piece (a body proxy
    // fitted under a head that ends at the neck, or [body] obj): faces from first_body_face on
    // (SIZE_MAX: one piece, as the built-in figure is). Stable address: the scalp refers to it.
    std::unique_ptr<Mesh> mesh;
    std::unique_ptr<Scalp> scalp;
    size_t first_body_face = SIZE_MAX;
    // What hair rests on below the head, for stats and messages: "built-in figure", "the head
    // mesh", "proxy" or the body OBJ's path.
    std::string body;
    // The head's landmarks found on its own faces (find_landmarks); empty when the mesh shows
    // no head to find them on (a test's flat patch, a sphere).
    std::optional<Landmarks> landmarks;
    std::string landmark_error;  // why there are none
};

// The most a head mesh may span on any axis after head.scale (cm): a head with its bust,
// with room to spare. The solver's head field is a grid over it (docs/style.md).
inline constexpr float kMaxHeadSpan = 300.f;

// Builds the head a style names, with its body ([body], BodySpec); throws wisp::Error naming
// the file on bad input, a mesh wider than kMaxHeadSpan, or an empty scalp.
Head load_head(const HeadSpec& spec);
// The same without the scalp (Head::scalp stays empty): the mesh with its body and the
// landmarks, for pictures of hair on the head.
Head load_head_mesh(const HeadSpec& spec);

}  // namespace wisp
