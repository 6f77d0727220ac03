#include "groom/head.hpp"

#include "core/error.hpp"
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
        // Checked before any grid is sized by it (a 30× scale made a 10⁹-node head field).
        const Vec3f span = head.mesh->bounds().size();
        if (span.maxCoeff() > kMaxHeadSpan)
            fail(head.source, ": the head spans ", span.x(), " × ", span.y(), " × ", span.z(),
                 " cm after head.scale = ", spec.scale, "; a head may span at most ", kMaxHeadSpan,
                 " cm (is head.scale right? it turns the OBJ's units into cm)");
    }
    head.scalp = std::make_unique<Scalp>(*head.mesh, spec.scalp, head.source);
    return head;
}

}  // namespace wisp
