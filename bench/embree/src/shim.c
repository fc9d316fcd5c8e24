/* A thin layer over Embree 3 so that Rust needs no bindings to its structs: each call
 * takes a flat array of rays and writes flat answers, and loops over the array here, as an
 * application tracing a batch of rays through Embree would. Packet functions gather W
 * consecutive rays into Embree's SoA packet and scatter the answers back; that copying is
 * part of what an application pays for packets, so it is timed with them. */
#include <embree3/rtcore.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

/* The layout shared with Rust (`embree::Ray`). */
typedef struct {
    float org[3];
    float tnear;
    float dir[3];
    float tfar;
} PeRay;

RTCDevice pe_device_new(void) { return rtcNewDevice(NULL); }
void pe_device_release(RTCDevice device) { rtcReleaseDevice(device); }
int pe_device_error(RTCDevice device) { return (int)rtcGetDeviceError(device); }

/* Whether Embree's build on this machine has native W-wide packet kernels. */
int pe_native_packets(RTCDevice device, int width) {
    enum RTCDeviceProperty p = width == 16  ? RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED
                               : width == 8 ? RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED
                                            : RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED;
    return (int)rtcGetDeviceProperty(device, p);
}

/* One triangle mesh in a new scene, not yet committed (so the build can be timed alone).
 * `quality` is 1 for RTC_BUILD_QUALITY_MEDIUM, 2 for RTC_BUILD_QUALITY_HIGH. Default scene
 * flags: neither ROBUST nor COMPACT, Embree as most applications use it. */
RTCScene pe_scene_new(RTCDevice device, const float *positions, size_t vertex_count,
                      const unsigned *indices, size_t triangle_count, int quality) {
    RTCScene scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, quality == 2 ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    /* Embree's own buffers carry the padding its SIMD vertex loads need. */
    float *v = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), vertex_count);
    unsigned *i = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                          3 * sizeof(unsigned), triangle_count);
    if (!v || !i) {
        rtcReleaseGeometry(geom);
        return scene;
    }
    memcpy(v, positions, vertex_count * 3 * sizeof(float));
    memcpy(i, indices, triangle_count * 3 * sizeof(unsigned));
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene, geom);
    rtcReleaseGeometry(geom);
    return scene;
}

void pe_scene_commit(RTCScene scene) { rtcCommitScene(scene); }
void pe_scene_release(RTCScene scene) { rtcReleaseScene(scene); }

static void init_context(struct RTCIntersectContext *ctx, int coherent) {
    rtcInitIntersectContext(ctx);
    ctx->flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
}

/* Nearest hits: t (INFINITY for a miss) and the triangle's index. */
void pe_intersect1(RTCScene scene, int coherent, const PeRay *rays, size_t n, float *t,
                   unsigned *prim) {
    struct RTCIntersectContext ctx;
    init_context(&ctx, coherent);
    for (size_t i = 0; i < n; i++) {
        const PeRay *r = &rays[i];
        struct RTCRayHit rh;
        rh.ray.org_x = r->org[0];
        rh.ray.org_y = r->org[1];
        rh.ray.org_z = r->org[2];
        rh.ray.tnear = r->tnear;
        rh.ray.dir_x = r->dir[0];
        rh.ray.dir_y = r->dir[1];
        rh.ray.dir_z = r->dir[2];
        rh.ray.time = 0.0f;
        rh.ray.tfar = r->tfar;
        rh.ray.mask = ~0u;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        int hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        t[i] = hit ? rh.ray.tfar : INFINITY;
        prim[i] = hit ? rh.hit.primID : ~0u;
    }
}

/* Any hit: 1 where something lies between tnear and tfar. */
void pe_occluded1(RTCScene scene, int coherent, const PeRay *rays, size_t n,
                  unsigned char *occluded) {
    struct RTCIntersectContext ctx;
    init_context(&ctx, coherent);
    for (size_t i = 0; i < n; i++) {
        const PeRay *r = &rays[i];
        struct RTCRay ray;
        ray.org_x = r->org[0];
        ray.org_y = r->org[1];
        ray.org_z = r->org[2];
        ray.tnear = r->tnear;
        ray.dir_x = r->dir[0];
        ray.dir_y = r->dir[1];
        ray.dir_z = r->dir[2];
        ray.time = 0.0f;
        ray.tfar = r->tfar;
        ray.mask = ~0u;
        ray.id = 0;
        ray.flags = 0;
        rtcOccluded1(scene, &ctx, &ray);
        /* Embree marks an occluded ray by setting tfar to -infinity. */
        occluded[i] = ray.tfar < 0.0f;
    }
}

/* Fills lane k of a W-wide SoA ray from rays[i], or makes it an inactive lane. */
#define FILL_LANE(R, k, valid, rays, i, n)                                                    \
    do {                                                                                      \
        if ((i) < (n)) {                                                                      \
            const PeRay *r = &(rays)[i];                                                      \
            (valid)[k] = -1;                                                                  \
            (R).org_x[k] = r->org[0];                                                         \
            (R).org_y[k] = r->org[1];                                                         \
            (R).org_z[k] = r->org[2];                                                         \
            (R).tnear[k] = r->tnear;                                                          \
            (R).dir_x[k] = r->dir[0];                                                         \
            (R).dir_y[k] = r->dir[1];                                                         \
            (R).dir_z[k] = r->dir[2];                                                         \
            (R).tfar[k] = r->tfar;                                                            \
        } else {                                                                              \
            (valid)[k] = 0;                                                                   \
            (R).org_x[k] = (R).org_y[k] = (R).org_z[k] = 0.0f;                                \
            (R).dir_x[k] = (R).dir_y[k] = 0.0f;                                               \
            (R).dir_z[k] = 1.0f;                                                              \
            (R).tnear[k] = 0.0f;                                                              \
            (R).tfar[k] = -INFINITY;                                                          \
        }                                                                                     \
        (R).time[k] = 0.0f;                                                                   \
        (R).mask[k] = ~0u;                                                                    \
        (R).id[k] = 0;                                                                        \
        (R).flags[k] = 0;                                                                     \
    } while (0)

/* W-wide packets of consecutive rays (the last one partial). */
#define PACKETS(W)                                                                            \
    void pe_intersect##W(RTCScene scene, int coherent, const PeRay *rays, size_t n, float *t, \
                         unsigned *prim) {                                                    \
        struct RTCIntersectContext ctx;                                                       \
        init_context(&ctx, coherent);                                                         \
        for (size_t base = 0; base < n; base += W) {                                          \
            struct RTCRayHit##W rh;                                                           \
            int valid[W];                                                                     \
            for (int k = 0; k < W; k++) {                                                     \
                FILL_LANE(rh.ray, k, valid, rays, base + k, n);                               \
                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;                                   \
                rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;                                \
            }                                                                                 \
            rtcIntersect##W(valid, scene, &ctx, &rh);                                         \
            for (int k = 0; k < W && base + k < n; k++) {                                     \
                int hit = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;                        \
                t[base + k] = hit ? rh.ray.tfar[k] : INFINITY;                                \
                prim[base + k] = hit ? rh.hit.primID[k] : ~0u;                                \
            }                                                                                 \
        }                                                                                     \
    }                                                                                         \
    void pe_occluded##W(RTCScene scene, int coherent, const PeRay *rays, size_t n,            \
                        unsigned char *occluded) {                                            \
        struct RTCIntersectContext ctx;                                                       \
        init_context(&ctx, coherent);                                                         \
        for (size_t base = 0; base < n; base += W) {                                          \
            struct RTCRay##W ray;                                                             \
            int valid[W];                                                                     \
            for (int k = 0; k < W; k++)                                                       \
                FILL_LANE(ray, k, valid, rays, base + k, n);                                  \
            rtcOccluded##W(valid, scene, &ctx, &ray);                                         \
            for (int k = 0; k < W && base + k < n; k++)                                       \
                occluded[base + k] = ray.tfar[k] < 0.0f;                                      \
        }                                                                                     \
    }

PACKETS(8)
PACKETS(16)
