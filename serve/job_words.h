// A failed job's message in the service's own terms: the library names its settings in its own words ("the
// cube size", "the resolution"); a client set them as the job's keys ("cube", "resolution"), and budgets a
// client cannot set are the server's (the host memory budget -> the server's host memory per job).
#pragma once
#include <string>

namespace mv::serve {

std::string in_job_terms(const std::string& message);

}  // namespace mv::serve
