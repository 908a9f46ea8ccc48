// Trilinear samples and central-difference gradients inside one leaf's brick, border included.
// Everything constant over a leaf (its slot, level and texture placement) is computed once when
// the ray enters it; a sample is then one filtered fetch and a multiply-add.
struct LeafSampler {
    vec3 scale;      // octree coordinates -> brick sample coordinates (u), per axis
    vec3 offset;     // u = p * scale - offset
    vec3 cellTex;    // texture coordinate of the slot's first sample centre
    vec3 texelSize;  // 1 / pool size
    vec2 decode;     // normalised texel -> stored value
    float uMax;      // last sample centre inside the brick
    float h;         // one voxel of this level, in octree units (gradients)
};

LeafSampler leafSampler(uint node, vec3 leafLo) {
    uvec4 nd = hvxNodes[node];
    uint depth = nd.y & 0xFFu;
    uint slot = nd.x;
    int e = int(brick.z);
    LeafSampler L;
    float s = float(brick.x) * float(1u << depth);
    vec3 lo = floor(leafLo * float(1u << depth) + 0.5) * float(brick.x);
    L.scale = vec3(s);
    L.offset = lo - float(brick.y) + 0.5;
    ivec3 cell = ivec3(int(slot % brick.w), int((slot / brick.w) % (image.z / brick.w)), int(slot / image.z)) * e;
    L.texelSize = 1.0 / vec3(textureSize(brickPool, 0));
    L.cellTex = (vec3(cell) + 0.5) * L.texelSize;
    L.decode = slotDecode[slot];
    L.uMax = float(e - 1);
    L.h = 1.0 / s;
    return L;
}

// Hardware trilinear filtering inside the slot: u stays within the brick's sample centres (the
// border replicates neighbours), so the filter never reads another slot. The decode is linear,
// so it applies after filtering.
float leafSample(LeafSampler L, vec3 p) {
    vec3 u = clamp(p * L.scale - L.offset, vec3(0.0), vec3(L.uMax));
    return texture(brickPool, L.cellTex + u * L.texelSize).r * L.decode.x + L.decode.y;
}

// Central differences `spread` voxels apart (2: the smoothed normal of relief shading).
vec3 leafGradientSpread(LeafSampler L, vec3 p, float spread) {
    float h = L.h * spread;
    return vec3(leafSample(L, p + vec3(h, 0, 0)) - leafSample(L, p - vec3(h, 0, 0)),
                leafSample(L, p + vec3(0, h, 0)) - leafSample(L, p - vec3(0, h, 0)),
                leafSample(L, p + vec3(0, 0, h)) - leafSample(L, p - vec3(0, 0, h))) / (2.0 * h);
}

vec3 leafGradient(LeafSampler L, vec3 p) { return leafGradientSpread(L, p, 1.0); }
