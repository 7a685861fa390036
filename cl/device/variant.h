/* What this build of the kernel runs: the one switch, chosen by the host for its device
 * (host/opencl/kernel_variant.cpp) and passed to the build as one define, -DRAY_CPU_LANES=n.
 *
 *  - Absent: a device whose work-items run in SIMT lanes, a GPU (or Mesa's llvmpipe, which
 *    runs them as a GPU does). A work-item renders one pixel (cl/render/pixel.cl) and walks
 *    the four-wide tree testing its children a box at a time (cl/device/gpu/); every function
 *    on the trace path is inlined, as GPU drivers build OpenCL.
 *  - 1: a CPU device whose work-items are threads (PoCL), one pixel a work-item. A ray walks
 *    the sixteen-wide tree (cl/device/cpu/walk.cl), testing a node's children at once in
 *    vector registers, and some helpers stay calls.
 *  - 4, 8 or 16: the same CPU device, a work-item rendering a block of that many pixels whose
 *    camera and shadow rays it traces as packets in OpenCL vector types
 *    (cl/device/cpu/packet_*.cl); the rest of each pixel's ray tree as with 1.
 *
 * Everything outside cl/device/ is the same source for every device. From the switch follow
 * RAY_DEVICE_CPU (defined for 1, 4, 8, 16), RAY_PACKET_WIDTH (4, 8 or 16) and the two
 * inlining attributes below. */
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
 * loop that calls it: inlined there, the loop holds more state and spills it
 * (docs/performance.md, "The walk a ray at a time on CPUs").
 * RAY_INLINED_ON_GPU: a function on the trace path (traceSample, transmitFromInside,
 * traceCameraRay, shadeFrame, traceBvh, the intersectors). Where LLVM keeps one a call on a
 * GPU, each call level has a frame of its own and saves the registers live across it, in
 * scratch memory (docs/performance.md, "The kernel on GPUs"). */
#ifdef RAY_DEVICE_CPU
#define RAY_CALL_ON_CPU __attribute__((noinline))
#define RAY_INLINED_ON_GPU
#else
#define RAY_CALL_ON_CPU inline __attribute__((always_inline))
#define RAY_INLINED_ON_GPU __attribute__((always_inline))
#endif

#endif
