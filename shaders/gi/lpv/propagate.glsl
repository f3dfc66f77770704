// One LPV propagation step (Kaplanyan's gather, as described in Elvek's thesis): every cell
// gathers from its 6 neighbours; a neighbour's light is split over the 5 faces of this cell it
// leaves through (exact face integrals, gi/lpv.h), optionally attenuated by the geometry
// volume at the shared face, and re-emitted from this cell's centre as a cosine lobe around
// the face normal. Writes the new wavefront and adds it to the accumulation volume.
// Included by propagate_<format>.comp, which defines LPV_FORMAT (storage images that are read
// must declare their format on lavapipe).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv.h"

layout(local_size_x = LPV_LOCAL_SIZE_X, local_size_y = LPV_LOCAL_SIZE_Y, local_size_z = LPV_LOCAL_SIZE_Z) in;
layout(push_constant) uniform PushBlock { LpvPropagatePush pc; };
// Specialised instead of branched on: with the occlusion loop present the free path was ~1.5x slower.
layout(constant_id = LPV_SPEC_OCCLUSION) const bool kOcclusion = false;

layout(set = 1, binding = LPV_BINDING_SRC_R, LPV_FORMAT) uniform readonly image3D srcR;
layout(set = 1, binding = LPV_BINDING_SRC_G, LPV_FORMAT) uniform readonly image3D srcG;
layout(set = 1, binding = LPV_BINDING_SRC_B, LPV_FORMAT) uniform readonly image3D srcB;
layout(set = 1, binding = LPV_BINDING_DST_R, LPV_FORMAT) uniform writeonly image3D dstR;
layout(set = 1, binding = LPV_BINDING_DST_G, LPV_FORMAT) uniform writeonly image3D dstG;
layout(set = 1, binding = LPV_BINDING_DST_B, LPV_FORMAT) uniform writeonly image3D dstB;
layout(set = 1, binding = LPV_BINDING_ACC_R, LPV_FORMAT) uniform image3D accR;
layout(set = 1, binding = LPV_BINDING_ACC_G, LPV_FORMAT) uniform image3D accG;
layout(set = 1, binding = LPV_BINDING_ACC_B, LPV_FORMAT) uniform image3D accB;
layout(set = 1, binding = LPV_BINDING_GV, rgba16f) uniform readonly image3D geometryVolume;

// Mean blocking SH over the 4 GV cells at the corners of the face shared with the source.
vec4 sharedFaceBlocking(ivec3 p, int i) {
    ivec3 c = lpvSharedFaceCorner(p, i);
    ivec3 eb = lpvUnitAxis(((i >> 1) + 1) % 3), ec = lpvUnitAxis(((i >> 1) + 2) % 3);
    return 0.25 * (imageLoad(geometryVolume, c) + imageLoad(geometryVolume, c + eb) +
                   imageLoad(geometryVolume, c + ec) + imageLoad(geometryVolume, c + eb + ec));
}

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    ivec3 size = pc.gridSize.xyz;
    if (any(greaterThanEqual(p, size)))
        return;
    vec4 sumR = vec4(0.0), sumG = vec4(0.0), sumB = vec4(0.0);
    for (int i = 0; i < 6; ++i) {
        // Clamped load times a 0/1 weight rather than a branch: keeps the 8 lanes convergent.
        ivec3 q = p - lpvAxisStep(i);
        float inside = float(all(greaterThanEqual(q, ivec3(0))) && all(lessThan(q, size)));
        q = clamp(q, ivec3(0), size - 1);
        vec4 r = inside * imageLoad(srcR, q), g = inside * imageLoad(srcG, q), b = inside * imageLoad(srcB, q);
        if (!kOcclusion) {
            vec3 d = vec3(p - q);
            sumR += lpvPropagateFree(r, d);
            sumG += lpvPropagateFree(g, d);
            sumB += lpvPropagateFree(b, d);
            continue;
        }
        vec4 blocking = sharedFaceBlocking(p, i);
        for (int f = 0; f < 5; ++f) {
            vec4 w = lpvFaceWeight(i, f) * lpvTransmittance(blocking, lpvFaceDirection(i, f));
            vec4 lobe = lpvReprojection(lpvFaceNormal(i, f));
            sumR += dot(r, w) * lobe;
            sumG += dot(g, w) * lobe;
            sumB += dot(b, w) * lobe;
        }
    }
    imageStore(dstR, p, sumR);
    imageStore(dstG, p, sumG);
    imageStore(dstB, p, sumB);
    imageStore(accR, p, imageLoad(accR, p) + sumR);
    imageStore(accG, p, imageLoad(accG, p) + sumG);
    imageStore(accB, p, imageLoad(accB, p) + sumB);
}
