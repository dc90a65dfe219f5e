/* The C API's smallest whole program: opens the default device, builds an octahedron held in memory into a
 * 32^3 voxel DAG, shoots a 16 x 16 grid of rays down through it and prints how many hit. The README builds it
 * against a build tree (pkg-config or CMake); tests/install/build_tree.sh checks that it still does.
 * Exit status 0 when every call succeeded. */
#include <math.h>
#include <stdio.h>

#include <megavox/megavox.h>

int main(void) {
  /* an octahedron of radius 1 around the origin: 6 vertices, 8 triangles */
  static const float vertices[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  static const uint32_t indices[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  MvDevice dev;
  MvDeviceInfo device;
  MvBuildArguments args;
  MvScene scene;
  MvTraceRay rays[256];
  MvTraceHit hits[256];
  int i, hit = 0;

  dev = mvNewDevice(NULL); /* $MEGAVOX_DEVICE, else the first GPU, else PoCL */
  if (!dev) {
    fprintf(stderr, "device: %s\n", mvGetDeviceLastErrorMessage(NULL));
    return 1;
  }
  mvGetDeviceInfo(dev, &device);
  printf("megavox %s on %s (%s)\n", mvGetVersionString(), device.name, device.selector);

  mvInitBuildArguments(&args);
  args.resolution = 32; /* no output file: the scene stays in memory */
  scene = mvBuildSceneFromMemory(dev, vertices, 6, indices, 8, &args);
  if (!scene) {
    fprintf(stderr, "build: %s\n", mvGetDeviceLastErrorMessage(dev));
    mvReleaseDevice(dev);
    return 1;
  }

  /* rays through the centres of a 16 x 16 grid over [-1, 1]^2, from z = 2 down */
  for (i = 0; i < 256; ++i) {
    rays[i].org[0] = -1 + ((i % 16) + 0.5f) / 8;
    rays[i].org[1] = -1 + ((i / 16) + 0.5f) / 8;
    rays[i].org[2] = 2;
    rays[i].dir[0] = rays[i].dir[1] = 0;
    rays[i].dir[2] = -1;
    rays[i].tmax = INFINITY;
  }
  if (mvTraceRays(scene, rays, hits, 256, NULL) != MV_ERROR_NONE) {
    fprintf(stderr, "trace: %s\n", mvGetDeviceLastErrorMessage(dev));
    mvReleaseScene(scene);
    mvReleaseDevice(dev);
    return 1;
  }
  for (i = 0; i < 256; ++i) hit += !isinf(hits[i].t);
  printf("hits %d of 256\n", hit);

  mvReleaseScene(scene);
  mvReleaseDevice(dev);
  return 0;
}
