// A failed job's message in the service's own terms: the names the layers below use (the library's CLI
// flags, as the point-cloud and mask jobs meet them; the C API's fields, as build jobs do) become the job's
// keys (--cube -> "cube"), and budgets a client cannot set become the server's (--memory -> the server's
// host memory per job). See host/option_words.h for why messages are reworded rather than worded twice.
#pragma once
#include <string>

namespace mv::serve {

std::string in_job_terms(const std::string& message);

}  // namespace mv::serve
