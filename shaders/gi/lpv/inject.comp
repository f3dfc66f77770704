#version 460
// LPV injection, pass 2: every valid RSM texel (surfel) adds the SH of a Lambertian emitter,
// (flux / M / pi) * cosineLobe(n), to the cell it falls in moved half a cell along its normal.
// Each invocation walks LPV_INJECT_RUN texels of a row and sums runs that share a cell before
// adding them to the buffer with integer atomics (exact, order-independent).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv_passes.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(push_constant) uniform PushBlock { LpvInjectPush pc; };
layout(set = 1, binding = LPV_INJECT_BINDING_POSITION, rgba32f) uniform readonly image2DArray rsmPosition;
layout(set = 1, binding = LPV_INJECT_BINDING_NORMAL, rgba16f) uniform readonly image2DArray rsmNormal;
layout(set = 1, binding = LPV_INJECT_BINDING_FLUX, rgba32f) uniform readonly image2DArray rsmFlux;
layout(set = 1, binding = LPV_INJECT_BINDING_BUFFER, std430) buffer Injection { int data[]; } injection;

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

void main() {
    float m = uintBitsToFloat(uint(injection.data[0]));
    if (!(m > 0.0))
        return; // nothing lit this frame
    ivec3 start = ivec3(gl_GlobalInvocationID.x * LPV_INJECT_RUN, gl_GlobalInvocationID.yz);
    if (start.x >= pc.rsm.x || start.y >= pc.rsm.x || start.z >= pc.rsm.y)
        return;
    ivec3 cell = ivec3(-1);
    vec4 r = vec4(0.0), g = vec4(0.0), b = vec4(0.0);
    int end = min(start.x + LPV_INJECT_RUN, pc.rsm.x);
    for (ivec3 t = start; t.x < end; ++t.x) {
        if (imageLoad(rsmPosition, t).w <= 0.0)
            continue;
        vec3 p = imageLoad(rsmPosition, t).xyz;
        vec3 n = imageLoad(rsmNormal, t).xyz;
        vec3 flux = imageLoad(rsmFlux, t).rgb / m;
        float nn = dot(n, n);
        // Bad input (zero-length normal, NaN/Inf anywhere) is skipped rather than spread.
        if (!(nn > 1e-12 && nn < 1e30) || !(abs(flux.r) + abs(flux.g) + abs(flux.b) < 1e30) ||
            !(abs(p.x) + abs(p.y) + abs(p.z) < 1e30))
            continue;
        // A reduced RSM's normal is a mean of unit normals (inject_reduce.comp): shorter than 1,
        // and the lobe of that length is the exact sum of its texels' lobes. The cell offset uses
        // the unit normal.
        vec3 lobeNormal = n * min(inversesqrt(nn), 1.0);
        n *= inversesqrt(nn);
        ivec3 c = lpvInjectionCell(pc.grid, p, n);
        if (c != cell) {
            flush(cell, r, g, b);
            cell = c;
            r = g = b = vec4(0.0);
        }
        vec4 lobe = shCosineLobe(lobeNormal) * (1.0 / kShPi);
        r += flux.r * lobe;
        g += flux.g * lobe;
        b += flux.b * lobe;
    }
    flush(cell, r, g, b);
}
