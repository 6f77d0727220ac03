#include "groom/head.hpp"

#include "geometry/builtin_head.hpp"

namespace wisp {

Head load_head(const HeadSpec& spec) {
    Head head;
    if (spec.obj.empty()) {
        head.source = "built-in head";
        head.mesh = std::make_unique<Mesh>(builtin_head_mesh());
    } else {
        head.source = spec.obj.string();
        head.mesh = std::make_unique<Mesh>(read_obj_mesh(spec.obj, spec.scale));
    }
    head.scalp = std::make_unique<Scalp>(*head.mesh, spec.scalp, head.source);
    return head;
}

}  // namespace wisp
