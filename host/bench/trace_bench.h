// `megavox bench trace`: rays per second of the traversal kernel per encoding (primary, shadow and AO rays
// of the renderer's camera), against Embree tracing the source triangles with the same primary rays, the
// kernel's code compiled for the host, and the flat reference DDA.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/device.h"
#include "megavox/render.h"

namespace mv::bench {

struct TraceBenchOptions {
  uint32_t width = 1280, height = 720;
  std::string view = "iso";
  bool use_camera = false;  // trace from `camera` instead of the preset view
  Camera camera;
  double lod_pixels = 1;
  uint32_t ao_samples = 4;
  uint32_t repeats = 7;  // best of, alternating between the files
  uint64_t cache_bytes = 0;  // nonzero: paged files traced through a page cache of this size
};

// Mean steps per ray (each a cell visited: a descent into it or a move to it), the kernel's walk on the host.
struct StepsPerRay {
  double primary = 0, primary_hit = 0;  // every primary ray; those that hit
  double shadow = 0, ao = 0;            // the rays cast from the hits
};

struct TraceBenchEncoding {
  std::string file, format;
  uint32_t resolution = 0;
  uint64_t hits = 0;
  double primary_seconds = 0, shadow_seconds = 0, ao_seconds = 0;  // best of `repeats`
  double primary_mrays = 0, shadow_mrays = 0, ao_mrays = 0;
  double primary_mrays_no_beam = 0;  // the same primary rays without the beam pre-pass, same run
  double beam_steps = 0, beam_hit_steps = 0;  // the device's steps per primary ray with it (all; the hits)
  double host_core_mrays = 0;   // the same primary rays, kernel code built for the host (TBB threads)
  double reference_mrays = 0;   // the flat voxel DDA (a sample of the rays); 0 = skipped (over 64 Mi voxels)
  double silhouette_agreement = 0;  // pixels where the voxels and Embree's triangles agree on hit / miss
  double over_embree = 0;           // primary Mrays/s / Embree's
  bool paged = false;               // traced through the page cache
  bool converged = true;            // paged: every render of the repeats ended with the resident picture
  StepsPerRay steps;
};

struct TraceBenchResult {
  std::string mesh, device;
  uint32_t width = 0, height = 0;
  double lod_pixels = 0;
  std::vector<TraceBenchEncoding> encodings;
  bool have_embree = false;
  uint64_t triangles = 0;
  double embree_build_seconds = 0, embree_seconds = 0, embree_mrays = 0;  // rtcIntersect1, all threads
  double embree16_mrays = 0;         // rtcIntersect16, packets of 4 x 4 camera rays, all threads
  uint64_t embree16_mismatches = 0;  // pixels where the packets' hit flag differs from the single rays'
  uint64_t embree_hits = 0;
  // When both encodings were given: SSVDAG / SVDAG trace time of whole renders (primary + shadow + AO rays),
  // the median over the repeats of each back-to-back pair (steadier than ratios of best times on a noisy
  // machine), and the ratio of the best primary-pass times.
  double ssvdag_over_svdag = 0;
  double ssvdag_over_svdag_primary = 0;
};

TraceBenchResult run_trace_bench(Device& dev, const std::vector<std::string>& files, const std::string& mesh,
                                 const TraceBenchOptions& options);

}  // namespace mv::bench
