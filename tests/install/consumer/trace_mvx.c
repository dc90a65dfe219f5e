/* trace_mvx FILE.mvx: opens a scene through the installed C API, shoots a 16 x 16 grid of rays through its
 * bounds along -z and prints "hits N of 256". Exit status 1 on any error. */
#include <math.h>
#include <stdio.h>

#include <megavox/megavox.h>

int main(int argc, char** argv) {
  MvDevice dev;
  MvScene scene;
  MvSceneInfo info;
  MvTraceRay rays[256];
  MvTraceHit hits[256];
  int i, hit = 0;
  if (argc != 2) {
    fprintf(stderr, "usage: trace_mvx FILE.mvx\n");
    return 2;
  }
  printf("megavox %s\n", mvGetVersionString());
  dev = mvNewDevice(NULL);
  if (!dev) {
    fprintf(stderr, "device: %s\n", mvGetDeviceLastErrorMessage(NULL));
    return 1;
  }
  scene = mvOpenScene(dev, argv[1]);
  if (!scene || mvGetSceneInfo(scene, &info) != MV_ERROR_NONE) {
    fprintf(stderr, "scene: %s\n", mvGetDeviceLastErrorMessage(dev));
    return 1;
  }
  for (i = 0; i < 256; ++i) {
    rays[i].org[0] = (float)(info.lower[0] + (info.upper[0] - info.lower[0]) * ((i % 16) + 0.5) / 16);
    rays[i].org[1] = (float)(info.lower[1] + (info.upper[1] - info.lower[1]) * ((i / 16) + 0.5) / 16);
    rays[i].org[2] = (float)(info.upper[2] + 1);
    rays[i].dir[0] = rays[i].dir[1] = 0;
    rays[i].dir[2] = -1;
    rays[i].tmax = INFINITY;
  }
  if (mvTraceRays(scene, rays, hits, 256, NULL) != MV_ERROR_NONE) {
    fprintf(stderr, "trace: %s\n", mvGetDeviceLastErrorMessage(dev));
    return 1;
  }
  for (i = 0; i < 256; ++i) hit += !isinf(hits[i].t);
  printf("hits %d of 256\n", hit);
  mvReleaseScene(scene);
  mvReleaseDevice(dev);
  return 0;
}
