// Set-1 bindings of the engine's own test, smoke and bench shaders (shaders/engine), shared by
// those shaders and the tests and tools that dispatch them. Defines only: no types.
#ifndef VKGI_ENGINE_TEST_BINDINGS_H
#define VKGI_ENGINE_TEST_BINDINGS_H

// smoke.comp: the compute-path smoke test.
#define ENGINE_SMOKE_BINDING_VALUES 0 // one uint per texel: index * kScale + offset (writeonly)
#define ENGINE_SMOKE_BINDING_IMAGE 1  // R32UI image: x * 1000 + y (writeonly)
// frame_smoke.comp: FrameConstants seen by a shader.
#define ENGINE_FRAME_SMOKE_BINDING_VALUES 0 // copied FrameConstants fields, one vec4 each (writeonly)
// stream_copy.comp: vkgi-bench's memory-bound streaming probe.
#define ENGINE_STREAM_COPY_BINDING_SOURCE 0 // uvec4 elements read
#define ENGINE_STREAM_COPY_BINDING_TARGET 1 // uvec4 elements written
// test/fill.comp, test/mip_sum.comp, test/reduce.comp: the render-graph test's sum pyramid.
#define ENGINE_FILL_BINDING_TARGET 0    // R32UI mip 0, filled with x + width * y
#define ENGINE_MIP_SUM_BINDING_SOURCE 0 // R32UI mip k - 1
#define ENGINE_MIP_SUM_BINDING_TARGET 1 // R32UI mip k: 2x2 sums of the source
#define ENGINE_REDUCE_BINDING_LEVEL 0   // R32UI n x n mip copied out
#define ENGINE_REDUCE_BINDING_TOP 1     // R32UI 1x1 mip copied out after it
#define ENGINE_REDUCE_BINDING_VALUES 2  // uint buffer of n * n + 1 values
// test/tiny.comp: the smallest useful dispatch (graph overhead benchmarks).
#define ENGINE_TINY_BINDING_COUNTER 0 // uint counter, incremented (read and written)

#endif
