// The spatial index as shader storage buffers, and the accessor macros that let
// core/streaming/IndexTraversal.glsl run unchanged on the GPU.
layout(std430, binding = 0) readonly buffer IndexNodes { uvec4 hvxNodes[]; };
layout(std430, binding = 1) readonly buffer IndexRopes { uint hvxRopes[]; };

#define HVX_INDEX_PARAM int hvxIndexUnused
#define HVX_INDEX_ARG 0
#define HVX_NODE(i) hvxNodes[(i)]
#define HVX_ROPE(i, f) hvxRopes[(i) * 6u + uint(f)]
#define HVX_INOUT(T) inout T
#define HVX_FN
