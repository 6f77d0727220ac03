// The pictures of an animation (wisp animate --png/--mp4 and the editor's Motion export):
// ffmpeg found on PATH or refused with a message naming the output.
#include "dynamics/animation_pictures.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "core/error.hpp"

namespace wisp {
namespace {

TEST(AnimationPictures, FindsProgramsOnPathOnly) {
    EXPECT_TRUE(program_on_path("sh"));
    EXPECT_FALSE(program_on_path("no-such-program-wisp"));
    EXPECT_EQ(run_program({"no-such-program-wisp"}), 127);
    EXPECT_EQ(run_program({"sh", "-c", "exit 3"}), 3);
}

TEST(AnimationPictures, AnMp4WithoutFfmpegOrFrameNumbersIsAClearError) {
    const std::string path = std::getenv("PATH");
    setenv("PATH", "/nonexistent", 1);
    try {
        encode_mp4("f_####.png", 25, "/tmp/wisp-never.mp4");
        ADD_FAILURE() << "no error without ffmpeg";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("ffmpeg was not found"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("wisp-never.mp4"), std::string::npos) << e.what();
    }
    setenv("PATH", path.c_str(), 1);
    EXPECT_THROW(encode_mp4("frames.png", 25, "/tmp/wisp-never.mp4"), Error);
}

TEST(AnimationPictures, FramesOfAnMp4AloneGoToATemporaryFolderRemovedAfter) {
    EXPECT_EQ(PictureFrames("take_####.png", true).pattern(), "take_####.png");
    EXPECT_EQ(PictureFrames("", false).pattern(), "");
    std::filesystem::path folder;
    {
        const PictureFrames a("", true), b("", true);
        folder = std::filesystem::path(a.pattern()).parent_path();
        EXPECT_TRUE(std::filesystem::is_directory(folder)) << folder;
        EXPECT_NE(a.pattern(), b.pattern());  // two exports at once do not share a folder
        EXPECT_NE(a.pattern().find("####"), std::string::npos);
    }
    EXPECT_FALSE(std::filesystem::exists(folder)) << folder;
}

}  // namespace
}  // namespace wisp
