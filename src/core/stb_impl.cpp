// stb_image and stb_image_write, compiled here rather than linked from Debian's libstb: stb
// says of itself that it is not hardened against hostile files, and its JPEG, GIF, PSD, PIC,
// HDR and PNM decoders (2.27) have known memory-safety bugs (a JPEG Huffman table of more than
// 256 codes writes past its arrays). wisp reads only PNG, BMP and TGA through stb, the formats
// its fuzzer has searched longest; JPEG goes to libjpeg-turbo (image.cpp); the rest are
// refused by name rather than handed to a decoder nobody trusts with them.
#define STBI_ONLY_PNG
#define STBI_ONLY_BMP
#define STBI_ONLY_TGA
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>

#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
