// The sanitized suite only (scripts/test.sh --sanitize): under ASan a failed operator new aborts the process
// instead of throwing std::bad_alloc, yet readers rely on a real machine's behaviour, where OpenVDB's
// allocation of a size a damaged file declares (64 GiB in FuzzRegressions.Vdb*) throws and the reader turns it
// into an mv::Error. operator new over malloc, which then returns null (allocator_may_return_null=1), puts
// that back; ASan still guards every block (no large blocks kept for reuse: that is the fuzz targets' speed).
#define MV_THROWING_NEW_LIMIT 0
#define MV_REUSE_LARGE_BLOCKS 0
#include "../fuzz/throwing_new.h"
