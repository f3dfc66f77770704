// One LPV propagation step (Kaplanyan's gather, as described in Elvek's thesis): every cell
// gathers from its 6 neighbours; a neighbour's light is split over the 5 faces of this cell it
// leaves through (exact face integrals, gi/lpv.h), optionally attenuated by the geometry
// volume at the shared face, and re-emitted from this cell's centre in the directions it crossed
// the face with (lpvFaceReprojection). Writes the new wavefront and adds it to the
// accumulation volume.
// Multi-bounce (Gaitatzes et al.): light that enters occupied voxels is reflected instead of
// passing through. Here "does not pass" is the geometry volume's job (its blocking at this
// cell's faces), and the voxel grid (sampled trilinearly at the cell centre: occupancy a, mean
// normal n, albedo rho) says what to do with the stopped flux S = flux(before GV) - flux(after
// GV), clamped to [0, flux before]: it leaves as a Lambertian lobe rho S / pi cosineLobe(n) in
// the new wavefront and the accumulation. Flux out <= flux in for rho <= 1, so it stays
// bounded by the no-occlusion energy; bounces need the GV (without it nothing is stopped).
// Included by propagate_<format>.comp, which defines LPV_FORMAT (storage images that are read
// must declare their format on lavapipe).
#extension GL_GOOGLE_include_directive : require
#include "gi/lpv.h"

layout(local_size_x = LPV_LOCAL_SIZE_X, local_size_y = LPV_LOCAL_SIZE_Y, local_size_z = LPV_LOCAL_SIZE_Z) in;
layout(push_constant) uniform PushBlock { LpvPropagatePush pc; };
// Specialised instead of branched on: with the occlusion loop present the free path was ~1.5x slower.
layout(constant_id = LPV_SPEC_OCCLUSION) const bool kOcclusion = false;
layout(constant_id = LPV_SPEC_BOUNCE) const bool kBounce = false;

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
layout(set = 1, binding = LPV_BINDING_VOXEL_ALBEDO) uniform sampler3D voxelAlbedo;
layout(set = 1, binding = LPV_BINDING_VOXEL_NORMAL) uniform sampler3D voxelNormal;

// Mean blocking SH over the 4 GV cells at the corners of each of the cell's 6 faces (the face
// shared with the source of gather direction i is faces[i]). The 8 corners are loaded once:
// every corner belongs to 3 faces (3x fewer loads than per face).
void faceBlocking(ivec3 p, out vec4 faces[6]) {
    vec4 c[8];
    for (int k = 0; k < 8; ++k)
        c[k] = imageLoad(geometryVolume, p + ivec3(k & 1, (k >> 1) & 1, k >> 2));
    faces[0] = 0.25 * (c[0] + c[2] + c[4] + c[6]); // lower x (source at -x, light travels +x)
    faces[1] = 0.25 * (c[1] + c[3] + c[5] + c[7]);
    faces[2] = 0.25 * (c[0] + c[1] + c[4] + c[5]);
    faces[3] = 0.25 * (c[2] + c[3] + c[6] + c[7]);
    faces[4] = 0.25 * (c[0] + c[1] + c[2] + c[3]);
    faces[5] = 0.25 * (c[4] + c[5] + c[6] + c[7]);
}

void main() {
    ivec3 p = ivec3(gl_GlobalInvocationID);
    ivec3 size = pc.gridSize.xyz;
    if (any(greaterThanEqual(p, size)))
        return;
    vec4 sumR = vec4(0.0), sumG = vec4(0.0), sumB = vec4(0.0);
    vec4 inR = vec4(0.0), inG = vec4(0.0), inB = vec4(0.0); // before GV attenuation (bounce only)
    vec4 faces[6];
    if (kOcclusion)
        faceBlocking(p, faces);
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
        vec4 blocking = faces[i];
        // Nothing at the shared face (most of the volume): transmittance 1 on all 5 faces, which
        // is the free-space closed form (the same operator, tested). Cornell 32^3: ~9 -> ~8 ms
        // per step (lanes of a SIMD group that straddle a surface still run the face loop).
        if (blocking == vec4(0.0)) {
            vec3 d = vec3(p - q);
            vec4 fr = lpvPropagateFree(r, d), fg = lpvPropagateFree(g, d), fb = lpvPropagateFree(b, d);
            sumR += fr;
            sumG += fg;
            sumB += fb;
            if (kBounce) {
                inR += fr;
                inG += fg;
                inB += fb;
            }
            continue;
        }
        for (int f = 0; f < 5; ++f) {
            vec4 open = lpvFaceWeight(i, f);
            vec4 w = open * lpvTransmittance(blocking, lpvFaceDirection(i, f));
            vec4 lobe = lpvFaceReprojection(i, f);
            sumR += dot(r, w) * lobe;
            sumG += dot(g, w) * lobe;
            sumB += dot(b, w) * lobe;
            if (kBounce) {
                inR += dot(r, open) * lobe;
                inG += dot(g, open) * lobe;
                inB += dot(b, open) * lobe;
            }
        }
    }
    if (kBounce) {
        if (!kOcclusion) {
            inR = sumR;
            inG = sumG;
            inB = sumB;
        }
        vec3 world = pc.lpvOrigin.xyz + (vec3(p) + 0.5) * pc.lpvOrigin.w;
        vec3 uvw = (world - pc.voxelOrigin.xyz) * pc.voxelOrigin.w;
        vec4 a = all(greaterThanEqual(uvw, vec3(0.0))) && all(lessThanEqual(uvw, vec3(1.0)))
                     ? textureLod(voxelAlbedo, uvw, 0.0) : vec4(0.0);
        if (a.a > 1e-3) {
            // Filtered encoding n * 0.5 + 0.5 over occupied voxels (empty ones are 0): 2x - a is
            // the sum of their normals. Where normals cancel (both sides of a thin wall) the
            // surface faces the light: reflect back against the incoming direction.
            vec3 n = 2.0 * textureLod(voxelNormal, uvw, 0.0).rgb - a.a;
            if (dot(n, n) < 1e-4 * a.a * a.a)
                n = -(inR.yzw + inG.yzw + inB.yzw);
            if (dot(n, n) > 1e-30) {
                n = normalize(n);
                vec3 rho = clamp(a.rgb / a.a, 0.0, 1.0);
                vec4 emit = shCosineLobe(n) * (1.0 / kShPi);
                // Light the geometry volume stopped at this cell's faces is reflected.
                vec3 blocked = vec3(clamp(shIntegral(inR - sumR), 0.0, max(shIntegral(inR), 0.0)),
                                    clamp(shIntegral(inG - sumG), 0.0, max(shIntegral(inG), 0.0)),
                                    clamp(shIntegral(inB - sumB), 0.0, max(shIntegral(inB), 0.0)));
                sumR += (rho.r * blocked.r) * emit;
                sumG += (rho.g * blocked.g) * emit;
                sumB += (rho.b * blocked.b) * emit;
            }
        }
    }
    imageStore(dstR, p, sumR);
    imageStore(dstG, p, sumG);
    imageStore(dstB, p, sumB);
    imageStore(accR, p, imageLoad(accR, p) + sumR);
    imageStore(accG, p, imageLoad(accG, p) + sumG);
    imageStore(accB, p, imageLoad(accB, p) + sumB);
}
