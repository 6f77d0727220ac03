#include "app/progress.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace wisp {

TEST(Progress, PlainLinesThrottledShowTheFirstAndTheLast) {
    std::ostringstream out;
    {
        Progress p("frame", 5, false, false, out, 3600.0);
        for (int i = 1; i <= 5; ++i)
            p.step(i);
    }
    EXPECT_EQ(out.str(), "wisp: frame 1/5\nwisp: frame 5/5\n");
}

TEST(Progress, PlainLinesEveryStepWithoutThrottle) {
    std::ostringstream out;
    Progress p("view", 2, false, false, out, 0.0);
    p.step(1, "front");
    p.step(2, "back");
    EXPECT_EQ(out.str(), "wisp: view 1/2 (front)\nwisp: view 2/2 (back)\n");
}

TEST(Progress, TerminalRewritesOneLineAndEndsIt) {
    std::ostringstream out;
    {
        Progress p("frame", 3, false, true, out);
        p.step(1);
        p.step(2);
    }  // stopped early (an error): the line is still ended
    EXPECT_EQ(out.str(), "\rwisp: frame 1/3\x1b[K\rwisp: frame 2/3\x1b[K\n");
}

TEST(Progress, QuietOrSingleStepSaysNothing) {
    std::ostringstream out;
    {
        Progress quiet("frame", 3, true, false, out);
        quiet.step(1);
        Progress single("view", 1, false, true, out);
        single.step(1);
    }
    EXPECT_EQ(out.str(), "");
}

}  // namespace wisp
