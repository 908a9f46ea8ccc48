// Walks rays through the spatial index with the shared traversal step and records the leaves
// each ray visits, so tests can compare the GPU walk with the CPU reference's.
#version 450
layout(local_size_x = 64) in;

#include "index_buffers.glsl"
#include "IndexTraversal.glsl"

struct ProbeRay {
    vec4 origin;     // octree space; w = tEnter
    vec4 direction;  // octree space; w = tLeave
};
layout(std430, binding = 2) readonly buffer Rays { ProbeRay rays[]; };
layout(std430, binding = 3) writeonly buffer Visits { uint visits[]; };  // MAX_VISITS per ray, HVX_NONE-terminated
uniform uint rayCount;
uniform float nudge;

void main() {
    uint r = gl_GlobalInvocationID.x;
    if (r >= rayCount) return;
    vec3 o = rays[r].origin.xyz;
    vec3 d = rays[r].direction.xyz;
    float t0 = rays[r].origin.w, t1 = rays[r].direction.w;
    vec3 inv = vec3(abs(d.x) > 1e-20 ? 1.0 / d.x : (d.x >= 0.0 ? 1e30 : -1e30),
                    abs(d.y) > 1e-20 ? 1.0 / d.y : (d.y >= 0.0 ? 1e30 : -1e30),
                    abs(d.z) > 1e-20 ? 1.0 / d.z : (d.z >= 0.0 ? 1e30 : -1e30));
    uint n = 0u;
    vec3 lo = vec3(0.0), hi = vec3(1.0);
    hvxDescend(0u, n, lo, hi, o + (t0 + nudge) * d);
    float tIn = t0;
    uint count = 0u;
    for (int guard = 0; guard < 4096 && count + 1u < MAX_VISITS; ++guard) {
        float tExit = 0.0;
        int face = hvxExitFace(o, inv, lo, hi, tExit);
        float tOut = min(tExit, t1);
        if (tOut > tIn) visits[r * MAX_VISITS + count++] = n;
        if (tExit >= t1) break;
        if (!hvxNextLeaf(0u, o, d, face, tExit, nudge, n, lo, hi)) break;
        tIn = max(tIn, tExit);
    }
    visits[r * MAX_VISITS + count] = HVX_NONE;
}
