// Single-pass ray casting over the spatial index, one invocation per pixel (thesis ch. 2–3).
// It mirrors core/reference/CpuRayCaster.cpp step for step; MODE selects a static variant
// (0 DVR, 1 isosurface, 2 MIP, 3 MinIP, 4 average); HVX_FUSION 1 marches a second volume with
// the first (DVR only); HVX_SPLIT 1 walks a split-voxel octree's cells (DVR only); HVX_REFRACT 1
// bends the rays by Snell's law (DVR only).
layout(local_size_x = 8, local_size_y = 8) in;

#include "index_buffers.glsl"
#include "IndexTraversal.glsl"
#include "raycast_inputs.glsl"
#include "transfer_function.glsl"
#include "brick_sampling.glsl"
#include "raycast_march.glsl"
#ifndef HVX_FUSION
#define HVX_FUSION 0
#endif
#if HVX_FUSION
#include "raycast_fusion.glsl"
#endif
#ifndef HVX_SPLIT
#define HVX_SPLIT 0
#endif
#if HVX_SPLIT
#include "raycast_split.glsl"
#endif
#ifndef HVX_REFRACT
#define HVX_REFRACT 0
#endif
#if HVX_REFRACT
#include "raycast_refract.glsl"
#endif

void main() {
    ivec2 px = ivec2(gl_GlobalInvocationID.xy) * int(pixels.z) + ivec2(pixels.xy);
    uint view = gl_GlobalInvocationID.z;
    if (px.x >= int(image.x) || px.y >= int(image.y) || view >= image.w) return;
    ViewCamera cam = views[view];
    vec4 eye = cam.eye, forward = cam.forward, right = cam.right, up = cam.up;
    vec4 screenCentre = cam.screenCentre, screenRight = cam.screenRight, screenUp = cam.screenUp;
    vec4 screenViewer = cam.screenViewer, screenProjector = cam.screenProjector;
    float nx = (float(px.x) + 0.5) / float(image.x) * 2.0 - 1.0;
    float ny = 1.0 - (float(px.y) + 0.5) / float(image.y) * 2.0;
    vec3 ow, dw;
    if (eye.w > 1.5) {  // screen: rays through the screen point, origins by Eq. 5.1 (core::View::ray)
        vec3 S = vec3((float(px.x) + 0.5) / float(image.x) - 0.5, 0.5 - (float(px.y) + 0.5) / float(image.y), 0.0) *
                 vec3(screenRight.w, screenUp.w, 0.0);
        vec3 E = screenProjector.xyz, V = screenViewer.xyz;
        float parallax = E.x + (S.x - E.x) / (S.z - E.z) * (V.z - E.z);
        vec3 O = vec3((1.0 - screenCentre.w) * V.x + screenCentre.w * parallax, V.y, V.z);
        vec3 n = normalize(cross(screenRight.xyz, screenUp.xyz));
        mat3 axes = mat3(screenRight.xyz, screenUp.xyz, n);
        ow = screenCentre.xyz + axes * O;
        dw = normalize(axes * (S - O));
    } else if (eye.w > 0.5) {  // pinhole
        ow = eye.xyz;
        dw = normalize(forward.xyz + right.xyz * (nx * forward.w * right.w) + up.xyz * (ny * forward.w));
    } else {            // orthographic
        ow = eye.xyz + right.xyz * (nx * forward.w * right.w) + up.xyz * (ny * forward.w);
        dw = forward.xyz;
    }
    float depth;
#if HVX_SPLIT
    vec4 c = castRaySplit(ow, dw, depth);
#elif HVX_REFRACT
    vec4 c = castRayRefract(ow, dw, depth);
#elif HVX_FUSION
    vec4 c = castRayFused(ow, dw, depth);
#else
    vec4 c = castRay(ow, dw, depth);
#endif
    uint i = (view * image.y + uint(px.y)) * image.x + uint(px.x);
    outColor[i] = c;
    outDepth[i] = depth;
}
