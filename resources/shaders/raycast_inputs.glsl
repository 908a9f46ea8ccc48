// Inputs and outputs of the ray caster (bindings shared with render/GpuRayCaster.cpp).
layout(std140, binding = 0) uniform Frame {
    mat4 patientToOctree;
    vec4 extent;     // xyz: the volume's box in octree space; w: 1 / rootVoxels
    vec4 tfRange;    // valueMin, valueMax, early termination, step scale
    vec4 shading;    // ambient, diffuse, specular, shininess
    vec4 extra;      // iso value, shading on, count rays (1/0), TF reference length (mm)
    vec4 enhance;    // boundary enhancement, view-dependent transparency, strength per gradient, gradient opacity's largest |∇f|
    uvec4 brick;     // brick size, border, edge, slots per row
    uvec4 image;     // width, height, slots per layer, views in the batch
    vec4 cropLo;     // xyz: the crop box in octree space (the whole volume: 0 and extent)
    vec4 cropHi;
    // A second volume fused over the first (HVX_FUSION; raycast_fusion.glsl):
    mat4 patientToOctreeB;
    vec4 extentB;    // xyz: its box in its octree space; w: 1 / its rootVoxels
    vec4 tfRangeB;   // its transfer function's valueMin, valueMax (table entries 4096 on), its gradient opacity's largest |∇f| (0: none)
    uvec4 brickB;    // its brick size, border, edge, slots per row of its pool
    uvec4 fusionB;   // its pool's slots per layer, its first slot record, its first index node
    uvec4 pixels;    // the pixels drawn: x, y phase and stride (core::RenderSettings::subFrame; 0, 0, 1: all)
    vec4 detail;     // normal unsharp masking k, exaggerated shading (HVX_DETAIL), -, -
};
// One camera per view of the batch (dispatch layer z = view index).
struct ViewCamera {
    vec4 eye;              // xyz; w: 1 pinhole, 0 orthographic, 2 screen (MCOP, thesis Eq. 5.1)
    vec4 forward;          // xyz; w: tan(fovY/2) or half the ortho height
    vec4 right;            // xyz; w: aspect
    vec4 up;
    vec4 screenCentre;     // screen model: xyz centre (patient); w: eta
    vec4 screenRight;      // xyz unit; w: width mm
    vec4 screenUp;         // xyz unit; w: height mm
    vec4 screenViewer;     // xyz: V in display coordinates
    vec4 screenProjector;  // xyz: E in display coordinates
};
layout(std430, binding = 8) readonly buffer Views { ViewCamera views[]; };
layout(std430, binding = 2) readonly buffer TfTable { vec4 tfF[]; };      // 4096 entries
layout(std430, binding = 3) readonly buffer TfIntegral { vec4 tfI[]; };   // 4097 entries
layout(std430, binding = 9) readonly buffer TfOpacity { vec2 tfA[]; };    // 4097 entries: (tfI.w, tfF.w)
layout(std430, binding = 4) writeonly buffer OutColor { vec4 outColor[]; };
layout(std430, binding = 5) writeonly buffer OutDepth { float outDepth[]; };
layout(binding = 0) uniform sampler3D brickPool;  // R8/R16/R32F, slot s at cell (s % row, s / row % rows, s / layer)
layout(binding = 1) uniform sampler3D brickPoolB;  // the fused volume's pool (HVX_FUSION)
struct SlotRecord {  // per pool slot (render::GpuRayCaster's SlotRecord)
    vec2 decode;     // stored value = texel * x + y
    uvec2 visible;   // the brick's 4x4x4 cells that may show (core::BrickCells), cell x + 4y + 16z
};
layout(std430, binding = 7) readonly buffer Slots { SlotRecord slotRecords[]; };
layout(std430, binding = 6) buffer RayCounts { uint rayCounts[]; };  // per index node (feedback)
#ifndef HVX_MULTILEVEL
#define HVX_MULTILEVEL 0
#endif
#ifndef HVX_DETAIL_PARENT
#define HVX_DETAIL_PARENT 0
#endif
#if HVX_MULTILEVEL || HVX_DETAIL_PARENT
// core::SpatialIndex::LevelLink, per index node: the slots of the parent (0), grandparent (1)
// and on, as far as the level field reaches; whether the leaf blends, and how many levels
// coarser than the leaf the field is at its corners.
#define HVX_LEVEL_SPAN 6u
struct HvxLevelLink {
    uint ancestors[HVX_LEVEL_SPAN];
    uint blends;
    uint clamped;
    float coarser[8];
};
layout(std430, binding = 12) readonly buffer IndexLevels { HvxLevelLink hvxLevels[]; };
#endif
#ifndef HVX_DETAIL
#define HVX_DETAIL 0
#endif
#ifndef HVX_GRADIENT_OPACITY
#define HVX_GRADIENT_OPACITY 0
#endif
#if HVX_GRADIENT_OPACITY
// Gradient opacity (core::TransferFunction::gradientTable): g(|∇f|) at 256 magnitudes over
// [0, largest]; a sample's opacity becomes 1 − (1 − a)^g. The table at `first` (a fused volume's
// follows the base's); a largest |∇f| of 0: that volume has no curve.
layout(std430, binding = 10) readonly buffer GradientTable { float gradientTable[]; };
float gradientOpacityOf(int first, float largest, float a, float len) {
    if (largest <= 0.0) return a;
    float p = clamp(len / largest * 255.0, 0.0, 255.0);
    int i = min(int(p), 254);
    float f = p - float(i);
    float g = gradientTable[first + i] * (1.0 - f) + gradientTable[first + i + 1] * f;
    float keep = 1.0 - a;
    return g <= 0.0 ? 0.0 : (keep <= 0.0 ? 1.0 : 1.0 - pow(keep, g));
}
float gradientOpacity(float a, float len) { return gradientOpacityOf(0, enhance.w, a, len); }
#endif
#ifndef HVX_TOOLS
#define HVX_TOOLS 0
#endif
#define HVX_FN
#define HVX_INOUT(T) inout T
#define HVX_TOOL_ON(bit) ((HVX_TOOLS & (bit)) != 0)
#include "Enhancers.glsl"
layout(std140, binding = 1) uniform Tools { HvxTools tools; };  // core::packTools
