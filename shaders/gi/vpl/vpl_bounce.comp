#version 460
#extension GL_GOOGLE_include_directive : require
// One more diffuse bounce of the VPLs (instant radiosity, Keller 1997): one thread per record;
// the records of generation g (pc.info.z) each take their parent, the VPL of generation g - 1 at
// the same Halton index of the same subset (vplParentRecord, gi/vpl.h), and trace one ray from it
// through the voxel grid's occupancy to the first occupied voxel, where they sit.
//
// The ray's direction is the entry's cosine-lobe point (pdf cos / pi about the parent's normal),
// so the parent's reflected flux Phi (a cosine emitter: Phi / pi * cos per steradian) that the ray
// carries is Phi / pi * cos / pdf = Phi: with one ray per parent the child receives Phi, reflects
// albedo(hit) * Phi, and the children's sum is an unbiased estimate of the light reflected once
// more. The ray is clipped to the grid's box and walked voxel by voxel (every voxel it crosses is
// tested, however long the ray); a parent outside the box (a distant sun VPL, when the grid is
// centred on the camera in a large world) starts its walk where the ray enters the box. A ray
// that leaves the grid, or never enters it, leaves an empty child: its light, reflected again
// outside the grid (far from the camera with a camera-centred grid), is lost.
//
// The child's normal is the coverage-weighted normal of the voxel's faces that look towards the
// ray (gi/voxel_grid.h faces volume), or the face the ray entered through when none does. Its
// footprint (the gathers' clamp radius, flux.w = r^2): the N children of a light's generation are
// N rays of a cosine emitter, one every pi / (N cos_parent) steradians, which at distance d meet
// the receiving surface over pi d^2 / (N cos_parent cos_child) square metres; r^2 is that area over
// pi (cosines taken no lower than kMinFootprintCos, as in vpl_generate.comp), and never below the
// parent's (the children are no denser than their parents).
//
// Half voxels (pc.grid.y twice the volumes' size: the camera-centred grid, gi/voxel_grid.h): the
// walk, the start offset and the box are in half voxels, a half is occupied when its bit is set,
// and the hit takes the albedo and faces of the voxel holding the half.
#include "gi/voxel_grid.h"
#include "gi/vpl.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_1D) in;
layout(push_constant) uniform PushBlock { VplBouncePush pc; };

layout(set = 1, binding = VPL_BOUNCE_BINDING_DIRECTIONS, std430) readonly buffer Directions { vec4 directions[]; };
layout(set = 1, binding = VPL_BOUNCE_BINDING_ALBEDO) uniform sampler3D albedoVolume;
layout(set = 1, binding = VPL_BOUNCE_BINDING_FACES, r32ui) uniform readonly uimage3D facesVolume;
layout(set = 1, binding = VPL_BOUNCE_BINDING_HALVES) uniform sampler3D halvesVolume; // a = half-voxel bits
layout(set = 1, binding = VPL_BOUNCE_BINDING_VPLS, std430) buffer Vpls { VplRecord vpls[]; };

const float kMinFootprintCos = 0.25;
const float kStartOffset = 1.5; // voxels off the parent's surface: out of its own (conservative) voxels

// Orthonormal tangents of unit n (Duff et al. 2017, branchless).
void tangentFrame(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.info.x)
        return;
    uint lights = pc.info.y;
    uint source = uint(directions[i].w);
    if (source / lights != pc.info.z)
        return; // another generation's record
    uint parentIndex = vplParentRecord(i, pc.info.w, lights, pc.grid.z, pc.grid.x);
    VplRecord child = VplRecord(vec4(0.0), vec4(0.0, 0.0, 1.0, 0.0), vec4(0.0));
    VplRecord parent = vpls[parentIndex];
    if (parent.position.w > 0.0 && any(greaterThan(parent.flux.rgb, vec3(0.0)))) {
        vec3 n = parent.direction.xyz;
        vec3 t, b;
        tangentFrame(n, t, b);
        vec3 local = directions[i].xyz;
        vec3 dir = normalize(t * local.x + b * local.y + n * local.z);
        float voxel = pc.origin.w;
        int cells = int(pc.grid.y);
        // Grid coordinates (voxel units); the ray clipped to the grid's box [0, cells]^3.
        vec3 o = (parent.position.xyz + n * (kStartOffset * voxel) - pc.origin.xyz) / voxel;
        vec3 inv = 1.0 / dir; // +-inf on axis-parallel rays: the slab test and the steps still work
        vec3 t0 = (vec3(0.0) - o) * inv, t1 = (vec3(float(cells)) - o) * inv;
        float tEnter = max(max(max(min(t0.x, t1.x), min(t0.y, t1.y)), min(t0.z, t1.z)), 0.0);
        float tExit = min(min(max(t0.x, t1.x), max(t0.y, t1.y)), max(t0.z, t1.z));
        if (tEnter < tExit) {
            // Amanatides & Woo: every voxel the ray crosses, in order.
            ivec3 v = clamp(ivec3(floor(o + dir * tEnter)), ivec3(0), ivec3(cells - 1));
            ivec3 stepDir = ivec3(sign(dir));
            vec3 tDelta = abs(inv);
            vec3 tNext = (vec3(v) + max(vec3(stepDir), vec3(0.0)) - o) * inv;
            tNext = mix(tNext, vec3(1e30), equal(stepDir, ivec3(0)));
            float tHit = tEnter;
            int axis = -1; // the axis of the face the ray entered the current voxel through
            bool hit = false;
            int maxSteps = 3 * cells;
            const int shift = cells > textureSize(albedoVolume, 0).x ? 1 : 0;
            for (int k = 0; k < maxSteps; ++k) {
                bool occupied;
                if (shift == 0) {
                    occupied = texelFetch(albedoVolume, v, 0).a > 0.5;
                } else {
                    uint bits = uint(texelFetch(halvesVolume, v >> 1, 0).a + 0.5);
                    occupied = ((bits >> (uint(v.x & 1) | (uint(v.y & 1) << 1u) | (uint(v.z & 1) << 2u))) & 1u) != 0u;
                }
                if (occupied) {
                    hit = true;
                    break;
                }
                axis = tNext.x < tNext.y ? (tNext.x < tNext.z ? 0 : 2) : (tNext.y < tNext.z ? 1 : 2);
                tHit = tNext[axis];
                v[axis] += stepDir[axis];
                tNext[axis] += tDelta[axis];
                if (v[axis] < 0 || v[axis] >= cells)
                    break;
            }
            if (hit) {
                // The faces a ray travelling along +axis sees look towards -axis, and vice versa.
                uint faces = imageLoad(facesVolume, v >> shift).x;
                vec3 m = vec3(0.0);
                for (uint a = 0u; a < 3u; ++a) {
                    bool positive = dir[a] > 0.0;
                    float cover = voxelFaceCoverage(faces, 2u * a + (positive ? 1u : 0u));
                    m[a] = positive ? -cover : cover;
                }
                if (dot(m, m) < 1e-6 && axis >= 0)
                    m[axis] = -float(stepDir[axis]);
                if (dot(m, m) >= 1e-6) {
                    vec3 nHit = normalize(m);
                    float cosHit = -dot(nHit, dir);
                    if (cosHit > 0.0) {
                        vec3 p = (o + dir * tHit) * voxel + pc.origin.xyz;
                        vec3 rho = texelFetch(albedoVolume, v >> shift, 0).rgb;
                        vec3 d = p - parent.position.xyz;
                        float footprint = dot(d, d) / (float(pc.grid.x) * max(local.z, kMinFootprintCos) *
                                                       max(cosHit, kMinFootprintCos));
                        child.position = vec4(p, 1.0);
                        child.direction = vec4(nHit, 0.0);
                        child.flux = vec4(parent.flux.rgb * rho, max(footprint, parent.flux.w));
                    }
                }
            }
        }
    }
    vpls[i] = child;
}
