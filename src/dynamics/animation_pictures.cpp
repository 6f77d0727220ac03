#include "dynamics/animation_pictures.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <string_view>

#include "core/error.hpp"
#include "core/image.hpp"

extern char** environ;

namespace wisp {

namespace {

// Points enclosing what a clip `clip` seconds long shows: the corners of `box` (frame 0's
// hair and body) turned about `centre` by every head rotation since frame 0 (sampled).
Mesh clip_envelope(const Motion& motion, double clip, const Box3& box, const Vec3f& centre) {
    Mesh envelope;
    const Mat3f start = motion.head.at(0).rotation.transpose();
    constexpr int kSamples = 48;
    for (int i = 0; i <= kSamples; ++i) {
        const Mat3f turn = motion.head.at(clip * i / kSamples).rotation * start;
        for (int k = 0; k < 8; ++k)
            envelope.vertices.push_back(centre + turn * (box.corner(k) - centre));
    }
    return envelope;
}

}  // namespace

AnimationPictures::AnimationPictures(const RenderOptions& look, const Mesh& body,
                                     const HeadFrame& head, const Motion& motion, double clip)
    : look_(look), body_(body), head_(head), motion_(motion), clip_(clip) {}

void AnimationPictures::write(const std::filesystem::path& png, const Hair& hair,
                              const FramePose& pose) {
    const Mesh body = pose_body(body_, head_, pose);
    const Vec3f centre = pose.head.apply(head_.center);
    if (!first_camera_) {
        const Mesh envelope = clip_envelope(motion_, clip_, framing_bounds(hair, &body), centre);
        first_camera_ = render_camera(Hair{}, &envelope, look_);
        first_centre_ = centre;
    }
    RenderOptions o = look_;
    const Vec3f shift = centre - first_centre_;
    o.look_at = LookAt{first_camera_->eye + shift,
                       first_camera_->eye + first_camera_->forward + shift, first_camera_->up};
    o.fov_y_degrees = first_camera_->fov_y_degrees;
    write_png(png, render(hair, &body, o));
}

PictureFrames::PictureFrames(std::string png_pattern, bool mp4) : pattern_(std::move(png_pattern)) {
    if (!pattern_.empty() || !mp4) return;
    // A folder per object: one process (the editor) may export twice at once.
    static std::atomic<unsigned> count{0};
    temp_ = std::filesystem::temp_directory_path() /
            cat("wisp-frames-", ::getpid(), "-", count.fetch_add(1));
    std::filesystem::create_directories(temp_);
    pattern_ = (temp_ / "frame_####.png").string();
}

PictureFrames::~PictureFrames() {
    std::error_code ec;
    if (!temp_.empty()) std::filesystem::remove_all(temp_, ec);
}

void encode_mp4(const std::string& png_pattern, double fps, const std::filesystem::path& mp4) {
    const std::filesystem::path tmp =
        mp4.parent_path() / (mp4.stem().string() + ".tmp-" + std::to_string(::getpid()) + ".mp4");
    std::string input = png_pattern;
    const size_t first = input.find('#');
    if (first == std::string::npos)
        fail(mp4.string(), ": the frames' name '", png_pattern, "' has no #### for the number");
    size_t last = first;
    while (last < input.size() && input[last] == '#')
        ++last;
    input = input.substr(0, first) + "%0" + std::to_string(last - first) + "d" + input.substr(last);
    const int status = run_program({"ffmpeg", "-y", "-loglevel", "error", "-framerate", cat(fps),
                                    "-i", input, "-c:v", "libx264", "-pix_fmt", "yuv420p", "-vf",
                                    "pad=ceil(iw/2)*2:ceil(ih/2)*2", tmp.string()});
    if (status != 0) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        fail(mp4.string(), status == 127 ? ": ffmpeg was not found on PATH (scripts/setup "
                                           "installs it)"
                                         : cat(": ffmpeg failed with status ", status));
    }
    std::filesystem::rename(tmp, mp4);
}

bool program_on_path(const std::string& program) {
    const char* path = std::getenv("PATH");
    std::string_view rest = path ? path : "";
    while (!rest.empty()) {
        const size_t colon = rest.find(':');
        const std::string_view dir = rest.substr(0, colon);
        rest = colon == std::string_view::npos ? std::string_view() : rest.substr(colon + 1);
        const std::string candidate = std::string(dir.empty() ? "." : dir) + "/" + program;
        if (::access(candidate.c_str(), X_OK) == 0) return true;
    }
    return false;
}

int run_program(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (const std::string& a : args)
        argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    pid_t pid = 0;
    if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return 127;
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) return 127;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

}  // namespace wisp
