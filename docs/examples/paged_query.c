/* A scene larger than its device budget through the C API: FILE.mvx opened on a device that holds it resident and
 * on one whose memory= budget is 1/PART of its nodes (default 8), 100,000 rays traced on each with their colours,
 * the hits and the colours compared byte for byte, and what the streamed scene loaded and held (mvGetSceneStats)
 * printed as one JSON line. The rays and the resident hits are written to RAYS.bin and hits_resident.bin (the
 * service's wire formats) for comparison with `megavox serve`. Exit 0 when hits and colours are identical, pages
 * were streamed and the peak stayed in the budget.
 *   cc -std=c99 -o paged_query docs/examples/paged_query.c $(pkg-config --cflags --libs megavox) -lm
 *   ./paged_query scan16k_s.mvx ocl:0 rays.bin [PART] */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <megavox/megavox.h>

static uint64_t rng = 88172645463325252ull;
static double unit(void) {
  rng ^= rng << 13; rng ^= rng >> 7; rng ^= rng << 17;
  return (double)(rng >> 11) / 9007199254740992.0;
}
static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char** argv) {
  if (argc < 4) { fprintf(stderr, "usage: paged_query FILE.mvx DEVICE RAYS.bin [PART]\n"); return 2; }
  const unsigned part = argc > 4 ? (unsigned)atoi(argv[4]) : 8;
  const size_t n = 100000;
  char config[256];
  snprintf(config, sizeof config, "device=%s", argv[2]);
  MvDevice big = mvNewDevice(config);
  MvScene a = mvOpenScene(big, argv[1]);
  if (!a) { fprintf(stderr, "%s\n", mvGetDeviceLastErrorMessage(big)); return 1; }
  MvSceneInfo info;
  mvGetSceneInfo(a, &info);
  MvTraceRay* rays = calloc(n, sizeof *rays);
  const double side = info.voxelSize * info.resolution;
  for (size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double target = info.lower[k] + unit() * (info.upper[k] - info.lower[k]);
      rays[i].org[k] = (float)(info.origin[k] + side * (0.5 + 1.5 * (2 * unit() - 1)));
      rays[i].dir[k] = (float)(target - rays[i].org[k]);
    }
    rays[i].tmax = INFINITY;
  }
  FILE* f = fopen(argv[3], "wb");
  fwrite(rays, sizeof *rays, n, f);
  fclose(f);
  MvTraceHit* want = calloc(n, sizeof *want);
  MvTraceHit* got = calloc(n, sizeof *got);
  uint8_t* want_rgba = calloc(n, 4);
  uint8_t* got_rgba = calloc(n, 4);
  double t0 = now();
  if (mvTraceRaysRgba(a, rays, want, want_rgba, n, NULL)) {
    fprintf(stderr, "resident: %s\n", mvGetDeviceLastErrorMessage(big));
    return 1;
  }
  const double resident_s = now() - t0;
  const uint64_t budget = info.bytes / part;
  snprintf(config, sizeof config, "device=%s,memory=%llu", argv[2], (unsigned long long)budget);
  MvDevice small = mvNewDevice(config);
  MvScene b = mvOpenScene(small, argv[1]);
  t0 = now();
  if (!b || mvTraceRaysRgba(b, rays, got, got_rgba, n, NULL)) {
    fprintf(stderr, "paged: %s\n", mvGetDeviceLastErrorMessage(small));
    return 1;
  }
  const double paged_s = now() - t0;
  size_t hits = 0, coloured = 0;
  for (size_t i = 0; i < n; ++i) hits += isfinite(want[i].t), coloured += want_rgba[4 * i + 3] != 0;
  const int same = memcmp(want, got, n * sizeof *got) == 0 && memcmp(want_rgba, got_rgba, 4 * n) == 0;
  MvSceneStats s = {sizeof s};
  mvGetSceneStats(b, &s);
  MvSceneStats r = {sizeof r};
  mvGetSceneStats(a, &r);
  printf("{\"file\": \"%s\", \"device\": \"%s\", \"dag_bytes\": %llu, \"budget\": %llu, \"rays\": %zu, \"hits\": %zu, "
         "\"coloured\": %zu, \"identical\": %s, \"paged\": %u, \"cache_bytes\": %llu, \"passes\": %llu, \"pages_streamed\": %llu, "
         "\"peak_device_bytes\": %llu, \"resident_paged\": %u, \"resident_s\": %.3f, \"paged_s\": %.3f}\n",
         argv[1], argv[2], (unsigned long long)info.bytes, (unsigned long long)budget, n, hits, coloured,
         same ? "true" : "false", s.paged, (unsigned long long)s.cacheBytes,
         (unsigned long long)s.passes, (unsigned long long)s.pagesStreamed, (unsigned long long)s.peakDeviceBytes,
         r.paged, resident_s, paged_s);
  f = fopen("hits_resident.bin", "wb");
  fwrite(want, sizeof *want, n, f);
  fclose(f);
  mvReleaseScene(a);
  mvReleaseScene(b);
  mvReleaseDevice(big);
  mvReleaseDevice(small);
  return same && s.peakDeviceBytes <= budget && s.pagesStreamed > 0 ? 0 : 1;
}
