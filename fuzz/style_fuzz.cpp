// libFuzzer harness for style TOML (groom/style_toml.hpp, toml++).
#include "fuzz_util.hpp"
#include "groom/style_toml.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace wisp;
    // Paths inside a style are only stored, never opened, by the parser.
    fuzz::attempt(
        [&] { return parse_style(fuzz::as_text(data, size), "fuzz.toml", "/nonexistent"); });
    return 0;
}
