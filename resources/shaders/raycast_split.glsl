// Split-voxel octrees (thesis §4.5, Fig. 4.5; HVX_SPLIT): each leaf's brick holds cells of two
// values and the plane between them, walked by a 3D DDA. The GPU side of
// core/reference/SplitCellMarch.h, operation for operation (CpuRayCaster::castSplit is its
// reference): a uniform cell adds its value over its length, shaded by the face it was entered
// through where the material changed there (ambient + diffuse inside a material); a split cell
// adds its two materials on either side of the plane, in the order the ray meets them, shaded
// by the plane's normal. Each segment composites at opacity 1 − exp(−f.w·δt), f being the
// value's table entry (labels) or table sample (intensities). DVR only.
#ifndef HVX_SPLIT_SIGNED
#define HVX_SPLIT_SIGNED 0
#endif
// RGBA16UI, one texel per cell: front and back (the stored values' bits), then the plane's four
// signed bytes (normal x | y << 8, normal z | offset << 8), as core::SplitVoxel encodes them.
layout(binding = 2) uniform usampler3D splitPool;

struct SplitCell {
    float front, back;
    vec3 normal;   // unit, in cell coordinates; zero for a uniform cell
    float offset;  // the plane: dot(normal, x − centre) = offset
};

float splitStored(uint bits) {
#if HVX_SPLIT_SIGNED
    return float(bitfieldExtract(int(bits), 0, 16));
#else
    return float(bits);
#endif
}

// core::SplitVoxel::decode.
SplitCell splitCell(ivec3 texel) {
    uvec4 q = texelFetch(splitPool, texel, 0);
    SplitCell c;
    c.front = splitStored(q.x);
    c.back = splitStored(q.y);
    vec3 n = vec3(float(bitfieldExtract(int(q.z), 0, 8)), float(bitfieldExtract(int(q.z), 8, 8)),
                  float(bitfieldExtract(int(q.w), 0, 8)));
    bool uniformCell = n == vec3(0.0) || c.front == c.back;
    c.normal = uniformCell ? vec3(0.0) : normalize(n);
    c.offset = uniformCell ? 0.0 : float(bitfieldExtract(int(q.w), 8, 8)) / 127.0 * 0.8660254;
    if (uniformCell) c.back = c.front;
    return c;
}

// What a ray has gathered: colour and opacity, depth of its first contribution, and the last
// material it added (core::SplitCompositor and SplitMarchState); previousHidden: the last
// material was one the transfer function hides, stepped over without reading it.
struct SplitRay {
    vec4 accum;
    float depth;
    float previous;
    bool havePrevious;
    bool previousHidden;
    // The illustrative tools (HVX_TOOLS): the ray's origin (world), its focal cone, MImDA state
    // and the longest piece a segment is cut into (mm; a cell's length along the ray).
    vec3 ow;
    float hTheta;
    bool entered;
    float importanceMax;
    float piece;
};

#if HVX_TOOLS != 0
// core::SplitCompositor::addWithTools: the segment in pieces, each a sample of the enhancers
// (gradient: the boundary's unit normal at full strength, none inside a material) composited
// by MImDA.
bool splitAddTools(inout SplitRay r, vec4 f, float value, float ta, float tb, bool boundary, vec3 normalCell, vec3 view) {
    vec3 g = boundary ? normalize(transpose(mat3(patientToOctree)) * normalCell) : vec3(0.0);
    int pieces = max(1, int(ceil((tb - ta) / r.piece)));
    float len = (tb - ta) / float(pieces);
    float a = 1.0 - exp(-f.w * len);
    vec3 dir = -view;
    for (int i = 0; i < pieces; ++i) {
        float t = ta + (float(i) + 0.5) * len;
        HvxSample x;
        x.p = r.ow + t * dir;
        x.v = dir;
        x.g = g;
        x.gn = boundary ? 1.0 : 0.0;
        x.s = value;
        x.c = f.rgb / f.w;
        x.a = a;
        x.lit = 1.0;
        x.importance = 1.0 - exp(-f.w * extra.w);
        float focalNorm = HVX_TOOL_ON(HVX_FOCAL_BIT) ? hvxFocalNorm(tools, x.p) : 2.0;
        bool enteredNow = r.entered;
        hvxEnhance(x, tools, HVX_TOOLS, focalNorm, g, r.hTheta, enteredNow);
        if (enteredNow && !r.entered) {  // clip what lies in front of the focal probe
            r.accum = vec4(0.0);
            r.importanceMax = 0.0;
            r.entered = true;
        }
        hvxMimda(r.accum, r.importanceMax, toolColour(x) * x.a, x.a, x.importance, tools.bandAxis.w);
        if (isinf(r.depth) && r.accum.w > 0.02) r.depth = t;
        if (hvxMimdaFutureDelta(r.accum.w, r.importanceMax, tools.bandAxis.w) < 1.0 - tfRange.z) return false;
    }
    return true;
}
#endif

// core::SplitCompositor::add: `value` over [ta, tb] (world mm), at a boundary of normal
// `normalCell` (cell coordinates) or inside a material. False once the ray is opaque.
bool splitAdd(inout SplitRay r, float value, float ta, float tb, bool boundary, vec3 normalCell, vec3 view) {
    if (tb <= ta) return true;
#if HVX_LABELS
    vec4 f = tfF[min(int(tfPosition(value)), 4095)];
#else
    vec4 f = tfSample(value);
#endif
    if (f.w <= 0.0) return true;
#if HVX_TOOLS != 0
    return splitAddTools(r, f, value, ta, tb, boundary, normalCell, view);
#endif
    float a = 1.0 - exp(-f.w * (tb - ta));
    vec3 colour = f.rgb / f.w;
    if (extra.y > 0.5) {
        if (!boundary) {
            colour *= shading.x + shading.y;
        } else {
            float facing = abs(dot(normalize(transpose(mat3(patientToOctree)) * normalCell), view));
            colour = colour * (shading.x + shading.y * facing) + vec3(shading.z * pow(facing, shading.w));
        }
    }
    if (r.accum.w == 0.0) r.depth = ta;
    float w = (1.0 - r.accum.w) * a;
    r.accum += vec4(colour * w, w);
    return r.accum.w < tfRange.z;
}

// The DDA's next face crossings from `cell` on, for the ray o + t·d.
void splitDdaAxes(vec3 o, vec3 d, ivec3 cell, out ivec3 stepDir, out vec3 tNext, out vec3 tDelta) {
    for (int a = 0; a < 3; ++a) {
        stepDir[a] = d[a] > 0.0 ? 1 : -1;
        bool parallel = abs(d[a]) < 1e-30;
        tDelta[a] = parallel ? 1e30 : 1.0 / abs(d[a]);
        float face = d[a] > 0.0 ? float(cell[a]) + 1.0 : float(cell[a]);
        tNext[a] = parallel ? 1e30 : (face - o[a]) / d[a];
    }
}

// core::marchSplitCells over the brickSize³ cells of the slot whose first texel is `corner`,
// for the ray o + t·d in the leaf's cell coordinates, t from t0 to t1 (inside the leaf). The
// brick's 4×4×4 blocks the transfer function hides (`visible`, core::BrickCells::ofSplit) are
// crossed in one step: nothing in them adds to the ray, and the cell after them is entered
// from a hidden material, as the cell-by-cell march would have it.
bool splitMarchLeaf(vec3 o, vec3 d, float t0, float t1, ivec3 corner, uvec2 visible, inout SplitRay r, vec3 view) {
    if (t0 >= t1) return true;
    int dims = int(brick.x);
    int block = max(1, dims / 4);
    vec3 invD = vec3(abs(d.x) > 1e-30 ? 1.0 / d.x : 1e30, abs(d.y) > 1e-30 ? 1.0 / d.y : 1e30,
                     abs(d.z) > 1e-30 ? 1.0 / d.z : 1e30);
    ivec3 cell = clamp(ivec3(floor(o + d * t0)), ivec3(0), ivec3(dims - 1)), stepDir;
    vec3 tNext, tDelta;
    splitDdaAxes(o, d, cell, stepDir, tNext, tDelta);
    float tIn = t0;
    int crossed = -1;
    for (int guard = 0; guard < 4 * 1024 && tIn < t1; ++guard) {
        ivec3 b = min(cell / block, ivec3(3));
        int bit = b.x + 4 * b.y + 16 * b.z;
        if (((bit < 32 ? visible.x : visible.y) & (1u << uint(bit & 31))) == 0u) {
            // A hidden block: on to its far face, and into the cell beyond it.
            vec3 lo = vec3(b * block), hi = lo + float(block);
            vec3 far = max((lo - o) * invD, (hi - o) * invD);
            int a = far.x < far.y ? (far.x < far.z ? 0 : 2) : (far.y < far.z ? 1 : 2);
            r.havePrevious = true;
            r.previousHidden = true;
            crossed = a;
            tIn = max(tIn, far[a]);
            if (tIn >= t1) break;
            cell = clamp(ivec3(floor(o + d * tIn)), ivec3(0), ivec3(dims - 1));
            cell[a] = d[a] > 0.0 ? int(hi[a]) : int(lo[a]) - 1;  // never back into the block
            if (cell[a] < 0 || cell[a] >= dims) break;
            splitDdaAxes(o, d, cell, stepDir, tNext, tDelta);
            continue;
        }
        int a = tNext.x < tNext.y ? (tNext.x < tNext.z ? 0 : 2) : (tNext.y < tNext.z ? 1 : 2);
        float tOut = min(tNext[a], t1);
        SplitCell v = splitCell(corner + cell);
        bool go = true;
        if (v.normal == vec3(0.0)) {
            bool changed = r.havePrevious && (r.previousHidden || r.previous != v.front);
            vec3 face = vec3(0.0);
            if (crossed >= 0 && changed) face[crossed] = 1.0;
            go = splitAdd(r, v.front, tIn, tOut, crossed >= 0 && changed, face, view);
            r.previous = v.front;
        } else {
            float dn = dot(v.normal, d);
            float at = dot(v.normal, o - (vec3(cell) + 0.5));
            if (abs(dn) < 1e-30) {  // along the plane: the side the ray runs on
                float side = at >= v.offset ? v.front : v.back;
                go = splitAdd(r, side, tIn, tOut, true, v.normal, view);
                r.previous = side;
            } else {
                // The material met first is the front one when the ray runs against the normal.
                bool frontFirst = dn <= 0.0;
                float first = frontFirst ? v.front : v.back, second = frontFirst ? v.back : v.front;
                float tPlane = (v.offset - at) / dn;
                if (tPlane <= tIn) {
                    go = splitAdd(r, second, tIn, tOut, true, v.normal, view);
                    r.previous = second;
                } else if (tPlane >= tOut) {
                    go = splitAdd(r, first, tIn, tOut, true, v.normal, view);
                    r.previous = first;
                } else {
                    go = splitAdd(r, first, tIn, tPlane, true, v.normal, view) &&
                         splitAdd(r, second, tPlane, tOut, true, v.normal, view);
                    r.previous = second;
                }
            }
        }
        r.havePrevious = true;
        r.previousHidden = false;
        if (!go) return false;
        if (tOut >= t1) break;
        cell[a] += stepDir[a];
        if (cell[a] < 0 || cell[a] >= dims) break;
        tNext[a] += tDelta[a];
        crossed = a;
        tIn = tOut;
    }
    return true;
}

// The ray through the split-voxel octree: clipped to the volume (or its crop box), leaf by leaf
// through the index (shared traversal step) as castRay walks it, each leaf's cells by the DDA.
vec4 castRaySplit(vec3 ow, vec3 dw, out float depth) {
    depth = 1.0 / 0.0;
    vec3 o = (patientToOctree * vec4(ow, 1.0)).xyz;
    vec3 d = mat3(patientToOctree) * dw;
    float t0, t1;
    if (!clipToCrop(o, d, t0, t1)) return vec4(0.0);
    vec3 inv = rayInverse(d);
    float nudge = 1e-3 * extent.w / max(1e-12, length(d));
    uint n = 0u;
    vec3 lo = vec3(0.0), hi = vec3(1.0);
    hvxDescend(0u, n, lo, hi, o + (t0 + nudge) * d);
    SplitRay r;
    r.accum = vec4(0.0);
    r.depth = 1.0 / 0.0;
    r.previous = 0.0;
    r.havePrevious = false;
    r.previousHidden = false;
    r.ow = ow;
    r.entered = false;
    r.importanceMax = 0.0;
    r.piece = 1.0;
#if HVX_TOOLS != 0
    r.hTheta = HVX_TOOL_ON(HVX_FOCAL_BIT) ? hvxFocalAngle(tools, ow, dw) : 1.0;
#else
    r.hTheta = 1.0;
#endif
    vec3 view = -normalize(dw);
    float tIn = t0;
    for (int guard = 0; guard < 65536; ++guard) {
        float tExit = 0.0;
        int face = hvxExitFace(o, inv, lo, hi, tExit);
        float tOut = min(tExit, t1);
        if (tOut > tIn) {
            uvec4 nd = hvxNodes[n];
            if (nd.x == HVX_NONE) {  // nothing the transfer function shows
                r.havePrevious = false;
            } else {
                if (extra.z > 0.5) atomicAdd(rayCounts[n], 1u);  // visibility feedback
                uint level = nd.y & 0xFFu;
                float scale = float(brick.x) * float(1u << level);
                vec3 origin = floor(lo * float(1u << level) + 0.5) * float(brick.x);
                uint slot = nd.x;
                r.piece = tfRange.w / length(d * scale);  // a cell's length along the ray (mm)
                ivec3 corner = ivec3(uvec3(slot % brick.w, slot / brick.w % brick.w, slot / image.z) * brick.z);
                if (!splitMarchLeaf(o * scale - origin, d * scale, tIn, tOut, corner, slotRecords[slot].visible, r, view))
                    break;
            }
        }
        if (tExit >= t1) break;
        if (!hvxNextLeaf(0u, o, d, face, tExit, nudge, n, lo, hi)) break;
        tIn = max(tIn, tExit);
    }
    depth = r.depth;
    return r.accum;
}
