// libFuzzer harness for USC-HairSalon `.data` (io/hairsalon.hpp): the in-memory decoder and the
// file reader (read straight into the arrays) on the same bytes must agree; whatever they
// read, the .data and .npz writers write (resampling every strand) without failing, and the
// .data written reads back with the same strand count.
#include "fuzz_util.hpp"
#include "io/hair_io.hpp"
#include "io/hairsalon.hpp"
#include "io/npz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace wisp;
    static fuzz::ScratchFile file(".data");
    const auto from_memory =
        fuzz::attempt([&] { return decode_hairsalon(fuzz::as_text(data, size), "fuzz.data"); });
    const auto from_file = fuzz::attempt([&] { return read_hair(file.write(data, size)); });
    fuzz::check_same(from_memory, from_file);
    if (from_memory) {
        fuzz::check_valid(*from_memory);
        const Hair again = decode_hairsalon(encode_hairsalon(*from_memory, "w.data", 4), "w.data");
        if (again.strand_count() != from_memory->strand_count())
            fuzz::broken("the .data writer's output reads back with another strand count");
        if (encode_npz(*from_memory, "w.npz", NpzWriteOptions{.points_per_strand = 4}).empty())
            fuzz::broken("the .npz writer wrote nothing");
    }
    return 0;
}
