// libFuzzer harness for USD `.usda` (io/usda.hpp): the parser, what `wisp info` asks of every
// BasisCurves prim (its problem, its segments), and the conversion to strands.
#include "fuzz_util.hpp"
#include "io/usda.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace wisp;
    const auto layer =
        fuzz::attempt([&] { return parse_usda(fuzz::as_text(data, size), "fuzz.usda"); });
    if (!layer) return 0;
    for (const UsdCurves& c : layer->curves) {
        if (!usd_curves_problem(c).empty()) continue;
        for (size_t i = 0; i < c.counts.size(); ++i)
            usd_segment_count(c, i);
    }
    const auto hair = fuzz::attempt([&] { return hair_from_usda(*layer, "fuzz.usda"); });
    if (hair) fuzz::check_valid(*hair);
    return 0;
}
