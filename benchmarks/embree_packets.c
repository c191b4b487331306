/* Embree 4's ray queries one ray at a time and in packets of 16 (rtcIntersect16,
 * rtcOccluded16: what Mitsuba 3 calls on AVX-512 hosts), on a mesh and ray set in the Embree
 * anchor's format: the measurement behind benchmarks/cornell_rays.py's packet columns.
 *
 * It links the Embree library that the anchor's embreex wheel ships, which comes without
 * headers, so the few API calls and the ray layouts it needs are declared here from Embree 4's
 * public headers (rtcore_ray.h: RTCRayHit, RTCRayHit16; robust scene flag, triangle geometry).
 * Build (the wheel's library folder; adjust the Python version):
 *
 *   L=~/venvs/embree/lib/python3.11/site-packages/embreex.libs
 *   cc -O2 benchmarks/embree_packets.c -o /tmp/embree_packets -L$L -l:$(ls $L | grep embree4) -Wl,-rpath,$L -lm
 *
 * Run: embree_packets MESH.ply RAYS.rays closest|occluded [REPEATS] [mitsuba]
 * MESH is a binary little-endian PLY of float x, y, z vertices and uchar-count int faces (the
 * anchor's write_ply). Prints one line: rays, hits and Mrays/s for each mode (best of REPEATS).
 * Packets are consecutive rays of the file, sixteen at a time (a last partial packet is not
 * traced). The scene is robust, as the Embree anchor builds it; with `mitsuba`, it is built as
 * Mitsuba 3 builds its scenes instead (no scene flags, high build quality:
 * src/render/scene_embree.inl).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef void *RTCDevice, *RTCScene, *RTCGeometry;
RTCDevice rtcNewDevice(const char *config);
RTCScene rtcNewScene(RTCDevice device);
void rtcSetSceneFlags(RTCScene scene, int flags);
void rtcSetSceneBuildQuality(RTCScene scene, int quality);
RTCGeometry rtcNewGeometry(RTCDevice device, int type);
void *rtcSetNewGeometryBuffer(RTCGeometry geometry, int type, unsigned slot, int format, size_t stride, size_t count);
void rtcCommitGeometry(RTCGeometry geometry);
unsigned rtcAttachGeometry(RTCScene scene, RTCGeometry geometry);
void rtcReleaseGeometry(RTCGeometry geometry);
void rtcCommitScene(RTCScene scene);
void rtcIntersect1(RTCScene scene, void *rayhit, void *arguments);
void rtcOccluded1(RTCScene scene, void *ray, void *arguments);
void rtcIntersect16(const int *valid, RTCScene scene, void *rayhit, void *arguments);
void rtcOccluded16(const int *valid, RTCScene scene, void *ray, void *arguments);

enum { SCENE_FLAG_NONE = 0, SCENE_FLAG_ROBUST = 1 << 2, BUILD_QUALITY_HIGH = 2 };
enum { GEOMETRY_TRIANGLE = 0, BUFFER_INDEX = 0, BUFFER_VERTEX = 1 };
enum { FORMAT_UINT3 = 0x5003, FORMAT_FLOAT3 = 0x9003 };
#define INVALID 0xFFFFFFFFu
/* Field offsets in floats, per lane, of an RTCRayHitN with N lanes: the ray's 12 fields, then
 * the hit's normal (3), u, v, primID (slot 17). Room is left for the hit's instance fields. */
enum { ORG = 0, TNEAR = 3, DIR = 4, TIME = 7, TFAR = 8, MASK = 9, ID = 10, FLAGS = 11, PRIM = 17, SLOTS = 24 };

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + t.tv_nsec * 1e-9;
}

static void *read_file(const char *path, size_t *size) {
    FILE *f = fopen(path, "rb");
    if (!f) { fprintf(stderr, "cannot open %s\n", path); exit(1); }
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    void *data = malloc(*size);
    if (fread(data, 1, *size, f) != *size) { fprintf(stderr, "cannot read %s\n", path); exit(1); }
    fclose(f);
    return data;
}

/* Lane k of a packet of `lanes` rays (lanes = 1: a single RTCRayHit) set to ray r of the file. */
static void set_ray(float *packet, int lanes, int k, const float *r) {
    for (int s = 0; s < SLOTS; s++) packet[s * lanes + k] = 0.0f;
    for (int a = 0; a < 3; a++) { packet[(ORG + a) * lanes + k] = r[a]; packet[(DIR + a) * lanes + k] = r[3 + a]; }
    packet[TNEAR * lanes + k] = r[6];
    packet[TFAR * lanes + k] = r[7];
    ((unsigned *)packet)[MASK * lanes + k] = INVALID;
    ((unsigned *)packet)[PRIM * lanes + k] = INVALID;
}

/* Whether lane k hit: a closest hit names a primitive; an occluded ray's tfar becomes -inf. */
static int was_hit(const float *packet, int lanes, int k, int occluded) {
    if (occluded) return isinf(packet[TFAR * lanes + k]) && packet[TFAR * lanes + k] < 0;
    return ((const unsigned *)packet)[PRIM * lanes + k] != INVALID;
}

int main(int argc, char **argv) {
    if (argc < 4) {
        fprintf(stderr, "usage: %s MESH.ply RAYS.rays closest|occluded [REPEATS] [mitsuba]\n", argv[0]);
        return 2;
    }
    int occluded = strcmp(argv[3], "occluded") == 0, repeats = argc > 4 ? atoi(argv[4]) : 5;
    int as_mitsuba = argc > 5 && strcmp(argv[5], "mitsuba") == 0;
    size_t size, vertices = 0, faces = 0;
    char *ply = read_file(argv[1], &size), *body = strstr(ply, "end_header\n");
    char *v = strstr(ply, "element vertex "), *f = strstr(ply, "element face ");
    if (!body || !v || !f) { fprintf(stderr, "%s: not the anchor's binary PLY\n", argv[1]); return 1; }
    vertices = strtoul(v + 15, NULL, 10);
    faces = strtoul(f + 13, NULL, 10);
    body += strlen("end_header\n");

    RTCDevice device = rtcNewDevice(NULL);
    RTCScene scene = rtcNewScene(device);
    if (as_mitsuba) {
        rtcSetSceneFlags(scene, SCENE_FLAG_NONE);
        rtcSetSceneBuildQuality(scene, BUILD_QUALITY_HIGH);
    } else {
        rtcSetSceneFlags(scene, SCENE_FLAG_ROBUST);
    }
    RTCGeometry mesh = rtcNewGeometry(device, GEOMETRY_TRIANGLE);
    memcpy(rtcSetNewGeometryBuffer(mesh, BUFFER_VERTEX, 0, FORMAT_FLOAT3, 12, vertices), body, vertices * 12);
    unsigned *index = rtcSetNewGeometryBuffer(mesh, BUFFER_INDEX, 0, FORMAT_UINT3, 12, faces);
    for (size_t i = 0; i < faces; i++) memcpy(index + 3 * i, body + vertices * 12 + i * 13 + 1, 12);
    rtcCommitGeometry(mesh);
    rtcAttachGeometry(scene, mesh);
    rtcReleaseGeometry(mesh);
    rtcCommitScene(scene);

    const float *rays = read_file(argv[2], &size);
    size_t count = size / 32, packed = count / 16 * 16;
    float *one = aligned_alloc(64, SLOTS * 4), *sixteen = aligned_alloc(64, SLOTS * 16 * 4);
    int valid[16];
    for (int k = 0; k < 16; k++) valid[k] = -1;
    double best_one = INFINITY, best_sixteen = INFINITY;
    long hits_one = 0, hits_sixteen = 0;
    for (int r = 0; r < repeats; r++) {
        long hits = 0;
        double start = now();
        for (size_t i = 0; i < count; i++) {
            set_ray(one, 1, 0, rays + 8 * i);
            if (occluded) rtcOccluded1(scene, one, NULL); else rtcIntersect1(scene, one, NULL);
            hits += was_hit(one, 1, 0, occluded);
        }
        double seconds = now() - start;
        if (seconds < best_one) best_one = seconds;
        hits_one = hits;
        hits = 0;
        start = now();
        for (size_t i = 0; i < packed; i += 16) {
            for (int k = 0; k < 16; k++) set_ray(sixteen, 16, k, rays + 8 * (i + k));
            if (occluded) rtcOccluded16(valid, scene, sixteen, NULL); else rtcIntersect16(valid, scene, sixteen, NULL);
            for (int k = 0; k < 16; k++) hits += was_hit(sixteen, 16, k, occluded);
        }
        seconds = now() - start;
        if (seconds < best_sixteen) best_sixteen = seconds;
        hits_sixteen = hits;
    }
    printf("rays=%zu query=%s single_hits=%ld single_mrays=%.4f packet16_hits=%ld packet16_mrays=%.4f\n", count,
           occluded ? "occluded" : "closest", hits_one, count / best_one / 1e6, hits_sixteen, packed / best_sixteen / 1e6);
    return 0;
}
