// Illustrative "enhancers" (thesis §3.2.2 and ch. 6): per-sample functions chained before
// shading and compositing, written once in the subset of GLSL that C++ also compiles (through
// GLM and the macros of core/appearance/Enhancers.h). The shader compiles only the tools a frame uses
// (static variants, HVX_TOOL_* defines); the CPU reference calls the same functions.
//
// Conventions: world space is patient LPS mm; v is the unit view direction (eye -> sample);
// g is the world gradient (stored units per mm) and gn its strength in [0, 1] (the value change
// per finest voxel as a fraction of the transfer function's range, 10% = 1, as for boundary
// enhancement). HVX_FN prefixes functions (inline in C++, empty in GLSL).

// Thesis Eq. 6.2 is GLSL's smoothstep(a, b, t); written out so both languages agree exactly.
HVX_FN float hvxSmooth(float a, float b, float t) {
    float x = clamp((t - a) / max(b - a, 1e-6f), 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

// One sample as the enhancers see and modify it.
#define HVX_CLIP_BIT 1
#define HVX_FOCAL_BIT 2
#define HVX_CONTEXT_BIT 4
#define HVX_BAND_BIT 8
#define HVX_MIMDA_BIT 16

struct HvxSample {
    vec3 p;            // world position
    vec3 v;            // unit view direction
    vec3 g;            // world gradient
    float gn;          // gradient strength [0, 1]
    float s;           // stored value
    vec3 c;            // colour (not premultiplied)
    float a;           // opacity of this segment
    float lit;         // 1: Phong shading; 0: ambient + emission (emphasis); < 0: already shaded
    float importance;  // for MImDA
};

// ---- Clip plane with view-dependent context (thesis §6.4.1) ---------------------------------
// plane: n (unit, xyz) and p (w): delta = n.x + p. On the positive side opacity is scaled by
// mu = smoothstep(1 - max(0, -n.v), fl, fh): a cut-away seen face-on, context when oblique.
// In the slab -thickness < delta < 0 opacity and shading blend to full opacity and
// ambient + emission at the plane.
HVX_FN float hvxClipMu(vec4 plane, vec3 v, float fl, float fh) {
    return hvxSmooth(fl, fh, 1.0f - max(0.0f, -dot(vec3(plane), v)));
}

HVX_FN void hvxClip(HVX_INOUT(HvxSample) x, vec4 plane, float thickness, float fl, float fh) {
    float delta = dot(vec3(plane), x.p) + plane.w;
    if (delta > 0.0f) {
        x.a *= hvxClipMu(plane, x.v, fl, fh);
    } else if (thickness > 0.0f && delta > -thickness) {
        float w = 1.0f + delta / thickness;  // 0 at -thickness, 1 at the plane
        x.a = mix(x.a, 1.0f, w);
        x.lit = min(x.lit, 1.0f - w);
    }
}

// ---- Context-preserving focal probe (thesis §6.3, Eqs 6.6-6.16) -----------------------------
// The pq-norm of the probe-local position (Eqs 6.6-6.7): p = q = 2 sphere, p = 2, q = 4
// cylinder, p = q = 4 rounded cube.
HVX_FN float hvxPqNorm(vec3 local, float p, float q) {
    if (p == 2.0f && q == 2.0f) return length(local);  // the sphere (the default): no pow
    float xy = pow(pow(abs(local.x), p) + pow(abs(local.y), p), 1.0f / p);
    return pow(pow(xy, q) + pow(abs(local.z), q), 1.0f / q);
}

// Eq. 6.9
HVX_FN float hvxGBeta(float t, float beta) { return t / (exp(beta * (1.0f - t)) + t); }

// Eq. 6.8: 1 inside rho, falling off to the probe surface, 0 outside.
HVX_FN float hvxFocusWeight(float norm, float rho, float beta) {
    if (norm <= rho) return 1.0f;
    if (norm > 1.0f) return 0.0f;
    return 1.0f - hvxGBeta((norm - rho) / (1.0f - rho), beta);
}

// Eq. 6.16: h(theta) for the angle between the eye->probe-centre direction and the ray,
// 0 inside the focus cone (phiFocus), rising to 1 at the probe's silhouette cone (phiProbe).
HVX_FN float hvxContextAngle(float cosTheta, float cosFocus, float cosProbe) {
    if (cosTheta >= cosFocus) return 0.0f;
    if (cosTheta <= cosProbe) return 1.0f;
    return 1.0f - (cosTheta - cosFocus) / (cosProbe - cosFocus);
}

// Focus and context styles blended by distance (Eqs 6.10-6.15). lambda: the Phong factor of
// the sample (Eq. 6.5); relief: r_i of Eq. 6.14; hTheta: Eq. 6.16 for this ray.
HVX_FN void hvxFocalProbe(HVX_INOUT(HvxSample) x, float norm, float rho, float beta, float gl, float gh, float sl,
                          float sh, float lambda, float relief, float hTheta) {
    float w = hvxSmooth(gl, gh, x.gn);                                     // Eq. 6.1
    float gl2 = dot(x.g, x.g);
    float facing = gl2 > 0.0f ? abs(dot(x.g, x.v)) / sqrt(gl2) : 1.0f;
    float si = w * hvxSmooth(sl, sh, 1.0f - facing);                       // Eq. 6.11
    vec3 cFocus = (1.0f - si) * relief * x.c;                              // Eq. 6.12
    float aFocus = clamp(relief * x.a, 0.0f, 1.0f);
    vec3 cContext = lambda * x.c;                                          // Eq. 6.15
    float aContext = clamp(hTheta * si * lambda * x.a, 0.0f, 1.0f);
    float d = hvxFocusWeight(norm, rho, beta);
    x.c = d * cFocus + (1.0f - d) * cContext;                              // Eq. 6.10
    x.a = d * aFocus + (1.0f - d) * aContext;
    x.lit = -1.0f;  // the styles carry their own lighting
}

// Eq. 6.14 with Eq. 6.13: relief shading from the light L, the gradient direction and a
// smoothed normal.
HVX_FN float hvxRelief(vec3 L, vec3 gDir, vec3 nSmooth, float ka, float kd, float toon) {
    vec3 Lstar = L - nSmooth * dot(nSmooth, L);
    return ka + kd * (dot(L, gDir) + toon * clamp(dot(Lstar, gDir), 0.0f, 1.0f));
}

// ---- Context-preserving probe (thesis §6.4.2, Eqs 6.17-6.18) --------------------------------
// A sphere (centre, radius) with a tool axis. omegaD: 1 on the plane through the centre facing
// the viewer, 0 at one radius from it; omegaA: 1 when the axis is aligned with the view.
HVX_FN void hvxContextProbe(HVX_INOUT(HvxSample) x, vec3 centre, float radius, vec3 axis, float gl, float gh,
                            float al, float ah) {
    vec3 r = x.p - centre;
    if (dot(r, r) >= radius * radius) return;
    float along = dot(r, x.v);  // < 0 in front of the centre plane
    float omegaD = max(0.0f, 1.0f - (along / radius) * (along / radius));
    float omegaA = hvxSmooth(al, ah, abs(dot(axis, x.v)));
    float gl2 = dot(x.g, x.g);
    float facing = gl2 > 0.0f ? abs(dot(x.g, x.v)) / sqrt(gl2) : 1.0f;
    float f = 1.0f - facing;
    float eta = omegaA * hvxSmooth(gl, gh, x.importance * x.gn) * f * f * f * f;
    float muA = along < 0.0f ? mix(0.0f, eta, omegaD) : mix(eta, 1.0f, 1.0f - omegaD);   // Eq. 6.17
    float muI = along < 0.0f ? 1.0f - eta : mix(1.0f - eta, 1.0f, 1.0f - omegaD);         // Eq. 6.18
    x.a *= muA;
    x.c *= muI;
}

// ---- Band picker (thesis §6.4.3) -------------------------------------------------------------
// A trapezoid band b0 <= b1 <= b2 <= b3 (stored values): importance is its membership; outside
// the band opacity fades as the view aligns with the tool axis (only the band when looking
// straight at it, context at an angle).
HVX_FN float hvxBand(vec4 band, float s) {
    if (s < band.x || s > band.w) return 0.0f;
    if (s < band.y) return band.y > band.x ? (s - band.x) / (band.y - band.x) : 1.0f;
    if (s > band.z) return band.w > band.z ? (band.w - s) / (band.w - band.z) : 1.0f;
    return 1.0f;
}

HVX_FN void hvxBandPicker(HVX_INOUT(HvxSample) x, vec4 band, vec3 axis, float al, float ah) {
    float inBand = hvxBand(band, x.s);
    float omegaA = hvxSmooth(al, ah, abs(dot(axis, x.v)));
    x.importance = inBand;
    x.a *= mix(1.0f - omegaA, 1.0f, inBand);
}

// ---- MImDA compositing (thesis §3.2.2, Eqs 3.2-3.3) ------------------------------------------
// accum: rgb premultiplied colour, a opacity; importanceMax is updated. gamma = 0 is plain DVR.
HVX_FN void hvxMimda(HVX_INOUT(vec4) accum, HVX_INOUT(float) importanceMax, vec3 premultiplied, float a,
                     float importance, float gamma) {
    float delta = max(importance - importanceMax, 0.0f);
    float b = 1.0f - gamma * delta;
    vec3 c = vec3(accum) * b + (1.0f - b * accum.w) * premultiplied;
    float alpha = accum.w * b + (1.0f - b * accum.w) * a;
    accum = vec4(c, alpha);
    importanceMax = max(importanceMax, importance);
}

// The revised early-termination test: the largest opacity still to come.
HVX_FN float hvxMimdaFutureDelta(float alpha, float importanceMax, float gamma) {
    return 1.0f - (1.0f - gamma * (1.0f - importanceMax)) * alpha;
}

// ---- Multilevel shading (thesis §3.2.2, Fig. 3.7) ----------------------------------------------
// The diffuse and specular factors of a sample under a headlight L (unit, towards the eye), from
// its gradient g (not zero) and a smoothed gradient gs (the coarser scale), two-sided as the
// Phong shading here is. Normal unsharp masking (Cignoni et al. 2005): n' = normalize(n +
// k·(n − n_s)). Exaggerated shading (Rusinkiewicz et al. 2006) over the two scales: the finer
// one lit by the light projected onto the plane of the coarser normal, l_s = L − n_s(n_s·L),
// a grazing light that shows only its departure from the coarser scale, clamp(a·n'·l_s, −1, 1)
// with a = 4; under a headlight the coarser scale, lit head-on, would be flat (the paper's
// clamp(a·n_s·L) saturates), so it keeps its plain Lambert term and the finer scale modulates
// it: |n_s·L|·(1 + clamp(a·n'·l_s, −1, 1)), at most 1, blended with the plain factor by
// `exaggerate`. Both scale with the boundary's strength gn (as boundary enhancement's, [0, 1]):
// in homogeneous tissue a gradient's direction is noise, not detail. Returns (diffuse, |n'·L|
// for the specular term); with k = 0 and exaggerate = 0, (|n·L|, |n·L|).
#define HVX_EXAGGERATION 4.0f
HVX_FN vec2 hvxDetailShading(vec3 g, vec3 gs, vec3 L, float unsharp, float exaggerate, float gn) {
    vec3 n = g / sqrt(dot(g, g));
    if (dot(n, L) < 0.0f) n = -n;
    float sl2 = dot(gs, gs);
    vec3 ns = sl2 > 0.0f ? gs / sqrt(sl2) : n;
    if (dot(ns, n) < 0.0f) ns = -ns;
    vec3 u = n + gn * unsharp * (n - ns);
    float ul2 = dot(u, u);
    if (ul2 > 0.0f) n = u / sqrt(ul2);
    float ndl = abs(dot(n, L));
    vec3 ls = L - ns * dot(ns, L);
    float e = min(1.0f, abs(dot(ns, L)) * (1.0f + clamp(HVX_EXAGGERATION * dot(n, ls), -1.0f, 1.0f)));
    return vec2(mix(ndl, e, gn * exaggerate), ndl);
}

// ---- Projection grey ---------------------------------------------------------------------------
// MIP, MinIP and the average show a value through a window: on screen its grey is linear in the
// value, as a windowed slice's is. A frame holds linear light, which the outputs encode to sRGB
// (PNG, the views), so the window's fraction g in [0, 1] becomes the light whose sRGB code is g
// (IEC 61966-2-1); written straight, a value at a quarter of the window had shown 54 % grey.
HVX_FN float hvxProjectionLight(float g) {
    g = clamp(g, 0.0f, 1.0f);
    return g <= 0.04045f ? g / 12.92f : pow((g + 0.055f) / 1.055f, 2.4f);
}

// ---- The chain -------------------------------------------------------------------------------
// Tool parameters as the shader's uniform block holds them (std140: vec4s only); filled from
// core::ToolSet by both sides.
struct HvxTools {
    vec4 clipPlane;      // n (unit), offset
    vec4 clipParams;     // thickness, fl, fh, -
    vec4 focalCentre;    // xyz, p
    vec4 focalRadii;     // xyz, q
    vec4 focalRot0;      // the probe's axes (columns) in patient space; focalRot0.w: the context step
    vec4 focalRot1;
    vec4 focalRot2;
    vec4 focalParams;    // beta, rho, g_l, g_h
    vec4 focalStyle;     // s_l, s_h, toon a, bounding radius (ToolSet::FocalProbe::boundingRadius)
    vec4 contextCentre;  // xyz, radius
    vec4 contextAxis;    // xyz (unit), -
    vec4 contextParams;  // g_l, g_h, a_l, a_h
    vec4 band;           // b0, b1, b2, b3
    vec4 bandAxis;       // xyz (unit), MImDA gamma
    vec4 bandParams;     // a_l, a_h, -, -
    vec4 shading;        // k_a, k_d, k_s, shininess
};

// Eq. 6.16 for a ray: the angle between it and the eye -> probe-centre direction, against the
// cones of the probe (its largest radius) and of its focus (rho times that).
HVX_FN float hvxFocalAngle(HvxTools t, vec3 origin, vec3 dir) {
    vec3 toC = vec3(t.focalCentre) - origin;
    float dist = max(length(toC), 1e-6f);
    float radius = max(t.focalRadii.x, max(t.focalRadii.y, t.focalRadii.z));
    float sinProbe = min(1.0f, radius / dist);
    float sinFocus = min(1.0f, t.focalParams.y * radius / dist);
    return hvxContextAngle(dot(toC / dist, dir), sqrt(1.0f - sinFocus * sinFocus), sqrt(1.0f - sinProbe * sinProbe));
}

// The focal probe's pq-norm at a point (<= 1 inside the probe).
HVX_FN float hvxFocalNorm(HvxTools t, vec3 p) {
    mat3 rot = mat3(vec3(t.focalRot0), vec3(t.focalRot1), vec3(t.focalRot2));
    vec3 local = (transpose(rot) * (p - vec3(t.focalCentre))) / vec3(t.focalRadii);
    return hvxPqNorm(local, t.focalCentre.w, t.focalRadii.w);
}

// Whether the tools make a sample at p on a ray of direction v fully transparent whatever its
// value and gradient (hvxEnhance would set x.a to exactly 0), so that the ray caster may skip
// its gradient and enhancers. Conservative: true only where
// - the focal probe's focus cone holds the ray (hTheta = 0) and p lies outside the probe's
//   bounding sphere (the context there is scaled by hTheta, Eq. 6.15);
// - the clip plane is seen so nearly face-on that mu = 0 and p lies on its cut-away side;
// - the context probe's axis is far enough from the view that omega_a = 0 and p lies in the
//   probe's front half (Eq. 6.17: mu_a = omega_d · eta, eta = 0).
// The last two only outside the focal probe's sphere (a sample inside it may open the probe,
// which clears what lies in front), and none under MImDA (a hidden sample still raises the
// ray's maximum importance).
HVX_FN bool hvxHidden(HvxTools t, int hvxBits, vec3 p, vec3 v, float hTheta) {
    if (HVX_TOOL_ON(HVX_MIMDA_BIT)) return false;
    if (HVX_TOOL_ON(HVX_FOCAL_BIT)) {
        vec3 r = p - vec3(t.focalCentre);
        if (dot(r, r) <= t.focalStyle.w * t.focalStyle.w) return false;
        if (hTheta <= 0.0f) return true;
    }
    if (HVX_TOOL_ON(HVX_CLIP_BIT) && dot(vec3(t.clipPlane), p) + t.clipPlane.w > 0.0f &&
        hvxClipMu(t.clipPlane, v, t.clipParams.y, t.clipParams.z) <= 0.0f)
        return true;
    if (HVX_TOOL_ON(HVX_CONTEXT_BIT)) {
        vec3 r = p - vec3(t.contextCentre);
        if (dot(r, r) < t.contextCentre.w * t.contextCentre.w && dot(r, v) < 0.0f &&
            hvxSmooth(t.contextParams.z, t.contextParams.w, abs(dot(vec3(t.contextAxis), v))) <= 0.0f)
            return true;
    }
    return false;
}

// The chord of a ray (origin, unit direction dir; t in world mm from the origin) through the
// sphere (centre, r), as (first, last); empty (first > last) when the ray misses it.
HVX_FN vec2 hvxSphereChord(vec3 centre, float r, vec3 origin, vec3 dir) {
    vec3 toC = centre - origin;
    float along = dot(toC, dir);
    vec3 gap = toC - along * dir;  // from the ray's line to the centre (not |toC|² - along², which cancels far away)
    float gap2 = dot(gap, gap);
    if (!(r > 0.0f) || gap2 > r * r) return vec2(1e30f, -1e30f);
    float chord = sqrt(r * r - gap2);
    return vec2(along - chord, along + chord);
}

// The chord of a ray (origin, unit direction dir; t in world mm from the origin) through the
// focal probe's bounding sphere grown by a thousandth of its radius against rounding, as (first,
// last); empty (first > last) when the ray misses it.
HVX_FN vec2 hvxProbeChord(HvxTools t, vec3 origin, vec3 dir) {
    return hvxSphereChord(vec3(t.focalCentre), t.focalStyle.w * 1.001f, origin, dir);
}

// The part of a ray (origin, unit direction dir) on the kept side of a clip plane seen so nearly
// face-on that mu = 0 (hvxClip), as (first, last); the whole ray when the plane shows context
// to this ray, or when the ray (nearly) parallels it. The cut-away side is
// delta = dot(n, p) + offset > 0; the span reaches into it by a margin against rounding (1e-4 of
// the distances involved: to the cut, and the origin's and the plane's from the patient origin),
// so that every sample outside it computes delta > 0 as hvxHidden does.
HVX_FN vec2 hvxClipSpan(HvxTools t, vec3 origin, vec3 dir) {
    vec2 whole = vec2(-1e30f, 1e30f);
    if (hvxClipMu(t.clipPlane, dir, t.clipParams.y, t.clipParams.z) > 0.0f) return whole;
    float d0 = dot(vec3(t.clipPlane), origin) + t.clipPlane.w;  // delta at t = 0
    float rate = dot(vec3(t.clipPlane), dir);                    // d delta / dt
    if (abs(rate) < 1e-3f) return whole;  // only with f_l near 1: a plane along the ray
    float tCut = -d0 / rate;  // delta = 0
    float margin = 1e-4f * (1.0f + abs(tCut) + (length(origin) + abs(t.clipPlane.w)) / abs(rate));
    return rate < 0.0f ? vec2(tCut - margin, 1e30f) : vec2(-1e30f, tCut + margin);
}

// The stretch of a ray (origin, unit direction dir; t in world mm from the origin) outside which
// hvxHidden holds for every sample, as (first, last; empty when first > last). Without MImDA:
// in the focal probe's focus cone (hTheta = 0), the chord through the probe's bounding sphere
// (hvxProbeChord); without the focal probe, the kept side of a clip plane seen face-on
// (hvxClipSpan); the whole ray otherwise. The ray caster starts and ends such a ray there,
// rather than stepping through the hidden samples one by one. (Outside the focus cone the focal
// probe samples its context k samples at a time, on a grid that starts where the ray does: a
// ray that started at the cut would sample the context elsewhere than the dense march.)
HVX_FN vec2 hvxVisibleSpan(HvxTools t, int hvxBits, vec3 origin, vec3 dir, float hTheta) {
    vec2 whole = vec2(-1e30f, 1e30f);
    if (HVX_TOOL_ON(HVX_MIMDA_BIT)) return whole;
    if (HVX_TOOL_ON(HVX_FOCAL_BIT)) return hTheta <= 0.0f ? hvxProbeChord(t, origin, dir) : whole;
    if (HVX_TOOL_ON(HVX_CLIP_BIT)) return hvxClipSpan(t, origin, dir);
    return whole;
}

// A stretch inside a ray where hvxHidden holds for every sample, as (first, last; empty when
// first >= last): the context probe's front half when its axis is so far from the ray that
// omega_a = 0 (Eq. 6.17: mu_a = omega_d · eta, eta = 0), from where the ray enters the probe's
// sphere to where it crosses the plane through the centre. Against rounding the sphere shrinks
// and the plane moves towards the viewer by a margin (1e-4 of the distances involved: along the
// ray, the radius, and the origin's and the centre's from the patient origin). Only without the
// focal probe (whose context grid starts where the ray does, as in hvxVisibleSpan) and without
// MImDA. The ray caster jumps over it.
HVX_FN vec2 hvxHiddenGap(HvxTools t, int hvxBits, vec3 origin, vec3 dir) {
    vec2 none = vec2(1e30f, -1e30f);
    if (HVX_TOOL_ON(HVX_MIMDA_BIT) || HVX_TOOL_ON(HVX_FOCAL_BIT) || !HVX_TOOL_ON(HVX_CONTEXT_BIT)) return none;
    if (hvxSmooth(t.contextParams.z, t.contextParams.w, abs(dot(vec3(t.contextAxis), dir))) > 0.0f) return none;
    float along = dot(vec3(t.contextCentre) - origin, dir);  // where the ray crosses the plane through the centre
    float margin = 1e-4f * (1.0f + abs(along) + t.contextCentre.w + length(origin) + length(vec3(t.contextCentre)));
    vec2 chord = hvxSphereChord(vec3(t.contextCentre), t.contextCentre.w - margin, origin, dir);
    return chord.x <= chord.y ? vec2(chord.x, along - margin) : none;
}

// Focus and context sampling (ToolSet::FocalProbe::contextStep): the stretch of a ray in which
// it samples every dt, as hvxProbeChord; the whole ray (every sample) without the focal probe
// or with a step of 1.
HVX_FN vec2 hvxFocusChord(HvxTools t, int hvxBits, vec3 origin, vec3 dir) {
    if (!HVX_TOOL_ON(HVX_FOCAL_BIT) || !(t.focalRot0.w > 1.0f)) return vec2(-1e30f, 1e30f);
    return hvxProbeChord(t, origin, dir);
}

// The step from a sample at t (world mm) to the next: dt within the focus chord, and in the
// context before or behind it k·dt (k = the context step), landing on the last sample before the
// chord rather than past it. Every step is a whole number of dt, so the ray stays on its
// sampling grid; pre-integrated segments take any length. The focus is sampled exactly as with
// k = 1; outside it the probe draws only the ghosted context (Eq. 6.15).
HVX_FN float hvxStepAfter(float t, float dt, vec2 chord, float k) {
    if (k <= 1.0f) return dt;
    if (t >= chord.y) return k * dt;  // behind the probe (or a ray that misses it)
    float ahead = chord.x - t;         // to the chord (no division of the far sentinels)
    if (ahead >= k * dt) return k * dt;
    return max(1.0f, floor(ahead / dt)) * dt;
}

// How many samples long the segment ending at t (the previous sample at tPrev) is when it lies
// in the context, outside the focus chord; 1 in the focus.
HVX_FN float hvxContextSegment(float t, float tPrev, float dt, vec2 chord) {
    return (t < chord.x || t > chord.y) ? (t - tPrev) / dt : 1.0f;
}

// Opacity correction (Max 1995) for a context segment k samples long (hvxStepAfter): the
// enhancers scale one sample's opacity, so a segment's is taken back to one sample's before them
// (hvxOpacityPerSample) and raised to the segment's after (hvxOpacityOfSegment). Without it the
// context's silhouettes fade as the step grows: scaling 1 - (1 - a)^k is not scaling a k times.
HVX_FN float hvxOpacityPerSample(float a, float k) { return k > 1.0f ? 1.0f - pow(max(1.0f - a, 0.0f), 1.0f / k) : a; }
HVX_FN float hvxOpacityOfSegment(float a, float k) { return k > 1.0f ? 1.0f - pow(max(1.0f - a, 0.0f), k) : a; }

// Applies the active tools in a fixed order: clip plane, focal probe, context probe, band
// picker. HVX_TOOL_ON(bit) is a compile-time constant in the shader (a static variant) and a
// test of hvxBits on the CPU. `entered` becomes true at the first sample inside the focal probe,
// where the caller clears what was accumulated in front of it (thesis §6.3.5). The caller
// computes the focal probe's norm at x.p once (hvxFocalNorm) and passes it; gSmooth (the smoothed
// gradient of relief shading) matters only inside the probe: callers may pass g elsewhere.
HVX_FN void hvxEnhance(HVX_INOUT(HvxSample) x, HvxTools t, int hvxBits, float focalNorm, vec3 gSmooth, float hTheta,
                       HVX_INOUT(bool) entered) {
    if (HVX_TOOL_ON(HVX_CLIP_BIT)) hvxClip(x, t.clipPlane, t.clipParams.x, t.clipParams.y, t.clipParams.z);
    if (HVX_TOOL_ON(HVX_FOCAL_BIT)) {
        float norm = focalNorm;
        if (norm <= 1.0f) entered = true;
        vec3 L = -x.v;  // headlight
        float gl2 = dot(x.g, x.g);
        vec3 gDir = gl2 > 0.0f ? x.g / sqrt(gl2) : L;
        if (dot(gDir, L) < 0.0f) gDir = -gDir;
        float sl2 = dot(gSmooth, gSmooth);
        vec3 nSmooth = sl2 > 0.0f ? gSmooth / sqrt(sl2) : gDir;
        float ndl = dot(gDir, L);
        float lambda = t.shading.x + t.shading.y * ndl + t.shading.z * pow(ndl, t.shading.w);   // Eq. 6.5
        float relief = hvxRelief(L, gDir, nSmooth, t.shading.x, t.shading.y, t.focalStyle.z);  // Eq. 6.14
        hvxFocalProbe(x, norm, t.focalParams.y, t.focalParams.x, t.focalParams.z, t.focalParams.w, t.focalStyle.x,
                      t.focalStyle.y, lambda, relief, hTheta);
    }
    if (HVX_TOOL_ON(HVX_CONTEXT_BIT))
        hvxContextProbe(x, vec3(t.contextCentre), t.contextCentre.w, vec3(t.contextAxis), t.contextParams.x,
                        t.contextParams.y, t.contextParams.z, t.contextParams.w);
    if (HVX_TOOL_ON(HVX_BAND_BIT)) hvxBandPicker(x, t.band, vec3(t.bandAxis), t.bandParams.x, t.bandParams.y);
}
