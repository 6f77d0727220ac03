#pragma once
// Small solved hairstyles on the built-in head, shared by the dynamics tests.
#include <string>
#include <vector>

#include "dynamics/animate.hpp"
#include "groom/style_toml.hpp"
#include "solve/pipeline.hpp"

namespace wisp::test {

struct Groomed {
    Style style;
    Hair hair;
    HeadFrame head;
    std::vector<float> held;  // per wisp: SolveStats::held_length
};

inline const Head& builtin_head() {
    static const Head head = load_head(HeadSpec{});
    return head;
}

// A preset at a small size (wisps, strands, points per strand). `unparted`: without the
// growth field, hair falling from the scalp under gravity alone.
inline Groomed groomed(const std::string& preset, int wisps = 120, int strands = 1200,
                       int points = 16, bool unparted = false) {
    Groomed g;
    g.style = load_preset(preset);
    g.style.wisps = wisps;
    g.style.strands = strands;
    g.style.points_per_strand = points;
    if (unparted)
        std::erase_if(g.style.solve.field,
                      [](const FieldTerm& t) { return t.kind == FieldTerm::Kind::kGrowth; });
    HairstyleResult r = generate_hairstyle(g.style, builtin_head());
    g.hair = std::move(r.hair);
    g.held = std::move(r.solve.held_length);
    g.head = head_frame(*builtin_head().scalp);
    return g;
}

}  // namespace wisp::test
