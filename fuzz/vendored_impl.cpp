// The implementation of the header-only OBJ parser the head reader uses, compiled into the
// harnesses with the fuzzer's instrumentation. Debian ships it prebuilt (libtinyobjloader.so)
// without it, so libFuzzer would be blind inside it and the sanitizers would not see its
// memory; the executable's definitions take precedence over the shared library's.
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
