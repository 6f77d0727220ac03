// libFuzzer harness for PNG maps and masks (core/image.hpp, stb_image): the reader takes only a
// path. stb_image's own code is compiled into the harness (vendored_impl.cpp) so that libFuzzer
// sees its branches and the sanitizers its memory.
#include "core/image.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace wisp;
    static fuzz::ScratchFile file(".png");
    const auto image = fuzz::attempt([&] { return read_gray_image(file.write(data, size)); });
    if (image && image->values.size() != static_cast<size_t>(image->width) * image->height)
        fuzz::broken("an image holds a different number of values than its size says");
    return 0;
}
