// libFuzzer harness for motion JSON (dynamics/motion.hpp, nlohmann-json): the reader takes only
// a path. A motion it accepts must give finite poses and velocities at its keys and between
// them, as the animation will ask.
#include "dynamics/motion.hpp"
#include "fuzz_util.hpp"

namespace {

void check_track(const wisp::MotionTrack& track) {
    using namespace wisp;
    for (size_t i = 0; i < track.keys.size(); ++i) {
        const double t = track.keys[i].time;
        if (i > 0 && !(t > track.keys[i - 1].time)) wisp::fuzz::broken("motion keys out of order");
        const double next = i + 1 < track.keys.size() ? track.keys[i + 1].time : t + 1;
        for (double s : {t, 0.5 * (t + next)}) {
            const RigidTransform x = track.at(s);
            const RigidVelocity v = track.velocity(s);
            if (!x.rotation.allFinite() || !x.translation.allFinite() || !v.turn.allFinite() ||
                !v.linear.allFinite())
                wisp::fuzz::broken("a motion gives a non-finite pose or velocity");
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace wisp;
    static fuzz::ScratchFile file(".json");
    const auto motion =
        fuzz::attempt([&] { return read_motion(file.write(data, size), HeadFrame{}); });
    if (!motion) return 0;
    check_track(motion->head);
    check_track(motion->body);
    if (!motion->wind_at(0.25).allFinite()) fuzz::broken("a motion gives a non-finite wind");
    return 0;
}
