// Inputs the fuzz targets (fuzz/, scripts/fuzz.sh) found that crashed, hung or misbehaved: each file in
// tests/fuzz_regressions/ goes through its reader again, which must refuse it with an mv::Error (or read it)
// and do no more; and the cases crafted from what fuzzing showed. Without the fixes these abort, run out of
// memory, loop forever, or (the UB cases) are caught by a sanitizer build.
#include <string>

#include "io/symvox_file.h"
#include "megavox/error.h"
#include "test_support.h"

namespace mv::test {
namespace {

std::string regression(const std::string& name) {
  return std::string(MEGAVOX_SOURCE_DIR) + "/tests/fuzz_regressions/" + name;
}

// The message of the mv::Error reading `path` throws ("" if it reads; any other exception fails).
template <class Read>
std::string error_of(Read&& read) {
  try {
    read();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(FuzzRegressions, SymvoxBrickCountCheckedBeforeAllocating) {
  // A 16-bit SymVox file whose brick byte count says 2.8 GB: it was allocated before being checked.
  const std::string p = regression("symvox_brick_count_oom.ssvdag");
  const std::string e = error_of([&] { io::read_symvox(p); });
  EXPECT_NE(e.find("the brick byte count"), std::string::npos) << e;
  EXPECT_NE(e.find("bytes left in the file"), std::string::npos) << e;
}

TEST(FuzzRegressions, SymvoxEmptySectionIsNotAMemcpyFromNull) {
  // An empty section: memcpy(nullptr, ..., 0), undefined behaviour (UBSan: "null pointer passed as argument 1").
  const std::string p = regression("symvox_empty_take_null.svdag");
  EXPECT_NE(error_of([&] { io::read_symvox(p); }), "");
}

}  // namespace
}  // namespace mv::test
