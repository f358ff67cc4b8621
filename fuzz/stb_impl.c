/* stb_image and stb_image_write compiled from Debian's headers with the fuzzer's
   instrumentation (the main build links Debian's precompiled libstb instead). */
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
