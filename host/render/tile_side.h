// The side of a frame's square tiles, chosen here for every renderer of tiles (the OpenCL
// engine for one process, rank 0 for the ranks of a distributed render), and the samples a
// pixel takes, which it depends on.
#pragma once

#include "render/render_settings.h"
#include "scene/scene.h"

namespace ray {

// Short launches keep GPU watchdogs quiet and let progress move.
constexpr int kDefaultTileSide = 128;

// `requested` when the caller names one (--tile-size; at least 8), else cancellableTileSize
// when the frame can be cancelled, else kDefaultTileSide.
int frameTileSide(const RenderSettings& settings, const Scene& scene, bool cancellable, int requested = 0);

// The side of the square tiles of a cancellable frame, a multiple of the 8x8 work-group
// from 8 to kDefaultTileSide: small enough that the few tiles already queued when it is
// cancelled finish within about a second on PoCL, given the samples per pixel and the
// shadow rays of the scene's area lights.
int cancellableTileSize(const RenderSettings& settings, const Scene& scene);

// The most samples a pixel takes with the settings' antialiasing (also for the statistics).
int maxSamplesPerPixel(const RenderSettings& settings);

}  // namespace ray
