// Layering probe: a C API user sees the installed headers.
#include "megavox/megavox.h"
#include "megavox/megavox.hpp"
