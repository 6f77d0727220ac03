#include "core/atomic_file.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <fstream>

#include "core/error.hpp"

namespace wisp {

TEST(AtomicFile, WritesAndRenames) {
    const auto path = std::filesystem::temp_directory_path() / "wisp_atomic_test.txt";
    write_file_atomic(path, std::string_view("hello"));
    EXPECT_EQ(read_file(path), "hello");
    std::filesystem::remove(path);
}

TEST(AtomicFile, UncommittedWriteLeavesTheTargetUntouched) {
    const auto path = std::filesystem::temp_directory_path() / "wisp_atomic_test2.txt";
    write_file_atomic(path, std::string_view("old"));
    {
        AtomicFile f(path);
        f.stream() << "partial";
        // destroyed without commit(), as when an exception unwinds
    }
    EXPECT_EQ(read_file(path), "old");
    for (const auto& e : std::filesystem::directory_iterator(path.parent_path()))
        EXPECT_EQ(e.path().string().find("wisp_atomic_test2.txt.tmp"), std::string::npos);
    std::filesystem::remove(path);
}

// Replacing: over a file (names exchanged, the old file unlinked) the target holds the new
// bytes, written at offsets in any order, and no temporary is left; over a symbolic link the
// link is replaced, its file kept; over a folder the commit fails and the folder stays.
TEST(AtomicFile, ReplacesFilesAndLinksButNotFolders) {
    const auto dir = std::filesystem::temp_directory_path() / "wisp_atomic_replace";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir / "folder");
    write_file_atomic(dir / "file", std::string_view("old bytes"));
    {
        AtomicFile f(dir / "file");
        f.write_at("new", 3, 0);
        f.write_at("bytes!", 6, 4);
        f.write_at(" ", 1, 3);
        f.commit();
    }
    EXPECT_EQ(read_file(dir / "file"), "new bytes!");
    write_file_atomic(dir / "kept", std::string_view("kept"));
    std::filesystem::create_symlink("kept", dir / "link");
    write_file_atomic(dir / "link", std::string_view("new"));
    EXPECT_FALSE(std::filesystem::is_symlink(dir / "link"));
    EXPECT_EQ(read_file(dir / "link"), "new");
    EXPECT_EQ(read_file(dir / "kept"), "kept");
    EXPECT_THROW(write_file_atomic(dir / "folder", std::string_view("x")), Error);
    EXPECT_TRUE(std::filesystem::is_directory(dir / "folder"));
    size_t entries = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
        ++entries;
    }
    EXPECT_EQ(entries, 4u);  // file, kept, link, folder
    std::filesystem::remove_all(dir);
}

TEST(AtomicFile, ReadingAMissingFileNamesIt) {
    try {
        read_file("/nonexistent/wisp/file.hair");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/wisp/file.hair"), std::string::npos);
    }
}

// Ctrl-C (SIGINT) or SIGTERM while an output is being written removes its temporary, and
// the process still dies of the signal.
TEST(AtomicFileDeathTest, SignalsRemoveTheTemporaries) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const auto dir = std::filesystem::temp_directory_path();
    for (const int sig : {SIGINT, SIGTERM}) {
        const auto path = dir / ("wisp_atomic_signal_" + std::to_string(sig) + ".usda");
        EXPECT_EXIT(
            {
                AtomicFile a(path);
                AtomicFile b(dir / "wisp_atomic_signal_other.hair");
                a.stream() << "partial";
                a.stream().flush();
                std::raise(sig);
            },
            testing::KilledBySignal(sig), "");
        EXPECT_FALSE(std::filesystem::exists(path));
        for (const auto& e : std::filesystem::directory_iterator(dir))
            EXPECT_EQ(e.path().filename().string().find("wisp_atomic_signal_"), std::string::npos)
                << e.path();
    }
}

// A series of numbered files (an animation's frames) is removed whole unless kept: when
// its owner unwinds, and on a signal (the files are complete, so AtomicFile's temporaries
// alone would leave them).
TEST(FileSeries, RemovedUnlessKeptAlsoOnSignals) {
    const auto dir = std::filesystem::temp_directory_path();
    const std::string prefix = (dir / "wisp_series_test_").string();
    auto write = [&](FileSeries& s, size_t n) {
        for (size_t i = 0; i < n; ++i) {
            write_file_atomic(s.path(i), std::string_view("frame"));
            s.added(i);
        }
    };
    {
        FileSeries s(prefix, ".hair", 4);
        EXPECT_EQ(s.path(7).string(), prefix + "0007.hair");
        EXPECT_EQ(s.path(12345).string(), prefix + "12345.hair");
        write(s, 3);
        EXPECT_TRUE(std::filesystem::exists(prefix + "0002.hair"));
    }
    for (int i = 0; i < 3; ++i)
        EXPECT_FALSE(std::filesystem::exists(FileSeries(prefix, ".hair", 4).path(i)));
    {
        FileSeries s(prefix, ".hair", 4);
        write(s, 2);
        s.keep();
    }
    EXPECT_TRUE(std::filesystem::exists(prefix + "0001.hair"));
    std::filesystem::remove(prefix + "0000.hair");
    std::filesystem::remove(prefix + "0001.hair");

    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_EXIT(
        {
            FileSeries s(prefix, ".usda", 2);
            write(s, 12);
            std::raise(SIGINT);
        },
        testing::KilledBySignal(SIGINT), "");
    for (const auto& e : std::filesystem::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find("wisp_series_test_"), std::string::npos)
            << e.path();
}

// Endless files (/dev/zero reports size 0) and files over a limit fail while being read.
TEST(AtomicFile, ReadLimitsAreCheckedWhileReading) {
    try {
        read_file("/dev/zero", {1 << 20, "a style file", true});
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "/dev/zero: byte 0 is a NUL byte, which a style file (text) never holds");
    }
    try {
        read_file("/dev/zero", {1 << 20, "an image file"});
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()),
                  "/dev/zero: larger than 1048576 bytes, the limit for an image file "
                  "(docs/formats.md)");
    }
    // NUL padding that ends a text file is cut off; padding longer than kMaxNulPadding (as
    // /dev/zero's endless NULs after byte 0 would be) is not padding.
    {
        const auto padded = std::filesystem::temp_directory_path() / "wisp_nul_padding.txt";
        const std::string text = "name = \"x\"\n";
        std::ofstream(padded, std::ios::binary) << text << std::string(100, '\0');
        EXPECT_EQ(read_file(padded, {1 << 20, "a style file", true}), text);
        std::ofstream(padded, std::ios::binary) << text << std::string(kMaxNulPadding + 1, '\0');
        EXPECT_THROW(read_file(padded, {1 << 20, "a style file", true}), Error);
        std::filesystem::remove(padded);
    }
    // A wrong magic stops reading at once: the format's parser names what it found.
    EXPECT_EQ(read_file("/dev/zero", {1 << 20, "a PLY file", false, "ply"}).substr(0, 3),
              std::string(3, '\0'));
    const auto path = std::filesystem::temp_directory_path() / "wisp_read_limit.txt";
    write_file_atomic(path, std::string_view("0123456789"));
    EXPECT_EQ(read_file(path, {10, "a file", true}), "0123456789");
    EXPECT_THROW(read_file(path, {9}), Error);
    std::filesystem::remove(path);
}

}  // namespace wisp
