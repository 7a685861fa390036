// Writing a PixelExplanation: as indented text for the terminal, and as JSON (--json, and
// the viewer's click-a-pixel panel).
#pragma once

#include <ostream>

#include <nlohmann/json.hpp>

#include "explain/pixel_explanation.h"

namespace ray {

void printExplanation(const PixelExplanation& explanation, const Scene& scene, std::ostream& out);

nlohmann::json explanationJson(const PixelExplanation& explanation, const Scene& scene);

}  // namespace ray
