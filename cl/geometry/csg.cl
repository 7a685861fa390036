/* Constructive solid geometry (host/scene/csg.h; the reference: host/reference/csg.cpp).
 *
 * Along the ray each operand's solid is one span (every operand is convex), from where the
 * line enters it to where it leaves, over the whole line (negative t too, so a ray starting
 * inside an operand needs no special case). The object's postfix program combines span lists
 * on an explicit stack of RAY_CSG_MAX_STACK lists of at most RAY_CSG_MAX_OPERANDS spans
 * (lists of m and n spans combine into at most m + n, and the host refuses objects with more
 * operands or a deeper stack), with no recursion. The combined solid's surface is where its
 * spans begin and end: the first such boundary in (0, hit->t) is the hit.
 *
 * A boundary is kept as its t and a code, the operand's record index in the object's
 * program · 2 + (1 where the ray leaves that operand): the normal and the part are
 * recomputed for the one boundary that is hit, which keeps the stack small. */

#define RAY_CSG_BOUNDARIES (2 * RAY_CSG_MAX_OPERANDS)
#define RAY_CSG_SLIVER 1e-5f /* host/scene/csg.h kCsgSliver: thinner spans and gaps are rounding */

static inline bool csgSliver(float t0, float t1) {
    return t1 - t0 <= RAY_CSG_SLIVER * fmax(fabs(t0), fabs(t1));
}

/* The nearest surface point of a unit convex primitive from o along d (t > 0). */
static inline bool csgNearestSurface(int type, float3 o, float3 d, float* t, int* part, float3* normal) {
    if (!convexShape(type)) return false; /* the loader refuses other operands */
    ShapeHit h = {RAY_INFINITY, 0, (float3)(0.0f)};
    intersectConvexShape(type, o, d, &h);
    *t = h.best;
    *part = h.part;
    *normal = h.normal;
    return h.best < RAY_INFINITY;
}

/* Where the line origin + t·direction crosses an operand's surface on entering it
 * (leaving = 0) or on leaving it (leaving = 1), with that surface's part and outward object
 * normal. The primitive intersectors find the nearest hit ahead of a ray; started from a
 * point before the operand's unit box (after it, looking back, for the exit) they find the
 * entry (the exit) of the whole line. The start lies a quarter of the box outside it, far
 * more than the rounding of moving the origin there. */
static inline bool csgCrossing(__global const RayPrimitive* operand, float3 origin, float3 direction, int leaving, float* t,
                        int* part, float3* normal) {
    float3 o = transformPoint(operand->worldToObject, origin);
    float3 d = transformVector(operand->worldToObject, direction);
    float3 inverse = safeInverse(d);
    float3 t0 = (-0.5f - o) * inverse, t1 = (0.5f - o) * inverse;
    float3 lo = fmin(t0, t1), hi = fmax(t0, t1);
    float boxEnter = fmax(fmax(lo.x, lo.y), lo.z), boxLeave = fmin(fmin(hi.x, hi.y), hi.z);
    if (!(boxEnter <= boxLeave)) return false;
    float margin = 0.25f / length(d);
    float start = leaving ? boxLeave + margin : boxEnter - margin;
    float s;
    if (!csgNearestSurface(operand->type, o + start * d, leaving ? -d : d, &s, part, normal)) return false;
    *t = leaving ? start - s : start + s;
    return true;
}

/* The span list of one operand: two boundaries, or none where the line misses or grazes
 * it. Codes are relative to the object's program, whose records number fewer than 128
 * (RAY_CSG_MAX_OPERANDS operands and one operator fewer), so a code fits a byte. */
static inline int csgOperandBoundaries(__global const RayPrimitive* prims, int index, int program, float3 origin,
                                       float3 direction, float* times, uchar* codes) {
    float enter, leave;
    int part;
    float3 normal;
    if (!csgCrossing(&prims[index], origin, direction, 0, &enter, &part, &normal)) return 0;
    if (!csgCrossing(&prims[index], origin, direction, 1, &leave, &part, &normal)) return 0;
    if (!(leave > enter) || !isfinite(enter) || !isfinite(leave)) return 0; /* as the reference */
    times[0] = enter;
    codes[0] = (uchar)((index - program) * 2);
    times[1] = leave;
    codes[1] = (uchar)((index - program) * 2 + 1);
    return 2;
}

static inline bool csgInside(int operation, bool a, bool b) {
    if (operation == RAY_CSG_UNION) return a || b;
    if (operation == RAY_CSG_INTERSECTION) return a && b;
    return a && !b; /* RAY_CSG_DIFFERENCE */
}

/* Merges list b (countB boundaries from times[countA]) into list a before it, by t, in place:
 * each of b's boundaries moves back past a's later ones (at most countA · countB moves, and
 * lists are short). Within a list t strictly increases (an operand's list is one span with
 * enter < leave; a combination keeps a subsequence of the distinct t it walks, see
 * csgCombine), so a boundary of b stops at b's previous one, and at equal t a's stays first. */
static inline void csgMergeByTime(int countA, int countB, float* times, uchar* codes) {
    for (int k = countA; k < countA + countB; ++k) {
        float t = times[k];
        uchar code = codes[k];
        int at = k;
        for (; at > 0 && times[at - 1] > t; --at) {
            times[at] = times[at - 1];
            codes[at] = codes[at - 1];
        }
        times[at] = t;
        codes[at] = code;
    }
}

/* Combines list a (countA boundaries) and list b, which starts at times[countA], into
 * times[0..], in place; returns the result's count. Boundaries at the same t are taken
 * together, and a result boundary on both surfaces is b's (the operand written later:
 * SPEC §4, coincident surfaces), as host/reference/csg.cpp combineCsgSpans does.
 *
 * The lists are first merged by t (csgMergeByTime); the walk then reads them in the order a
 * two-list walk would, telling b's boundaries by their codes: b's operands come after a's
 * in the postfix program, so every code of b exceeds every code of a. Counting each list's
 * boundaries read gives inside-ness (odd: inside), and at a t of both lists a's boundary
 * comes first, with b's next (the result keeps a's t there: equal to b's, it could differ
 * only in the sign of a zero, which no comparison sees). Each step reads at least one
 * boundary and writes at most one, so the result never overtakes what is still unread, and
 * never outgrows the two lists' room. */
static inline int csgCombine(int operation, int countA, int countB, float* times, uchar* codes) {
    int firstCodeOfB = 256; /* above every code (a byte): with b empty, all are a's */
    for (int k = countA; k < countA + countB; ++k) firstCodeOfB = min(firstCodeOfB, (int)codes[k]);
    csgMergeByTime(countA, countB, times, codes);
    int i = 0, j = 0, count = 0; /* boundaries of a and of b read; boundaries of the result */
    bool inside = false;
    for (int k = 0; k < countA + countB;) {
        float t = times[k];
        int code = codes[k++];
        if (code >= firstCodeOfB) {
            ++j;
        } else {
            ++i;
            if (k < countA + countB && times[k] == t) { /* b's, as a's next one is later */
                code = codes[k++];
                ++j;
            }
        }
        bool now = csgInside(operation, (i & 1) != 0, (j & 1) != 0);
        if (now == inside) continue;
        inside = now;
        /* A sliver of a gap (entering just after the last exit) or of a span (leaving just
         * after the last entry) takes back that boundary instead. */
        if (count > 0 && csgSliver(times[count - 1], t)) {
            --count;
            continue;
        }
        times[count] = t;
        codes[count] = (uchar)code;
        ++count;
    }
    return count;
}

/* The object's postfix program runs on one array of boundaries holding the stack's lists
 * end to end: an operand's list (at most two boundaries) is added at the end; an operator
 * combines the last two lists into the first of them. Every operand adds at most two
 * boundaries and a combination never adds any, so RAY_CSG_BOUNDARIES hold the whole stack
 * (5 bytes a boundary, 320 in all); a combination works in place, with no copy. */
RAY_INLINED_ON_GPU
void intersectCsg(__global const RayPrimitive* prims, __global const RayPrimitive* csg, float3 origin, float3 direction,
                  Hit* hit) {
    float times[RAY_CSG_BOUNDARIES];
    uchar codes[RAY_CSG_BOUNDARIES];
    int start[RAY_CSG_MAX_STACK + 1]; /* list k is times[start[k] .. start[k + 1]) */
    int top = 0;
    start[0] = 0;
    int first = csg->geometry;
    for (int step = first; prims[step].type != RAY_CSG_END; ++step) {
        int kind = prims[step].type;
        if (kind < RAY_CSG_UNION) {
            if (top >= RAY_CSG_MAX_STACK) return; /* the host never packs such a program */
            int at = start[top];
            start[top + 1] = at + csgOperandBoundaries(prims, step, first, origin, direction, times + at, codes + at);
            ++top;
            continue;
        }
        if (top < 2) return;
        int a = start[top - 2], countA = start[top - 1] - a, countB = start[top] - start[top - 1];
        start[top - 1] = a + csgCombine(kind, countA, countB, times + a, codes + a);
        --top;
    }
    if (top != 1) return;
    /* A boundary at exactly hit->t wins when the object is listed after the primitive hit
     * so far (the program's operand records carry the object's order). */
    const float limit = hitLimit(hit->t, hit->primitive, hit->order, prims[first].order);
    for (int k = 0; k < start[1]; ++k) {
        float t = times[k];
        if (!(t < limit)) return;
        if (!(t > 0.0f)) continue;
        int operand = first + (codes[k] >> 1), leaving = codes[k] & 1;
        float tAgain;
        int part;
        float3 normal;
        if (!csgCrossing(&prims[operand], origin, direction, leaving, &tAgain, &part, &normal)) return;
        /* Even boundaries enter the result. Where a subtracted operand is entered the result
         * is left (and the other way round): its outward normal turns to face out of the result. */
        bool entersResult = (k & 1) == 0;
        if (entersResult == (leaving != 0)) normal = -normal;
        hit->t = t;
        hit->primitive = operand;
        hit->order = prims[operand].order;
        hit->part = part;
        hit->objectPoint = transformPoint(prims[operand].worldToObject, origin) +
                           t * transformVector(prims[operand].worldToObject, direction);
        hit->objectNormal = normal;
        hit->barycentric = (float2)(0.0f);
        return;
    }
}
