// Layering probe: the base layer depends on nothing of megavox.
#include "megavox/device.h"
