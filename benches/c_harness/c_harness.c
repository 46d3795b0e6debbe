/*
 * The C side of the wrapper-overhead measurement (issue #5): Embree 3 called
 * from plain C on the mesh and rays `sturmray bench --c-harness DIR` writes,
 * with the scene settings sturmray's wrapper uses (robust flag, medium build
 * quality, geometry mask all ones, geometry ID 0, FTZ/DAZ, a device of one
 * thread). It traces on one
 * thread, one ray per rtcIntersect1 call ("single") and in streams of 256
 * through rtcIntersect1M ("batch", coherent for camera rays), as the wrapper
 * does, times it as sturmray's side does, and prints one line per measurement in the same format as the Rust
 * side, with a checksum of the hits. See docs/benchmarks.md.
 *
 *   cc -O2 -std=c11 benches/c_harness/c_harness.c -lembree3 -o c_harness
 *   ./c_harness DIR NAME [REPS]
 *
 * reads DIR/NAME.vertices.npy (V, 3) float32, DIR/NAME.triangles.npy (T, 3)
 * uint32 and DIR/NAME.camera.npy, DIR/NAME.incoherent.npy (N, 8) float32.
 */
#define _POSIX_C_SOURCE 199309L
#include <embree3/rtcore.h>
#include <math.h>
#include <pmmintrin.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <xmmintrin.h>

/* The wrapper's stream length (CHUNK in src/accel/embree/scene.rs). */
#define STREAM 256

static void die(const char *what, const char *detail) {
  fprintf(stderr, "c_harness: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
  exit(1);
}

/* A C-order .npy array of `cols` 4-byte columns; `data` points into `file`. */
typedef struct {
  char *file;
  const void *data;
  size_t rows;
} Array;

/* Reads a .npy file of dtype `descr` ("<f4" or "<u4") and shape (rows, cols). */
static Array load_npy(const char *path, const char *descr, size_t cols) {
  FILE *f = fopen(path, "rb");
  if (!f) die("cannot open", path);
  fseek(f, 0, SEEK_END);
  long size = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *file = malloc((size_t)size + 1);
  if (!file || fread(file, 1, (size_t)size, f) != (size_t)size) die("cannot read", path);
  fclose(f);
  file[size] = '\0';
  if (size < 12 || memcmp(file, "\x93NUMPY", 6) != 0) die("not a .npy file", path);
  size_t header_len, start;
  if (file[6] == 1) {
    header_len = (unsigned char)file[8] | (size_t)(unsigned char)file[9] << 8;
    start = 10;
  } else {
    header_len = 0;
    for (int i = 3; i >= 0; i--) header_len = header_len << 8 | (unsigned char)file[8 + i];
    start = 12;
  }
  if (start + header_len > (size_t)size) die("truncated header", path);
  char want[32];
  snprintf(want, sizeof want, "'descr': '%s'", descr);
  const char *header = file + start;
  const char *shape = strstr(header, "'shape': (");
  size_t rows, got_cols;
  if (!strstr(header, want) || !strstr(header, "'fortran_order': False") || !shape ||
      sscanf(shape, "'shape': (%zu, %zu)", &rows, &got_cols) != 2 || got_cols != cols)
    die("unexpected dtype, order or shape", path);
  if ((size_t)size - start - header_len != rows * cols * 4) die("data size does not match the shape", path);
  return (Array){file, file + start + header_len, rows};
}

static void error_function(void *user, enum RTCError code, const char *message) {
  (void)user;
  fprintf(stderr, "c_harness: Embree error %d: %s\n", (int)code, message);
  exit(1);
}

/* What the wrapper's Hit holds; a miss is t = inf with both IDs invalid. */
typedef struct {
  float t;
  unsigned int geom_id, prim_id;
  float u, v, ng[3];
} Hit;

static RTCScene build_scene(RTCDevice device, const char *dir, const char *name) {
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.vertices.npy", dir, name);
  Array vertices = load_npy(path, "<f4", 3);
  snprintf(path, sizeof path, "%s/%s.triangles.npy", dir, name);
  Array triangles = load_npy(path, "<u4", 3);

  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                     3 * sizeof(float), vertices.rows);
  unsigned int *t = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                            3 * sizeof(unsigned int), triangles.rows);
  memcpy(v, vertices.data, vertices.rows * 3 * sizeof(float));
  memcpy(t, triangles.data, triangles.rows * 3 * sizeof(unsigned int));
  rtcSetGeometryMask(g, 0xFFFFFFFFu);
  rtcCommitGeometry(g);
  rtcAttachGeometryByID(scene, g, 0);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  free(vertices.file);
  free(triangles.file);
  return scene;
}

/* A ray+hit record for row `r` of an (N, 8) ray array, as rtcore tutorials set it up. */
static inline void setup(struct RTCRayHit *rh, const float *r) {
  rh->ray.org_x = r[0];
  rh->ray.org_y = r[1];
  rh->ray.org_z = r[2];
  rh->ray.dir_x = r[3];
  rh->ray.dir_y = r[4];
  rh->ray.dir_z = r[5];
  rh->ray.tnear = r[6];
  rh->ray.tfar = r[7];
  rh->ray.time = 0.0f;
  rh->ray.mask = 0xFFFFFFFFu;
  rh->ray.id = 0;
  rh->ray.flags = 0;
  rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh->hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

static inline Hit result(const struct RTCRayHit *rh) {
  if (rh->hit.geomID == RTC_INVALID_GEOMETRY_ID)
    return (Hit){INFINITY, RTC_INVALID_GEOMETRY_ID, RTC_INVALID_GEOMETRY_ID, 0, 0, {0, 0, 0}};
  return (Hit){rh->ray.tfar, rh->hit.geomID, rh->hit.primID, rh->hit.u, rh->hit.v,
               {rh->hit.Ng_x, rh->hit.Ng_y, rh->hit.Ng_z}};
}

/* sturmray bench's CHUNK: rays per Accel::intersect_batch call, and the unit of timing. */
#define CHUNK 4096

static void trace_single(RTCScene scene, struct RTCIntersectContext *context, const float *rays,
                         size_t n, Hit *hits) {
  for (size_t i = 0; i < n; i++) {
    struct RTCRayHit rh;
    setup(&rh, rays + 8 * i);
    rtcIntersect1(scene, context, &rh);
    hits[i] = result(&rh);
  }
}

static void trace_batch(RTCScene scene, struct RTCIntersectContext *context, const float *rays,
                        size_t n, Hit *hits) {
  struct RTCRayHit records[STREAM];
  for (size_t start = 0; start < n; start += STREAM) {
    unsigned int m = n - start < STREAM ? (unsigned int)(n - start) : STREAM;
    for (unsigned int j = 0; j < m; j++) setup(&records[j], rays + 8 * (start + j));
    rtcIntersect1M(scene, context, records, m, sizeof(struct RTCRayHit));
    for (unsigned int j = 0; j < m; j++) hits[start + j] = result(&records[j]);
  }
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* The sum over chunks of CHUNK rays of each chunk's best time of `reps` passes,
   as sturmray's side times it (a short chunk often runs undisturbed on a busy
   machine in some pass, a whole pass rarely). */
static double best_per_chunk(RTCScene scene, const float *rays, size_t n, Hit *hits, int batch,
                             int coherent, int reps) {
  struct RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  if (batch && coherent) context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  size_t chunks = (n + CHUNK - 1) / CHUNK;
  double *best = malloc(chunks * sizeof(double));
  if (!best) die("out of memory", NULL);
  for (size_t c = 0; c < chunks; c++) best[c] = INFINITY;
  for (int rep = 0; rep < reps; rep++) {
    for (size_t c = 0; c < chunks; c++) {
      size_t start = c * CHUNK, m = n - start < CHUNK ? n - start : CHUNK;
      double t0 = now();
      if (batch)
        trace_batch(scene, &context, rays + 8 * start, m, hits + start);
      else
        trace_single(scene, &context, rays + 8 * start, m, hits + start);
      double seconds = now() - t0;
      if (seconds < best[c]) best[c] = seconds;
    }
  }
  double total = 0.0;
  for (size_t c = 0; c < chunks; c++) total += best[c];
  free(best);
  return total;
}

int main(int argc, char **argv) {
  if (argc < 3 || argc > 4) {
    fprintf(stderr, "usage: %s DIR NAME [REPS]\n", argv[0]);
    return 2;
  }
  const char *dir = argv[1], *name = argv[2];
  int reps = argc == 4 ? atoi(argv[3]) : 10; /* REPS in sturmray's c_harness.rs */
  if (reps < 1) die("REPS must be at least 1", NULL);

  /* Embree asks for FTZ/DAZ on every thread that traces; sturmray sets both. */
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  /* One thread, as sturmray builds for this measurement: no TBB workers are left
     spinning beside the traced thread. */
  RTCDevice device = rtcNewDevice("threads=1");
  if (!device) die("cannot create an Embree device", NULL);
  rtcSetDeviceErrorFunction(device, error_function, NULL);
  RTCScene scene = build_scene(device, dir, name);

  const char *kinds[] = {"camera", "incoherent"};
  for (int k = 0; k < 2; k++) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.%s.npy", dir, name, kinds[k]);
    Array rays = load_npy(path, "<f4", 8);
    Hit *hits = malloc(rays.rows * sizeof(Hit));
    if (!hits) die("out of memory", NULL);
    for (int batch = 0; batch < 2; batch++) {
      double seconds = best_per_chunk(scene, rays.data, rays.rows, hits, batch, k == 0, reps);
      /* The checksum: hits in ray order, the sum of their t and of their primIDs. */
      size_t count = 0;
      double tsum = 0.0;
      unsigned long long primsum = 0;
      for (size_t i = 0; i < rays.rows; i++) {
        if (hits[i].geom_id == RTC_INVALID_GEOMETRY_ID) continue;
        count++;
        tsum += hits[i].t;
        primsum += hits[i].prim_id;
      }
      printf("c %s %s %s rays=%zu mrays=%.4f hits=%zu tsum=%.17g primsum=%llu\n", name, kinds[k],
             batch ? "batch" : "single", rays.rows, rays.rows / seconds / 1e6, count, tsum, primsum);
      fflush(stdout);
    }
    free(hits);
    free(rays.file);
  }
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return 0;
}
