// A failed job's message in the service's own terms. The library's messages name the CLI's flags (raise
// --cube, over --memory): the checks that word them are shared by every front end, so rather than repeat a
// check to word it again, the service rewords the flags it has keys for (--cube -> "cube") and the budgets a
// client cannot set (--memory -> the server's share per job).
#pragma once
#include <string>

namespace mv::serve {

std::string in_job_terms(const std::string& message);

}  // namespace mv::serve
