// The ray march: clip to the volume (or its crop box), walk the index leaf by leaf (shared traversal step),
// sample each non-empty leaf at its voxel size and composite. The samples and their order of
// operations are those of core/reference/CpuRayCaster.cpp; two accelerations leave the image as it is:
// the costly work runs once per significant sample (see the loops below), and the cells of a
// brick that cannot show (core::BrickCells) are stepped over.
#ifndef MODE
#define MODE 0
#endif
// Whether the variant draws the focal probe. (Written with / and %: with '&' here, the context
// probe's variant drew a different image on Mesa's llvmpipe, so the preprocessor did not read
// it as a bit test.)
#define HVX_FOCAL_VARIANT ((HVX_TOOLS / HVX_FOCAL_BIT) % 2 == 1)
// The step after the sample at t: the focal probe samples its context more sparsely
// (hvxStepAfter; castRay's chord and kContext), every other variant every dt.
#if MODE == 0 && HVX_FOCAL_VARIANT
#define HVX_STEP(t) hvxStepAfter(t, dt, chord, kContext)
#else
#define HVX_STEP(t) dt
#endif
#define HVX_EMPHASIS_EMISSION 0.5  // core::kEmphasisEmission

// Shades a sample and scales its opacity `a` by boundary enhancement and view-dependent
// transparency (core::RenderSettings), with one gradient for both.
vec3 shadeSample(LeafSampler L, vec3 p, vec3 base, vec3 dw, inout float a) {
    bool enhanceOn = enhance.x > 0.0 || enhance.y > 0.0;
    if (extra.y < 0.5 && !enhanceOn && HVX_GRADIENT_OPACITY == 0) return base;
    vec3 g = transpose(mat3(patientToOctree)) * leafGradient(L, p);
    float len = length(g);
#if HVX_GRADIENT_OPACITY
    a = gradientOpacity(a, len);
#endif
    float ndl = len < 1e-9 ? 0.0 : abs(dot(g / len, -dw));  // headlight: L = V
    if (enhanceOn) {
        float strength = min(1.0, len * enhance.z);
        a *= (1.0 - enhance.x + enhance.x * strength) * (1.0 - enhance.y * strength * ndl);
    }
    if (extra.y < 0.5) return base;
    if (len < 1e-9) return base * (shading.x + shading.y);
#if HVX_DETAIL
    // normal unsharp masking and exaggerated shading against the coarser level's gradient
    vec2 f = hvxDetailShading(g, transpose(mat3(patientToOctree)) * leafCoarserGradient(L, p), -dw, detail.x, detail.y,
                              min(1.0, len * enhance.z));
    return base * (shading.x + shading.y * f.x) + vec3(shading.z * pow(f.y, shading.w));
#else
    return base * (shading.x + shading.y * ndl) + vec3(shading.z * pow(ndl, shading.w));
#endif
}

// The ray o + t·d (octree space, t in world mm from t = 0) clipped to the crop box (the whole
// volume when nothing is cropped): [t0, t1], false when it misses.
bool clipToCrop(vec3 o, vec3 d, out float t0, out float t1) {
    t0 = 0.0;
    t1 = 1e30;
    for (int a = 0; a < 3; ++a) {
        if (abs(d[a]) < 1e-15) {
            if (o[a] < cropLo[a] || o[a] > cropHi[a]) return false;
            continue;
        }
        float ta = (cropLo[a] - o[a]) / d[a], tb = (cropHi[a] - o[a]) / d[a];
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
    }
    return t1 > t0;
}

// 1 / d per axis, ±1e30 along an axis the ray (nearly) parallels: the traversal's slab tests.
vec3 rayInverse(vec3 d) {
    return vec3(abs(d.x) > 1e-20 ? 1.0 / d.x : (d.x >= 0.0 ? 1e30 : -1e30),
                abs(d.y) > 1e-20 ? 1.0 / d.y : (d.y >= 0.0 ? 1e30 : -1e30),
                abs(d.z) > 1e-20 ? 1.0 / d.z : (d.z >= 0.0 ? 1e30 : -1e30));
}

// A tool sample's colour (core::CpuRayCaster and SplitCompositor alike): Phong by its gradient
// (none: facing), or ambient + emission where a tool emphasises it, mixed by x.lit; a sample
// already shaded (x.lit < 0) keeps its colour.
vec3 toolColour(HvxSample x) {
    if (x.lit < 0.0) return x.c;
    float gl2 = dot(x.g, x.g);
    float ndl = gl2 > 0.0 ? abs(dot(x.g, -x.v)) / sqrt(gl2) : 1.0;
    vec3 phong = extra.y > 0.5 ? x.c * (shading.x + shading.y * ndl) + vec3(shading.z * pow(ndl, shading.w)) : x.c;
    return mix(x.c * (shading.x + HVX_EMPHASIS_EMISSION), phong, x.lit);
}

vec4 castRay(vec3 ow, vec3 dw, out float depth) {
    depth = 1.0 / 0.0;
    vec3 o = (patientToOctree * vec4(ow, 1.0)).xyz;
    vec3 d = mat3(patientToOctree) * dw;
    float t0, t1;
    if (!clipToCrop(o, d, t0, t1)) return vec4(0.0);
    vec3 inv = rayInverse(d);
    float octPerMm = length(d);
    float nudge = 1e-3 * extent.w / max(1e-12, octPerMm);

    vec3 color = vec3(0.0);
    float alpha = 0.0, sum = 0.0, travelled = 0.0;
    float extreme = MODE == 3 ? 1e30 : -1e30;
    bool hit = false, havePrev = false, done = false;
    float tPrev = 0.0, sPrev = 0.0;
    float pPrev = 0.0, iPrev = 0.0;  // DVR: the previous sample's TF position and opacity integral
    float tIn = t0;
    // A stretch inside the ray that the tools hide (hvxHiddenGap): the march stops at its start
    // (tStop) and goes on from its end.
    vec2 gap = vec2(1e30, -1e30);
    float tStop = t1;
#if MODE == 0 && HVX_FOCAL_VARIANT
    // The focus, sampled every dt; the focal probe's context around it every kContext·dt (HVX_STEP).
    vec2 chord = hvxFocusChord(tools, HVX_TOOLS, ow, dw);
    float kContext = tools.focalRot0.w;
#endif
#if MODE == 0 && HVX_TOOLS != 0
    // Tools: the focal probe's cone for this ray, its entry, and the MImDA accumulator.
    float hTheta = HVX_TOOL_ON(HVX_FOCAL_BIT) ? hvxFocalAngle(tools, ow, dw) : 1.0;
    bool entered = false;
    vec4 accum = vec4(0.0);
    float importanceMax = 0.0;
    // What the tools hide at either end of the ray (in the focus cone, all outside the probe's
    // bounding sphere; a clip plane seen face-on, its cut-away side) is not stepped through:
    // the ray starts and ends at hvxVisibleSpan, on its own sampling grid from t0.
    vec2 span = hvxVisibleSpan(tools, HVX_TOOLS, ow, dw, hTheta);
    tIn = max(t0, span.x);
    t1 = min(t1, span.y);
    gap = hvxHiddenGap(tools, HVX_TOOLS, ow, dw);
    if (gap.x <= tIn && gap.y > tIn) tIn = gap.y;  // the ray starts in it
    if (!(t1 > tIn)) return vec4(0.0);
    tStop = gap.x > tIn && gap.x < gap.y ? min(t1, gap.x) : t1;
#endif
    uint n = 0u;
    vec3 lo = vec3(0.0), hi = vec3(1.0);
    hvxDescend(0u, n, lo, hi, o + (tIn + nudge) * d);
    // The current leaf: where the ray leaves it, its sampler, step and next sample.
    float dt = 1.0, t = 0.0;
    LeafSampler L;
    uint counted = 0xFFFFFFFFu;  // the leaf last counted for the visibility feedback

    // Three nested loops, so that each kind of work runs as often as it must: leaves
    // (traversal), significant samples in a leaf (gradient, shading, compositing), and the
    // transparent samples between them (one fetch and the opacity test). SIMD drivers execute
    // a branch's code for every lane, taken or not (llvmpipe masks it), but leave a loop as
    // soon as all of its lanes have; a GPU warp does the same with divergent branches.
    for (int guard = 0; guard < 65536 && !done; ++guard) {
        float tExit = 0.0;
        int face = hvxExitFace(o, inv, lo, hi, tExit);
        float tOut = min(tExit, tStop);
        bool inLeaf = false;
        // For a leaf with a brick: its sampler, step and first sample on the ray's own sampling
        // grid. After empty space, the segment leading into the brick starts at its border
        // sample, as a dense marcher would (core/reference/CpuRayCaster.cpp). An empty leaf breaks the
        // chain of segments.
        if (tOut > tIn) {
            uvec4 nd = hvxNodes[n];
            if (nd.x == HVX_NONE) {
                havePrev = false;
            } else {
                inLeaf = true;
                if (extra.z > 0.5 && n != counted) {  // visibility feedback, once a leaf (a jump may land in the same)
                    atomicAdd(rayCounts[n], 1u);
                    counted = n;
                }
                L = leafSampler(n, nd, lo);
                float voxel = 1.0 / (float(brick.x) * float(1u << (nd.y & 0xFFu)));
                dt = tfRange.w * voxel / octPerMm;
                t = tPrev + dt;
                if (!havePrev) {
                    t = t0 + ceil((tIn - t0) / dt) * dt;
                    tPrev = t - dt;
                    if (tPrev >= t0) {
                        sPrev = leafSample(L, o + tPrev * d);
                        if (MODE == 0) {
                            pPrev = tfPosition(sPrev);
                            iPrev = tfOpacityIntegralAt(pPrev);
                        }
                        havePrev = MODE == 0 || MODE == 1;
                    }
                }
            }
        }
        while (inLeaf && t <= tOut && !done) {  // significant samples of this leaf
            bool significant = false;
            vec3 p = vec3(0.0);
            float s = 0.0, pS = 0.0, iS = 0.0, a = 0.0;
            for (; t <= tOut; t += HVX_STEP(t)) {  // samples of this leaf
                p = o + t * d;
                s = leafSample(L, p);
#if MODE == 0
                pS = tfPosition(s);
                iS = tfOpacityIntegralAt(pS);
                if (havePrev) {
                    a = 1.0 - exp(-tfSegmentOpacity(sPrev, s, pPrev, iPrev, pS, iS) * (t - tPrev));
#if HVX_TOOLS != 0
                    // where the tools leave nothing to see, the sample stays as cheap as a transparent one
                    if (a > 1e-6 && !hvxHidden(tools, HVX_TOOLS, ow + t * dw, dw, hTheta)) { significant = true; break; }
#else
                    if (a > 1e-6) { significant = true; break; }
#endif
                }
                pPrev = pS;
                iPrev = iS;
#elif MODE == 1
                if (havePrev && ((sPrev < extra.x) != (s < extra.x))) { significant = true; break; }
#else
                extreme = MODE == 3 ? min(extreme, s) : max(extreme, s);
                if (havePrev) { sum += 0.5 * (s + sPrev) * (t - tPrev); travelled += t - tPrev; }
                if (!hit) { hit = true; depth = t; }
#endif
                tPrev = t;
                sPrev = s;
                havePrev = true;
#if MODE <= 1
                // In a cell the transfer function leaves transparent (DVR) or that does not
                // straddle the iso value, every sample and every segment between two of them
                // adds nothing: land on the last sample before the cell's exit (it starts the
                // next segment) and go on from there.
                float cellExit;
                if (!cellVisible(L, p, o, inv, cellExit)) {
                    float k = ceil((cellExit - t) / dt);  // t + k·dt: the first sample past the exit
                    if (k >= 3.0) {
                        t += (k - 2.0) * dt;  // the loop's step makes it t + (k - 1)·dt
                        havePrev = false;
                    }
                }
#endif
            }
            if (!significant) break;
#if MODE == 0 && HVX_TOOLS != 0
            {  // enhancers, shading and MImDA as core/reference/CpuRayCaster.cpp
                vec4 f = tfSegment(sPrev, s);
                vec3 g = transpose(mat3(patientToOctree)) * leafGradient(L, p);
                HvxSample x;
                x.p = ow + t * dw;
                x.v = dw;
                x.g = g;
                x.gn = min(1.0, length(g) * enhance.z);
                x.s = s;
                x.c = f.rgb / f.w;
#if HVX_GRADIENT_OPACITY
                x.a = gradientOpacity(a, length(g));
#else
                x.a = a;
#endif
                x.lit = 1.0;
                x.importance = 1.0 - exp(-f.w * extra.w);
                float focalNorm = HVX_TOOL_ON(HVX_FOCAL_BIT) ? hvxFocalNorm(tools, x.p) : 2.0;
                vec3 gSmooth = focalNorm <= 1.0 ? transpose(mat3(patientToOctree)) * leafGradientSpread(L, p, 2.0) : g;
                bool enteredNow = entered;
#if HVX_FOCAL_VARIANT
                float kSegment = hvxContextSegment(t, tPrev, dt, chord);
                x.a = hvxOpacityPerSample(x.a, kSegment);
                hvxEnhance(x, tools, HVX_TOOLS, focalNorm, gSmooth, hTheta, enteredNow);
                x.a = hvxOpacityOfSegment(x.a, kSegment);
#else
                hvxEnhance(x, tools, HVX_TOOLS, focalNorm, gSmooth, hTheta, enteredNow);
#endif
                if (enteredNow && !entered) {  // clip what lies in front of the focal probe
                    accum = vec4(0.0);
                    importanceMax = 0.0;
                    entered = true;
                }
                vec3 colour = toolColour(x);
                hvxMimda(accum, importanceMax, colour * x.a, x.a, x.importance, tools.bandAxis.w);
                if (!hit && accum.w > 0.02) { hit = true; depth = t; }
                if (hvxMimdaFutureDelta(accum.w, importanceMax, tools.bandAxis.w) < 1.0 - tfRange.z) done = true;
            }
#elif MODE == 0
            {
                vec4 f = tfSegment(sPrev, s);
                vec3 c = shadeSample(L, p, f.rgb / f.w, dw, a);
                color += (1.0 - alpha) * a * c;
                alpha += (1.0 - alpha) * a;
                if (!hit && alpha > 0.02) { hit = true; depth = t; }
                if (alpha >= tfRange.z) done = true;
            }
#elif MODE == 1
            {  // first crossing of the iso value: bisection, then shading
                float ta = tPrev, tb = t, sa = sPrev;
                for (int k = 0; k < 8; ++k) {
                    float m = 0.5 * (ta + tb);
                    float sm = leafSample(L, o + m * d);
                    if ((sa < extra.x) != (sm < extra.x)) tb = m; else { ta = m; sa = sm; }
                }
                float th = 0.5 * (ta + tb);
                vec4 f = tfSample(extra.x);
                vec3 base = f.w > 0.0 ? f.rgb / f.w : vec3(0.9);
                if (length(base) < 0.1) base = vec3(0.9);
                float opaque = 1.0;
                color = shadeSample(L, o + th * d, base, dw, opaque);
                alpha = 1.0;
                depth = th;
                done = true;
            }
#endif
#if MODE == 0
            pPrev = pS;
            iPrev = iS;
#endif
            tPrev = t;
            sPrev = s;
            havePrev = true;
            t += HVX_STEP(t);
        }
        if (done || tExit >= t1) break;
        if (tExit >= tStop) {  // the hidden stretch: go on from its end (on the grid from t0, as after an empty leaf)
            tIn = gap.y;
            tStop = t1;
            if (!(t1 > tIn)) break;
            havePrev = false;
            hvxDescend(0u, n, lo, hi, o + (tIn + nudge) * d);
            continue;
        }
        if (!hvxNextLeaf(0u, o, d, face, tExit, nudge, n, lo, hi)) break;
        tIn = max(tIn, tExit);
    }
#if MODE >= 2
    if (!hit) return vec4(0.0);
    float v = MODE == 4 ? (travelled > 0.0 ? sum / travelled : extreme) : extreme;
    float g = hvxProjectionLight((v - tfRange.x) / (tfRange.y - tfRange.x));
    return vec4(g, g, g, 1.0);
#elif HVX_TOOLS != 0
    return accum;
#else
    return vec4(color, alpha);
#endif
}
