// Layering probe: a file format reader is compiled without the Device API.
#include "megavox/device.h"
