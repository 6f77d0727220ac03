// libFuzzer harness for OBJ polylines read as hair (io/obj_curves.hpp).
#include "fuzz_util.hpp"
#include "io/obj_curves.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace wisp;
    const auto hair =
        fuzz::attempt([&] { return decode_obj_curves(fuzz::as_text(data, size), "fuzz.obj"); });
    if (hair) fuzz::check_valid(*hair);
    return 0;
}
