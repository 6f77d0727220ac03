// libFuzzer harness for `.ply` hair, ASCII and binary (io/ply.hpp).
#include "fuzz_util.hpp"
#include "io/ply.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace wisp;
    const auto hair =
        fuzz::attempt([&] { return decode_ply(fuzz::as_text(data, size), "fuzz.ply"); });
    if (hair) fuzz::check_valid(*hair);
    return 0;
}
