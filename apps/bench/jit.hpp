#pragma once
// vkgi-bench --jit: what lavapipe's first-dispatch shader compilation costs per pass. Issue #4
// asks that no shader's JIT exceed ~1 s (../shared/LAVAPIPE.md: the cost grows much faster than
// the shader); this measures it instead of assuming it.
#include "vkgi/context.hpp"
#include "sweep.hpp"

namespace vkgi::bench {

// For a fixed list of configurations that together run every pass of every technique, renders
// the first frame of a fresh GiSystem (shaders compiled at their first dispatch) and opt.repeat
// warm frames; a pass's JIT cost is its first-frame GPU ms minus its warm median. Writes
// jit.csv into opt.outDir and prints the passes sorted by JIT cost. The caller must disable
// Mesa's disk cache (MESA_SHADER_CACHE_DISABLE) before creating the device, or cached shaders
// read as free. Returns the process exit code.
int runJit(Context& ctx, const Options& opt);

} // namespace vkgi::bench
