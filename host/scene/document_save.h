// Saving a document with the one writer's options (core/atomic_file.h): a read-only file
// replaced when the user said so. scene_document.h's saveDocument is this with the
// defaults; this header is apart so that the many users of scene_document.h need not see
// the writer's.
#pragma once

#include <filesystem>

#include "core/atomic_file.h"
#include "scene/scene_document.h"

namespace ray {

// saveDocument (scene_document.h) with `options`. Throws InputError, OutputRefused or
// FileWriteError.
void saveDocument(const SceneDocument& document, const Resources& resources, const std::filesystem::path& target,
                  const WriteOptions& options);

}  // namespace ray
