/* Antialiasing (SPEC §3): where a pixel's samples go and how their colors make the pixel's. */

static inline float largestChannel(float3 v) { return fmax(v.x, fmax(v.y, v.z)); }

/* Whether two samples differ by more than RAY_COURSE_AA_CONTRAST in some channel. */
static inline bool courseDiffers(float3 a, float3 b) {
    return largestChannel(fabs(a - b)) > RAY_COURSE_AA_CONTRAST;
}

/* Which quadrants of a, b, c, d the course subdivides: bit 0 a, 1 b, 2 c, 3 d. */
static inline int courseSubdivided(float3 a, float3 b, float3 c, float3 d) {
    int bits = 0;
    if (courseDiffers(a, b)) bits |= 1 | 2;
    if (courseDiffers(c, d)) bits |= 4 | 8;
    if (courseDiffers(a, c)) bits |= 1 | 4;
    if (courseDiffers(b, d)) bits |= 2 | 8;
    return bits;
}

/* Every antialiasing mode as a state machine that hands out one sample position at a time
 * and takes that sample's color back, so that the whole pixel is one loop around one
 * traceSample call (renderTile). A GPU compiler inlines every call: written as recursion-
 * free nested functions, the course's three levels alone held 84 copies of the trace.
 *
 * The course's adaptive antialiasing (docs/conventions.md, "Antialiasing";
 * host/reference/course_sampling.cpp): value(square, level) samples the centres of the
 * square's four quadrants a (top left), b (top right), c (bottom left), d (bottom right);
 * where level < 3, a quadrant whose sample differs from a horizontal or vertical
 * neighbour's (a–b, c–d, a–c, b–d; not the diagonals) by more than RAY_COURSE_AA_CONTRAST
 * in some channel is replaced by value(quadrant, level + 1). The result is the mean of the
 * four. The machine walks that recursion depth first with an explicit stack of levels, so
 * samples are taken (and numbered) in the order the recursive form takes them.
 *
 * --aa stratified: an n×n grid (n = floor(sqrt(samples))), one jittered sample per cell
 * warped through the tent reconstruction filter (rayTentOffset), averaged.
 * --aa adaptive (host/reference/course_sampling.h sampleAdaptive): 2×2 jittered samples
 * (numbers 0..3); where they spread by more than RAY_ADAPTIVE_CONTRAST, a k×k jittered grid
 * more (numbers 4..); the mean of every sample taken. With samples <= 4, stratified.
 * --aa off: one unclamped sample at the pixel's centre (for float outputs). */
#define RAY_COURSE_LEVELS 3

/* The course's machine, one entry per level of its recursion. A level's square is the
 * quadrant of its parent's that it replaces (courseCorner). */
typedef struct {
    PackedFloat3 quadrant[RAY_COURSE_LEVELS][4]; /* the (clamped) values of a, b, c, d */
    uchar taken[RAY_COURSE_LEVELS];    /* samples taken at the level: 0..4, then 5 once judged */
    uchar toRefine[RAY_COURSE_LEVELS]; /* quadrants still to replace by the next level (bits) */
    uchar refining[RAY_COURSE_LEVELS]; /* the quadrant the next level replaces */
    char level;                        /* the level being sampled; -1 when the pixel is done */
} CourseSampler;

/* The jittered modes (--aa off counts its one sample here). Plain float3: the course's
 * machine is larger, and so sets the union's size. */
typedef struct {
    float3 sum, low, high; /* of the samples taken; low and high of the first four (adaptive) */
    int count, side;       /* samples taken; the side of the grid being sampled */
    int extra;             /* adaptive: whether the k×k grid is being taken */
} JitteredSampler;

/* A pixel uses one mode (params->antialias), so the two machines share their memory. */
typedef union {
    CourseSampler course;
    JitteredSampler jittered;
} PixelSampler;

static inline void startSampler(PixelSampler* s, const RayRenderParams* params) {
    if (params->antialias == RAY_AA_COURSE) {
        s->course.level = 0;
        s->course.taken[0] = 0;
        return;
    }
    JitteredSampler* j = &s->jittered;
    j->count = 0;
    /* --aa off counts its one sample and nothing else: the rest is a per-pixel cost there,
     * paid by pixels that miss everything too */
    if (params->antialias == RAY_AA_OFF) return;
    j->sum = (float3)(0.0f);
    j->low = (float3)(INFINITY);
    j->high = (float3)(-INFINITY);
    j->extra = 0;
    int samples = params->samples;
    bool stratified = params->antialias == RAY_AA_STRATIFIED || samples <= 4;
    j->side = stratified ? max(1, (int)floor(sqrt((float)samples))) : 2;
}

/* The top left corner of the square that the course's level `level` samples: each level
 * above it moved it to the quadrant it refines, by half that level's size. */
static inline float2 courseCorner(const CourseSampler* s, int level) {
    float2 corner = (float2)(0.0f);
    for (int l = 0; l < level; ++l) {
        int q = s->refining[l];
        float halfSize = 1.0f / (float)(1 << l) * 0.5f;
        corner += (float2)((q & 1) ? halfSize : 0.0f, (q & 2) ? halfSize : 0.0f);
    }
    return corner;
}

static inline float3 quadrantValue(const CourseSampler* s, int level, int q) {
    return unpackFloat3(s->quadrant[level][q]);
}

/* The course's machine: the next sample position, or false when the pixel's value is
 * known (in *color). A level whose four samples are in is judged once; its quadrants to
 * refine are then entered one by one, and a finished level hands its mean to its parent. */
static inline bool nextCoursePosition(CourseSampler* s, float2* position, float3* color) {
    while (s->level >= 0) {
        int l = s->level;
        float size = 1.0f / (float)(1 << l);
        if (s->taken[l] < 4) {
            int q = s->taken[l];
            float quarter = size * 0.25f;
            *position = courseCorner(s, l) +
                        (float2)((q & 1) ? 3.0f * quarter : quarter, (q & 2) ? 3.0f * quarter : quarter);
            return true;
        }
        if (s->taken[l] == 4) { /* judged once, before any quadrant is replaced */
            s->toRefine[l] = l + 1 < RAY_COURSE_LEVELS
                                 ? courseSubdivided(quadrantValue(s, l, 0), quadrantValue(s, l, 1),
                                                    quadrantValue(s, l, 2), quadrantValue(s, l, 3))
                                 : 0;
            s->taken[l] = 5;
        }
        if (s->toRefine[l] != 0) {
            int q = 0;
            while (!(s->toRefine[l] & (1 << q))) ++q; /* a, b, c, d in turn */
            s->toRefine[l] &= ~(1 << q);
            s->refining[l] = q;
            s->taken[l + 1] = 0;
            s->level = l + 1;
            continue;
        }
        float3 mean = 0.25f * (quadrantValue(s, l, 0) + quadrantValue(s, l, 1) + quadrantValue(s, l, 2) +
                               quadrantValue(s, l, 3));
        s->level = l - 1;
        if (l == 0) *color = mean;
        else s->quadrant[l - 1][s->refining[l - 1]] = packFloat3(mean);
    }
    return false;
}

/* The jittered modes: sample number s->count (its random numbers pick the jitter) in cell
 * `cell` of the side×side grid being sampled, or false when the pixel's value is known
 * (in *color). */
static inline bool nextJitteredPosition(JitteredSampler* s, const RayRenderParams* params, uint pixel,
                                        float2* position, float3* color) {
    int cell = s->extra ? s->count - 4 : s->count;
    if (cell >= s->side * s->side) {
        bool refine = params->antialias == RAY_AA_ADAPTIVE && params->samples > 4 && !s->extra &&
                      largestChannel(s->high - s->low) > RAY_ADAPTIVE_CONTRAST;
        if (!refine) {
            *color = s->sum / (float)s->count;
            return false;
        }
        s->extra = 1;
        s->side = max(1, (int)floor(sqrt((float)params->samples)));
        cell = 0;
    }
    uint seed = (uint)params->seed, number = (uint)s->count;
    float side = (float)s->side;
    *position = (float2)(rayTentOffset(((float)(cell % s->side) + rayRandom(pixel, number, 0u, seed)) / side),
                         rayTentOffset(((float)(cell / s->side) + rayRandom(pixel, number, 1u, seed)) / side));
    return true;
}

/* The position of the pixel's next sample, in [0, 1)², or false when the pixel is done
 * and its color is in *color. */
static inline bool nextSamplePosition(PixelSampler* s, const RayRenderParams* params, uint pixel, float2* position,
                                      float3* color) {
    switch (params->antialias) {
        case RAY_AA_COURSE: return nextCoursePosition(&s->course, position, color);
        case RAY_AA_STRATIFIED:
        case RAY_AA_ADAPTIVE: return nextJitteredPosition(&s->jittered, params, pixel, position, color);
        default:
            if (s->jittered.count > 0) return false; /* addSample gave *color */
            *position = (float2)(0.5f);
            return true;
    }
}

/* Takes the color of the sample at the position nextSamplePosition gave: clamped, except
 * with --aa off, whose one sample is the pixel's unclamped color (*pixelColor). */
static inline void addSample(PixelSampler* s, const RayRenderParams* params, float3 color, float3* pixelColor) {
    if (params->antialias == RAY_AA_OFF) {
        *pixelColor = color;
        s->jittered.count++;
        return;
    }
    color = clamp(color, 0.0f, 1.0f);
    if (params->antialias == RAY_AA_COURSE) {
        CourseSampler* c = &s->course;
        int l = c->level;
        c->quadrant[l][c->taken[l]++] = packFloat3(color);
        return;
    }
    JitteredSampler* j = &s->jittered;
    j->sum += color;
    if (j->count < 4) {
        j->low = fmin(j->low, color);
        j->high = fmax(j->high, color);
    }
    j->count++;
}

