// The spatial index layout and the stackless traversal step, written once in the subset of
// GLSL that C++ also compiles (through GLM and the macros of core/streaming/SpatialIndexTraversal.h).
// Octree space: the root node is the unit cube; a node of depth d spans 1/2^d.
//
// Node record (uvec4): x = first of 8 children (inner) or brick slot / HVX_NONE (leaf);
//                      y = depth | HVX_LEAF_BIT; z = .hvo node id (HVX_NONE outside the volume);
//                      w = parent index.
// Ropes: 6 per node, order -x, +x, -y, +y, -z, +z: the adjacent node of equal or coarser
// depth, HVX_NONE at the domain boundary.
//
// The includer defines HVX_NODE(i), HVX_ROPE(i, f), HVX_INDEX_PARAM, HVX_INDEX_ARG and
// HVX_INOUT(T); HVX_FN prefixes every function (inline in C++, empty in GLSL).

#define HVX_NONE 0xFFFFFFFFu
#define HVX_LEAF_BIT 0x100u

HVX_FN bool hvxIsLeaf(uint depthFlags) { return (depthFlags & HVX_LEAF_BIT) != 0u; }
HVX_FN uint hvxDepth(uint depthFlags) { return depthFlags & 0xFFu; }

// From node n with box [lo, hi] containing p, descend to the leaf containing p.
HVX_FN void hvxDescend(HVX_INDEX_PARAM, HVX_INOUT(uint) n, HVX_INOUT(vec3) lo, HVX_INOUT(vec3) hi, vec3 p) {
    for (int guard = 0; guard < 24; ++guard) {
        uvec4 nd = HVX_NODE(n);
        if (hvxIsLeaf(nd.y)) return;
        vec3 mid = 0.5f * (lo + hi);
        vec3 s = step(mid, p);
        n = nd.x + uint(s.x) + 2u * uint(s.y) + 4u * uint(s.z);
        lo = mix(lo, mid, s);
        hi = mix(mid, hi, s);
    }
}

// The box of the depth-d node containing p.
HVX_FN void hvxSnapBox(uint depth, vec3 p, HVX_INOUT(vec3) lo, HVX_INOUT(vec3) hi) {
    float size = 1.0f / float(1u << depth);
    lo = floor(p / size) * size;
    hi = lo + vec3(size);
}

// Where the ray o + t*dir leaves the box: returns the face (0..5) and sets tExit.
HVX_FN int hvxExitFace(vec3 o, vec3 invDir, vec3 lo, vec3 hi, HVX_INOUT(float) tExit) {
    vec3 t1 = (lo - o) * invDir;
    vec3 t2 = (hi - o) * invDir;
    vec3 tFar = max(t1, t2);
    int axis = 0;
    tExit = tFar.x;
    if (tFar.y < tExit) { tExit = tFar.y; axis = 1; }
    if (tFar.z < tExit) { tExit = tFar.z; axis = 2; }
    float d = axis == 0 ? (t2.x > t1.x ? 1.0f : -1.0f) : axis == 1 ? (t2.y > t1.y ? 1.0f : -1.0f) : (t2.z > t1.z ? 1.0f : -1.0f);
    return 2 * axis + (d > 0.0f ? 1 : 0);
}

// One traversal step: leave leaf n through its exit face at tExit, follow the rope, snap the
// box to the neighbour's depth and descend to the leaf that contains the next point.
// Returns false when the ray leaves the octree.
// A ray that leaves through an edge or a corner (several faces at once, as rays along the edge
// where four bricks meet do) enters a diagonal neighbour, not the rope's node: the rope's box
// is taken where the ray crosses the exit face only, and when the next point is not in it the
// leaf is found from the root. (Taking the rope's node with the diagonal box sampled a brick
// far outside its own extent: thin bright lines in air along brick edges.)
HVX_FN bool hvxNextLeaf(HVX_INDEX_PARAM, vec3 o, vec3 dir, int face, float tExit, float nudge, HVX_INOUT(uint) n,
                 HVX_INOUT(vec3) lo, HVX_INOUT(vec3) hi) {
    uint next = HVX_ROPE(n, face);
    if (next == HVX_NONE) return false;
    vec3 p = o + (tExit + nudge) * dir;
    int axis = face / 2;
    // A grazing ray (nearly parallel to the face, as the near-orthographic rays of a light-field
    // display's compressed depth are) moves too little along the exit axis for the nudge to carry
    // the point over; the point is put across the face. (Component by component: a vector
    // component picked by a variable index goes through memory on SIMD drivers.)
    float across1 = (hi.x - lo.x) * 1e-4f;
    bool up = (face & 1) != 0;
    if (axis == 0) p.x = up ? max(p.x, hi.x + across1) : min(p.x, lo.x - across1);
    if (axis == 1) p.y = up ? max(p.y, hi.y + across1) : min(p.y, lo.y - across1);
    if (axis == 2) p.z = up ? max(p.z, hi.z + across1) : min(p.z, lo.z - across1);
    // The leaf's centre moved across the exit face only: inside the rope's node, which spans
    // at least the leaf's extent along the other two axes.
    vec3 across = 0.5f * (lo + hi);
    if (axis == 0) across.x = p.x;
    if (axis == 1) across.y = p.y;
    if (axis == 2) across.z = p.z;
    vec3 ropeLo = lo;
    vec3 ropeHi = hi;
    hvxSnapBox(hvxDepth(HVX_NODE(next).y), across, ropeLo, ropeHi);
    bool inRope = p.x >= ropeLo.x && p.x < ropeHi.x && p.y >= ropeLo.y && p.y < ropeHi.y && p.z >= ropeLo.z && p.z < ropeHi.z;
    if (inRope) {
        n = next;
        lo = ropeLo;
        hi = ropeHi;
    } else {
        // Where the ray leaves through this face it is inside the leaf's extent along the other
        // two axes; float rounding can put the point just past a face it runs along, or crossed a
        // moment ago, and the leaf found from there lay behind the ray, which ended (dark lines
        // along brick faces). The point is kept within that extent: a ray leaving through an
        // edge enters the face neighbour for no length, and the diagonal one next.
        vec3 inside = clamp(p, lo + vec3(across1), hi - vec3(across1));
        if (axis != 0) p.x = inside.x;
        if (axis != 1) p.y = inside.y;
        if (axis != 2) p.z = inside.z;
        n = 0u;
        lo = vec3(0.0f);
        hi = vec3(1.0f);
        if (p.x < 0.0f || p.y < 0.0f || p.z < 0.0f || p.x >= 1.0f || p.y >= 1.0f || p.z >= 1.0f) return false;
    }
    hvxDescend(HVX_INDEX_ARG, n, lo, hi, p);
    return true;
}
