#include "core/atomic_file.hpp"

#include <gtest/gtest.h>

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

TEST(AtomicFile, ReadingAMissingFileNamesIt) {
    try {
        read_file("/nonexistent/wisp/file.hair");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/wisp/file.hair"), std::string::npos);
    }
}

}  // namespace wisp
