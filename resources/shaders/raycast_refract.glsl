// The refract stepper (thesis §3.2.2, Figs 3.4–3.5; HVX_REFRACT): DVR whose rays bend at each
// step by Snell's law (core::glsl::hvxRefractStep), step for step as
// core/reference/CpuRefractedRay.cpp. A bent ray's exit from its leaf is not known on entry, so
// each step goes one voxel of the current leaf along the current direction and the point it
// reaches is tested against the leaf's box (and the crop box); a point in another leaf is found
// from the root. Empty leaves, and the cells of a brick that neither show nor refract, are
// crossed straight: nothing shows there and their index is 1 (core::TransferFunction::isEmpty);
// the ray then passes from index 1 into what follows, bending there. Each segment's index is ν averaged over the values it
// spans (the pre-integrated table); where it differs from the index the ray travels in, the ray
// bends at the sample about the normal of the scalar's gradient there. The change of index may
// lie a step behind, where the gradient's central differences at the sample no longer see it (a
// slab's face crossed between two samples); then the last boundary's normal is taken, so that
// no change of index is lost and a layered medium keeps ν·sin θ exactly: a ray leaves a slab
// parallel to how it entered. With no boundary seen yet the change waits for one.
#include "Refraction.glsl"

layout(std430, binding = 11) readonly buffer TfRefraction { vec2 tfN[]; };  // 4097: (∫(ν − 1), ν − 1)

float tfRefractionIntegralAt(float p) {
    int i = min(int(p), 4095);
    vec2 e = tfN[i];
    return e.x + e.y * (p - float(i));
}

// core::TransferFunction::refractionSegment, in the same float operations.
float tfSegmentRefraction(float a, float b) {
    float pa = tfPosition(a), pb = tfPosition(b);
    if (abs(pb - pa) > 1.0) return 1.0 + (tfRefractionIntegralAt(pb) - tfRefractionIntegralAt(pa)) / (pb - pa);
    float p = clamp(tfPosition(0.5 * (a + b)) - 0.5, 0.0, 4095.0);
    int i = int(p);
    int j = min(i + 1, 4095);
    return 1.0 + mix(tfN[i].y, tfN[j].y, p - float(i));
}

bool insideBox(vec3 p, vec3 lo, vec3 hi) { return all(greaterThanEqual(p, lo)) && all(lessThanEqual(p, hi)); }
bool insideLeaf(vec3 p, vec3 lo, vec3 hi) { return all(greaterThanEqual(p, lo)) && all(lessThan(p, hi)); }

vec4 castRayRefract(vec3 ow, vec3 dw, out float depth) {
    depth = 1.0 / 0.0;
    vec3 o = (patientToOctree * vec4(ow, 1.0)).xyz;
    vec3 w = dw;                          // the ray's unit direction (patient mm); bends
    vec3 d = mat3(patientToOctree) * w;   // the same, octree units per mm
    float t0, t1;
    if (!clipToCrop(o, d, t0, t1)) return vec4(0.0);
    float nudge = 1e-3 * extent.w;        // a thousandth of a level-0 voxel (octree units)
    float t = t0 + nudge / length(d);     // path length (mm)
    vec3 p = o + t * d;
    uint n = 0u;
    vec3 lo = vec3(0.0), hi = vec3(1.0);
    hvxDescend(0u, n, lo, hi, p);
    vec3 color = vec3(0.0);
    float alpha = 0.0;
    bool hit = false, havePrev = false, inBrick = false;
    bool clear = false;  // the ray has crossed clear space (index 1) since its last segment
    float sPrev = 0.0, pPrev = 0.0, iPrev = 0.0, nuPrev = 1.0, voxel = 1.0;
    vec3 normal = vec3(0.0);  // the last boundary's gradient (see below)
    vec3 inv = rayInverse(d);  // d's, until it bends
    float step = 1.0;          // the leaf's voxel along d (mm), set with the leaf and after a bend
    LeafSampler L;
    bool done = false;
    // Two nested loops, as raycast_march.glsl's: the inner one takes the cheap steps (a sample,
    // its opacity and index) until one shows or changes the index; shading, compositing and the
    // bend then run once for the SIMD lanes that stopped together. The steps are those of one
    // loop doing everything, in the same operations.
    for (int guard = 0; guard < 262144 && !done;) {
        bool significant = false;
        float s = 0.0, pS = 0.0, iS = 0.0, a = 0.0, nu = 1.0;
        for (; guard < 262144; ++guard) {
            if (!inBrick) {  // p lies in leaf n
                uvec4 nd = hvxNodes[n];
                if (nd.x == HVX_NONE) {  // empty: straight across
                    float tExit = 0.0;
                    int face = hvxExitFace(p, inv, lo, hi, tExit);
                    float across = max(tExit, 0.0) + nudge / length(d);
                    vec3 q = p + across * d;
                    if (!insideBox(q, cropLo.xyz, cropHi.xyz)) { done = true; break; }
                    if (!hvxNextLeaf(0u, p, d, face, max(tExit, 0.0), nudge / length(d), n, lo, hi)) { done = true; break; }
                    p = q;
                    t += across;
                    havePrev = false;
                    clear = true;
                    continue;
                }
                if (extra.z > 0.5) atomicAdd(rayCounts[n], 1u);  // visibility feedback
                L = leafSampler(n, nd, lo);
                voxel = 1.0 / (float(brick.x) * float(1u << (nd.y & 0xFFu)));
                step = tfRange.w * voxel / length(d);
                inBrick = true;
            }
            // A cell that neither shows nor refracts (core::BrickCells under TransferFunction::isEmpty,
            // which counts an index ≠ 1 as content) bends nothing: the ray lands on its last step
            // before the cell's exit, on its own steps, and goes on from there (as raycast_march.glsl).
            float dt = step;  // this step's length (a step into another leaf keeps this leaf's)
            float cellExit;
            if (!cellVisible(L, p, p, inv, cellExit)) {
                float k = ceil(cellExit / dt);  // p + k·dt: the first step past the exit
                if (k >= 3.0) {
                    p += (k - 1.0) * dt * d;
                    t += (k - 1.0) * dt;
                    if (!insideBox(p, cropLo.xyz, cropHi.xyz)) { done = true; break; }
                    havePrev = false;
                    clear = true;
                }
            }
            if (!havePrev) {  // the chain of segments starts here: after clear space in index 1,
                sPrev = leafSample(L, p);  // on entering the volume in the medium found (a cut is no boundary)
                pPrev = tfPosition(sPrev);
                iPrev = tfOpacityIntegralAt(pPrev);
                nuPrev = clear ? 1.0 : tfSegmentRefraction(sPrev, sPrev);
                havePrev = true;
            }
            vec3 q = p + dt * d;
            if (!insideBox(q, cropLo.xyz, cropHi.xyz)) { done = true; break; }
            if (!insideLeaf(q, lo, hi)) {  // the step ended in another leaf
                n = 0u;
                lo = vec3(0.0);
                hi = vec3(1.0);
                hvxDescend(0u, n, lo, hi, q);
                uvec4 nd = hvxNodes[n];
                p = q;
                t += dt;
                inBrick = false;
                if (nd.x == HVX_NONE) {
                    havePrev = false;
                    clear = true;
                    continue;
                }
                if (extra.z > 0.5) atomicAdd(rayCounts[n], 1u);
                L = leafSampler(n, nd, lo);
                voxel = 1.0 / (float(brick.x) * float(1u << (nd.y & 0xFFu)));
                step = tfRange.w * voxel / length(d);
                inBrick = true;
            } else {
                p = q;
                t += dt;
            }
            s = leafSample(L, p);
            pS = tfPosition(s);
            iS = tfOpacityIntegralAt(pS);
            a = 1.0 - exp(-tfSegmentOpacity(sPrev, s, pPrev, iPrev, pS, iS) * dt);
            nu = tfSegmentRefraction(sPrev, s);
            if (a > 1e-6 || abs(nu - nuPrev) > 1e-5) {
                significant = true;
                ++guard;
                break;
            }
            sPrev = s;
            pPrev = pS;
            iPrev = iS;
        }
        if (!significant) break;
        if (a > 1e-6) {
            vec4 f = tfSegment(sPrev, s);
            vec3 c = shadeSample(L, p, f.rgb / f.w, w, a);
            color += (1.0 - alpha) * a * c;
            alpha += (1.0 - alpha) * a;
            if (!hit && alpha > 0.02) { hit = true; depth = t; }
            if (alpha >= tfRange.z) break;
        }
        if (abs(nu - nuPrev) > 1e-5) {
            vec3 g = transpose(mat3(patientToOctree)) * leafGradient(L, p);
            if (dot(g, g) > 0.0) normal = g;
            if (dot(normal, normal) > 0.0) {
                w = hvxRefractStep(w, normal, nuPrev, nu);
                d = mat3(patientToOctree) * w;
                inv = rayInverse(d);
                step = tfRange.w * voxel / length(d);
                nuPrev = nu;
            }
        }
        sPrev = s;
        pPrev = pS;
        iPrev = iS;
    }
    return vec4(color, alpha);
}
