// libFuzzer harness for USC-HairSalon `.data` (io/hairsalon.hpp): the in-memory decoder and the
// file reader (read straight into the arrays) on the same bytes must agree.
#include "fuzz_util.hpp"
#include "io/hair_io.hpp"
#include "io/hairsalon.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace wisp;
    static fuzz::ScratchFile file(".data");
    const auto from_memory =
        fuzz::attempt([&] { return decode_hairsalon(fuzz::as_text(data, size), "fuzz.data"); });
    const auto from_file = fuzz::attempt([&] { return read_hair(file.write(data, size)); });
    fuzz::check_same(from_memory, from_file);
    if (from_memory) fuzz::check_valid(*from_memory);
    return 0;
}
