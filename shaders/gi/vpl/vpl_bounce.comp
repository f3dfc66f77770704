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
#include "gi/vpl_voxel_walk.h"

layout(local_size_x = GI_VPL_LOCAL_SIZE_1D) in;
layout(push_constant) uniform PushBlock { VplBouncePush pc; };

layout(set = 1, binding = VPL_BOUNCE_BINDING_DIRECTIONS, std430) readonly buffer Directions { vec4 directions[]; };
layout(set = 1, binding = VPL_BOUNCE_BINDING_ALBEDO) uniform sampler3D albedoVolume;
layout(set = 1, binding = VPL_BOUNCE_BINDING_FACES, r32ui) uniform readonly uimage3D facesVolume;
layout(set = 1, binding = VPL_BOUNCE_BINDING_HALVES) uniform sampler3D halvesVolume; // a = half-voxel bits
layout(set = 1, binding = VPL_BOUNCE_BINDING_VPLS, std430) buffer Vpls { VplRecord vpls[]; };

const float kMinFootprintCos = 0.25;
const float kStartOffset = 1.5; // voxels off the parent's surface: out of its own (conservative) voxels

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
        vplTangentFrame(n, t, b);
        vec3 local = directions[i].xyz;
        vec3 dir = normalize(t * local.x + b * local.y + n * local.z);
        float voxel = pc.origin.w;
        int cells = int(pc.grid.y);
        // Grid coordinates (voxel units); the ray clipped to the grid's box [0, cells]^3.
        vec3 o = (parent.position.xyz + n * (kStartOffset * voxel) - pc.origin.xyz) / voxel;
        VplVoxelHit walk = vplVoxelWalk(o, dir, cells, albedoVolume, halvesVolume);
        if (walk.hit) {
            const int shift = cells > textureSize(albedoVolume, 0).x ? 1 : 0;
            // The faces a ray travelling along +axis sees look towards -axis, and vice versa.
            uint faces = imageLoad(facesVolume, walk.v >> shift).x;
            vec3 m = vec3(0.0);
            for (uint a = 0u; a < 3u; ++a) {
                bool positive = dir[a] > 0.0;
                float cover = voxelFaceCoverage(faces, 2u * a + (positive ? 1u : 0u));
                m[a] = positive ? -cover : cover;
            }
            if (dot(m, m) < 1e-6 && walk.axis >= 0)
                m[walk.axis] = -sign(dir[walk.axis]);
            if (dot(m, m) >= 1e-6) {
                vec3 nHit = normalize(m);
                float cosHit = -dot(nHit, dir);
                if (cosHit > 0.0) {
                    vec3 p = (o + dir * walk.t) * voxel + pc.origin.xyz;
                    vec3 rho = texelFetch(albedoVolume, walk.v >> shift, 0).rgb;
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
    vpls[i] = child;
}
