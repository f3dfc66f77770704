// Geometry volume injection: every valid surfel of a position/normal image adds its blocking
// potential (A / s^2) * cosineLobe(-n) (the fraction of light travelling in direction w that
// it stops, Kaplanyan's fuzzy occlusion) to the GV cell nearest to it (GV cells are centred on
// LPV cell corners). A is the surfel's world area, estimated from the positions of its next
// (or previous) sampled neighbours in x and y and capped at one cell face (at depth discontinuities). Sums use integer
// atomics in slot `pc.rsm.z` of the GV buffer, so the RSM and the camera's surfels fill separate
// volumes that the resolve combines by max (a surface seen by both must not count twice).
// Included by gv_inject_rsm.comp (2D-array RSM) and gv_inject_camera.comp (2D G-buffer).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv_passes.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { LpvInjectPush pc; };
#if SURFEL_ARRAY
layout(set = 1, binding = LPV_GEOMETRY_VOLUME_BINDING_POSITION, rgba32f) uniform readonly image2DArray surfelPosition;
layout(set = 1, binding = LPV_GEOMETRY_VOLUME_BINDING_NORMAL, rgba16f) uniform readonly image2DArray surfelNormal;
#define SURFEL_TEXEL(t) (t)
// The full RSM behind a reduced one: blocks marked LPV_REDUCE_SPLIT add their texels one by one.
layout(set = 1, binding = LPV_GEOMETRY_VOLUME_BINDING_SOURCE_POSITION, rgba32f) uniform readonly image2DArray sourcePosition;
layout(set = 1, binding = LPV_GEOMETRY_VOLUME_BINDING_SOURCE_NORMAL, rgba16f) uniform readonly image2DArray sourceNormal;
#else
layout(set = 1, binding = LPV_GEOMETRY_VOLUME_BINDING_POSITION, rgba32f) uniform readonly image2D surfelPosition;
layout(set = 1, binding = LPV_GEOMETRY_VOLUME_BINDING_NORMAL, rgba16f) uniform readonly image2D surfelNormal;
#define SURFEL_TEXEL(t) (t).xy
#endif
layout(set = 1, binding = LPV_GEOMETRY_VOLUME_BINDING_SUMS, std430) buffer GeometryVolumeSums { int data[]; } sums;

bool finite3(vec3 v) {
    return abs(v.x) + abs(v.y) + abs(v.z) < 1e30;
}

// Edge vector to the next texel along `step` (or the previous one at the image border), or
// zero when both are missing or across a discontinuity (more than a cell away).
vec3 edge(ivec3 t, ivec3 step, vec3 p, float cell) {
    for (int side = 0; side < 2; ++side) {
        ivec3 u = side == 0 ? t + step : t - step;
        if (u.x < 0 || u.y < 0 || u.x >= pc.rsm.x || u.y >= pc.rsm.w)
            continue;
        vec4 q = imageLoad(surfelPosition, SURFEL_TEXEL(u));
        vec3 e = q.xyz - p;
        if (q.w > 0.0 && finite3(q.xyz) && dot(e, e) < cell * cell)
            return e;
    }
    return vec3(0.0);
}

#if SURFEL_ARRAY
// edge() in the full RSM (texels per row and rows: pc.params.w).
vec3 sourceEdge(ivec3 t, ivec3 step, vec3 p, float cell) {
    int size = int(pc.params.w);
    for (int side = 0; side < 2; ++side) {
        ivec3 u = side == 0 ? t + step : t - step;
        if (u.x < 0 || u.y < 0 || u.x >= size || u.y >= size)
            continue;
        vec4 q = imageLoad(sourcePosition, u);
        vec3 e = q.xyz - p;
        if (q.w > 0.0 && finite3(q.xyz) && dot(e, e) < cell * cell)
            return e;
    }
    return vec3(0.0);
}
#endif

// Adds the blocking potential of a surfel with unit normal n and edge vectors a, b.
void addBlocker(vec3 position, vec3 n, vec3 a, vec3 b) {
    float cell = pc.grid.origin.w;
    float coverage = min(length(cross(a, b)) / (cell * cell), 1.0);
    if (!(coverage > 0.0))
        return;
    ivec3 g = ivec3(round((position - pc.grid.origin.xyz) / cell));
    ivec3 size = pc.grid.size.xyz + 1;
    if (any(lessThan(g, ivec3(0))) || any(greaterThanEqual(g, size)))
        return;
    ivec4 q = ivec4(round(coverage * shCosineLobe(-n) * pc.params.x));
    int base = LPV_INJECT_HEADER_INTS + 4 * (g.x + size.x * (g.y + size.y * (g.z + size.z * pc.rsm.z)));
    for (int k = 0; k < 4; ++k)
        if (q[k] != 0)
            atomicAdd(sums.data[base + k], q[k]);
}

void main() {
    // Every `stride`-th texel per axis (pc.params.y; the camera G-buffer at high resolution): the
    // area estimate below then spans stride texels, so the summed coverage stays the same.
    int stride = max(int(pc.params.y), 1);
    ivec3 t = ivec3(ivec2(gl_GlobalInvocationID.xy) * stride, gl_GlobalInvocationID.z);
    if (t.x >= pc.rsm.x || t.y >= pc.rsm.w || t.z >= pc.rsm.y)
        return;
    vec4 position = imageLoad(surfelPosition, SURFEL_TEXEL(t));
    vec3 n = imageLoad(surfelNormal, SURFEL_TEXEL(t)).xyz;
    float nn = dot(n, n);
    if (position.w <= 0.0 || !finite3(position.xyz) || !(nn > 1e-12 && nn < 1e30))
        return;
    float cell = pc.grid.origin.w;
#if SURFEL_ARRAY
    if (position.w >= LPV_REDUCE_SPLIT) {
        int f = max(int(pc.params.z), 1);
        for (int y = 0; y < f; ++y)
            for (int x = 0; x < f; ++x) {
                ivec3 u = ivec3(t.xy * f + ivec2(x, y), t.z);
                if (u.x >= int(pc.params.w) || u.y >= int(pc.params.w))
                    continue;
                vec4 up = imageLoad(sourcePosition, u);
                vec3 un = imageLoad(sourceNormal, u).xyz;
                float unn = dot(un, un);
                if (up.w <= 0.0 || !finite3(up.xyz) || !(unn > 1e-12 && unn < 1e30))
                    continue;
                addBlocker(up.xyz, un * inversesqrt(unn), sourceEdge(u, ivec3(1, 0, 0), up.xyz, cell),
                           sourceEdge(u, ivec3(0, 1, 0), up.xyz, cell));
            }
        return;
    }
#endif
    n *= inversesqrt(nn);
    addBlocker(position.xyz, n, edge(t, ivec3(stride, 0, 0), position.xyz, cell),
               edge(t, ivec3(0, stride, 0), position.xyz, cell));
}
