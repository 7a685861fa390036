/* What this build of the kernel runs: the one switch, chosen by the host for its device
 * (host/opencl/kernel_variant.cpp) and passed to the build as one define, -DRAY_CPU_LANES=n.
 *
 *  - Absent: a device whose work-items run in SIMT lanes, a GPU (or Mesa's llvmpipe, which
 *    runs them as a GPU does). A work-item renders one pixel (renderPixel, cl/render.cl) and
 *    walks the four-wide tree testing its children a box at a time (cl/intersect.cl); every
 *    function on the trace path is inlined, as GPU drivers build OpenCL.
 *  - 1: a CPU device whose work-items are threads (PoCL), one pixel a work-item. A ray walks
 *    the sixteen-wide tree (traceBvh, cl/intersect.cl), testing a node's children at once in
 *    vector registers, and some helpers stay calls.
 *  - 4, 8 or 16: the same CPU device, a work-item rendering a block of that many pixels whose
 *    camera and shadow rays it traces as packets in OpenCL vector types (cl/packet_*.cl);
 *    the rest of each pixel's ray tree as with 1.
 *
 * From the switch follow RAY_DEVICE_CPU (defined for 1, 4, 8, 16), RAY_PACKET_WIDTH (4, 8 or
 * 16) and the two inlining attributes below. */
#ifndef RAY_DEVICE_VARIANT_H
#define RAY_DEVICE_VARIANT_H

#ifdef RAY_PACKET_WIDTH
#error "RAY_PACKET_WIDTH follows from RAY_CPU_LANES (cl/device/variant.h): pass that"
#endif
#ifdef RAY_CPU_LANES
#define RAY_DEVICE_CPU 1
#if RAY_CPU_LANES == 4 || RAY_CPU_LANES == 8 || RAY_CPU_LANES == 16
#define RAY_PACKET_WIDTH RAY_CPU_LANES
#elif RAY_CPU_LANES != 1
#error "RAY_CPU_LANES must be 1, 4, 8 or 16"
#endif
#endif

/* How the kernel's functions are built: on a CPU, as calls where that is faster; on a GPU,
 * inlined into the one kernel.
 *
 * RAY_CALL_ON_CPU: a helper that PoCL's CPU code runs faster as a call than inlined into the
 * loop that calls it (with intersectPrimitive inlined, traceBvh's walk held more state
 * and spilled it: chess took 5% more instructions).
 * RAY_INLINED_ON_GPU: a function on the trace path (traceSample, transmitFromInside,
 * traceCameraRay, shadeFrame, traceBvh, the intersectors). Where LLVM keeps one a call,
 * each call level has a frame of its own and saves the registers live across it: LLVM's
 * own build of renderTile for gfx906 (scripts/kernel_resources.py, "calls") kept
 * shadeFrame, intersectCsg and transmitFromInside calls and needed 2,336 B of scratch a
 * work-item; with the path inlined, 1,936 B. */
#ifdef RAY_DEVICE_CPU
#define RAY_CALL_ON_CPU __attribute__((noinline))
#define RAY_INLINED_ON_GPU
#else
#define RAY_CALL_ON_CPU inline __attribute__((always_inline))
#define RAY_INLINED_ON_GPU __attribute__((always_inline))
#endif

#endif
