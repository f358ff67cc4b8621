// volk's loader implementation (Debian ships it as a source file beside the header).
#define VOLK_IMPLEMENTATION
#include <volk.h>
