#include "app/head_args.hpp"

#include <filesystem>

#include "core/error.hpp"

namespace wisp {

void HeadArgs::add_to(CLI::App* command) {
    command
        ->add_option("--head", head,
                     "A head mesh (OBJ, Y up, facing +Z) to grow the style on instead of its own; "
                     "a head that ends at the neck gets a body proxy ([body] in docs/style.md)")
        ->check(CLI::ExistingFile);
    command
        ->add_option("--head-scale", scale,
                     "Multiplies --head's coordinates to reach centimetres (0.1 for mm, 10 for "
                     "dm, 100 for m)")
        ->check(CLI::PositiveNumber);
    command->add_option("--scalp", scalp,
                        "Where hair grows on the head: hairline (found on any head; the default "
                        "with --head), group:NAME (a face group or material) or mask:PNG (a "
                        "grayscale image in the mesh's UV space)");
}

void HeadArgs::apply(Style& style) const {
    if (head.empty() && scale != 1.f)
        throw CLI::ValidationError("--head-scale", "scales --head; give --head FILE.obj too");
    ScalpSpec& s = style.head.scalp;
    if (!head.empty()) {
        style.head.obj = std::filesystem::absolute(head);
        style.head.scale = scale;
        const ScalpSpec defaults;
        if (s.kind == defaults.kind && s.group == defaults.group)
            s.kind = ScalpSpec::Kind::kHairline;
    }
    if (scalp.empty()) return;
    if (scalp == "hairline") {
        s.kind = ScalpSpec::Kind::kHairline;
    } else if (scalp.starts_with("group:") && scalp.size() > 6) {
        s.kind = ScalpSpec::Kind::kGroup;
        s.group = scalp.substr(6);
    } else if (scalp.starts_with("mask:") && scalp.size() > 5) {
        s.kind = ScalpSpec::Kind::kMask;
        s.mask = std::filesystem::absolute(scalp.substr(5));
        if (!std::filesystem::is_regular_file(s.mask))
            throw CLI::ValidationError("--scalp",
                                       "mask " + excerpt(s.mask.string()) + " is not a file");
    } else {
        throw CLI::ValidationError(
            "--scalp", "expects hairline, group:NAME or mask:PNG, got '" + excerpt(scalp) + "'");
    }
}

}  // namespace wisp
