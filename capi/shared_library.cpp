// libmegavox.so's own translation unit: the C API's code comes whole from megavox_capi (cmake/Package.cmake),
// and this checks at build time that the hit record keeps the 32 bytes the API promises.
#include "megavox/megavox.h"

static_assert(sizeof(MvTraceHit) == 32, "MvTraceHit is the 32-byte hit record");
static_assert(sizeof(MvTraceRay) == 28, "MvTraceRay is 7 floats");
