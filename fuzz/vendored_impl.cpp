// The implementations of the header-only parsers the readers use, compiled into the harnesses
// with the fuzzer's instrumentation. Debian ships them prebuilt (libstb.so,
// libtinyobjloader.so) without it, so libFuzzer would be blind inside them and the sanitizers
// would not see their memory; the executable's definitions take precedence over the shared
// libraries'.
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
