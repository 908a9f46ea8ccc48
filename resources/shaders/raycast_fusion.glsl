// Fusion (HVX_FUSION): a second volume laid over the first in the same ray march, each walked
// through its own index and sampled from its own pool. The steps, classification, shading and
// compositing are those of core/reference/FusedRayCaster.cpp, operation for operation.
#ifndef HVX_LABELS_B
#define HVX_LABELS_B 0
#endif
#define TF_GRADIENT_ENTRIES 256  // core::TransferFunction::kGradientEntries

// A leaf's sampler in either pool (brickPool's leafSampler with the pool's own layout).
LeafSampler fusedLeafSampler(bool second, uvec4 nd, vec3 leafLo) {
    uvec4 brk = second ? brickB : brick;
    uint depth = nd.y & 0xFFu;
    float slot = float(nd.x), row = float(brk.w), layer = float(second ? fusionB.x : image.z);
    float z = floor((slot + 0.5) / layer);
    float inLayer = slot - z * layer;
    float y = floor((inLayer + 0.5) / row);
    vec3 cell = vec3(inLayer - y * row, y, z) * float(brk.z);
    vec3 texel = 1.0 / vec3(second ? textureSize(brickPoolB, 0) : textureSize(brickPool, 0));
    float s = float(brk.x) * float(1u << depth);
    vec3 lo = floor(leafLo * float(1u << depth) + 0.5) * float(brk.x);
    LeafSampler L;
    L.scale = vec3(s) * texel;
    L.offset = (cell + float(brk.y) - lo) * texel;
    L.texLo = (cell + 0.5) * texel;
    L.texHi = (cell + float(brk.z) - 0.5) * texel;
    SlotRecord record = slotRecords[(second ? fusionB.y : 0u) + nd.x];
    L.decode = record.decode;
    L.h = 1.0 / s;
    L.visible = record.visible;
    L.leafLo = leafLo;
    L.cell = 0.25 / float(1u << depth);
    return L;
}

float fusedFetch(bool second, vec3 tex) {
    return second ? texture(brickPoolB, tex).r : texture(brickPool, tex).r;
}

float fusedSampleLinear(bool second, LeafSampler L, vec3 p) {
    return fusedFetch(second, clamp(p * L.scale + L.offset, L.texLo, L.texHi)) * L.decode.x + L.decode.y;
}

float fusedSample(bool second, LeafSampler L, vec3 p) {
    bool labels = second ? HVX_LABELS_B != 0 : HVX_LABELS != 0;
    if (!labels) return fusedSampleLinear(second, L, p);
    vec3 size = vec3(second ? textureSize(brickPoolB, 0) : textureSize(brickPool, 0));
    vec3 centre = (floor((p * L.scale + L.offset) * size) + 0.5) / size;
    return fusedFetch(second, clamp(centre, L.texLo, L.texHi)) * L.decode.x + L.decode.y;
}

vec3 fusedGradient(bool second, LeafSampler L, vec3 p) {
    float h = L.h;
    return vec3(fusedSampleLinear(second, L, p + vec3(h, 0, 0)) - fusedSampleLinear(second, L, p - vec3(h, 0, 0)),
                fusedSampleLinear(second, L, p + vec3(0, h, 0)) - fusedSampleLinear(second, L, p - vec3(0, h, 0)),
                fusedSampleLinear(second, L, p + vec3(0, 0, h)) - fusedSampleLinear(second, L, p - vec3(0, 0, h))) /
           (2.0 * h);
}

// Either volume's pre-integrated table (the second's entries follow the first's), as
// transfer_function.glsl; a label map takes its end sample's own entry.
float fusedPosition(bool second, float v) {
    vec2 r = second ? tfRangeB.xy : tfRange.xy;
    return clamp((v - r.x) / (r.y - r.x) * 4096.0, 0.0, 4096.0);
}

vec4 fusedTfSample(bool second, float v) {
    int f = second ? 4096 : 0;
    float p = clamp(fusedPosition(second, v) - 0.5, 0.0, 4095.0);
    int i = int(p);
    int j = min(i + 1, 4095);
    return mix(tfF[f + i], tfF[f + j], p - float(i));
}

vec4 fusedSegment(bool second, float a, float b) {
    int f = second ? 4096 : 0, F = second ? 4097 : 0;
    float pa = fusedPosition(second, a), pb = fusedPosition(second, b);
    if (second ? HVX_LABELS_B != 0 : HVX_LABELS != 0) return tfF[f + min(int(pb), 4095)];
    if (abs(pb - pa) > 1e-3) {
        int ia = min(int(pa), 4095), ib = min(int(pb), 4095);
        vec4 Fa = tfI[F + ia] + tfF[f + ia] * (pa - float(ia));
        vec4 Fb = tfI[F + ib] + tfF[f + ib] * (pb - float(ib));
        return (Fb - Fa) / (pb - pa);
    }
    return fusedTfSample(second, 0.5 * (a + b));
}

// fusedSegment(...).w alone, from one 8-byte entry per end (tfA): most samples stop here.
float fusedExtinction(bool second, float a, float b) {
    int F = second ? 4097 : 0;
    float pa = fusedPosition(second, a), pb = fusedPosition(second, b);
    if (second ? HVX_LABELS_B != 0 : HVX_LABELS != 0) return tfA[F + min(int(pb), 4095)].y;
    if (abs(pb - pa) > 1e-3) {
        int ia = min(int(pa), 4095), ib = min(int(pb), 4095);
        vec2 ea = tfA[F + ia], eb = tfA[F + ib];
        return ((eb.x + eb.y * (pb - float(ib))) - (ea.x + ea.y * (pa - float(ia)))) / (pb - pa);
    }
    float p = clamp(fusedPosition(second, 0.5 * (a + b)) - 0.5, 0.0, 4095.0);
    int i = int(p);
    int j = min(i + 1, 4095);
    return mix(tfA[F + i].y, tfA[F + j].y, p - float(i));
}

// One volume's walk along the ray (core/reference/FusedRayCaster.cpp's Cursor).
struct FusedCursor {
    vec3 o, d, inv;
    float octPerMm, nudge, tLo, tHi, tExit, dt, sPrev, tPrev;
    float quietUntil;  // after a step: where the stretch that cannot show ends (t when it can show)
    bool empty, havePrev;
    LeafSampler L;
};

void fusedLocate(bool second, inout FusedCursor k, float t) {
    if (t < k.tLo || t >= k.tHi) {
        k.empty = true;
        k.tExit = t < k.tLo ? k.tLo : 1.0 / 0.0;
        return;
    }
    uint base = second ? fusionB.z : 0u;
    uint n = 0u;
    vec3 lo = vec3(0.0), hi = vec3(1.0);
    hvxDescend(base, n, lo, hi, k.o + (t + k.nudge) * k.d);
    float tExit = 0.0;
    hvxExitFace(k.o, k.inv, lo, hi, tExit);
    k.tExit = min(tExit, k.tHi);
    uvec4 nd = hvxNodes[base + n];
    k.empty = nd.x == HVX_NONE;
    if (k.empty) return;
    if (extra.z > 0.5) atomicAdd(rayCounts[base + n], 1u);  // visibility feedback, per volume
    k.L = fusedLeafSampler(second, nd, lo);
    float voxel = 1.0 / (float(second ? brickB.x : brick.x) * float(1u << (nd.y & 0xFFu)));
    k.dt = tfRange.w * voxel / k.octPerMm;
}

FusedCursor fusedCursor(mat4 toOctree, vec3 boxLo, vec3 boxHi, float rootVoxelInv, vec3 ow, vec3 dw) {
    FusedCursor k;
    k.o = (toOctree * vec4(ow, 1.0)).xyz;
    k.d = mat3(toOctree) * dw;
    k.tLo = 0.0;
    k.tHi = 1.0 / 0.0;
    for (int a = 0; a < 3; ++a) {
        if (abs(k.d[a]) < 1e-15) {
            if (k.o[a] < boxLo[a] || k.o[a] > boxHi[a]) k.tHi = -1.0;
            continue;
        }
        float ta = (boxLo[a] - k.o[a]) / k.d[a], tb = (boxHi[a] - k.o[a]) / k.d[a];
        k.tLo = max(k.tLo, min(ta, tb));
        k.tHi = min(k.tHi, max(ta, tb));
    }
    if (!(k.tHi > k.tLo)) k.tHi = -1.0 / 0.0;
    k.inv = rayInverse(k.d);
    k.octPerMm = length(k.d);
    k.nudge = 1e-3 * rootVoxelInv / max(1e-12, k.octPerMm);
    k.tExit = -1.0 / 0.0;
    k.empty = true;
    k.havePrev = false;
    k.dt = 1.0 / 0.0;
    k.sPrev = 0.0;
    k.tPrev = 0.0;
    return k;
}

// Samples one volume at t, classifies the segment from its previous sample and shades it;
// returns the segment's opacity (0 where the volume is empty or transparent) and its colour.
float fusedStep(bool second, inout FusedCursor k, float t, float dt, float t0, vec3 dw, out vec3 c) {
    c = vec3(0.0);
    k.quietUntil = t;
    if (k.empty) {
        k.havePrev = false;
        k.quietUntil = k.tExit;
        return 0.0;
    }
    vec3 p = k.o + t * k.d;
    // A cell that cannot show (core::BrickCells) adds nothing, nor does any segment between two
    // of its samples: the volume is not sampled there, and the segment into the next cell that
    // can show starts from a fresh sample before it, as a dense march would have it.
    ivec3 cell = clamp(ivec3(floor((p - k.L.leafLo) / k.L.cell)), ivec3(0), ivec3(3));
    int bit = cell.x + 4 * cell.y + 16 * cell.z;
    if (((bit < 32 ? k.L.visible.x : k.L.visible.y) & (1u << uint(bit & 31))) == 0u) {
        k.havePrev = false;
        vec3 lo = k.L.leafLo + vec3(cell) * k.L.cell;
        vec3 far = max((lo - k.o) * k.inv, (lo + k.L.cell - k.o) * k.inv);
        k.quietUntil = min(min(far.x, far.y), far.z);
        return 0.0;
    }
    float s = fusedSample(second, k.L, p);
    if (!k.havePrev && t - dt >= max(t0, k.tLo)) {  // after empty space: the brick's border sample
        k.sPrev = fusedSample(second, k.L, k.o + (t - dt) * k.d);
        k.tPrev = t - dt;
        k.havePrev = true;
    }
    float a = 0.0;
    if (k.havePrev) {
        a = 1.0 - exp(-fusedExtinction(second, k.sPrev, s) * (t - k.tPrev));
        if (a > 1e-6) {
            vec4 f = fusedSegment(second, k.sPrev, s);
            vec3 base = f.rgb / f.w;
            c = base;
#if HVX_GRADIENT_OPACITY
            float largest = second ? tfRangeB.z : enhance.w;  // 0: this volume has no curve
            bool scaled = largest > 0.0;
#else
            bool scaled = false;
#endif
            if (extra.y > 0.5 || scaled) {  // this volume's own gradient: its opacity curve, then headlight Phong
                mat4 toOctree = second ? patientToOctreeB : patientToOctree;
                vec3 g = transpose(mat3(toOctree)) * fusedGradient(second, k.L, p);
                float len = length(g);
#if HVX_GRADIENT_OPACITY
                a = gradientOpacityOf(second ? TF_GRADIENT_ENTRIES : 0, largest, a, len);
#endif
                if (extra.y > 0.5) {
                    float ndl = len < 1e-9 ? 0.0 : abs(dot(g / len, -dw));
                    c = len < 1e-9 ? base * (shading.x + shading.y)
                                   : base * (shading.x + shading.y * ndl) + vec3(shading.z * pow(ndl, shading.w));
                }
            }
        } else {
            a = 0.0;
        }
    }
    k.sPrev = s;
    k.tPrev = t;
    k.havePrev = true;
    return a;
}

vec4 castRayFused(vec3 ow, vec3 dw, out float depth) {
    depth = 1.0 / 0.0;
    FusedCursor A = fusedCursor(patientToOctree, cropLo.xyz, cropHi.xyz, extent.w, ow, dw);
    FusedCursor B = fusedCursor(patientToOctreeB, vec3(0.0), extentB.xyz, extentB.w, ow, dw);
    float t0 = A.tLo, t1 = A.tHi;
    if (!(t1 > t0)) return vec4(0.0);
    vec3 color = vec3(0.0);
    float alpha = 0.0;
    bool hit = false;
    float t = t0;
    fusedLocate(false, A, t);
    fusedLocate(true, B, t);
    for (int guard = 0; guard < 4194304 && t <= t1; ++guard) {
        if (t >= A.tExit) fusedLocate(false, A, t);
        if (t >= B.tExit) fusedLocate(true, B, t);
        if (A.empty && B.empty) {  // nothing in either volume: on to the nearer leaf
            float next = min(A.tExit, B.tExit);
            if (!(next > t)) next = t + A.nudge;
            if (next > t1) break;
            t = next;
            A.havePrev = false;
            B.havePrev = false;
            continue;
        }
        float dt = min(A.empty ? 1.0 / 0.0 : A.dt, B.empty ? 1.0 / 0.0 : B.dt);
        vec3 cA, cB;
        float aA = fusedStep(false, A, t, dt, t0, dw, cA);
        float aB = fusedStep(true, B, t, dt, t0, dw, cB);
        float both = 1.0 - (1.0 - aA) * (1.0 - aB);
        if (both > 1e-6) {
            vec3 mixed = (aA * cA + aB * cB) / (aA + aB);
            color += (1.0 - alpha) * both * mixed;
            alpha += (1.0 - alpha) * both;
            if (!hit && alpha > 0.02) { hit = true; depth = t; }
            if (alpha >= tfRange.z) break;
        } else if (A.quietUntil > t && B.quietUntil > t) {
            // Neither volume can show before the nearer of their quiet stretches ends: land on
            // the last sample before it, as the single-volume march steps over a cell.
            float k = ceil((min(A.quietUntil, B.quietUntil) - t) / dt);
            if (k >= 3.0) t += (k - 2.0) * dt;
        }
        t += dt;
    }
    return vec4(color, alpha);
}
