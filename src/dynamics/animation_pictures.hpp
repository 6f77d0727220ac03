#pragma once
// The pictures of an animation as `wisp animate --png/--mp4` makes them, and the editor's
// Motion export with them (issue 17): every frame rendered from one camera for the whole
// clip, and the frames encoded into an MP4 by ffmpeg (the Debian program).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/hair.hpp"
#include "dynamics/animate.hpp"
#include "dynamics/motion.hpp"
#include "geometry/mesh.hpp"
#include "render/camera.hpp"
#include "render/render.hpp"

namespace wisp {

// `wisp animate --size`'s default and the editor's: square pictures this many pixels a side.
constexpr int kAnimationPictureSide = 640;

// Renders the frames of one clip. The camera frames frame 0's hair and body turned by every
// head rotation the clip goes through (so a lean or a nod stays in the picture), and follows
// the head's translation (so a running or jumping character stays in view without the
// framing jittering).
class AnimationPictures {
  public:
    // look: size, view, lights and shading (RenderOptions; its view is the clip's). body: the
    // body mesh at rest, posed at each frame (pose_body); clip: the clip's length, s. `body`
    // and `motion` must outlive this.
    AnimationPictures(const RenderOptions& look, const Mesh& body, const HeadFrame& head,
                      const Motion& motion, double clip);

    // Renders a frame (the moved hair and where the character is) to `png`.
    void write(const std::filesystem::path& png, const Hair& hair, const FramePose& pose);

  private:
    RenderOptions look_;
    const Mesh& body_;
    HeadFrame head_;
    const Motion& motion_;
    double clip_;
    std::optional<Camera> first_camera_;
    Vec3f first_centre_ = Vec3f::Zero();
};

// Where an animation's PNG frames go: `png_pattern` (a run of '#' for the frame number) when
// PNGs were asked for; else, for an MP4 alone, frame_####.png in a temporary folder of its
// own, removed with this object however the run ends; else nowhere (pattern() empty). Shared
// by `wisp animate --png/--mp4` and the editor's Motion export.
class PictureFrames {
  public:
    PictureFrames(std::string png_pattern, bool mp4);
    ~PictureFrames();
    PictureFrames(const PictureFrames&) = delete;
    PictureFrames& operator=(const PictureFrames&) = delete;

    const std::string& pattern() const { return pattern_; }

  private:
    std::string pattern_;
    std::filesystem::path temp_;
};

// Encodes PNG frames into an MP4 (H.264, yuv420p, 25 … fps) with ffmpeg. `png_pattern`
// names the frames with a run of '#' for the frame number from 0 (frame_####.png). ffmpeg
// writes beside `mp4` and the file is renamed when complete. Throws wisp::Error naming `mp4`
// when ffmpeg is not on PATH or fails.
void encode_mp4(const std::string& png_pattern, double fps, const std::filesystem::path& mp4);

// Whether `program` is an executable file in a folder of PATH.
bool program_on_path(const std::string& program);

// Runs a program found on PATH with `args` and waits; returns its exit status (127 when it
// cannot be started).
int run_program(const std::vector<std::string>& args);

}  // namespace wisp
