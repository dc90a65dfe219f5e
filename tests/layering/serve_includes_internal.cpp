// Layering probe: the service sees the public C API, not the C++ library under it.
#include "megavox/build.h"
