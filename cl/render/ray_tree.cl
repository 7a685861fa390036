/* A camera ray's tree of rays (SPEC §4: a reflected and a refracted branch a hit) as an
 * explicit stack, since OpenCL C has no recursion: its frames, the rays they spawn, and the
 * weights and media that follow from the path to a frame. The walk over it is
 * cl/render/tree_walk.cl, the shading that spawns the rays cl/render/hit_shading.cl. */

#ifndef RAY_MAX_FRAMES
#define RAY_MAX_FRAMES 5 /* ray-tree frames, at least max depth + 1: the host passes its bucket (kernelFrames) */
#endif

/* A float3 kept in 12 bytes: in a private struct a float3 takes 16, and private memory is
 * what a GPU has least of. Only loads and stores change: the arithmetic stays on float3. */
typedef struct {
    float x, y, z;
} PackedFloat3;

static inline PackedFloat3 packFloat3(float3 v) {
    PackedFloat3 packed = {v.x, v.y, v.z};
    return packed;
}

static inline float3 unpackFloat3(PackedFloat3 packed) { return (float3)(packed.x, packed.y, packed.z); }

/* How a child ray's media (cl/shading/optics.cl) follow from its parent's: a reflected ray, or a
 * refracted one under total internal reflection, stays in its parent's; a refracted ray
 * enters the object (pushes its ior) or leaves it (pops). Kept instead of the media
 * themselves, which mediaOf rebuilds. */
#define RAY_MEDIUM_SAME 0
#define RAY_MEDIUM_ENTERED 1
#define RAY_MEDIUM_LEFT 2

/* A ray a hit spawns, kept until it is traced: its weight in its parent's color and its
 * medium change (the kind in its frame). Its time is the camera sample's, given as it is
 * traced. */
typedef struct {
    PackedFloat3 origin, direction;
    PackedFloat3 weight; /* ks·Or or kt·Ot (times R or 1 − R with --fresnel) */
    float enteredIor;    /* the ior it pushes when its medium change is RAY_MEDIUM_ENTERED */
} ChildRay;

/* One ray of the tree awaiting its children; its depth is its index in the stack. Its
 * color is folded into its parent, clamped to [0, 1] and weighted, once all of its
 * children are folded into it (SPEC §4: I_r is clamped before it is weighted). Its first
 * child is written straight into the frame above it and the ray traced next, and pushed at
 * once, so only the second is kept (RayTree): private memory is what a GPU has least of. */
typedef struct {
    PackedFloat3 color;          /* local shading plus the children folded in so far */
    PackedFloat3 weightInParent; /* ks·Or (or kt·Ot) of the parent for this ray */
    float enteredIor;            /* the ior this ray pushes if its medium is RAY_MEDIUM_ENTERED */
    uchar medium;                /* this ray's medium change from its parent's (RAY_MEDIUM_*) */
    uchar secondMedium;          /* the second child's */
    uchar childCount, nextChild; /* 0..2 */
} Frame;

/* The ray tree's stack: the frames, and the second child of each frame that can spawn
 * (every frame but the last), traced once the first's tree is folded in. */
typedef struct {
    Frame frames[RAY_MAX_FRAMES];
    ChildRay seconds[RAY_MAX_FRAMES > 1 ? RAY_MAX_FRAMES - 1 : 1];
} RayTree;

/* Whether a frame at `depth` spawns no child: the bounce limit (--depth, a launch
 * parameter), or the last frame the kernel was built with (RAY_MAX_FRAMES, the host's bucket,
 * at least --depth + 1), so that the first child always has a frame above to go to. */
static inline bool atDepthLimit(const RayRenderParams* params, int depth) {
    return depth >= params->maxDepth || depth + 1 >= RAY_MAX_FRAMES;
}

/* Records a ray spawned by `frame`: the first goes straight into the frame above (`above`)
 * and the ray traced next (`aboveRay`; its time stays: every ray of the tree sees the
 * scene at its camera sample's time), the second into the frame. */
static inline void spawnChild(RayTree* tree, int depth, Ray* aboveRay, float3 origin, float3 direction,
                              float3 weight, uchar medium, float enteredIor) {
    Frame* frame = &tree->frames[depth];
    if (frame->childCount++ == 0) {
        Frame* above = &tree->frames[depth + 1]; /* in the stack: atDepthLimit */
        aboveRay->origin = origin;
        aboveRay->direction = direction;
        above->weightInParent = packFloat3(weight);
        above->medium = medium;
        above->enteredIor = enteredIor;
        return;
    }
    ChildRay* second = &tree->seconds[depth];
    second->origin = packFloat3(origin);
    second->direction = packFloat3(direction);
    second->weight = packFloat3(weight);
    second->enteredIor = enteredIor;
    frame->secondMedium = medium;
}

/* The path weight of frame `top`: the product of the weights from the camera ray to it,
 * multiplied in the order the tree spawned them, so that it is the same to the bit as a
 * product kept in each frame; recomputed, because private memory is what a GPU has least of. */
static inline float3 pathWeightOf(const Frame* stack, int top) {
    float3 weight = (float3)(1.0f);
    for (int k = 1; k <= top; ++k) weight *= unpackFloat3(stack[k].weightInParent);
    return weight;
}

/* The media of frame `top`'s ray: the camera's (air) changed by each frame's medium change
 * from the camera ray up, as iorBeyond changed them when the frames were spawned. Rebuilt
 * where a transparent surface needs them, because private memory is what a GPU has least
 * of (and most rays never meet one). */
static inline MediumStack mediaOf(const Frame* stack, int top) {
    MediumStack media;
    media.count = 0; /* the camera is in air */
    for (int k = 1; k <= top; ++k) {
        if (stack[k].medium == RAY_MEDIUM_SAME) continue;
        MediumStack beyond;
        iorBeyond(&media, stack[k].medium == RAY_MEDIUM_ENTERED, stack[k].enteredIor, &beyond);
        media = beyond;
    }
    return media;
}

/* A frame about to be shaded: no color and no children yet. */
static inline void startFrame(Frame* frame) {
    frame->color = packFloat3((float3)(0.0f));
    frame->childCount = 0;
    frame->nextChild = 0;
}

/* Adds a shaded frame's direct lighting, summed (LightSamples), to its color. */
static inline void addLights(Frame* frame, const LightSamples* lights) {
    frame->color = packFloat3(unpackFloat3(frame->color) + lights->sum);
}

