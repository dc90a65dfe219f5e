// Layering probe: the runtime knows no file format.
#include "io/file_ops.h"
