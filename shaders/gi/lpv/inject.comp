#version 460
// LPV injection, pass 2: every valid RSM texel (surfel) adds the SH of a Lambertian emitter,
// (flux / M / pi) * cosineLobe(n), to the cell it falls in moved half a cell along its normal.
// Each invocation walks LPV_INJECT_RUN texels of a row and sums runs that share a cell before
// adding them to the buffer with integer atomics (exact, order-independent). Surfels closer than
// the finest grid's cell to a point or spot light are left out (lpvInjectsNearLight, docs/lpv.md).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv_passes.h"
#include "gi/direct_types.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { LpvInjectPush pc; };
layout(set = 1, binding = LPV_INJECT_BINDING_POSITION, rgba32f) uniform readonly image2DArray rsmPosition;
layout(set = 1, binding = LPV_INJECT_BINDING_NORMAL, rgba16f) uniform readonly image2DArray rsmNormal;
layout(set = 1, binding = LPV_INJECT_BINDING_FLUX, rgba32f) uniform readonly image2DArray rsmFlux;
layout(set = 1, binding = LPV_INJECT_BINDING_BUFFER, std430) buffer Injection { int data[]; } injection;
layout(set = 1, binding = LPV_INJECT_BINDING_SOURCE_POSITION, rgba32f) uniform readonly image2DArray sourcePosition;
layout(set = 1, binding = LPV_INJECT_BINDING_SOURCE_NORMAL, rgba16f) uniform readonly image2DArray sourceNormal;
layout(set = 1, binding = LPV_INJECT_BINDING_SOURCE_FLUX, rgba32f) uniform readonly image2DArray sourceFlux;
layout(set = 1, binding = LPV_INJECT_BINDING_SHADOW_VIEWS, std430) readonly buffer ShadowViews { GpuShadowView views[]; } shadowViews;

void flush(ivec3 cell, vec4 r, vec4 g, vec4 b) {
    ivec3 size = pc.grid.size.xyz;
    if (any(lessThan(cell, ivec3(0))) || any(greaterThanEqual(cell, size)))
        return;
    int base = LPV_INJECT_HEADER_INTS + LPV_INJECT_CELL_INTS * (cell.x + size.x * (cell.y + size.y * cell.z));
    ivec4 q[3] = ivec4[3](ivec4(round(r * pc.params.x)), ivec4(round(g * pc.params.x)), ivec4(round(b * pc.params.x)));
    for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 4; ++k)
            if (q[c][k] != 0)
                atomicAdd(injection.data[base + 4 * c + k], q[c][k]);
}

// The run being summed: the cell it lands in and its SH per channel.
ivec3 runCell = ivec3(-1);
vec4 runR = vec4(0.0), runG = vec4(0.0), runB = vec4(0.0);

// Adds one surfel (flux already divided by M) to the run, flushing the run when the cell changes.
void addSurfel(vec3 p, vec3 n, vec3 flux, vec4 eye) {
    float nn = dot(n, n);
    // Bad input (zero-length normal, NaN/Inf anywhere) is skipped rather than spread.
    if (!(nn > 1e-12 && nn < 1e30) || !(abs(flux.r) + abs(flux.g) + abs(flux.b) < 1e30) ||
        !(abs(p.x) + abs(p.y) + abs(p.z) < 1e30))
        return;
    if (!lpvInjectsNearLight(eye, p, pc.params.y))
        return;
    // A reduced RSM's normal is a mean of unit normals (inject_reduce.comp): shorter than 1,
    // and the lobe of that length is the exact sum of its texels' lobes. The cell offset uses
    // the unit normal.
    vec3 lobeNormal = n * min(inversesqrt(nn), 1.0);
    n *= inversesqrt(nn);
    ivec3 c = lpvInjectionCell(pc.grid, p, n);
    if (c != runCell) {
        flush(runCell, runR, runG, runB);
        runCell = c;
        runR = runG = runB = vec4(0.0);
    }
    vec4 lobe = shCosineLobe(lobeNormal) * (1.0 / kShPi);
    runR += flux.r * lobe;
    runG += flux.g * lobe;
    runB += flux.b * lobe;
}

void main() {
    float m = uintBitsToFloat(uint(injection.data[0]));
    if (!(m > 0.0))
        return; // nothing lit this frame
    ivec3 start = ivec3(gl_GlobalInvocationID.x * LPV_INJECT_RUN, gl_GlobalInvocationID.yz);
    if (start.x >= pc.rsm.x || start.y >= pc.rsm.x || start.z >= pc.rsm.y)
        return;
    int end = min(start.x + LPV_INJECT_RUN, pc.rsm.x);
    int f = max(pc.rsm.z, 1);
    vec4 eye = shadowViews.views[start.z].eye;
    for (ivec3 t = start; t.x < end; ++t.x) {
        float w = imageLoad(rsmPosition, t).w;
        if (w <= 0.0)
            continue;
        if (w < LPV_REDUCE_SPLIT) {
            addSurfel(imageLoad(rsmPosition, t).xyz, imageLoad(rsmNormal, t).xyz, imageLoad(rsmFlux, t).rgb / m, eye);
            continue;
        }
        for (int y = 0; y < f; ++y)
            for (int x = 0; x < f; ++x) {
                ivec3 u = ivec3(t.xy * f + ivec2(x, y), t.z);
                if (u.x >= pc.rsm.w || u.y >= pc.rsm.w || imageLoad(sourcePosition, u).w <= 0.0)
                    continue;
                addSurfel(imageLoad(sourcePosition, u).xyz, imageLoad(sourceNormal, u).xyz,
                          imageLoad(sourceFlux, u).rgb / m, eye);
            }
    }
    flush(runCell, runR, runG, runB);
}
