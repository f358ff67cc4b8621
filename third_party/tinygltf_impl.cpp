// The one translation unit that compiles tinygltf (header-only, libtinygltf-dev). stb_image
// and stb_image_write come compiled from Debian's libstb (linked as `stb`).
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#include <tiny_gltf.h>
