// What this build of the baselines holds (compile definitions of the megavox_baselines target).
#include "baselines.h"

namespace mv::baseline {

#ifndef MEGAVOX_HAVE_BOOST_SORT
#define MEGAVOX_HAVE_BOOST_SORT 0
#endif
#ifndef MEGAVOX_HAVE_IPS4O
#define MEGAVOX_HAVE_IPS4O 0
#endif
#ifndef MEGAVOX_HAVE_VQSORT
#define MEGAVOX_HAVE_VQSORT 0
#endif
#ifndef MEGAVOX_HAVE_EMBREE
#define MEGAVOX_HAVE_EMBREE 0
#endif
#ifndef MEGAVOX_HAVE_OPENCV
#define MEGAVOX_HAVE_OPENCV 0
#endif

Baseline boost_sort() { return {"boost::sort::block_indirect_sort", "libboost-dev", MEGAVOX_HAVE_BOOST_SORT != 0}; }
Baseline ips4o() { return {"ips4o::parallel::sort", "libips4o-dev", MEGAVOX_HAVE_IPS4O != 0}; }
Baseline vqsort() { return {"vqsort (1 thread)", "libhwy-dev", MEGAVOX_HAVE_VQSORT != 0}; }
Baseline embree() { return {"Embree 3", "libembree-dev", MEGAVOX_HAVE_EMBREE != 0}; }
Baseline opencv() { return {"OpenCV cv::grabCut", "libopencv-imgproc-dev", MEGAVOX_HAVE_OPENCV != 0}; }

std::string missing_note(const Baseline& b) {
  return std::string(b.name) + ": not built in (needs " + b.package +
         ", which scripts/setup.sh --bench installs, and a build with -DMEGAVOX_BASELINES=AUTO, "
         "as scripts/run.sh and scripts/bench.sh make)";
}

}  // namespace mv::baseline
