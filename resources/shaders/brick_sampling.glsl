// Trilinear samples and central-difference gradients inside one leaf's brick, border included.
float brickSample(uint node, vec3 leafLo, vec3 p) {
    uvec4 nd = hvxNodes[node];
    uint depth = nd.y & 0xFFu;
    uint slot = nd.x;
    int e = int(brick.z);
    float scale = float(brick.x) * float(1u << depth);
    vec3 lo = floor(leafLo * float(1u << depth) + 0.5) * float(brick.x);
    vec3 u = clamp(p * scale - (lo - float(brick.y)) - 0.5, vec3(0.0), vec3(float(e - 1)));
    // Hardware trilinear filtering inside the slot: u stays within the brick's sample centres
    // (the border replicates neighbours), so the filter never reads another slot.
    ivec3 cell = ivec3(int(slot % brick.w), int((slot / brick.w) % (image.z / brick.w)), int(slot / image.z)) * e;
    vec2 decode = slotDecode[slot];  // normalised texel -> stored value (linear, so after filtering)
    return texture(brickPool, (vec3(cell) + u + 0.5) / vec3(textureSize(brickPool, 0))).r * decode.x + decode.y;
}

vec3 brickGradient(uint node, vec3 leafLo, vec3 p) {
    uint depth = hvxNodes[node].y & 0xFFu;
    float h = 1.0 / (float(brick.x) * float(1u << depth));
    return vec3(brickSample(node, leafLo, p + vec3(h, 0, 0)) - brickSample(node, leafLo, p - vec3(h, 0, 0)),
                brickSample(node, leafLo, p + vec3(0, h, 0)) - brickSample(node, leafLo, p - vec3(0, h, 0)),
                brickSample(node, leafLo, p + vec3(0, 0, h)) - brickSample(node, leafLo, p - vec3(0, 0, h))) / (2.0 * h);
}
