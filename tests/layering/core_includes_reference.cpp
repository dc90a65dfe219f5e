// Layering probe: production code never calls a test oracle.
#include "points_reference.h"
