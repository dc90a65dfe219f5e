// Layering probe: the runtime knows no pipeline.
#include "megavox/build.h"
