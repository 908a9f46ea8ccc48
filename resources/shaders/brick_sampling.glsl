// Trilinear samples and central-difference gradients inside one leaf's brick, border included.
// Everything constant over a leaf (its slot, level and texture placement) is computed once when
// the ray enters it; a sample is then one filtered fetch and a multiply-add.
struct LeafSampler {
    vec3 scale;     // octree coordinates -> pool texture coordinates: tex = p * scale + offset
    vec3 offset;
    vec3 texLo;     // the brick's first and last sample centres in the pool: the filter never
    vec3 texHi;     // reads past them, so never into another slot
    vec2 decode;    // normalised texel -> stored value
    float h;        // one voxel of this level, in octree units (gradients)
    uvec2 visible;  // which of the brick's 4x4x4 cells may show (core::BrickCells), cell x + 4y + 16z
    vec3 leafLo;    // the leaf's corner and cell size, in octree units
    float cell;
#if HVX_MULTILEVEL || HVX_DETAIL_PARENT
    // The parent's placement in the pool and its decode: for multilevel sampling
    // (core::RenderSettings::multilevel) where the level field is coarser than the leaf,
    // and for the detail shading's coarser gradient (HVX_DETAIL_PARENT) wherever it is resident.
    vec3 pScale;
    vec3 pOffset;
    vec3 pTexLo;
    vec3 pTexHi;
    vec2 pDecode;
    bool hasParent;
#endif
#if HVX_MULTILEVEL
    bool blends;    // core::SpatialIndex::LevelLink: the level field is coarser than the leaf somewhere,
    vec4 coarserLo; // by this many levels at corners 0-3 and 4-7
    vec4 coarserHi;
    float highest;  // the largest of them: the field's bound (the weights may sum to a rounding above 1)
    float size;
#if HVX_MULTILEVEL >= 3
    uint node;      // the leaf's index node and depth: further ancestors' placements on demand
    uint depth;
#endif
#if HVX_MULTILEVEL >= 2
    // The grandparent's placement, where the field reaches past the parent.
    vec3 gScale;
    vec3 gOffset;
    vec3 gTexLo;
    vec3 gTexHi;
    vec2 gDecode;
#endif
#endif
};

// Whether the cell of the leaf containing p may show; if not, sets cellExit to the ray
// parameter where the ray o + t·d leaves that cell (invD = 1 / d).
bool cellVisible(LeafSampler L, vec3 p, vec3 o, vec3 invD, out float cellExit) {
    ivec3 c = clamp(ivec3(floor((p - L.leafLo) / L.cell)), ivec3(0), ivec3(3));
    int bit = c.x + 4 * c.y + 16 * c.z;
    uint word = bit < 32 ? L.visible.x : L.visible.y;
    cellExit = 0.0;
    if ((word & (1u << uint(bit & 31))) != 0u) return true;
    vec3 lo = L.leafLo + vec3(c) * L.cell;
    vec3 far = max((lo - o) * invD, (lo + L.cell - o) * invD);
    cellExit = min(min(far.x, far.y), far.z);
    return false;
}

// Where a slot's brick lies in the pool: the map from octree coordinates to texture coordinates
// (tex = p * scale + offset) and the first and last sample centres, for a brick of `depth` whose
// corner is `grid` bricks from the origin. The slot's cell in the pool is found with float
// arithmetic (exact below 2^23 slots): integer division is not a vector instruction on CPUs,
// and this runs once per leaf.
void slotPlacement(uint slotId, uint depth, vec3 grid, out vec3 scale, out vec3 offset, out vec3 texLo, out vec3 texHi) {
    float slot = float(slotId), row = float(brick.w), layer = float(image.z);
    float z = floor((slot + 0.5) / layer);
    float inLayer = slot - z * layer;
    float y = floor((inLayer + 0.5) / row);
    vec3 cell = vec3(inLayer - y * row, y, z) * float(brick.z);
    vec3 texel = 1.0 / vec3(textureSize(brickPool, 0));
    float s = float(brick.x) * float(1u << depth);
    vec3 lo = grid * float(brick.x);
    // u = p * s - (lo - border + 0.5) is the brick sample coordinate; tex = (cell + 0.5 + u) * texel.
    scale = vec3(s) * texel;
    offset = (cell + float(brick.y) - lo) * texel;
    texLo = (cell + 0.5) * texel;
    texHi = (cell + float(brick.z) - 0.5) * texel;
}

// The sampler of leaf `node` (record nd, box corner leafLo).
LeafSampler leafSampler(uint node, uvec4 nd, vec3 leafLo) {
    uint depth = nd.y & 0xFFu;
    LeafSampler L;
    slotPlacement(nd.x, depth, floor(leafLo * float(1u << depth) + 0.5), L.scale, L.offset, L.texLo, L.texHi);
    float s = float(brick.x) * float(1u << depth);
    SlotRecord record = slotRecords[nd.x];
    L.decode = record.decode;
    L.h = 1.0 / s;
    L.visible = record.visible;
    L.leafLo = leafLo;
    L.cell = 0.25 / float(1u << depth);
#if HVX_MULTILEVEL || HVX_DETAIL_PARENT
    HvxLevelLink lv = hvxLevels[node];
    L.hasParent = false;
#if HVX_MULTILEVEL
    L.blends = false;
#endif
    if (depth > 0u && lv.ancestors[0] != HVX_NONE && (HVX_DETAIL_PARENT != 0 || lv.blends != 0u)) {
        // the ancestors' corners: the leaf's, rounded down to their grids (exact in float)
        slotPlacement(lv.ancestors[0], depth - 1u, floor(leafLo * float(1u << (depth - 1u)) + 0.25), L.pScale, L.pOffset,
                      L.pTexLo, L.pTexHi);
        L.pDecode = slotRecords[lv.ancestors[0]].decode;
        L.hasParent = true;
#if HVX_MULTILEVEL
        if (lv.blends != 0u) {
            L.blends = true;
            L.coarserLo = vec4(lv.coarser[0], lv.coarser[1], lv.coarser[2], lv.coarser[3]);
            L.coarserHi = vec4(lv.coarser[4], lv.coarser[5], lv.coarser[6], lv.coarser[7]);
            vec4 corner = max(L.coarserLo, L.coarserHi);
            L.highest = max(max(corner.x, corner.y), max(corner.z, corner.w));
            L.size = 1.0 / float(1u << depth);
            L.visible = uvec2(0xFFFFFFFFu);  // the ancestors' values are not bounded by the leaf's cells
#if HVX_MULTILEVEL >= 3
            L.node = node;
            L.depth = depth;
#endif
#if HVX_MULTILEVEL >= 2
            if (lv.ancestors[1] != HVX_NONE) {
                slotPlacement(lv.ancestors[1], depth - 2u, floor(leafLo * float(1u << (depth - 2u)) + 0.125), L.gScale, L.gOffset,
                              L.gTexLo, L.gTexHi);
                L.gDecode = slotRecords[lv.ancestors[1]].decode;
            }
#endif
        }
#endif
    }
#endif
    return L;
}

#if HVX_MULTILEVEL
// How many levels coarser than the leaf the level field is at p: the corners' values,
// interpolated trilinearly, at most the largest of them (core::CpuRayCaster::levelOffset): the
// eight weights may sum to a rounding above 1, which would reach past the ancestors linked.
float levelOffset(LeafSampler L, vec3 p) {
    vec3 u = clamp((p - L.leafLo) / L.size, vec3(0.0), vec3(1.0));
    float f = 0.0;
    for (uint c = 0u; c < 8u; ++c)
        f += (c < 4u ? L.coarserLo[c] : L.coarserHi[c - 4u]) *
             (((c & 1u) != 0u ? u.x : 1.0 - u.x) * ((c & 2u) != 0u ? u.y : 1.0 - u.y) * ((c & 4u) != 0u ? u.z : 1.0 - u.z));
    return min(f, L.highest);
}

#endif

#if HVX_MULTILEVEL >= 2
// Trilinear in the grandparent's brick (where the field reaches past the parent).
float grandparentSampleLinear(LeafSampler L, vec3 p) {
    return texture(brickPool, clamp(p * L.gScale + L.gOffset, L.gTexLo, L.gTexHi)).r * L.gDecode.x + L.gDecode.y;
}
#endif

#if HVX_MULTILEVEL || HVX_DETAIL_PARENT
// Trilinear in the parent's brick (L.hasParent).
float parentSampleLinear(LeafSampler L, vec3 p) {
    return texture(brickPool, clamp(p * L.pScale + L.pOffset, L.pTexLo, L.pTexHi)).r * L.pDecode.x + L.pDecode.y;
}
#endif

#if HVX_MULTILEVEL >= 3
// Trilinear in the brick of the leaf's ancestor k >= 3 levels up, one the level field reaches (a
// leaf beside one three or more levels coarser, rare): its placement worked out here.
float farAncestorSampleLinear(LeafSampler L, uint k, vec3 p) {
    uint slot = hvxLevels[L.node].ancestors[k - 1u];
    vec3 scale, offset, texLo, texHi;
    slotPlacement(slot, L.depth - k, floor(L.leafLo * float(1u << (L.depth - k)) + 0.5 / float(1u << k)), scale, offset, texLo,
                  texHi);
    vec2 decode = slotRecords[slot].decode;
    return texture(brickPool, clamp(p * scale + offset, texLo, texHi)).r * decode.x + decode.y;
}
#endif

// Hardware trilinear filtering inside the slot (the border replicates the neighbours). The
// decode is linear, so it applies after filtering.
float leafSampleLinear(LeafSampler L, vec3 p) {
    float own = texture(brickPool, clamp(p * L.scale + L.offset, L.texLo, L.texHi)).r * L.decode.x + L.decode.y;
#if HVX_MULTILEVEL
    if (L.blends) {  // quadrilinear: trilinear at the two levels around the field's, blended
        // The variant knows how far the cut's field reaches (SpatialIndex::levelReach; within the
        // resident ancestors): SIMD drivers run a branch's code for every lane, so the common
        // cases do not carry the far ancestors' code.
        float f = levelOffset(L, p);
        float parent = parentSampleLinear(L, p);
#if HVX_MULTILEVEL == 1
        own = own * (1.0 - f) + parent * f;
#elif HVX_MULTILEVEL == 2
        if (f <= 1.0) own = own * (1.0 - f) + parent * f;
        else own = parent * (2.0 - f) + grandparentSampleLinear(L, p) * (f - 1.0);
#else
        if (f <= 1.0) {
            own = own * (1.0 - f) + parent * f;
        } else if (f <= 2.0) {
            own = parent * (2.0 - f) + grandparentSampleLinear(L, p) * (f - 1.0);
        } else {  // between the ancestors k and k + 1 levels up
            float k = ceil(f) - 1.0;
            float lower = k == 2.0 ? grandparentSampleLinear(L, p) : farAncestorSampleLinear(L, uint(k), p);
            own = lower * (k + 1.0 - f) + farAncestorSampleLinear(L, uint(k) + 1u, p) * (f - k);
        }
#endif
    }
#endif
    return own;
}

// A label map (HVX_LABELS) reads the nearest sample, as nearest-neighbour reconstruction does
// (HVX_NEAREST): the filtered fetch at a texel's centre returns that texel alone, so no label
// is ever blended with its neighbour.
#ifndef HVX_NEAREST
#define HVX_NEAREST 0
#endif
float leafSample(LeafSampler L, vec3 p) {
#if HVX_LABELS || HVX_NEAREST
    vec3 size = vec3(textureSize(brickPool, 0));
    vec3 centre = (floor((p * L.scale + L.offset) * size) + 0.5) / size;
    return texture(brickPool, clamp(centre, L.texLo, L.texHi)).r * L.decode.x + L.decode.y;
#else
    return leafSampleLinear(L, p);
#endif
}

// A sample of one of the leaf's levels: its own (blended where multilevel), or its parent's.
float levelSample(LeafSampler L, vec3 p, bool parent) {
#if HVX_MULTILEVEL || HVX_DETAIL_PARENT
    if (parent) return parentSampleLinear(L, p);
#endif
    return leafSampleLinear(L, p);
}

// Central differences of a level, `h` apart (octree units).
vec3 centralDifference(LeafSampler L, vec3 p, float h, bool parent) {
    return vec3(levelSample(L, p + vec3(h, 0, 0), parent) - levelSample(L, p - vec3(h, 0, 0), parent),
                levelSample(L, p + vec3(0, h, 0), parent) - levelSample(L, p - vec3(0, h, 0), parent),
                levelSample(L, p + vec3(0, 0, h), parent) - levelSample(L, p - vec3(0, 0, h), parent)) /
           (2.0 * h);
}

// Central differences `spread` voxels apart (2: the smoothed normal of relief shading).
vec3 leafGradientSpread(LeafSampler L, vec3 p, float spread) { return centralDifference(L, p, L.h * spread, false); }

vec3 leafGradient(LeafSampler L, vec3 p) { return leafGradientSpread(L, p, 1.0); }

// The coarser scale of the detail shading (core::CpuRayCaster::coarserGradient): the parent
// level's gradient, central differences one parent voxel apart (HVX_DETAIL_PARENT, where the
// parent is resident); otherwise the leaf's own at twice its spacing.
vec3 leafCoarserGradient(LeafSampler L, vec3 p) {
#if HVX_DETAIL_PARENT
    if (L.hasParent) return centralDifference(L, p, 2.0 * L.h, true);
#endif
    return leafGradientSpread(L, p, 2.0);
}
