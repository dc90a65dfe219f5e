/* A C99 program on the C API alone (compiled with -std=c99 -pedantic-errors): on every device it can open
 * (ocl:0, ocl:1, ..., then vk:0, ...), builds an octahedron from memory, traces rays at it, renders it, and
 * checks the errors of a bad call. Exit status 0 when every check holds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "megavox/megavox.h"

static int failures = 0;

#define CHECK(cond)                                                      \
  do {                                                                   \
    if (!(cond)) {                                                       \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                        \
    }                                                                    \
  } while (0)

static int errors_seen = 0;
static void on_error(void* user, MvError code, const char* message) {
  (void)user;
  (void)code;
  (void)message;
  ++errors_seen;
}

static bool on_progress(void* user, const char* stage, double fraction) {
  (void)stage;
  CHECK(fraction >= 0 && fraction <= 1);
  ++*(int*)user;
  return true;
}

static void run_on(MvDevice dev) {
  static const float vertices[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  static const uint32_t indices[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  MvBuildArguments args;
  MvSceneInfo info;
  MvTraceRay rays[2];
  MvTraceHit hits[2];
  MvRenderArguments render;
  uint8_t* rgba;
  int progress_calls = 0, lit = 0, i;
  MvScene scene;

  mvSetDeviceErrorFunction(dev, on_error, NULL);
  mvInitBuildArguments(&args);
  args.resolution = 32;
  args.format = "ssvdag";
  args.progress = on_progress;
  args.progressUserPtr = &progress_calls;
  scene = mvBuildSceneFromMemory(dev, vertices, 6, indices, 8, &args);
  CHECK(scene != NULL);
  if (!scene) {
    fprintf(stderr, "build: %s\n", mvGetDeviceLastErrorMessage(dev));
    return;
  }
  CHECK(progress_calls > 0);
  CHECK(mvGetSceneInfo(scene, &info) == MV_ERROR_NONE);
  CHECK(info.resolution == 32 && info.voxels > 0 && strcmp(info.encoding, "ssvdag") == 0);

  /* one ray down the z axis onto the octahedron's tip, one past it */
  memset(rays, 0, sizeof rays);
  rays[0].org[2] = 5;
  rays[0].dir[2] = -1;
  rays[0].tmax = INFINITY;
  rays[1] = rays[0];
  rays[1].org[0] = 3;
  CHECK(mvTraceRays(scene, rays, hits, 2, NULL) == MV_ERROR_NONE);
  CHECK(hits[0].t > 3.9f && hits[0].t < 4.1f);
  CHECK(hits[0].normal[2] == 1 && hits[0].level == 0);
  CHECK(isinf(hits[1].t));

  mvInitRenderArguments(&render);
  render.width = 40;
  render.height = 30;
  render.shading = "normal";
  rgba = (uint8_t*)malloc((size_t)40 * 30 * 4);
  CHECK(mvRenderScene(scene, NULL, &render, rgba, 0) == MV_ERROR_NONE);
  for (i = 0; i < 40 * 30; ++i) lit += rgba[4 * i] != rgba[0] || rgba[4 * i + 1] != rgba[1];
  CHECK(lit > 0 && rgba[3] == 255);
  free(rgba);

  /* errors: a code, the message, the function */
  CHECK(mvTraceRays(scene, NULL, hits, 1, NULL) == MV_ERROR_INVALID_ARGUMENT);
  CHECK(mvGetDeviceError(dev) == MV_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(mvGetDeviceLastErrorMessage(dev), "NULL") != NULL);
  CHECK(mvOpenScene(dev, "/no/such/scene.mvx") == NULL);
  CHECK(mvGetDeviceError(dev) == MV_ERROR_IO);
  CHECK(errors_seen == 2);
  errors_seen = 0;
  mvReleaseScene(scene);
}

int main(void) {
  static const char* backends[2] = {"ocl", "vk"};
  char config[64];
  int b, n, devices = 0;
  CHECK(mvGetVersion() == MV_VERSION_MAJOR * 10000 + MV_VERSION_MINOR * 100 + MV_VERSION_PATCH);
  CHECK(strcmp(mvGetVersionString(), MV_VERSION_STRING) == 0);
  CHECK(sizeof(MvTraceHit) == 32);
  for (b = 0; b < 2; ++b)
    for (n = 0;; ++n) {
      MvDevice dev;
      sprintf(config, "device=%s:%d", backends[b], n);
      dev = mvNewDevice(config);
      if (!dev) {
        CHECK(mvGetDeviceError(NULL) == MV_ERROR_UNSUPPORTED_DEVICE);
        break;
      }
      printf("%s\n", config);
      run_on(dev);
      mvReleaseDevice(dev);
      ++devices;
    }
  CHECK(devices > 0);
  printf("%d device(s), %d failure(s)\n", devices, failures);
  return failures ? 1 : 0;
}
