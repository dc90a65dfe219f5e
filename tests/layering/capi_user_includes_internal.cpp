// Layering probe: a C API user sees no internal C++ header.
#include "megavox/build.h"
