// Which full-resolution pixels the VCT refine traces (vct_upsample.comp decides and lists them,
// vct_trace_refine.comp traces them). The includer declares push constants `pc` (VctTracePush).

// Reach of the first cone samples in voxels (lowResFitTapsAt): a cone starts one voxel off the
// surface and takes its first sample one voxel along itself, a footprint one voxel wide.
// Cornell 256^2, 64^3: 4917 refined pixels against lowResTaps' 7097, relMSE unchanged to 1%
// (docs/vct.md).
const float kUpsampleReach = 2.0;
// How far (voxels) a refined pixel may be from the pixel whose trace it takes (vctSameSpot).
const float kShareReach = 0.75;

// Refined pixels of a 4x4 block share traces: in block order (vctRefineOrder), a refined pixel
// takes the trace of the first traced pixel before it that lies on its surface within 3/4 of a
// voxel of it (normal within the threshold), else it is traced itself. Near a concave corner,
// where most refined pixels are, the gather changes over the 2 voxels its first samples reach; a
// cone origin moved by 3/4 of a voxel moves the first sample (one voxel wide) by 3/4 of its width.
// Cornell 256^2 (pixels 0.3 voxels wide): 1845 of the 4917 refined pixels traced (2x2 quads
// with half a voxel: 2675; 4x4 blocks with half a voxel: 2554, with one voxel: 1281), relMSE
// within 1% (docs/vct.md).
bool vctSameSpot(vec4 pa, vec3 na, vec4 pb, vec3 nb) {
    return 1.0 - dot(na, nb) <= pc.eye.w && distance(pa.xyz, pb.xyz) <= kShareReach * pc.grid.originSize.w;
}

// Blocks: 4x4 pixels from vctRefineBlockOrigin, shifted by f / 2 so that they hold whole cells
// of pixels that interpolate the same 2x2 low-res texels (lowResTapCell: pixels fa + f/2 ..
// fa + f/2 + f - 1 lie in cell a): one at f = 4, four at f = 2 (f is 2 or 4); the first block row
// and column lie partly outside the image.
ivec2 vctRefineBlockOrigin(ivec2 block, int f) { return block * 4 - f / 2; }
// Order of the pixels k (x = k & 3, y = k >> 2) in which a block picks its traced pixels: the
// four centre pixels first (each can serve the pixels around it), then the rim.
uint vctRefineOrder(int s) { return (s < 8 ? 0x3210A965u >> (4 * s) : 0xFEDCB874u >> (4 * (s - 8))) & 15u; }

// Refine list entry: the traced pixel (x, y < 2^16), its index k in the block and the mask of
// the block's pixels its trace writes (bit k included).
uvec2 vctRefineEntry(ivec2 base, uint k, uint serves) {
    ivec2 px = base + ivec2(k & 3u, k >> 2);
    return uvec2(uint(px.x) | (uint(px.y) << 16), serves | (k << 16));
}
ivec2 vctRefinePixel(uvec2 entry) { return ivec2(entry.x & 0xffffu, entry.x >> 16); }
uint vctRefineIndex(uvec2 entry) { return entry.y >> 16; }
uint vctRefineServes(uvec2 entry) { return entry.y & 0xffffu; }
