// TOML values and JSON (groom/toml_json.hpp): a float is written as the shortest text that
// reads back to the same double, so a value a user wrote (0.55) comes back as written.
#include "groom/toml_json.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace wisp {
namespace {

TEST(TomlJson, FloatsAreTheShortestTextThatReadsBackToTheSameDouble) {
    EXPECT_EQ(json_to_toml_value(0.55, "x"), "0.55");
    EXPECT_EQ(json_to_toml_value(2.0, "x"), "2.0");
    EXPECT_EQ(json_to_toml_value(-1.15, "x"), "-1.15");
    EXPECT_EQ(json_to_toml_value(1e-7, "x"), "1e-07");
    EXPECT_EQ(json_to_toml_value(nlohmann::json::array({0.0, -0.45}), "x"), "[0.0, -0.45]");
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 2000; ++i) {
        const double d = u(rng) * std::pow(10.0, i % 13 - 6);
        const nlohmann::json back = toml_value_to_json(json_to_toml_value(d, "x"));
        ASSERT_TRUE(back.is_number_float()) << d;
        EXPECT_EQ(back.get<double>(), d);
    }
}

}  // namespace
}  // namespace wisp
