// tinygltf and stb_image compiled into the fuzz targets, so their code (the
// glTF JSON conversion, PNG and JPEG decoding) is instrumented like the
// engine's: coverage guides the fuzzer through it and AddressSanitizer checks
// it. The release build links Debian's libtinygltf.so and libstb.so, built
// from these same headers. The fuzz targets take these definitions first (the
// objects are on the link line before the engine's archives) and link with
// --as-needed, so the shared libraries are not loaded at all.
#define TINYGLTF_IMPLEMENTATION
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <tiny_gltf.h>
