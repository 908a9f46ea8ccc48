// Trilinear samples and central-difference gradients inside one leaf's brick, border included.
float brickSample(uint node, vec3 leafLo, vec3 p) {
    uvec4 nd = hvxNodes[node];
    uint depth = nd.y & 0xFFu;
    uint slot = nd.x;
    int e = int(brick.z);
    float scale = float(brick.x) * float(1u << depth);
    vec3 lo = floor(leafLo * float(1u << depth) + 0.5) * float(brick.x);
    vec3 u = clamp(p * scale - (lo - float(brick.y)) - 0.5, vec3(0.0), vec3(float(e - 1)));
    ivec3 i0 = min(ivec3(u), ivec3(max(e - 2, 0)));
    vec3 f = u - vec3(i0);
    ivec3 cell = ivec3(int(slot % brick.w), int((slot / brick.w) % (image.z / brick.w)), int(slot / image.z)) * e;
    ivec3 i1 = min(i0 + ivec3(1), ivec3(e - 1));
    float c000 = texelFetch(brickPool, cell + ivec3(i0.x, i0.y, i0.z), 0).r;
    float c100 = texelFetch(brickPool, cell + ivec3(i1.x, i0.y, i0.z), 0).r;
    float c010 = texelFetch(brickPool, cell + ivec3(i0.x, i1.y, i0.z), 0).r;
    float c110 = texelFetch(brickPool, cell + ivec3(i1.x, i1.y, i0.z), 0).r;
    float c001 = texelFetch(brickPool, cell + ivec3(i0.x, i0.y, i1.z), 0).r;
    float c101 = texelFetch(brickPool, cell + ivec3(i1.x, i0.y, i1.z), 0).r;
    float c011 = texelFetch(brickPool, cell + ivec3(i0.x, i1.y, i1.z), 0).r;
    float c111 = texelFetch(brickPool, cell + ivec3(i1.x, i1.y, i1.z), 0).r;
    float c00 = c000 * (1.0 - f.x) + c100 * f.x;
    float c10 = c010 * (1.0 - f.x) + c110 * f.x;
    float c01 = c001 * (1.0 - f.x) + c101 * f.x;
    float c11 = c011 * (1.0 - f.x) + c111 * f.x;
    return (c00 * (1.0 - f.y) + c10 * f.y) * (1.0 - f.z) + (c01 * (1.0 - f.y) + c11 * f.y) * f.z;
}

vec3 brickGradient(uint node, vec3 leafLo, vec3 p) {
    uint depth = hvxNodes[node].y & 0xFFu;
    float h = 1.0 / (float(brick.x) * float(1u << depth));
    return vec3(brickSample(node, leafLo, p + vec3(h, 0, 0)) - brickSample(node, leafLo, p - vec3(h, 0, 0)),
                brickSample(node, leafLo, p + vec3(0, h, 0)) - brickSample(node, leafLo, p - vec3(0, h, 0)),
                brickSample(node, leafLo, p + vec3(0, 0, h)) - brickSample(node, leafLo, p - vec3(0, 0, h))) / (2.0 * h);
}
