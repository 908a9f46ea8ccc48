// Refraction (thesis §3.2.2, Figs 3.4–3.5), written once in the subset of GLSL that C++ also
// compiles (core/appearance/Refraction.h): the ray's direction changes at each integration step
// by Snell's law, the refraction index of each segment coming from the transfer function's
// pre-integrated ν(s) table.
//
// The includer defines HVX_FN (inline in C++, empty in GLSL).

// The unit direction d after passing from a medium of index nu1 into one of index nu2 across
// the boundary whose normal is along the scalar gradient g (either orientation; a gradient of
// ν(s) is parallel to the scalar's). Where Snell's law has no solution (total internal
// reflection) the ray is reflected; with no boundary (g = 0) or no change of index it goes on
// unchanged. In a layered medium the steps keep ν·sin θ, so a slab of constant index offsets a
// ray and lets it leave parallel to how it came in.
HVX_FN vec3 hvxRefractStep(vec3 d, vec3 g, float nu1, float nu2) {
    float len = length(g);
    if (len < 1e-20f || nu1 == nu2) return d;
    vec3 n = g / len;
    if (dot(n, d) > 0.0f) n = -n;  // against the ray, as refract() expects
    vec3 r = refract(d, n, nu1 / nu2);
    if (dot(r, r) == 0.0f) r = reflect(d, n);
    return normalize(r);
}
