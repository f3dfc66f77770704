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
// Specialised instead of branched on: the occlusion loop left in a free step slows it down.
layout(constant_id = LPV_SPEC_OCCLUSION) const bool kOcclusion = false;
layout(constant_id = LPV_SPEC_BOUNCE) const bool kBounce = false;
// The accumulation's load and store are a sizeable part of a step: a pair of steps does it once,
// the second adding the first's wavefront (its source, at this cell) with its own.
layout(constant_id = LPV_SPEC_ACCUMULATE) const int kAccumulate = LPV_ACCUMULATE_OWN;

layout(set = 1, binding = LPV_PROPAGATE_BINDING_SOURCE_R, LPV_FORMAT) uniform readonly image3D sourceR;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_SOURCE_G, LPV_FORMAT) uniform readonly image3D sourceG;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_SOURCE_B, LPV_FORMAT) uniform readonly image3D sourceB;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_TARGET_R, LPV_FORMAT) uniform writeonly image3D targetR;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_TARGET_G, LPV_FORMAT) uniform writeonly image3D targetG;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_TARGET_B, LPV_FORMAT) uniform writeonly image3D targetB;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_ACCUMULATION_R, LPV_FORMAT) uniform image3D accumulationR;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_ACCUMULATION_G, LPV_FORMAT) uniform image3D accumulationG;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_ACCUMULATION_B, LPV_FORMAT) uniform image3D accumulationB;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_GEOMETRY_VOLUME, rgba16f) uniform readonly image3D geometryVolume;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_VOXEL_ALBEDO) uniform sampler3D voxelAlbedo;
layout(set = 1, binding = LPV_PROPAGATE_BINDING_VOXEL_NORMAL) uniform sampler3D voxelNormal;

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

// Source SH of gather direction i (zero outside the grid). A clamped load times a 0/1 weight
// rather than a branch: keeps the 8 lanes of a SIMD group convergent.
void loadSource(ivec3 p, ivec3 size, int i, out vec4 r, out vec4 g, out vec4 b) {
    ivec3 q = p - lpvAxisStep(i);
    float inside = float(all(greaterThanEqual(q, ivec3(0))) && all(lessThan(q, size)));
    q = clamp(q, ivec3(0), size - 1);
    r = inside * imageLoad(sourceR, q);
    g = inside * imageLoad(sourceG, q);
    b = inside * imageLoad(sourceB, q);
}

// The face loop of one neighbour (5 faces: lpvFaceWeight, lpvTransmittance at lpvFaceDirection,
// lpvFaceReprojection) written out in the neighbour's own frame, where every constant is a
// scalar: SH vectors are permuted to (c0, c_a, c_b, c_c) with a the gather axis (propagation
// direction d = sign e_a) and b, c the two other axes; the front face has normal d, the side faces
// +-e_b, +-e_c. Face fluxes: front Y00 Om_F c0 + sign Y1 a_F c_a, side Y00 Om_S c0 + sign Y1 b_S c_a
// +- Y1 l_S c_{b,c}; each is scaled by its transmittance and re-emitted as (Y00, Y1 V_f / Om_f).
// ~20 flops per colour instead of 5 dot products and 5 vec4 FMAs, with the 5 transmittances shared
// by the 3 colours. Same operator as the face loop (LpvPropagation's GPU-vs-CPU tests).
const float kOccFront0 = kShY00 * kLpvFrontSolidAngle;
const float kOccFront1 = kShY1 * kLpvFrontAxial;
const float kOccSide0 = kShY00 * kLpvSideSolidAngle;
const float kOccSide1 = kShY1 * kLpvSideAxial;
const float kOccSide2 = kShY1 * kLpvSideLateral;
const float kOccOutFront = kShY1 * kLpvFrontAxial / kLpvFrontSolidAngle;
const float kOccOutSideAxial = kShY1 * kLpvSideAxial / kLpvSideSolidAngle;
const float kOccOutSideLateral = kShY1 * kLpvSideLateral / kLpvSideSolidAngle;

// lpvPropagateFree (the closed form of the 5 open faces) in the neighbour's frame.
vec4 propagateFree(vec4 c, float sign) {
    float e = sign * c.y;
    return vec4(c.x * (1.0 / 6.0) + kLpvFreeB * e, kLpvFreeS * c.y + sign * (kLpvFreeC * c.x + kLpvFreeD * e),
                kLpvFreeS * c.z, kLpvFreeS * c.w);
}

// Transmittances (front; sides +b, -b, +c, -c) of a face with permuted blocking SH `bl`.
void faceTransmittance(vec4 bl, float sign, out float front, out vec4 sides) {
    float e0 = kShY00 * bl.x;
    front = 1.0 - clamp(e0 + (sign * kShY1) * bl.y, 0.0, 1.0);
    float base = e0 + (sign * kShY1 * kLpvSideDirectionAxial) * bl.y;
    float hb = (kShY1 * kLpvSideDirectionLateral) * bl.z, hc = (kShY1 * kLpvSideDirectionLateral) * bl.w;
    sides = 1.0 - clamp(vec4(base + hb, base - hb, base + hc, base - hc), 0.0, 1.0);
}

// Permuted light a neighbour with permuted SH c sends into this cell through its 5 exit faces.
vec4 propagateThroughFaces(vec4 c, float sign, float front, vec4 sides) {
    float gF = (kOccFront0 * c.x + (sign * kOccFront1) * c.y) * front;
    float P = kOccSide0 * c.x + (sign * kOccSide1) * c.y;
    float qb = kOccSide2 * c.z, qc = kOccSide2 * c.w;
    vec4 gS = vec4(P + qb, P - qb, P + qc, P - qc) * sides;
    float s = (gS.x + gS.y) + (gS.z + gS.w);
    return vec4(kShY00 * (gF + s), sign * (kOccOutFront * gF + kOccOutSideAxial * s), kOccOutSideLateral * (gS.x - gS.y),
                kOccOutSideLateral * (gS.z - gS.w));
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
    // One neighbour in its own frame: PERM maps (x, y, z) SH to (c0, c_a, c_b, c_c), UNPERM back.
    // Written out for the 6 neighbours: a loop over i kept lpvAxisStep(i) and the face vectors as
    // run-time values instead of folding them into constants.
#define LPV_GATHER(I, PERM, UNPERM)                                                                           \
    {                                                                                                        \
        vec4 r, g, b;                                                                                        \
        loadSource(p, size, I, r, g, b);                                                                     \
        float sign = float(1 - 2 * (I & 1));                                                                 \
        if (!kOcclusion) {                                                                                   \
            sumR += propagateFree(r.PERM, sign).UNPERM;                                                      \
            sumG += propagateFree(g.PERM, sign).UNPERM;                                                      \
            sumB += propagateFree(b.PERM, sign).UNPERM;                                                      \
        } else {                                                                                             \
            float front;                                                                                     \
            vec4 sides;                                                                                      \
            faceTransmittance(faces[I].PERM, sign, front, sides);                                            \
            sumR += propagateThroughFaces(r.PERM, sign, front, sides).UNPERM;                                \
            sumG += propagateThroughFaces(g.PERM, sign, front, sides).UNPERM;                                \
            sumB += propagateThroughFaces(b.PERM, sign, front, sides).UNPERM;                                \
            if (kBounce) {                                                                                   \
                inR += propagateThroughFaces(r.PERM, sign, 1.0, vec4(1.0)).UNPERM;                           \
                inG += propagateThroughFaces(g.PERM, sign, 1.0, vec4(1.0)).UNPERM;                           \
                inB += propagateThroughFaces(b.PERM, sign, 1.0, vec4(1.0)).UNPERM;                           \
            }                                                                                                \
        }                                                                                                    \
    }
    LPV_GATHER(0, xyzw, xyzw)
    LPV_GATHER(1, xyzw, xyzw)
    LPV_GATHER(2, xzwy, xwyz)
    LPV_GATHER(3, xzwy, xwyz)
    LPV_GATHER(4, xwyz, xzwy)
    LPV_GATHER(5, xwyz, xzwy)
#undef LPV_GATHER
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
    imageStore(targetR, p, sumR);
    imageStore(targetG, p, sumG);
    imageStore(targetB, p, sumB);
    if (kAccumulate == LPV_ACCUMULATE_PAIR) {
        imageStore(accumulationR, p, imageLoad(accumulationR, p) + (imageLoad(sourceR, p) + sumR));
        imageStore(accumulationG, p, imageLoad(accumulationG, p) + (imageLoad(sourceG, p) + sumG));
        imageStore(accumulationB, p, imageLoad(accumulationB, p) + (imageLoad(sourceB, p) + sumB));
    } else if (kAccumulate == LPV_ACCUMULATE_OWN) {
        imageStore(accumulationR, p, imageLoad(accumulationR, p) + sumR);
        imageStore(accumulationG, p, imageLoad(accumulationG, p) + sumG);
        imageStore(accumulationB, p, imageLoad(accumulationB, p) + sumB);
    }
}
