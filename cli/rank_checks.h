// Under mpirun: checks every rank makes together before a build spread over them does any work.
#pragma once
#include <string>

namespace mv::cli {

// Every rank reads the input: a rank that cannot is found before any work and named, on every rank (throws
// mv::IoError). A no-op in one process.
void check_every_rank_reads(const std::string& input);

}  // namespace mv::cli
