#version 460
#extension GL_GOOGLE_include_directive : require
// One work group per large sun window (docs/vpl.md, "Candidates weighted by the image"): N of
// its M world-fixed candidate VPLs by priority sampling (Duffield, Lund & Thorup), written to the
// sun's N VPL slots.
//
// Candidate i has weight w_i (vpl_importance.comp, plus a defensive floor: the share
// pc.params.x of the total weight spread by flux alone, so that every lit candidate can be
// drawn) and a key u_i in (0, 1] fixed by its lattice point (vplCandidateUniform). Its priority is
// q_i = w_i / u_i; the N candidates of highest priority are kept, tau is the (N + 1)-th priority
// (0 when fewer than N + 1 are positive), and a kept candidate is included with probability
// p_i = min(1, w_i / tau), so its flux is divided by p_i: for weights that do not depend on the
// keys, the sum of the kept fluxes is an unbiased estimate of the candidates' total (priority
// sampling), with exactly min(N, positive candidates) VPLs. The keys belong to the lattice
// points, so a camera that moves changes only the candidates whose priority crosses tau.
//
// Slots: the candidate table is subset-major like the VPLs (a candidate's subset is its
// lattice class, focusedWindowPoints); a kept candidate takes the next slot of its subset's block
// in candidate order, and the candidates a full block cannot hold fill the other blocks' free
// slots in order (the interleave filter averages every subset with the same weight, so the
// filtered sum does not depend on which block holds a VPL). Slots left over stay empty (as
// vpl_generate.comp wrote them). For every generation g >= 1 the slot's child entry of the
// generation table gets the bounce ray the candidate's id names (vplBounceDirection), so a VPL
// keeps its children's rays whatever slot it takes.
#include "gi/vpl.h"
#include "gi/vpl_term.h"

layout(local_size_x = GI_VPL_SELECT_LOCAL_SIZE) in;
layout(push_constant) uniform PushBlock { VplSelectPush pc; };

layout(set = 1, binding = VPL_SELECT_BINDING_TABLE, std430) readonly buffer Table { vec4 table[]; };
layout(set = 1, binding = VPL_SELECT_BINDING_IDS, std430) readonly buffer Ids { uint ids[]; };
layout(set = 1, binding = VPL_SELECT_BINDING_CANDIDATES, std430) readonly buffer Candidates { VplRecord candidates[]; };
layout(set = 1, binding = VPL_SELECT_BINDING_WEIGHTS, std430) readonly buffer Weights { float weights[]; };
layout(set = 1, binding = VPL_SELECT_BINDING_VPLS, std430) writeonly buffer Vpls { VplRecord vpls[]; };
layout(set = 1, binding = VPL_SELECT_BINDING_DIRECTIONS, std430) writeonly buffer Directions { vec4 directions[]; };

const uint kMaxSubsets = GI_VPL_MAX_INTERLEAVE * GI_VPL_MAX_INTERLEAVE;
shared float sSum[GI_VPL_SELECT_LOCAL_SIZE];
shared float sFlux[GI_VPL_SELECT_LOCAL_SIZE];
shared uint sCount;
shared uint sKept[kMaxSubsets];
shared uint sScan[GI_VPL_SELECT_LOCAL_SIZE];

uint first;       // the sun's first candidate
float floorShare; // defensive floor per unit of flux luminance
float weightScale;

float weightOf(uint c) {
    float flux = candidates[first + c].position.w > 0.0 ? vplLuminance(candidates[first + c].flux.rgb) : 0.0;
    return flux > 0.0 ? weights[first + c] * weightScale + floorShare * flux : 0.0;
}

float priorityOf(uint c) {
    return weightOf(c) / vplCandidateUniform(ids[first + c]);
}

// The candidate block's first index of subset s (the candidate table's subset-major order).
uint candidateBlock(uint s, uint subsets) { return (s * pc.info.x) / subsets; }

// Writes kept candidate c (its rank among the kept ones) into a slot of the sun's source `light`.
void place(uint c, uint rank, uint light, uint N, uint n, uint sources, uint lights, uint generations, float tau) {
    uint subsets = n * n;
    // Home subset h, the rank within it, and the slot; past a full block, the overflow's place
    // among the free slots of all blocks, in order.
    uint h = 0u, keptBeforeHome = 0u, overflowBefore = 0u;
    while (h + 1u < subsets && candidateBlock(h + 1u, subsets) <= c) {
        keptBeforeHome += sKept[h];
        uint slotsH = (vplSubsetStart(h + 1u, n, sources, N) - vplSubsetStart(h, n, sources, N)) / sources;
        overflowBefore += sKept[h] > slotsH ? sKept[h] - slotsH : 0u;
        h += 1u;
    }
    uint r = rank - keptBeforeHome;
    uint target = h;
    uint slotsHome = (vplSubsetStart(h + 1u, n, sources, N) - vplSubsetStart(h, n, sources, N)) / sources;
    if (r >= slotsHome) {
        uint o = overflowBefore + (r - slotsHome);
        target = subsets; // none found: cannot happen, at most N candidates are kept
        for (uint t = 0u; t < subsets && target == subsets; ++t) {
            uint slotsT = (vplSubsetStart(t + 1u, n, sources, N) - vplSubsetStart(t, n, sources, N)) / sources;
            uint room = sKept[t] < slotsT ? slotsT - sKept[t] : 0u;
            if (o < room) {
                target = t;
                r = min(sKept[t], slotsT) + o;
            } else {
                o -= room;
            }
        }
    }
    if (target == subsets)
        return;
    uint subsetFirst = vplSubsetStart(target, n, sources, N);
    uint block = (vplSubsetStart(target + 1u, n, sources, N) - subsetFirst) / sources;
    uint slot = subsetFirst + light * block + r;
    VplRecord v = candidates[first + c];
    float p = tau > 0.0 ? min(1.0, weightOf(c) / tau) : 1.0;
    v.flux /= p; // rgb: the unbiased flux; w: the footprint grows with the area the VPL stands for
    vpls[slot] = v;
    uint id = ids[first + c];
    for (uint g = 1u; g < generations; ++g)
        directions[slot + g * lights * block] = vec4(vplBounceDirection(id % N + 1u, g), float(g * lights + light));
}

void main() {
    uint tid = gl_LocalInvocationID.x;
    uint M = pc.info.x, N = pc.info.y, n = pc.info.z, lights = pc.info.w;
    uint sources = pc.shape.x, generations = pc.shape.y;
    uint subsets = n * n;
    first = gl_WorkGroupID.x * M;
    uint light = uint(table[first].w);

    // Totals of the weights and of the flux luminance.
    float w = 0.0, f = 0.0;
    for (uint c = tid; c < M; c += GI_VPL_SELECT_LOCAL_SIZE) {
        VplRecord v = candidates[first + c];
        float flux = v.position.w > 0.0 ? vplLuminance(v.flux.rgb) : 0.0;
        if (flux > 0.0) {
            w += weights[first + c];
            f += flux;
        }
    }
    sSum[tid] = w;
    sFlux[tid] = f;
    barrier();
    for (uint stride = GI_VPL_SELECT_LOCAL_SIZE / 2; stride > 0u; stride >>= 1u) {
        if (tid < stride) {
            sSum[tid] += sSum[tid + stride];
            sFlux[tid] += sFlux[tid + stride];
        }
        barrier();
    }
    float totalWeight = sSum[0], totalFlux = sFlux[0];
    barrier();
    // Weights normalised to sum 1 - floor, the floor's share spread by flux; nothing seen: flux alone.
    float share = totalWeight > 0.0 ? pc.params.x : 1.0;
    weightScale = totalWeight > 0.0 ? (1.0 - share) / totalWeight : 0.0;
    floorShare = totalFlux > 0.0 ? share / totalFlux : 0.0;

    // tau: the smallest priority t (bisection on the float's bits, which order like the values
    // for t >= 0) with at most N priorities above it, i.e. the (N + 1)-th priority.
    uint lo = 0u, hi = 0x7f800000u;
    while (lo < hi) {
        uint mid = lo + (hi - lo) / 2u;
        float t = uintBitsToFloat(mid);
        if (tid == 0u)
            sCount = 0u;
        barrier();
        uint above = 0u;
        for (uint c = tid; c < M; c += GI_VPL_SELECT_LOCAL_SIZE)
            above += priorityOf(c) > t ? 1u : 0u;
        atomicAdd(sCount, above);
        barrier();
        if (sCount <= N)
            hi = mid;
        else
            lo = mid + 1u;
        barrier();
    }
    float tau = uintBitsToFloat(lo);

    // Kept candidates per subset block.
    if (tid < kMaxSubsets)
        sKept[tid] = 0u;
    barrier();
    for (uint s = 0u; s < subsets; ++s) {
        uint kept = 0u;
        uint end = candidateBlock(s + 1u, subsets);
        for (uint c = candidateBlock(s, subsets) + tid; c < end; c += GI_VPL_SELECT_LOCAL_SIZE)
            kept += priorityOf(c) > tau ? 1u : 0u;
        atomicAdd(sKept[s], kept);
    }
    barrier();

    // Candidates in order, a work group's width at a time: each kept one's rank among the kept.
    uint keptBefore = 0u;
    for (uint base = 0u; base < M; base += GI_VPL_SELECT_LOCAL_SIZE) {
        uint c = base + tid;
        float q = c < M ? priorityOf(c) : 0.0;
        bool kept = c < M && q > tau;
        sScan[tid] = kept ? 1u : 0u;
        barrier();
        // Inclusive scan (Hillis-Steele).
        for (uint stride = 1u; stride < GI_VPL_SELECT_LOCAL_SIZE; stride <<= 1u) {
            uint add = tid >= stride ? sScan[tid - stride] : 0u;
            barrier();
            sScan[tid] += add;
            barrier();
        }
        uint rank = keptBefore + sScan[tid] - (kept ? 1u : 0u);
        uint chunkKept = sScan[GI_VPL_SELECT_LOCAL_SIZE - 1];
        barrier();
        keptBefore += chunkKept;
        if (kept)
            place(c, rank, light, N, n, sources, lights, generations, tau);
    }
}
