// Layering probe: formats use errors, huge pages and the kernels' layout headers.
#include "common/morton.h"
#include "huge_pages.h"
#include "io/file_ops.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
