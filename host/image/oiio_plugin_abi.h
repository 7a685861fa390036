// The C interface of libray_oiio.so, the module that holds every use of OpenImageIO
// (host/image/oiio_plugin.cpp). ray loads it with dlopen only when it meets an image that
// is neither PNG nor JPEG (png_codec.h says why), so this header is the whole contract
// between the two: plain C types, no C++ objects across the boundary.
//
// Every function that can fail returns 0 and writes a message (without the file name) into
// `error`, `errorSize` bytes including the terminating zero; success returns 1.
#pragma once

#include <stddef.h>

extern "C" {

// A decoder opened on a file: its size and channel count, read before anything is decoded.
struct RayOiioImageInfo {
    int width, height, channels;
};

// Opens the file with the reader of `format` (an extension such as "tga"), that reader
// alone; with none (NULL or ""), OpenImageIO chooses by the name and then tries every
// reader it has. *handle receives the decoder, released by rayOiioClose.
typedef int (*RayOiioOpen)(const char* path, const char* format, void** handle, RayOiioImageInfo* info, char* error,
                           size_t errorSize);
// Decodes the whole image as width × height × 3 floats (v / max for integer formats; grey
// copied to RGB, alpha dropped) into rgb.
typedef int (*RayOiioReadRgb)(void* handle, float* rgb, char* error, size_t errorSize);
typedef void (*RayOiioClose)(void* handle);
// 1 when this OpenImageIO build has a writer for the path's extension.
typedef int (*RayOiioCanWrite)(const char* path);
// Writes width × height × 3 samples, floats (asFloat = 1) or bytes, in the format the path's
// extension names. The caller writes to a temporary file and renames it.
typedef int (*RayOiioWrite)(const char* path, int width, int height, int asFloat, const void* samples, char* error,
                            size_t errorSize);

}  // extern "C"

// The exported symbol names, one per typedef above.
#define RAY_OIIO_OPEN "ray_oiio_open"
#define RAY_OIIO_READ_RGB "ray_oiio_read_rgb"
#define RAY_OIIO_CLOSE "ray_oiio_close"
#define RAY_OIIO_CAN_WRITE "ray_oiio_can_write"
#define RAY_OIIO_WRITE "ray_oiio_write"
