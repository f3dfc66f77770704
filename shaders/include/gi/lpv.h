// Light propagation volume geometry shared by the C++ reference/tests and the GLSL passes:
// the 6 gather directions, the 5 faces each contribution is split over, their exact solid
// angles and direction integrals, and the reprojection lobe. Derivation: docs/lpv.md.
//
// Units: a cell stores the radiant intensity I(w) (W/sr, or the scene's luminous equivalent)
// leaving its centre in propagation direction w, as 2-band SH per colour channel (gi/sh.h).
// Lengths are in cells. Radiance in a cell is I / cellArea (cellArea = cell size squared).
#ifndef VKGI_GI_LPV_H
#define VKGI_GI_LPV_H

#include "gi/sh.h"

// Push-descriptor bindings (set 1) of lpv/propagate_<format>.comp: one image per colour channel.
#define LPV_PROPAGATE_BINDING_SOURCE_R 0       // wavefront the step gathers from, read only
#define LPV_PROPAGATE_BINDING_SOURCE_G 1
#define LPV_PROPAGATE_BINDING_SOURCE_B 2
#define LPV_PROPAGATE_BINDING_TARGET_R 3       // the new wavefront, written whole
#define LPV_PROPAGATE_BINDING_TARGET_G 4
#define LPV_PROPAGATE_BINDING_TARGET_B 5
#define LPV_PROPAGATE_BINDING_ACCUMULATION_R 6 // light accumulated over the steps, read-modify-write
#define LPV_PROPAGATE_BINDING_ACCUMULATION_G 7
#define LPV_PROPAGATE_BINDING_ACCUMULATION_B 8
#define LPV_PROPAGATE_BINDING_GEOMETRY_VOLUME 9 // blocking potential on the cell corners (RGBA16F, cells + 1)
#define LPV_PROPAGATE_BINDING_VOXEL_ALBEDO 10   // shared voxel grid (gi/voxel_grid.h), sampled trilinearly
#define LPV_PROPAGATE_BINDING_VOXEL_NORMAL 11   // its filtered normal encoding, sampled trilinearly

// Specialization constant ids of lpv/propagate.comp.
#define LPV_SPEC_OCCLUSION 0 // bool: attenuate by the geometry volume
#define LPV_SPEC_BOUNCE 1    // bool: reflect at occupied voxels (Gaitatzes et al.)
// int: what the step adds to the accumulation (one read-modify-write per two steps):
// LPV_ACCUMULATE_NONE, _OWN (the new wavefront), _PAIR (the source wavefront and the new one).
#define LPV_SPEC_ACCUMULATE 2
#define LPV_ACCUMULATE_NONE 0
#define LPV_ACCUMULATE_OWN 1
#define LPV_ACCUMULATE_PAIR 2

#define LPV_LOCAL_SIZE_X 8 // 8x8x4 rather than 4x4x4: lavapipe runs the wider groups faster (../shared/LAVAPIPE.md)
#define LPV_LOCAL_SIZE_Y 8
#define LPV_LOCAL_SIZE_Z 4

GI_NAMESPACE_BEGIN

GI_GPU_STRUCT(LpvPropagatePush) {
    ivec4 gridSize;    // xyz: cells per axis; w: zero
    vec4 lpvOrigin;    // xyz: world min corner of the LPV; w: cell size (bounce only)
    vec4 voxelOrigin;  // xyz: world min corner of the voxel grid; w: 1 / (voxel size * N) (bounce only)
    vec4 params;       // zero
};
GI_CHECK_SIZE(LpvPropagatePush, 64);

// Geometry of one gather direction d, in cell units with the source cell centred at the origin
// and the destination cell centred at d. Light leaving the source through their shared face
// (the "near" face, solid angle 2 pi / 3) leaves the destination through exactly one of its 5
// other faces: the front face (normal d) or one of 4 side faces (normal s, perpendicular to d).
// Omega = solid angle of the face seen from the source centre, V = integral of w dw over it.
const float kLpvFrontSolidAngle = 0.40066968f; // 4 asin(1/10)
const float kLpvSideSolidAngle = 0.42343135f;  // (2 pi / 3 - front) / 4
const float kLpvFrontAxial = 0.38741363f;      // V_front = 0.38741363 d
const float kLpvSideAxial = 0.33835647f;       // V_side = 0.33835647 d + 0.21937313 s
const float kLpvSideLateral = 0.21937313f;

const float kLpvSideDirectionAxial = 0.83907600f;   // normalize(V_side) = 0.839076 d + 0.544014 s
const float kLpvSideDirectionLateral = 0.54401422f;

// Unit vector along axis a in [0, 3) (branch-free: no dynamic vector indexing, which costs
// scratch memory on lavapipe).
GI_INLINE ivec3 lpvUnitAxis(int a) {
    return ivec3(equal(ivec3(a), ivec3(0, 1, 2)));
}

// Offset from the destination to its source for gather direction i in [0, 6):
// +x, -x, +y, -y, +z, -z (the propagation direction is lpvAxisStep(i)).
GI_INLINE ivec3 lpvAxisStep(int i) {
    return (1 - 2 * (i & 1)) * lpvUnitAxis(i >> 1);
}

// Outward normal of face f of the destination cell for gather direction i: f = 0 is the
// front face (normal = propagation direction), f = 1..4 the side faces.
GI_INLINE vec3 lpvFaceNormal(int i, int f) {
    if (f == 0)
        return vec3(lpvAxisStep(i));
    return vec3((1 - 2 * ((f - 1) & 1)) * lpvUnitAxis(((i >> 1) + 1 + ((f - 1) >> 1)) % 3));
}

// Integral of the 4 basis functions over face f's solid angle: the flux through the face of
// a source with intensity SH c is exactly dot(c, lpvFaceWeight(i, f)) (no point sampling).
GI_INLINE vec4 lpvFaceWeight(int i, int f) {
    vec3 d = vec3(lpvAxisStep(i));
    if (f == 0)
        return vec4(kShY00 * kLpvFrontSolidAngle, (kShY1 * kLpvFrontAxial) * d);
    vec3 v = kLpvSideAxial * d + kLpvSideLateral * lpvFaceNormal(i, f);
    return vec4(kShY00 * kLpvSideSolidAngle, kShY1 * v);
}

// Mean direction of light crossing face f (where the geometry volume is evaluated).
GI_INLINE vec3 lpvFaceDirection(int i, int f) {
    vec3 d = vec3(lpvAxisStep(i));
    if (f == 0)
        return d;
    return kLpvSideDirectionAxial * d + kLpvSideDirectionLateral * lpvFaceNormal(i, f);
}

// Intensity SH of a flux of 1 re-emitted from the destination centre in the directions it
// crossed exit face f with (uniform over the face's solid angle as seen from the source):
// (Y00, Y1 V_f / Omega_f), the exact 2-band projection of that distribution. Its integral is
// exactly 1, so the flux a face receives is the flux it passes on (no amplification factor).
// Kaplanyan re-emits a Lambertian lobe around the face normal instead (band 1 = 2/3 Y1 n),
// which turns every step's light into a half-space of directions: light then random-walks,
// a lit wall lights itself and the accumulated light near emitters grows with the step count
// (docs/lpv.md, LpvPropagationCpu.ALitWallDoesNotLightItself).
GI_INLINE vec4 lpvFaceReprojection(int i, int f) {
    vec3 d = vec3(lpvAxisStep(i));
    if (f == 0)
        return vec4(kShY00, (kShY1 * kLpvFrontAxial / kLpvFrontSolidAngle) * d);
    vec3 v = kLpvSideAxial * d + kLpvSideLateral * lpvFaceNormal(i, f);
    return vec4(kShY00, (kShY1 / kLpvSideSolidAngle) * v);
}

// Second moments S_f = integral of w w^T dw over face f, for the CPU reference's 3-band
// propagation (band 2 of the face integrals is shBand2FromMoment(S_f); docs/lpv.md, "Alternatives
// measured and rejected"). By symmetry, in the frame of d, a side normal s and
// t = d x s: front S = A d d^T + B (I - d d^T); side S = P d d^T + Q s s^T + R t t^T +
// X (d s^T + s d^T). trace(S) = Omega (A + 2 B = front, P + Q + R = side).
const float kLpvFrontMomentAxial = 0.37476564f;   // A
const float kLpvFrontMomentLateral = 0.01295202f; // B
const float kLpvSideMomentAxial = 0.27329161f;    // P
const float kLpvSideMomentNormal = 0.11805722f;   // Q
const float kLpvSideMomentOther = 0.03208253f;    // R
const float kLpvSideMomentCross = 0.17234933f;    // X

GI_INLINE mat3 lpvFaceMoment(int i, int f) {
    vec3 d = vec3(lpvAxisStep(i));
    mat3 dd = outerProduct(d, d);
    if (f == 0)
        return kLpvFrontMomentAxial * dd + kLpvFrontMomentLateral * (mat3(1.0f) - dd);
    vec3 n = lpvFaceNormal(i, f);
    mat3 nn = outerProduct(n, n);
    mat3 dn = outerProduct(d, n);
    return kLpvSideMomentAxial * dd + kLpvSideMomentNormal * nn + kLpvSideMomentOther * (mat3(1.0f) - dd - nn) +
           kLpvSideMomentCross * (dn + transpose(dn));
}

// Band 2 of lpvFaceWeight: integral of Y2 over face f.
GI_INLINE vec4 lpvFaceWeightBand2(int i, int f) {
    return shBand2FromMoment(lpvFaceMoment(i, f));
}
GI_INLINE float lpvFaceWeightBand2Last(int i, int f) {
    return shBand2FromMomentLast(lpvFaceMoment(i, f));
}

// The face's solid angle (band 0 of its weight over Y00).
GI_INLINE float lpvFaceSolidAngle(int f) {
    return f == 0 ? kLpvFrontSolidAngle : kLpvSideSolidAngle;
}

// Band 2 of lpvFaceReprojection: the uniform distribution over the face's solid angle projects
// to its face integrals over Omega_f in every band (bands 0 and 1 above are W_f / Omega_f too).
GI_INLINE vec4 lpvFaceReprojectionBand2(int i, int f) {
    return lpvFaceWeightBand2(i, f) * (1.0f / lpvFaceSolidAngle(f));
}
GI_INLINE float lpvFaceReprojectionBand2Last(int i, int f) {
    return lpvFaceWeightBand2Last(i, f) * (1.0f / lpvFaceSolidAngle(f));
}

// The geometry volume has (gridSize + 1)^3 cells centred on the LPV cell corners (offset half a
// cell). The face a destination p shares with its source for gather direction i has its lowest
// corner at this GV index; its other corners add the unit steps of the two other axes.
GI_INLINE ivec3 lpvSharedFaceCorner(ivec3 p, int i) {
    return p + (i & 1) * lpvUnitAxis(i >> 1);
}

// Without occlusion the 5 face terms of one neighbour sum to a fixed linear map of its SH c
// (sum over faces of lpvFaceReprojection(f) * lpvFaceWeight(f)^T), which collapses to a closed
// form because d is an axis: with e = dot(d, c.yzw), sum over f of V_f = V_near = 1.7408 d, and
// sum over f of V_f V_f^T / Omega_f = (a^2 / Om_front + (4 b^2 - 2 l^2) / Om_side) d d^T
// + (2 l^2 / Om_side) I (a, b, l the front axial, side axial and side lateral parts of V):
//   out.x   = c.x / 6 + kLpvFreeB * e                       (Y00^2 * 2 pi / 3 = 1/6 exactly)
//   out.yzw = kLpvFreeS * c.yzw + d * (kLpvFreeC * c.x + kLpvFreeD * e)
// Same operator as the face loop (tested), ~12 FMA instead of ~40 per colour and neighbour.
const float kLpvFreeB = kShY00 * kShY1 * (kLpvFrontAxial + 4.0f * kLpvSideAxial); // Y00 Y1 |V_near|
const float kLpvFreeC = kShY1 * kShY00 * (kLpvFrontAxial + 4.0f * kLpvSideAxial);
const float kLpvFreeS = kShY1 * kShY1 * 2.0f * kLpvSideLateral * kLpvSideLateral / kLpvSideSolidAngle;
const float kLpvFreeD = kShY1 * kShY1 *
                        (kLpvFrontAxial * kLpvFrontAxial / kLpvFrontSolidAngle +
                         (4.0f * kLpvSideAxial * kLpvSideAxial - 2.0f * kLpvSideLateral * kLpvSideLateral) / kLpvSideSolidAngle);

// Light that neighbour SH c sends along unit axis d into the adjacent cell, in empty space.
GI_INLINE vec4 lpvPropagateFree(vec4 c, vec3 d) {
    float e = dot(d, vec3(c.y, c.z, c.w));
    vec3 band1 = kLpvFreeS * vec3(c.y, c.z, c.w) + (kLpvFreeC * c.x + kLpvFreeD * e) * d;
    return vec4(c.x * (1.0f / 6.0f) + kLpvFreeB * e, band1);
}

// Fraction of light in direction `w` that passes a face whose interpolated geometry-volume
// blocking potential is `blocking` (SH of the fraction of light travelling in w that is stopped).
GI_INLINE float lpvTransmittance(vec4 blocking, vec3 w) {
    return 1.0f - clamp(shEvaluate(blocking, w), 0.0f, 1.0f);
}

GI_NAMESPACE_END

#endif
