// Pre-integrated transfer function (thesis Eq. 3.1) from the tables of core/TransferFunction;
// for a label map (HVX_LABELS) a segment takes its end sample's own entry (TransferFunction::entry).
#ifndef HVX_LABELS
#define HVX_LABELS 0
#endif
float tfPosition(float v) { return clamp((v - tfRange.x) / (tfRange.y - tfRange.x) * 4096.0, 0.0, 4096.0); }

vec4 tfSample(float v) {
    float p = clamp(tfPosition(v) - 0.5, 0.0, 4095.0);
    int i = int(p);
    int j = min(i + 1, 4095);
    return mix(tfF[i], tfF[j], p - float(i));
}

vec4 tfIntegralAt(float v) {
    float p = tfPosition(v);
    int i = min(int(p), 4095);
    return tfI[i] + tfF[i] * (p - float(i));
}

vec4 tfSegment(float a, float b) {
#if HVX_LABELS
    return tfF[min(int(tfPosition(b)), 4095)];
#endif
    float pa = tfPosition(a), pb = tfPosition(b);
    if (abs(pb - pa) > 1e-3) return (tfIntegralAt(b) - tfIntegralAt(a)) / (pb - pa);
    return tfSample(0.5 * (a + b));
}

// The same segment's extinction alone (tfSegment(a, b).w, in the same float operations), from
// one 8-byte entry per end: most samples stop here, transparent. `pa` and `ia` are position and
// opacity integral at a, carried from the previous sample; `pb` and `ib` are returned for b.
float tfOpacityIntegralAt(float p) {
    int i = min(int(p), 4095);
    vec2 e = tfA[i];
    return e.x + e.y * (p - float(i));
}

float tfSegmentOpacity(float a, float b, float pa, float ia, float pb, float ib) {
#if HVX_LABELS
    return tfA[min(int(pb), 4095)].y;
#endif
    if (abs(pb - pa) > 1e-3) return (ib - ia) / (pb - pa);
    float p = clamp(tfPosition(0.5 * (a + b)) - 0.5, 0.0, 4095.0);
    int i = int(p);
    int j = min(i + 1, 4095);
    return mix(tfA[i].y, tfA[j].y, p - float(i));
}
