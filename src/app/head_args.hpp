#pragma once
// --head, --head-scale and --scalp: any preset or style on the user's own head, in one
// command (generate, animate, edit).
#include <string>

#include <CLI/CLI.hpp>

#include "groom/style.hpp"

namespace wisp {

struct HeadArgs {
    std::string head;   // an OBJ head mesh, empty: the style's
    float scale = 1.f;  // multiplies its coordinates to reach centimetres
    std::string scalp;  // hairline, group:NAME or mask:PNG; empty: see apply()

    void add_to(CLI::App* command);
    // Puts the style on --head: the mesh (absolute, so a style written later still finds it),
    // its scale, and the scalp --scalp names, else the hairline unless the style chose a
    // scalp of its own (a head of the user's seldom has the built-in head's `scalp` group).
    // --scalp alone changes the scalp of the style's head. Throws CLI::ValidationError naming
    // the option on a malformed --scalp or a --head-scale without --head.
    void apply(Style& style) const;
};

}  // namespace wisp
