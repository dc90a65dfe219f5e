// Layering probe: the service is written on the public C API and its own headers.
#include "job_pool.h"
#include "megavox/megavox.hpp"
