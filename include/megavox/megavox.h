/* megavox — the C API (C99): devices, scenes (voxel DAGs), point-cloud builds, masks and jobs, in Embree's
 * conventions.
 *
 * Handles are opaque and reference counted: mvNew... / mvOpen... / mvBuild... return one reference,
 * mvRetain... adds one, mvRelease... drops one; the object goes when the last reference does. A scene and a
 * job keep their device alive.
 *
 * Errors: no C++ exception crosses this API. A call that fails returns NULL (constructors) or an MvError, and
 * records the error on its device: mvGetDeviceError returns the code of the last error and clears it,
 * mvGetDeviceLastErrorMessage says what went wrong, and an error function set with mvSetDeviceErrorFunction
 * is called at once with both. Errors of mvNewDevice, and of calls given a NULL device, go to a per-thread
 * record read with mvGetDeviceError(NULL).
 *
 * Threads: every call on one device (and on its scenes) is serialised by the device; use one device per
 * thread for parallel work. Jobs run on their own thread and take the device's lock while they build.
 *
 * Units: rays and cameras are in the model's own units (the scene's world-to-grid transform).
 */
#ifndef MEGAVOX_MEGAVOX_H
#define MEGAVOX_MEGAVOX_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "megavox/version.h" /* MV_VERSION_MAJOR, _MINOR, _PATCH, MV_VERSION_STRING */

#ifdef __cplusplus
extern "C" {
#endif

#if defined(__GNUC__)
#define MV_API __attribute__((visibility("default")))
#else
#define MV_API
#endif

/* ---- versions ---- */

/* MAJOR * 10000 + MINOR * 100 + PATCH of the library in use (compare with the MV_VERSION_* the caller built with). */
MV_API uint32_t mvGetVersion(void);
MV_API const char* mvGetVersionString(void);

/* ---- errors ---- */

typedef enum MvError {
  MV_ERROR_NONE = 0,
  MV_ERROR_UNKNOWN = 1,            /* an internal failure: a fault inside megavox, not the caller's */
  MV_ERROR_INVALID_ARGUMENT = 2,   /* a NULL pointer, a bad option, an unknown name */
  MV_ERROR_INVALID_OPERATION = 3,  /* the call does not apply to this object now (a job not done) */
  MV_ERROR_OUT_OF_MEMORY = 4,      /* the device or host memory budget cannot hold the work */
  MV_ERROR_UNSUPPORTED_DEVICE = 5, /* no device matches the selector */
  MV_ERROR_CANCELLED = 6,          /* a progress function (or mvCancelJob) stopped the work */
  MV_ERROR_INPUT = 7,              /* the input file or arrays are malformed, or not what the call takes */
  MV_ERROR_IO = 8,                 /* a file or folder cannot be opened, read, written or renamed */
  MV_ERROR_DEVICE = 9              /* the device or its driver failed (a lost device, a kernel it cannot build) */
} MvError;

/* "MV_ERROR_INPUT", ...: the name of a code. */
MV_API const char* mvGetErrorString(MvError code);

/* ---- devices ---- */

typedef struct MvDeviceTy* MvDevice;

/* config: NULL or "" for the defaults, else comma-separated key=value:
 *   device=SEL        "ocl:N", "vk:N" or part of a device, platform or vendor name (default: $MEGAVOX_DEVICE,
 *                     else the first GPU, else PoCL)
 *   memory=SIZE       device memory budget, e.g. 512M (default: 3/4 of what the device reports)
 *   host_memory=SIZE  host RAM budget of builds (default: half the physical RAM)
 *   cache_memory=SIZE ray queries and renders of a paged .mvx stream it through a device page cache of SIZE
 *                     (default: only when the scene does not fit what is left of the budget; then the
 *                     cache takes part of what is left)
 *   kernel_shape=S    how kernels are launched: gpu, cpu or auto (by the device's type; default:
 *                     $MEGAVOX_KERNEL_SHAPE, else auto). Every shape gives the same bytes
 * Returns NULL on failure (mvGetDeviceError(NULL) says why). */
MV_API MvDevice mvNewDevice(const char* config);
MV_API void mvRetainDevice(MvDevice device);
MV_API void mvReleaseDevice(MvDevice device);

/* The code of the device's last error (MV_ERROR_NONE when none), clearing it. NULL: this thread's record. */
MV_API MvError mvGetDeviceError(MvDevice device);
/* The message of the last error ("" when none); valid until the next failing call on the device. */
MV_API const char* mvGetDeviceLastErrorMessage(MvDevice device);

/* Called on the failing thread, after the error is recorded. NULL removes it. */
typedef void (*MvErrorFunction)(void* userPtr, MvError code, const char* message);
MV_API void mvSetDeviceErrorFunction(MvDevice device, MvErrorFunction function, void* userPtr);

typedef struct MvDeviceInfo {
  char name[128];   /* as the driver reports it */
  char backend[16]; /* "opencl" or "vulkan" */
  char selector[16]; /* "ocl:N" / "vk:N" */
  uint64_t memoryBudget, memoryUsed; /* bytes */
} MvDeviceInfo;
MV_API MvError mvGetDeviceInfo(MvDevice device, MvDeviceInfo* info);
/* One compute device as listing finds it, before any is opened. */
typedef struct MvDeviceDescription {
  char selector[16];   /* "ocl:N" / "vk:N": the device= of mvNewDevice */
  char name[128];      /* as the driver reports it */
  char backend[16];    /* "opencl" or "vulkan" */
  char type[16];       /* "cpu", "gpu" or "other" */
  char platform[128];  /* OpenCL: the platform's name; Vulkan: the driver's */
  uint64_t memoryBytes; /* global memory the device reports */
  bool isDefault;      /* the device mvNewDevice picks without device= (and $MEGAVOX_DEVICE as it is now) */
} MvDeviceDescription;
/* Every OpenCL and Vulkan device (OpenCL first): writes the first min(count, capacity) into devices (NULL when
 * capacity is 0) and returns count. Errors go to this thread's record (mvGetDeviceError(NULL)); 0 then. */
MV_API size_t mvListDevices(MvDeviceDescription* devices, size_t capacity);

/* The host RAM budget of the device's builds, in bytes: its host_memory, else the default (half the physical
 * RAM). NULL: the default. */
MV_API uint64_t mvGetHostMemoryBudget(MvDevice device);

/* ---- progress ---- */

/* Called with a stage name ("read", "voxelize", ...) and the fraction done (0..1); return false to cancel. */
typedef bool (*MvProgressMonitorFunction)(void* userPtr, const char* stage, double fraction);

/* ---- scenes ---- */

typedef struct MvSceneTy* MvScene;

/* MvBuildArguments.cube: never out of core (0 there asks for the default, as for every other field). */
#define MV_CUBE_IN_CORE UINT32_MAX

typedef struct MvBuildArguments {
  size_t byteSize;         /* sizeof(MvBuildArguments), set by mvInitBuildArguments */
  const char* format;      /* "svo", "svdag" (default), "ussvdag" or "ssvdag" */
  uint32_t resolution;     /* voxels per axis, a power of two; 0: 1024 (a .vdb: its own extent) */
  uint32_t cube;           /* above this resolution build out of core in cubes of this side (a power of two);
                              0: the default, 1024 (the CLI's --cube); MV_CUBE_IN_CORE: always in core */
  const char* voxelize;    /* "conservative" (default) or "thin" */
  const char* gridOrigin;  /* "center" (default) or "min" */
  const char* grid;        /* a .vdb input: the grid to read (NULL: the first) */
  const char* output;      /* the .mvx to write (to a temporary name, renamed at the end); NULL: a scratch
                              file of the scene's own, removed with it. The built scene is this file, read on
                              its first use (a caller that wants only the file never reads it back): leave it
                              in place while the scene lives. */
  MvProgressMonitorFunction progress; /* NULL: none; called on the building thread */
  void* progressUserPtr;
} MvBuildArguments;
MV_API void mvInitBuildArguments(MvBuildArguments* args);

/* Builds a scene from a mesh file (PLY, OBJ, glTF, STL, ... or a .vdb volume). args NULL: the defaults. */
MV_API MvScene mvBuildSceneFromFile(MvDevice device, const char* path, const MvBuildArguments* args);
/* From caller memory: vertexCount vertices of 3 floats, triangleCount triangles of 3 indices (read only
 * during the call). */
MV_API MvScene mvBuildSceneFromMemory(MvDevice device, const float* vertices, size_t vertexCount,
                                      const uint32_t* indices, size_t triangleCount, const MvBuildArguments* args);
/* As mvBuildSceneFromMemory, with a colour per vertex: rgb[3 * v .. 3 * v + 2] (8-bit R, G, B) for vertex v,
 * or NULL for none. A voxel takes the colour of the surface it covers, as from a PLY with vertex colours. */
MV_API MvScene mvBuildSceneFromMemoryRgb(MvDevice device, const float* vertices, size_t vertexCount,
                                         const uint32_t* indices, size_t triangleCount, const uint8_t* rgb,
                                         const MvBuildArguments* args);
/* Opens a voxel .mvx. A paged one (what builds write) is mapped and kept paged: its header and page index are
 * checked now, each page when a query first reads it (a damaged page fails that query, named); any other is
 * read whole and checked (checksums, structure) before it returns. */
MV_API MvScene mvOpenScene(MvDevice device, const char* path);
MV_API void mvRetainScene(MvScene scene);
MV_API void mvReleaseScene(MvScene scene);
/* Writes the scene as a .mvx (temporary name, then renamed). */
MV_API MvError mvSaveScene(MvScene scene, const char* path);

typedef struct MvSceneInfo {
  char encoding[16];     /* "svo", "svdag", "ussvdag" or "ssvdag" */
  uint32_t resolution;   /* voxels per axis */
  uint32_t levels;
  uint64_t voxels;
  uint64_t bytes;        /* the encoded DAG as the file stores it (a paged file: its paged node stream) */
  double origin[3];      /* world position of the grid's min corner */
  double voxelSize;      /* world units per voxel */
  double lower[3], upper[3]; /* the model's bounds */
} MvSceneInfo;
MV_API MvError mvGetSceneInfo(MvScene scene, MvSceneInfo* info);

/* How a scene's queries have used the device so far. A paged .mvx (what builds write) whose nodes do not fit
 * what is left of the device budget, or any paged one on a device with cache_memory=, streams through a page
 * cache: a ray that reaches a missing page asks for it, and the batch repeats (in smaller batches where the
 * cache cannot hold a batch's pages) until every ray is resolved, so the hits are those of the resident scene.
 * The budget covers everything: the cache, its update, the ray and hit buffers (batches split to fit). */
typedef struct MvSceneStats {
  size_t byteSize;           /* set to sizeof(MvSceneStats) before the call */
  uint32_t paged;            /* 1: queries stream through a page cache; 0: the scene is resident */
  uint64_t cacheBytes;       /* the page cache's slots on the device (0 when resident) */
  uint64_t passes;           /* trace passes over ray batches, all queries so far */
  uint64_t pagesStreamed;    /* pages loaded into the cache, all queries so far */
  uint64_t peakDeviceBytes;  /* the most device memory in use while the scene's calls ran */
} MvSceneStats;
MV_API MvError mvGetSceneStats(MvScene scene, MvSceneStats* stats);

/* ---- ray queries ---- */

typedef struct MvTraceRay {
  float org[3];
  float dir[3]; /* need not be unit: t is in units of its length */
  float tmax;   /* +inf: unbounded */
} MvTraceRay;

/* 32 bytes (the record a ray-query service can send as is). */
typedef struct MvTraceHit {
  float t;           /* hit point org + t * dir; +inf: a miss; NaN: gave up after maxSteps */
  uint32_t level;    /* 0: a voxel; above 0 a coarser cell */
  uint32_t cell[3];  /* the cell at `level`; its first voxel is cell << level */
  int32_t normal[3]; /* the face entered (axis-aligned); zero when the ray starts in a full voxel */
} MvTraceHit;

typedef struct MvTraceArguments {
  size_t byteSize;   /* sizeof(MvTraceArguments), set by mvInitTraceArguments */
  uint32_t maxSteps; /* traversal steps before a ray gives up (default 60000) */
} MvTraceArguments;
MV_API void mvInitTraceArguments(MvTraceArguments* args);

/* Traces count rays into hits[0..count) (args NULL: the defaults). The same bytes on every device. */
MV_API MvError mvTraceRays(MvScene scene, const MvTraceRay* rays, MvTraceHit* hits, size_t count, const MvTraceArguments* args);

/* As mvTraceRays, and each hit's colour into rgba[4 * i .. 4 * i + 3] (R, G, B, A) when rgba is not NULL: for a
 * scene with voxel colours (built from a coloured point cloud) the hit cell's colour, a voxel's own or, at a
 * coarser level, the mean of the voxels below it, with A = 255; all four 0 for a miss or a scene without colours.
 * A scene streamed through a page cache (MvSceneStats.paged) finds them through the cache too, the same bytes,
 * where its file carries the size plane (written since .mvx version 5); an older file streams without colours. */
MV_API MvError mvTraceRaysRgba(MvScene scene, const MvTraceRay* rays, MvTraceHit* hits, uint8_t* rgba, size_t count,
                               const MvTraceArguments* args);

/* The scene's stored colours (voxels and inner nodes, depth-first) into *entries: 0 when it has none, or when its
 * queries stream an older file without a size plane through a page cache (they return no colours then). */
MV_API MvError mvGetSceneColourEntries(MvScene scene, uint64_t* entries);

/* ---- pictures ---- */

typedef struct MvCamera {
  double eye[3], target[3], up[3];
  double fov; /* vertical, degrees */
} MvCamera;

typedef struct MvRenderArguments {
  size_t byteSize;      /* sizeof(MvRenderArguments), set by mvInitRenderArguments */
  uint32_t width, height;
  const char* shading;  /* "shaded" (default), "normal", "depth", "level", "heat" or "colour" (a scene with voxel
                           colours is shaded with them; "colour": unlit) */
  const char* view;     /* camera NULL: "iso" (default), "front", "back", "left", "right" or "top" */
  double lodPixels;     /* stop at cells smaller than this many pixels; 0: voxels only (default 1) */
  uint32_t aoSamples;   /* ambient-occlusion rays per hit (default 8, at most 256) */
} MvRenderArguments;
MV_API void mvInitRenderArguments(MvRenderArguments* args);

/* MvCamera.fov of the preset views when none is asked for (degrees). */
#define MV_DEFAULT_FOV 40.0

/* The camera of a preset view ("iso", "front", "back", "left", "right" or "top") framing the scene's model at
 * fov degrees (0: MV_DEFAULT_FOV), as mvRenderScene frames it when given no camera. */
MV_API MvError mvGetSceneViewCamera(MvScene scene, const char* view, double fov, MvCamera* camera);

/* Renders into rgba: height rows of width pixels, 4 bytes each (alpha 255), rows rowStride bytes apart
 * (0: width * 4), top row first. camera NULL: args->view framing the model. */
MV_API MvError mvRenderScene(MvScene scene, const MvCamera* camera, const MvRenderArguments* args, uint8_t* rgba,
                             size_t rowStride);

/* Writes height rows of width RGBA pixels (rows rowStride bytes apart, 0: width * 4; alpha is dropped) as
 * the path's extension says: JPEG for .jpg / .jpeg, else PNG (a temporary name, then renamed). Errors go to
 * this thread's record (mvGetDeviceError(NULL)). */
MV_API MvError mvWriteImage(const char* path, const uint8_t* rgba, uint32_t width, uint32_t height, size_t rowStride);

/* ---- jobs: builds on their own thread ---- */

typedef struct MvJobTy* MvJob;

typedef enum MvJobStatus {
  MV_JOB_QUEUED = 0,  /* waiting for the device */
  MV_JOB_RUNNING = 1,
  MV_JOB_DONE = 2,
  MV_JOB_FAILED = 3,
  MV_JOB_CANCELLED = 4
} MvJobStatus;

/* As mvBuildSceneFromFile / mvBuildSceneFromMemory (the arrays are copied), but returning at once; the
 * progress function, if any, is called on the job's thread (returning false cancels). Point-cloud and mask
 * jobs (below) are the same kind of job. */
MV_API MvJob mvBuildSceneFromFileAsync(MvDevice device, const char* path, const MvBuildArguments* args);
MV_API MvJob mvBuildSceneFromMemoryAsync(MvDevice device, const float* vertices, size_t vertexCount,
                                         const uint32_t* indices, size_t triangleCount,
                                         const MvBuildArguments* args);
MV_API void mvRetainJob(MvJob job);
/* The last release of a job still running cancels it and waits for it to stop; from the job's own progress
 * function it cancels it and returns at once (the job stops when that function returns). Any handle may be
 * released from any thread or callback: a call in flight keeps what it uses until it returns, and a scene or
 * job keeps its device, so a device may be released before them. */
MV_API void mvReleaseJob(MvJob job);
/* The status now; fraction (may be NULL) gets the fraction done of the whole build (0..1). */
MV_API MvJobStatus mvGetJobStatus(MvJob job, double* fraction);
/* The stage running now, or when it ended, the failure's message ("" when none); valid until the next call on the job. */
MV_API const char* mvGetJobMessage(MvJob job);
/* Asks the job to stop at its next progress point; nothing of its output file is left. */
MV_API void mvCancelJob(MvJob job);
/* Waits until the job ends: MV_ERROR_NONE when it did its work, else why not (also recorded on the device). */
MV_API MvError mvWaitJob(MvJob job);
/* The built scene, a new reference (release it); NULL unless the job is MV_JOB_DONE and built a scene (a
 * point-cloud or mask job writes a file instead: MV_ERROR_INVALID_OPERATION). */
MV_API MvScene mvGetJobScene(MvJob job);

/* ---- point clouds: a PLY or LAS cloud to a point hierarchy ---- */

typedef struct MvPointBuildArguments {
  size_t byteSize;         /* sizeof(MvPointBuildArguments), set by mvInitPointBuildArguments */
  const char* format;      /* "mvx" (default): a .mvx point hierarchy; "3dtiles": a 3D Tiles folder */
  uint32_t depth;          /* the leaf level, at most 21; 0: picked from the point count */
  uint32_t maxNodePoints;  /* points a node keeps at most (default 16384) */
  MvProgressMonitorFunction progress; /* stages "read", "build", "write"; NULL: none */
  void* progressUserPtr;
  /* Added later: a caller built against the shorter struct (byteSize without them) gets their defaults. */
  const char* tilesVersion; /* "3dtiles": "1.1" (default: glTF tiles, placed on the globe with a CRS) or "1.0" */
  const char* crs;          /* "3dtiles": the CRS to place the tileset with (EPSG:N, WKT); NULL: the input's */
  const double* bounds;     /* LAS and LAZ: only the points in {min x, y, z, max x, y, z}; NULL: every point */
} MvPointBuildArguments;
MV_API void mvInitPointBuildArguments(MvPointBuildArguments* args);

/* Builds output (a .mvx file, or a 3D Tiles folder; written under a temporary name, then renamed) from the
 * cloud at input, within the device's host memory budget (out of core past it). args NULL: the defaults. */
MV_API MvError mvBuildPointsFile(MvDevice device, const char* input, const char* output,
                                 const MvPointBuildArguments* args);
/* The same as a job (mvGetJobScene does not apply: the result is the output). */
MV_API MvJob mvBuildPointsFileAsync(MvDevice device, const char* input, const char* output,
                                    const MvPointBuildArguments* args);

/* A cloud in caller memory (read only during the call). Positions become integers on a grid as a PLY's do
 * (docs/points.md): xyz32 as float x, y, z, xyz64 as double; so a cloud gives the same hierarchy from these
 * arrays as from a PLY holding the same values. */
typedef struct MvPointArrays {
  size_t byteSize;            /* sizeof(MvPointArrays), set by mvInitPointArrays */
  size_t count;               /* points */
  const float* xyz32;         /* 3 per point: exactly one of xyz32 and xyz64 is not NULL */
  const double* xyz64;
  const uint16_t* rgb;        /* 3 per point as stored (a PLY's uchar colours stay 0-255), or NULL */
  const uint16_t* intensity;  /* 1 per point, or NULL */
  const uint8_t* extra;       /* extraBytes raw bytes per point (carried as a LAS file's extra bytes), or NULL */
  uint32_t extraBytes;
} MvPointArrays;
MV_API void mvInitPointArrays(MvPointArrays* points);

/* As mvBuildPointsFile, from arrays instead of a file (in memory whole: the host memory budget does not apply). */
MV_API MvError mvBuildPointsFromMemory(MvDevice device, const MvPointArrays* points, const char* output,
                                       const MvPointBuildArguments* args);

/* ---- point hierarchies read back ---- */

typedef struct MvPointsTy* MvPoints;

/* Reads a .mvx point hierarchy whole (checked) into memory. */
MV_API MvPoints mvOpenPoints(MvDevice device, const char* path);
MV_API void mvRetainPoints(MvPoints points);
MV_API void mvReleasePoints(MvPoints points);

typedef struct MvPointsInfo {
  uint64_t nodes, points;       /* points stored: every leaf's and the inner nodes' representatives */
  uint64_t pointsIn, pointsKept, pointsDropped;
  uint32_t depth;               /* the deepest level that holds a node */
  uint32_t attributes;          /* MV_POINT_* bits of the columns it carries */
  uint32_t extraBytes;          /* per point, with MV_POINT_EXTRA */
  double scale[3], offset[3];   /* the input's grid: world = offset + scale * X */
  char format[64];              /* what the build read: "LAS 1.2, point format 3", "float32 arrays", ... */
} MvPointsInfo;
#define MV_POINT_RGB 1u
#define MV_POINT_NORMAL 2u
#define MV_POINT_INTENSITY 4u
#define MV_POINT_EXTRA 8u
MV_API MvError mvGetPointsInfo(MvPoints points, MvPointsInfo* info);
/* The CRS the input declared (a LAS file's WKT) into text, cut to capacity bytes with its NUL (text may be NULL
 * when capacity is 0); returns its whole length in bytes, without the NUL (0: none). */
MV_API size_t mvGetPointsCrs(MvPoints points, char* text, size_t capacity);

/* A named field of each point's extra bytes: a LAS file's return numbers, classification, scan angle, GPS time,
 * NIR, ... and its typed extra bytes (docs/points.md). */
typedef struct MvPointField {
  char name[64];    /* NUL-terminated (longer names are cut) */
  uint32_t type;    /* MV_FIELD_U8 ... MV_FIELD_F64 */
  uint32_t offset;  /* bytes into the point's extraBytes */
  uint32_t count;   /* values (little-endian, unaligned) */
  uint32_t reserved;
  double scale, add; /* the quantity is value * scale + add */
} MvPointField;
#define MV_FIELD_U8 0u
#define MV_FIELD_I8 1u
#define MV_FIELD_U16 2u
#define MV_FIELD_I16 3u
#define MV_FIELD_U32 4u
#define MV_FIELD_I32 5u
#define MV_FIELD_U64 6u
#define MV_FIELD_I64 7u
#define MV_FIELD_F32 8u
#define MV_FIELD_F64 9u
/* Copies up to capacity fields into fields (NULL when capacity is 0); returns how many there are (0: the extra
 * bytes are unnamed, or there are none). */
MV_API size_t mvGetPointFields(MvPoints points, MvPointField* fields, size_t capacity);

/* 40 bytes, as .mvx stores it. Nodes are breadth-first, root first, each node's children contiguous in octant
 * order; node i's points are [firstPoint, firstPoint + pointCount). code: the Morton code with a sentinel bit
 * (the root is 1, child o of c is (c << 3) | o). */
typedef struct MvPointNode {
  uint64_t code, firstPoint, subtreePoints;
  uint32_t pointCount, firstChild;
  uint8_t childMask, level;
  uint16_t pad;
  uint32_t reserved;
} MvPointNode;
/* Copies nodes [first, first + count) into nodes. */
MV_API MvError mvGetPointNodes(MvPoints points, uint64_t first, uint64_t count, MvPointNode* nodes);
/* Copies points [first, first + count): positions in world units (3 doubles each), and where not NULL the
 * colours (3 x uint16), intensities, extra bytes (extraBytes each) and normals (3 floats) of a hierarchy that
 * carries them (MV_ERROR_INVALID_ARGUMENT when it does not). */
MV_API MvError mvGetPointData(MvPoints points, uint64_t first, uint64_t count, double* xyz, uint16_t* rgb,
                              uint16_t* intensity, uint8_t* extra, float* normal);

/* ---- masks: GrabCut of a photograph or range map ---- */

typedef struct MvMaskArguments {
  size_t byteSize;       /* sizeof(MvMaskArguments), set by mvInitMaskArguments */
  bool hasRect;          /* start from rect: outside it sure background, inside probable foreground */
  uint32_t rect[4];      /* x, y, width, height in pixels, inside the image */
  const char* seeds;     /* a seed map image (0 / 64 / 128 / 192 / 255 per pixel, the image's size); NULL: none */
  const char* model;     /* a trained .mvm mask model; NULL: none */
  uint32_t iterations;   /* GrabCut iterations (default 5) */
  uint32_t erode;        /* erosion radius of the post-processing in pixels (default 2; 0: none) */
  MvProgressMonitorFunction progress; /* stages "read", "mask", "write"; NULL: none */
  void* progressUserPtr;
} MvMaskArguments;
MV_API void mvInitMaskArguments(MvMaskArguments* args);

/* Masks the image at input (PNG, JPEG, PPM or PGM) from at least one start (rect, seeds, model) and writes the
 * mask to output as a one-channel PNG (0 background, 255 foreground; a temporary name, then renamed). */
MV_API MvError mvMaskImageFile(MvDevice device, const char* input, const char* output, const MvMaskArguments* args);
/* The same as a job (mvGetJobScene does not apply: the result is the output). */
MV_API MvJob mvMaskImageFileAsync(MvDevice device, const char* input, const char* output,
                                  const MvMaskArguments* args);

/* An image in caller memory: height rows of width pixels, channels samples each (1: grey or a range map; 3:
 * R, G, B), bytesPerSample 1 (uint8) or 2 (uint16, host order), rows rowStride bytes apart (0: packed). */
typedef struct MvImageView {
  const void* pixels;
  uint32_t width, height, channels, bytesPerSample;
  size_t rowStride;
} MvImageView;

/* As mvMaskImageFile on pixels in memory: the mask (0 / 255, width * height bytes, rows packed) into mask.
 * seeds: NULL, or a seed map in memory (width * height bytes, 0 / 64 / 128 / 192 / 255), used instead of
 * args->seeds. */
MV_API MvError mvMaskImage(MvDevice device, const MvImageView* image, const uint8_t* seeds,
                           const MvMaskArguments* args, uint8_t* mask);

/* Trains a mask model (`megavox mask train`) on count images with their masks (width * height bytes each: 255
 * foreground, 0 background, anything else skipped) and writes it to output as a .mvm (a temporary name, then
 * renamed). Every image has the same channel count. */
MV_API MvError mvTrainMaskModel(MvDevice device, const MvImageView* images, const uint8_t* const* masks, size_t count,
                                const char* output);

#ifdef __cplusplus
}
#endif

#endif /* MEGAVOX_MEGAVOX_H */
