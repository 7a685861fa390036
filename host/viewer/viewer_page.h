// The viewer's page (web/index.html), embedded into the binary at build time
// (cmake/embed_text.cmake) so that `ray view` serves no file from disk.
#pragma once

namespace ray {
extern const char* const kViewerPage;
}
