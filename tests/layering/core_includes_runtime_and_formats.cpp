// Layering probe: pipelines dispatch kernels and read and write files.
#include "io/mesh_source.h"
#include "megavox/build.h"
#include "megavox/device.h"
#include "paging/page_layout.h"
#include "points/omicron.h"
