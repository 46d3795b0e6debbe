/*
 * What Embree's own settings are worth on one mesh, on one thread: each
 * query as sturmray makes it (RTC_SCENE_FLAG_ROBUST, one ray a call) against
 * the settings Mitsuba 3 runs with (no robust flag, high build quality) and
 * against packets of 8 (rtcIntersect8/rtcOccluded8, what Mitsuba's llvm
 * variants call with AVX2) and streams of 256 (rtcIntersect1M). See
 * docs/peers.md ("What Embree's settings are worth").
 *
 *   cc -O2 -std=c11 tools/peers/embree_modes.c -lembree3 -lm -o embree_modes
 *   ./embree_modes MESH.obj [RAYS] [ROUNDS]
 *
 * Rays, all from a fixed generator (the same on every run):
 *   camera: a pinhole at the bounds' front, looking along +z at their centre,
 *     in 8x1 runs of neighbouring pixels (one packet each);
 *   bounce: origins uniform in the bounds, directions uniform on the sphere
 *     (the diffuse rays of a path inside a closed room such as the Cornell box);
 *   shadow: from the same origins towards other uniform points in the bounds,
 *     stopping just short of them (occlusion queries).
 * Every mode is timed at its best of ROUNDS passes, the modes alternating
 * within each round. Exits 1 if a mode finds a different primitive from the
 * robust single-ray query on more than 0.1% of the rays (robust and
 * non-robust tests may part at shared edges; nothing else should differ).
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

#define PACKET 8
#define STREAM 256

static void die(const char *what, const char *detail) {
  fprintf(stderr, "embree_modes: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
  exit(1);
}

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* xorshift64*: a fixed sequence, so every run traces the same rays. */
static uint64_t state = 0x9e3779b97f4a7c15ull;
static float uniform(void) {
  state ^= state >> 12;
  state ^= state << 25;
  state ^= state >> 27;
  return (float)((state * 0x2545f4914f6cdd1dull) >> 40) * (1.0f / 16777216.0f);
}

typedef struct {
  float *v;
  unsigned *f;
  size_t nv, nf;
  float lo[3], hi[3];
} Mesh;

/* The `v` and `f` lines of an OBJ; polygons as fans, negative indices
 * relative, texture and normal indices ignored. */
static Mesh read_obj(const char *path) {
  FILE *file = fopen(path, "r");
  if (!file) die("cannot open", path);
  Mesh m = {0};
  size_t cv = 64, cf = 64;
  m.v = malloc(cv * 3 * sizeof(float));
  m.f = malloc(cf * 3 * sizeof(unsigned));
  for (int a = 0; a < 3; a++) m.lo[a] = INFINITY, m.hi[a] = -INFINITY;
  char line[4096];
  while (fgets(line, sizeof line, file)) {
    if (line[0] == 'v' && line[1] == ' ') {
      if (m.nv == cv) m.v = realloc(m.v, (cv *= 2) * 3 * sizeof(float));
      float *p = m.v + 3 * m.nv;
      if (sscanf(line + 2, "%f %f %f", p, p + 1, p + 2) != 3) die("bad vertex", line);
      for (int a = 0; a < 3; a++) {
        if (p[a] < m.lo[a]) m.lo[a] = p[a];
        if (p[a] > m.hi[a]) m.hi[a] = p[a];
      }
      m.nv++;
    } else if (line[0] == 'f' && line[1] == ' ') {
      long idx[64];
      int n = 0;
      for (char *tok = strtok(line + 2, " \t\r\n"); tok && n < 64; tok = strtok(NULL, " \t\r\n")) {
        long i = strtol(tok, NULL, 10);
        idx[n++] = i < 0 ? (long)m.nv + i : i - 1;
      }
      for (int k = 1; k + 1 < n; k++) {
        if (m.nf == cf) m.f = realloc(m.f, (cf *= 2) * 3 * sizeof(unsigned));
        long tri[3] = {idx[0], idx[k], idx[k + 1]};
        for (int c = 0; c < 3; c++) {
          if (tri[c] < 0 || tri[c] >= (long)m.nv) die("face index out of range", path);
          m.f[3 * m.nf + c] = (unsigned)tri[c];
        }
        m.nf++;
      }
    }
  }
  fclose(file);
  if (m.nf == 0) die("no faces in", path);
  return m;
}

static RTCScene build(RTCDevice device, const Mesh *m, int robust) {
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneFlags(scene, robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
  rtcSetSceneBuildQuality(scene, robust ? RTC_BUILD_QUALITY_MEDIUM : RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                     3 * sizeof(float), m->nv);
  unsigned *f = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                        3 * sizeof(unsigned), m->nf);
  memcpy(v, m->v, m->nv * 3 * sizeof(float));
  memcpy(f, m->f, m->nf * 3 * sizeof(unsigned));
  rtcCommitGeometry(g);
  rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) die("Embree could not build the scene", NULL);
  return scene;
}

/* A ray: origin, direction, tfar. */
typedef struct {
  float o[3], d[3], tfar;
} Ray;

static Ray *make_rays(const Mesh *m, const char *kind, size_t n) {
  Ray *rays = malloc(n * sizeof(Ray));
  float size[3], centre[3];
  for (int a = 0; a < 3; a++) size[a] = m->hi[a] - m->lo[a], centre[a] = 0.5f * (m->lo[a] + m->hi[a]);
  size_t side = (size_t)ceil(sqrt((double)n));
  for (size_t i = 0; i < n; i++) {
    Ray *r = rays + i;
    if (kind[0] == 'c') {
      /* Pixel (i % side, i / side) of a 40-degree view from in front. */
      float px = ((float)(i % side) + 0.5f) / (float)side - 0.5f;
      float py = ((float)(i / side) + 0.5f) / (float)side - 0.5f;
      float back = 1.5f * size[1] / 0.728f;
      r->o[0] = centre[0], r->o[1] = centre[1], r->o[2] = m->lo[2] - back;
      r->d[0] = 0.728f * px, r->d[1] = 0.728f * py, r->d[2] = 1.0f;
      r->tfar = INFINITY;
      continue;
    }
    for (int a = 0; a < 3; a++) r->o[a] = m->lo[a] + size[a] * (0.01f + 0.98f * uniform());
    if (kind[0] == 'b') {
      float z = 2.0f * uniform() - 1.0f, phi = 6.2831853f * uniform(), s = sqrtf(fmaxf(0.0f, 1.0f - z * z));
      r->d[0] = s * cosf(phi), r->d[1] = s * sinf(phi), r->d[2] = z;
      r->tfar = INFINITY;
    } else {
      float to[3], len = 0.0f;
      for (int a = 0; a < 3; a++) {
        to[a] = m->lo[a] + size[a] * (0.01f + 0.98f * uniform()) - r->o[a];
        len += to[a] * to[a];
      }
      len = sqrtf(len);
      for (int a = 0; a < 3; a++) r->d[a] = to[a] / len;
      r->tfar = len * (1.0f - 1e-4f);
    }
  }
  return rays;
}

/* The primitive each ray hits (RTC_INVALID_GEOMETRY_ID for none; for
 * occlusion 1 when blocked, 0 when not). */
static void single(RTCScene scene, const Ray *rays, size_t n, int occlusion, unsigned *out) {
  struct RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t i = 0; i < n; i++) {
    const Ray *r = rays + i;
    struct RTCRayHit rh = {0};
    rh.ray.org_x = r->o[0], rh.ray.org_y = r->o[1], rh.ray.org_z = r->o[2];
    rh.ray.dir_x = r->d[0], rh.ray.dir_y = r->d[1], rh.ray.dir_z = r->d[2];
    rh.ray.tfar = r->tfar;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    if (occlusion) {
      rtcOccluded1(scene, &context, &rh.ray);
      out[i] = rh.ray.tfar < 0.0f;
    } else {
      rtcIntersect1(scene, &context, &rh);
      out[i] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID : rh.hit.primID;
    }
  }
}

static void packets(RTCScene scene, const Ray *rays, size_t n, int occlusion, unsigned *out) {
  struct RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t i = 0; i < n; i += PACKET) {
    RTC_ALIGN(32) struct RTCRayHit8 rh;
    RTC_ALIGN(32) int valid[PACKET];
    memset(&rh, 0, sizeof rh);
    for (size_t k = 0; k < PACKET; k++) {
      const Ray *r = rays + (i + k < n ? i + k : n - 1);
      valid[k] = i + k < n ? -1 : 0;
      rh.ray.org_x[k] = r->o[0], rh.ray.org_y[k] = r->o[1], rh.ray.org_z[k] = r->o[2];
      rh.ray.dir_x[k] = r->d[0], rh.ray.dir_y[k] = r->d[1], rh.ray.dir_z[k] = r->d[2];
      rh.ray.tfar[k] = r->tfar;
      rh.ray.mask[k] = 0xffffffffu;
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    }
    if (occlusion)
      rtcOccluded8(valid, scene, &context, &rh.ray);
    else
      rtcIntersect8(valid, scene, &context, &rh);
    for (size_t k = 0; k < PACKET && i + k < n; k++)
      out[i + k] = occlusion ? rh.ray.tfar[k] < 0.0f
                   : rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID
                                                                 : rh.hit.primID[k];
  }
}

static void streams(RTCScene scene, const Ray *rays, size_t n, int occlusion, unsigned *out,
                    int coherent) {
  static struct RTCRayHit records[STREAM];
  struct RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  for (size_t i = 0; i < n; i += STREAM) {
    size_t m = n - i < STREAM ? n - i : STREAM;
    memset(records, 0, m * sizeof records[0]);
    for (size_t k = 0; k < m; k++) {
      const Ray *r = rays + i + k;
      struct RTCRayHit *rh = records + k;
      rh->ray.org_x = r->o[0], rh->ray.org_y = r->o[1], rh->ray.org_z = r->o[2];
      rh->ray.dir_x = r->d[0], rh->ray.dir_y = r->d[1], rh->ray.dir_z = r->d[2];
      rh->ray.tfar = r->tfar;
      rh->ray.mask = 0xffffffffu;
      rh->hit.geomID = RTC_INVALID_GEOMETRY_ID;
    }
    if (occlusion)
      rtcOccluded1M(scene, &context, (struct RTCRay *)records, (unsigned)m, sizeof records[0]);
    else
      rtcIntersect1M(scene, &context, records, (unsigned)m, sizeof records[0]);
    for (size_t k = 0; k < m; k++)
      out[i + k] = occlusion ? records[k].ray.tfar < 0.0f
                   : records[k].hit.geomID == RTC_INVALID_GEOMETRY_ID ? RTC_INVALID_GEOMETRY_ID
                                                                      : records[k].hit.primID;
  }
}

enum { SINGLE, PACKETS, STREAMS, APIS };
static const char *api_names[APIS] = {"one ray a call", "packets of 8", "streams of 256"};

int main(int argc, char **argv) {
  if (argc < 2) die("usage: embree_modes MESH.obj [RAYS] [ROUNDS]", NULL);
  size_t n = argc > 2 ? (size_t)strtoull(argv[2], NULL, 10) : 1u << 20;
  int rounds = argc > 3 ? atoi(argv[3]) : 5;
  if (n == 0 || rounds < 1) die("RAYS and ROUNDS must be positive", NULL);
  /* As sturmray's render threads run. */
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  Mesh mesh = read_obj(argv[1]);
  RTCDevice device = rtcNewDevice("threads=1");
  if (!device) die("rtcNewDevice failed", NULL);
  RTCScene scenes[2] = {build(device, &mesh, 1), build(device, &mesh, 0)};
  const char *kinds[3] = {"camera", "bounce", "shadow"};
  unsigned *reference = malloc(n * sizeof(unsigned)), *found = malloc(n * sizeof(unsigned));
  printf("%s: %zu triangles, %zu rays a kind, best of %d rounds, 1 thread\n", argv[1], mesh.nf, n,
         rounds);
  printf("| rays | API | ns a ray, robust (sturmray) | ns a ray, not robust (Mitsuba) | against sturmray's |\n");
  printf("|---|---|---:|---:|---:|\n");
  int failed = 0;
  for (int k = 0; k < 3; k++) {
    Ray *rays = make_rays(&mesh, kinds[k], n);
    int occlusion = kinds[k][0] == 's';
    double best[2][APIS];
    for (int s = 0; s < 2; s++)
      for (int a = 0; a < APIS; a++) best[s][a] = INFINITY;
    single(scenes[0], rays, n, occlusion, reference);
    for (int round = 0; round < rounds; round++) {
      for (int s = 0; s < 2; s++) {
        for (int a = 0; a < APIS; a++) {
          double t0 = now();
          if (a == SINGLE) single(scenes[s], rays, n, occlusion, found);
          if (a == PACKETS) packets(scenes[s], rays, n, occlusion, found);
          if (a == STREAMS) streams(scenes[s], rays, n, occlusion, found, k == 0);
          double t = now() - t0;
          if (t < best[s][a]) best[s][a] = t;
          if (round == 0) {
            size_t differ = 0;
            for (size_t i = 0; i < n; i++) differ += found[i] != reference[i];
            if (differ * 1000 > n) {
              fprintf(stderr, "embree_modes: %s rays, %s, %s: %zu of %zu rays differ\n", kinds[k],
                      api_names[a], s ? "not robust" : "robust", differ, n);
              failed = 1;
            }
          }
        }
      }
    }
    for (int a = 0; a < APIS; a++)
      printf("| %s | %s | %.1f | %.1f | %.2f× / %.2f× |\n", kinds[k], api_names[a],
             1e9 * best[0][a] / (double)n, 1e9 * best[1][a] / (double)n,
             best[0][a] / best[0][SINGLE], best[1][a] / best[0][SINGLE]);
    free(rays);
  }
  rtcReleaseScene(scenes[0]);
  rtcReleaseScene(scenes[1]);
  rtcReleaseDevice(device);
  return failed;
}
