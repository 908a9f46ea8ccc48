// The spatial index as shader storage buffers, and the accessor macros that let
// core/streaming/IndexTraversal.glsl run unchanged on the GPU. A second volume's index (fusion)
// follows the first in the same buffers: a traversal passes the position of the volume's first
// node as the index argument (0 for the first volume), and node numbers stay the volume's own.
// Inside the traversal, HVX_INDEX_ARG passes the function's own index on.
layout(std430, binding = 0) readonly buffer IndexNodes { uvec4 hvxNodes[]; };
layout(std430, binding = 1) readonly buffer IndexRopes { uint hvxRopes[]; };

#define HVX_INDEX_PARAM uint hvxBase
#define HVX_INDEX_ARG hvxBase
#define HVX_NODE(i) hvxNodes[hvxBase + (i)]
#define HVX_ROPE(i, f) hvxRopes[(hvxBase + (i)) * 6u + uint(f)]
#define HVX_INOUT(T) inout T
#define HVX_FN
