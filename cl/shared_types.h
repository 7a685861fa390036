/* The buffer layouts shared by the host (C++) and the kernel (OpenCL C).
 *
 * This header is the single definition of every structure that crosses the host/device
 * boundary. The host includes it from C++ (with the small shim below); the kernel sources
 * are compiled with this header first. Both compilers check every size and offset it relies
 * on (RAY_LAYOUT_CHECK, at the end).
 *
 * Rules that keep the two compilers in agreement:
 *  - a point, direction or color is a float4 read as .xyz, its .w unused (0): no float3,
 *    whose size is 16 in OpenCL C but 12 in a C++ struct of three floats (the one table that
 *    grows with a mesh's triangles, RayTriangleShading, holds float[3] read with vload3
 *    instead, a fifth smaller); a pair of texture
 *    coordinates is a float2; the wide BVH nodes' lanes are float4 / int4 or float16 / int16;
 *  - every other value is a named scalar field (int or float, 4 bytes), in runs that fill
 *    16 bytes, with named padding where a run falls short, so that neither compiler pads;
 *    the host declares a record with {} so that its padding is zero (tables are compared
 *    and uploaded byte for byte);
 *  - integers are ints, never bit-cast into a float (a denormal bit pattern may be flushed
 *    by some devices).
 */
#ifndef RAY_SHARED_TYPES_H
#define RAY_SHARED_TYPES_H

/* OpenCL C, as opposed to the host's C++. Not every OpenCL C compiler defines
 * __OPENCL_VERSION__ (clang for AMD GCN and NVPTX defines only __OPENCL_C_VERSION__). */
#if defined(__OPENCL_VERSION__) || defined(__OPENCL_C_VERSION__)
#define RAY_OPENCL_C 1
#endif

#ifndef RAY_OPENCL_C
#include <cstddef>
#include <cstdint>
namespace ray::gpu {
struct alignas(8) float2 {
    float x = 0, y = 0;
};
struct alignas(16) float4 {
    float x = 0, y = 0, z = 0, w = 0;
};
struct alignas(16) int4 {
    int32_t x = 0, y = 0, z = 0, w = 0;
};
struct alignas(64) float16 {
    float s[16] = {};
};
struct alignas(64) int16 {
    int32_t s[16] = {};
};
#define RAY_STRUCT(name) struct name
/* The tables a ray walks (BVH nodes, primitives) start on a cache line on the host
 * too: a CPU device reads them where they are (CL_MEM_USE_HOST_PTR), and at malloc's 16-byte
 * alignment a 128-byte node would straddle three cache lines instead of two, as it never
 * does in a buffer the driver allocates (PoCL: 128-byte aligned). Their sizes are multiples
 * of 64, so the layout is unchanged. */
#define RAY_TABLE_STRUCT(name) struct alignas(64) name
#define RAY_END_STRUCT(name)
#else
#define RAY_STRUCT(name) typedef struct name
#define RAY_TABLE_STRUCT(name) typedef struct name
#define RAY_END_STRUCT(name) name
#endif

/* Values of RayPrimitive.type; equal to ray::PrimitiveType on the host. */
#define RAY_PRIM_CUBE 0
#define RAY_PRIM_SPHERE 1
#define RAY_PRIM_CYLINDER 2
#define RAY_PRIM_CONE 3
#define RAY_PRIM_TORUS 4
#define RAY_PRIM_MESH 5
#define RAY_PRIM_CSG 6 /* its material is its first operand's, its geometry its program */

/* The torus of SPEC §2: a ring of major radius RAY_TORUS_MAJOR_RADIUS around the y axis, in
 * the xz plane, swept by a circle of radius RAY_TORUS_MINOR_RADIUS. Both renderers and the
 * scene's bounds (host/scene/scene_primitives.cpp) read them from here; floats whose values
 * are exact in double too. */
#define RAY_TORUS_MAJOR_RADIUS 0.375f
#define RAY_TORUS_MINOR_RADIUS 0.125f

/* Constructive solid geometry (host/scene/csg.h, cl/geometry/csg.cl). A csg object's postfix
 * program is a run of records in the primitive buffer, after the primitives the BVH indexes
 * (so no BVH leaf names them), from its record's `geometry` on: an operand step is the
 * operand's own RayPrimitive (its type a RAY_PRIM_* of a convex primitive), an operator step
 * has the type RAY_CSG_UNION, RAY_CSG_INTERSECTION or RAY_CSG_DIFFERENCE, and a record of
 * type RAY_CSG_END ends the program (the rest of those records unused). A hit on a csg
 * object reports the operand record as the hit primitive, so shading reads its transform and
 * material as it does any primitive's. The limits equal ray::kCsgMaxOperands and
 * ray::kCsgMaxStack (checked on the host); the loader refuses objects beyond them. */
#define RAY_CSG_UNION 16
#define RAY_CSG_INTERSECTION 17
#define RAY_CSG_DIFFERENCE 18
#define RAY_CSG_END 19
#define RAY_CSG_MAX_OPERANDS 32
#define RAY_CSG_MAX_STACK 4

/* Values of RayLight.type; equal to ray::LightType on the host. */
#define RAY_LIGHT_POINT 0
#define RAY_LIGHT_DIRECTIONAL 1
#define RAY_LIGHT_SPOT 2
#define RAY_LIGHT_AREA 3

/* Values of RayRenderParams.antialias; equal to ray::AntialiasMode on the host. */
#define RAY_AA_OFF 0
#define RAY_AA_COURSE 1
#define RAY_AA_STRATIFIED 2
#define RAY_AA_ADAPTIVE 3

/* The antialiasing thresholds (SPEC §3), one definition for both renderers
 * (host/render/render_settings.h): the course mode subdivides a quadrant whose sample differs
 * from a horizontal or vertical neighbour's by more than RAY_COURSE_AA_CONTRAST, 50 8-bit
 * levels, in some channel (docs/conventions.md, "Antialiasing");
 * --aa adaptive adds its k×k pass where the first four spread by more than
 * RAY_ADAPTIVE_CONTRAST, a tenth of the range, well above the 8-bit step, so that the
 * flat regions of an image stay at four samples. */
#define RAY_COURSE_AA_CONTRAST (50.0f / 255.0f)
#define RAY_ADAPTIVE_CONTRAST 0.1f

/* Bits of RayRenderParams.features: the feature switches of the command line. */
#define RAY_FEATURE_SHADOWS 1
#define RAY_FEATURE_REFLECTIONS 2
#define RAY_FEATURE_REFRACTION 4
#define RAY_FEATURE_TEXTURES 8
/* (--no-dof sets the lens radius to 0 instead of a bit.) */
#define RAY_FEATURE_COURSE_FILTER 16 /* --texture-filter course: bilinear, texel corners at integers (SPEC §5) */
#define RAY_FEATURE_BILINEAR 32
#define RAY_FEATURE_TRILINEAR 64 /* with BILINEAR: mipmapped, footprint of host/reference/texture_filtering.h */
#define RAY_FEATURE_FRESNEL 128  /* --fresnel: transparent surfaces weight their branches by exact Fresnel (SPEC §4) */
#define RAY_FEATURE_COURSE_MESHES 256 /* --course-meshes: mesh hits keyed and placed by t·|M⁻¹d|, face normals */
#define RAY_FEATURE_LENS_DISK 512 /* --dof disk: one random point of the lens disk a sample, not the course's grid */

/* The course's depth of field (SPEC §3): a sample is the mean of the clamped rays from a
 * RAY_LENS_GRID_SIDE² grid of lens points spaced aperture/2 (the lens radius), both renderers. */
#define RAY_LENS_GRID_SIDE 5

/* A node of the four-wide BVH the kernel walks: 128 bytes, two cache lines.
 *
 * The host builds a two-wide tree (host/accel/bvh.h) and collapses it
 * (host/accel/wide_bvh.h): a node keeps up to four of its binary descendants as children,
 * so a ray visits about half as many nodes, and one fetch tests four boxes with float4
 * operations laid out structure-of-arrays: lane c of minX..maxZ is child c's box, and the
 * slab distances of all four come from six subtracts and six multiplies.
 *
 * index, count: lane c describes child c. A count of 0 means an inner node at that index;
 * a count > 0 a leaf holding primitives [index, index + count) of the primitive buffer
 * (stored in BVH order, as the binary tree's leaves order them). An absent child has index
 * -1 (its bounds are empty, but the walk tests the index: a slab test can "hit" an empty
 * box). Node 0 is the root. Leaves and children are in the binary tree's order, absent
 * children last: the primitives under a node are one range, from its leftmost leaf to its
 * rightmost (cl/traversal/wide_walk.cl leafRange, which a walk whose short stack overflows uses). */
RAY_TABLE_STRUCT(RayWideBvhNode) {
    float4 minX, maxX;
    float4 minY, maxY;
    float4 minZ, maxZ;
    int4 index;
    int4 count;
} RAY_END_STRUCT(RayWideBvhNode);

/* A node of the sixteen-wide BVH over the scene's primitives that CPU devices walk a ray at
 * a time (cl/device/cpu/walk.cl): 512 bytes, eight cache lines.
 *
 * Why a second tree: on a CPU a ray's walk is a chain of steps, each waiting on the node it
 * loads and on the branches its box tests decide, and the single-ray walk of reflected rays
 * and their shadow rays was most of the render on large scenes (docs/performance.md). With
 * sixteen children a node, one float16 slab test (an AVX-512 register, two AVX ones) takes
 * a ray past what four-wide nodes take two steps for, so a walk takes about half the steps
 * (docs/performance.md, "The walk a ray at a time on CPUs"). GPUs keep the four-wide tree, whose small nodes suit their registers, and so does
 * the packet walk (cl/device/cpu/packet_trace.cl), whose box tests grow with the children a node has.
 *
 * The host collapses the four-wide scene tree into it (host/accel/wide_bvh.h). Lanes as in
 * RayWideBvhNode: lane c of minX..maxZ is child c's box, index and count its link. A count
 * of 0: an inner node of this table; > 0: a leaf of the primitive buffer; -1: node `index`
 * of the four-wide table, where the walk goes on (a subtree too small to fill a node of its
 * own: the four-wide tree's lowest nodes hold two leaves of one sphere each, and sixteen-
 * wide nodes of them would be mostly absent children, a table several times larger). Index -1: absent,
 * absent children last. Node 0 is the root. Meshes keep their trees in RayWideBvhNode. */
#define RAY_CPU_BVH_WIDTH 16
RAY_TABLE_STRUCT(RayCpuBvhNode) {
    float16 minX, maxX;
    float16 minY, maxY;
    float16 minZ, maxZ;
    int16 index;
    int16 count;
} RAY_END_STRUCT(RayCpuBvhNode);

/* A primitive instance: 64 bytes.
 * worldToObject: rows of the 3×4 world-to-object transform (translation in .w). The normal
 * transform (inverse transpose of object-to-world) is the transpose of its 3×3 part, so it
 * needs no storage of its own.
 * order: the instance's place in the scene's list of primitives; in a csg operand's record,
 * the place of (the first instance of) its csg object. Hits at exactly the same distance
 * (coplanar faces) go to the higher order, the primitive listed later, as in the reference
 * renderer (hitLimit, cl/geometry/shapes.cl), so that the image does not depend on the order
 * in which a BVH visits them. */
RAY_TABLE_STRUCT(RayPrimitive) {
    float4 worldToObject[3];
    int type;     /* RAY_PRIM_*, or in a csg program RAY_CSG_* */
    int material; /* index in the materials */
    int order;
    int geometry; /* where its shape is stored: a mesh's root node in the nodes, a csg object's
                     program's first record in the primitives; -1 for the unit shapes */
} RAY_END_STRUCT(RayPrimitive);

/* A mesh leaf's triangles for intersection, four side by side (Embree's triangle4): 144
 * bytes. Lane k of p0x..p0z is triangle k's corner p0, of e1x..e2z its edges e1 = p1 − p0
 * and e2 = p2 − p0, in the mesh's object space; one ray tests the four at once in float4s,
 * a packet each of them for every ray (cl/geometry/triangle_records.cl). A mesh's leaf is one
 * record: its tree is built with leaves of at most RAY_TRIANGLES_PER_RECORD triangles, costed
 * by the record (host/accel/bvh.h leafBlock), so that they are nearly full (3.9 triangles a
 * leaf on a scanned surface). A lane a leaf leaves unused has zero edges, which no ray hits.
 *
 * A triangle's index is its slot, 4 · record + lane: the triangle shading table is indexed
 * by it, and a mesh leaf's node link (index, count) is its first slot and its triangle
 * count. Each mesh's records are stored once, in the order of its own BVH, whose nodes
 * follow the scene's in the node buffer (RayPrimitive.geometry is a mesh instance's root
 * node there). */
#define RAY_TRIANGLES_PER_RECORD 4
RAY_STRUCT(RayTriangle4) {
    float4 p0x, p0y, p0z;
    float4 e1x, e1y, e1z;
    float4 e2x, e2y, e2z;
} RAY_END_STRUCT(RayTriangle4);

/* What shading needs of a triangle, one a slot of the triangle records (RayTriangle4; an
 * unused slot's zeros): 80 bytes. The corner normals (the file's vn, or the face normal for
 * every corner of a face without them) and texture coordinates ((0, 0) without vt). Its
 * directions are three floats each, read with vload3, not float4s: this table grows with a
 * mesh's triangles (a million: 80 MB, where float4s would make it 96). */
RAY_STRUCT(RayTriangleShading) {
    float normal0[3], normal1[3], normal2[3];
    float uTangent[3];  /* the unit direction in which u grows over the triangle (bump mapping; 0 without vt) */
    float2 uv0, uv1, uv2;
    float uvDensity;    /* texture units per object unit (trilinear filtering) */
    float uvHandedness; /* ±1: whether the texture is mirrored on the triangle (bump mapping) */
} RAY_END_STRUCT(RayTriangleShading);

/* A material: 144 bytes. */
RAY_STRUCT(RayMaterial) {
    float4 diffuse, ambient, specular, reflective, transparent, emissive;
    float blend;     /* of the texture over the diffuse color (SPEC §5) */
    float shininess;
    float ior;       /* index of refraction */
    float padding0;
    float2 textureRepeat, bumpRepeat;
    int textureMap;  /* index in the textures; -1: none */
    int bumpMap;     /* index in the textures; -1: none */
    int padding1, padding2;
} RAY_END_STRUCT(RayMaterial);

/* A light: 96 bytes. */
RAY_STRUCT(RayLight) {
    int type;        /* RAY_LIGHT_* */
    int areaSamples; /* an area light's samples per side */
    int padding0, padding1;
    float4 color;
    float4 position;
    float4 direction; /* unit length: where a directional, spot or area light points */
    /* the attenuation 1/(c1 + c2 d + c3 d²) of a light at distance d */
    float constantAttenuation, linearAttenuation, quadraticAttenuation;
    float padding2;
    float outerAngle, innerAngle; /* a spot light's cones, in radians */
    float width, height;          /* an area light's rectangle */
} RAY_END_STRUCT(RayLight);

/* A texture in the texel buffer: texels [offset, offset + width·height) of uchar4 (RGBA8,
 * row 0 at the top), values v/255 exactly as the course reads them. With trilinear
 * filtering its mipmap levels follow, back to back: level k is max(1, width >> k) ×
 * max(1, height >> k) (host/reference/texture_filtering.h); otherwise the level count is 1. */
RAY_STRUCT(RayTexture) {
    int offset; /* in texels */
    int width, height;
    int levels; /* mipmap levels, ≥ 1 */
} RAY_END_STRUCT(RayTexture);

/* A texel of the texel buffer: red, green, blue, alpha (RGBA8), 4 bytes. */
#ifndef RAY_OPENCL_C
struct RayTexel {
    uint8_t x = 0, y = 0, z = 0, w = 0;
};
#else
typedef uchar4 RayTexel;
#endif

/* The tile a launch renders: its top left pixel in the image, and its size. */
RAY_STRUCT(RayTile) {
    int x0, y0;
    int width, height;
} RAY_END_STRUCT(RayTile);

/* Everything else a launch needs: 160 bytes, passed by value. */
RAY_STRUCT(RayRenderParams) {
    float4 eye;      /* camera position */
    float4 right;    /* U · w: the view plane's half-width axis (SPEC §3) */
    float4 up;       /* V · h: its half-height axis */
    float4 forward;  /* unit look direction */
    float lensRadius;       /* 0: a pinhole */
    float focalDistance;
    float shutter;          /* 0: no motion blur */
    float pixelSpreadAngle; /* trilinear filtering's footprint */
    float ka, kd, ks, kt;   /* the global coefficients (SPEC §4) */
    float weightThreshold;  /* --threshold */
    float rayOffset;        /* the clearance of secondary and shadow rays (surfaceClearance) */
    float padding0, padding1;
    int width, height;      /* the image's */
    int antialias;          /* RAY_AA_* */
    int samples;
    int maxDepth;
    int features;           /* RAY_FEATURE_* bits */
    int lightCount;
    int seed;
    RayTile tile;
} RAY_END_STRUCT(RayRenderParams);

/* The block of pixels one work-item renders (width × height): one pixel, or in a packet
 * build (RAY_PACKET_WIDTH lanes, CPU devices: cl/device/variant.h,
 * cl/device/cpu/packet_render.cl) a block of that many pixels, 4 × 4 for 16 lanes, 4 × 2
 * for 8, 2 × 2 for 4. The host sizes its launches and tile outputs by it
 * (host/opencl/device_slot.cpp tileEntries, device_worker.cpp). */
#define RAY_PIXEL_BLOCK_WIDTH(lanes) ((lanes) >= 8 ? 4 : (lanes) >= 4 ? 2 : 1)
#define RAY_PIXEL_BLOCK_HEIGHT(lanes) ((lanes) / RAY_PIXEL_BLOCK_WIDTH(lanes))

/* Which devices' kernels read a scene buffer (READERS in RAY_SCENE_BUFFERS): every device's,
 * or a CPU device's alone (cl/device/variant.h); the host packs and uploads a table that only
 * CPU devices read for CPU devices alone, and gives the others one unused element. */
#define RAY_EVERY_DEVICE 0
#define RAY_CPU_DEVICES 1

/* The scene's buffers: the one list of them, X(element type, name, what it holds, READERS),
 * in the order of renderTile's parameters. Each entry becomes, on the host (C++, types in
 * ray::gpu),
 *  - a table of PackedScene (host/opencl/scene_packing.h): std::vector<TYPE> NAME, which
 *    packScene fills; its visit in PackedScene::forEachBuffer, from which totalBytes, the
 *    device limits (WHAT names the buffer in the message), the device's buffers, their
 *    uploads and the kernel's arguments (host/opencl/kernel_arguments.h) all follow;
 * and in the kernel (OpenCL C),
 *  - a parameter of renderTile (cl/kernel.cl): __global const TYPE* NAME, after the launch
 *    parameters and before the tile's outputs;
 *  - a field of SceneBuffers (cl/shading/shading.cl), which the kernel reads as scene->NAME.
 * To add a buffer: an entry here (its type defined above, the same layout on both sides),
 * code in packScene that fills it, and the kernel code that reads it. Nothing else lists
 * the buffers. The kernel needs at least one element in each (OpenCL refuses empty
 * buffers): an empty table is uploaded as one unused element. */
#define RAY_SCENE_BUFFERS(X)                                                                     \
    /* the four-wide BVH (host/accel/wide_bvh.h): the scene's nodes, then each mesh's */       \
    X(RayWideBvhNode, nodes, "BVH nodes", RAY_EVERY_DEVICE)                                     \
    /* the scene's tree again, sixteen-wide, for CPU devices' walk a ray at a time */          \
    X(RayCpuBvhNode, cpuNodes, "CPU BVH nodes", RAY_CPU_DEVICES)                                \
    /* in BVH order, then the csg objects' programs */                                          \
    X(RayPrimitive, primitives, "primitives", RAY_EVERY_DEVICE)                                 \
    X(RayMaterial, materials, "materials", RAY_EVERY_DEVICE)                                    \
    X(RayLight, lights, "lights", RAY_EVERY_DEVICE)                                             \
    /* one per Scene::images entry */                                                           \
    X(RayTexture, textures, "texture records", RAY_EVERY_DEVICE)                                \
    /* every texture (and its mipmap levels) back to back */                                    \
    X(RayTexel, texels, "textures", RAY_EVERY_DEVICE)                                           \
    /* every mesh's triangles once, four a record, each mesh's in the order of its own BVH */   \
    X(RayTriangle4, triangles, "mesh triangles", RAY_EVERY_DEVICE)                              \
    X(RayTriangleShading, triangleShading, "mesh normals and texture coordinates", RAY_EVERY_DEVICE) \
    /* each primitive's world-space motion (.xyz), parallel to primitives, or empty when        \
     * nothing moves: a buffer of its own rather than a fifth float4 in RayPrimitive, so that   \
     * static scenes keep their 64-byte (one cache line) primitives, and the kernel reads a     \
     * motion only for a ray whose time is not 0 */                                             \
    X(float4, motions, "motions", RAY_EVERY_DEVICE)

/* Every size and offset the two compilers must agree on, checked by both. */
#ifdef RAY_OPENCL_C
#define RAY_LAYOUT_CHECK(condition) _Static_assert(condition, #condition)
#define RAY_OFFSET_OF(Type, field) __builtin_offsetof(Type, field)
#else
#define RAY_LAYOUT_CHECK(condition) static_assert(condition, #condition)
#define RAY_OFFSET_OF(Type, field) offsetof(Type, field)
#endif
RAY_LAYOUT_CHECK(sizeof(float2) == 8);
RAY_LAYOUT_CHECK(sizeof(float4) == 16);
RAY_LAYOUT_CHECK(sizeof(int4) == 16);
RAY_LAYOUT_CHECK(sizeof(float16) == 64);
RAY_LAYOUT_CHECK(sizeof(int16) == 64);
RAY_LAYOUT_CHECK(sizeof(RayWideBvhNode) == 128);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayWideBvhNode, minY) == 32);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayWideBvhNode, index) == 96);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayWideBvhNode, count) == 112);
RAY_LAYOUT_CHECK(sizeof(RayCpuBvhNode) == 512);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayCpuBvhNode, index) == 384);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayCpuBvhNode, count) == 448);
RAY_LAYOUT_CHECK(sizeof(RayPrimitive) == 64);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayPrimitive, type) == 48);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayPrimitive, geometry) == 60);
RAY_LAYOUT_CHECK(sizeof(RayTriangle4) == 144);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayTriangle4, e1x) == 48);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayTriangle4, e2x) == 96);
RAY_LAYOUT_CHECK(sizeof(RayTriangleShading) == 80);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayTriangleShading, uTangent) == 36);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayTriangleShading, uv0) == 48);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayTriangleShading, uv2) == 64);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayTriangleShading, uvHandedness) == 76);
RAY_LAYOUT_CHECK(sizeof(RayMaterial) == 144);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayMaterial, blend) == 96);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayMaterial, textureRepeat) == 112);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayMaterial, textureMap) == 128);
RAY_LAYOUT_CHECK(sizeof(RayLight) == 96);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayLight, color) == 16);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayLight, constantAttenuation) == 64);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayLight, outerAngle) == 80);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayLight, height) == 92);
RAY_LAYOUT_CHECK(sizeof(RayTexture) == 16);
RAY_LAYOUT_CHECK(sizeof(RayTexel) == 4);
RAY_LAYOUT_CHECK(sizeof(RayTile) == 16);
RAY_LAYOUT_CHECK(sizeof(RayRenderParams) == 160);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayRenderParams, lensRadius) == 64);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayRenderParams, ka) == 80);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayRenderParams, weightThreshold) == 96);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayRenderParams, width) == 112);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayRenderParams, maxDepth) == 128);
RAY_LAYOUT_CHECK(RAY_OFFSET_OF(RayRenderParams, tile) == 144);
#ifndef RAY_OPENCL_C
/* The host's own: the tables a ray walks start on a cache line (RAY_TABLE_STRUCT). */
static_assert(alignof(RayWideBvhNode) == 64 && alignof(RayCpuBvhNode) == 64 && alignof(RayPrimitive) == 64);
#endif
#undef RAY_LAYOUT_CHECK
#undef RAY_OFFSET_OF

#ifndef RAY_OPENCL_C
}  /* namespace ray::gpu */
#endif

#endif
