#include "groom/head.hpp"

#include "core/error.hpp"
#include "geometry/body_proxy.hpp"
#include "geometry/builtin_head.hpp"
#include "geometry/landmarks.hpp"

namespace wisp {
namespace {

// Checked before any grid is sized by it (a 30× scale made a 10⁹-node head field).
void check_span(const Mesh& mesh, const std::string& source, const char* what,
                const char* scale_key, float scale) {
    const Vec3f span = mesh.bounds().size();
    if (span.maxCoeff() > kMaxHeadSpan)
        fail(source, ": the ", what, " spans ", span.x(), " × ", span.y(), " × ", span.z(),
             " cm after ", scale_key, " = ", scale, "; a head with its body may span at most ",
             kMaxHeadSpan, " cm (is ", scale_key, " right? it turns the OBJ's units into cm)");
}

// Appends what hair rests on below a user's head mesh (BodySpec), with head.first_body_face.
void add_body(Head& head, const HeadSpec& spec) {
    using Kind = BodySpec::Kind;
    const BodySpec& body = spec.body;
    Mesh& mesh = *head.mesh;
    switch (body.kind) {
        case Kind::kMesh:
            head.body = "the head mesh";
            return;
        case Kind::kObj: {
            const std::string source = body.obj.string();
            const Mesh piece = read_obj_mesh(body.obj, body.scale);
            head.first_body_face = mesh.faces.size();
            append_mesh(mesh, piece, "body");
            check_span(mesh, source, "head with this body", "body.scale", body.scale);
            head.body = source;
            return;
        }
        case Kind::kAuto:
        case Kind::kProxy: {
            if (!head.landmarks) {
                if (body.kind == Kind::kProxy)
                    fail(head.source,
                         ": [body] method = \"proxy\" fits the body to the head's "
                         "landmarks, which were not found: ",
                         head.landmark_error);
                head.body = "the head mesh";  // nothing to fit to: taken as it is
                return;
            }
            const Landmarks& landmarks = *head.landmarks;
            // Long hair falls to the waist, two heads below the chin: a head or a bust that
            // stops above it gets the proxy below, a figure that reaches it is kept as it is.
            const float waist = landmarks.chin.y() - 2.f * landmarks.height;
            if (body.kind == Kind::kAuto && mesh.bounds().lo.y() < waist) {
                head.body = "the head mesh";
                return;
            }
            head.first_body_face = mesh.faces.size();
            append_mesh(mesh, fit_body_proxy(landmarks, &mesh));
            check_span(mesh, head.source, "head with its body proxy", "head.scale", spec.scale);
            head.body = "proxy";
            return;
        }
    }
}

// The landmarks of the head's mesh as it is now (before a body is added), or the reason none
// were found.
void find_head_landmarks(Head& head) {
    try {
        head.landmarks = find_landmarks(*head.mesh);
    } catch (const Error& e) {
        head.landmarks.reset();
        head.landmark_error = e.what();
    }
}

}  // namespace

Head load_head(const HeadSpec& spec) {
    Head head = load_head_mesh(spec);
    head.scalp = std::make_unique<Scalp>(*head.mesh, spec.scalp, head.source, head.first_body_face);
    if (head.landmarks) {
        const Landmarks& l = *head.landmarks;
        head.scalp->set_ears({l.ear_left, l.ear_right, l.height});
    }
    return head;
}

Head load_head_mesh(const HeadSpec& spec) {
    Head head;
    if (spec.obj.empty()) {
        head.source = "built-in head";
        head.mesh = std::make_unique<Mesh>(builtin_head_mesh());
        head.body = "built-in figure";
        find_head_landmarks(head);
    } else {
        head.source = spec.obj.string();
        head.mesh = std::make_unique<Mesh>(read_obj_mesh(spec.obj, spec.scale));
        check_span(*head.mesh, head.source, "head", "head.scale", spec.scale);
        find_head_landmarks(head);
        add_body(head, spec);
    }
    return head;
}

}  // namespace wisp
