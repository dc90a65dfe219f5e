// Layering probe: pipelines see the Device API, not a backend's internals.
#include "backend.h"
