// The viewer's page (web/index.html with its modules bundled in, built by web/build.mjs),
// embedded into the binary at build time (cmake/viewer_page.cmake) so that `ray view`
// serves no file from disk.
#pragma once

namespace ray {
extern const char* const kViewerPage;
// The page's Content-Security-Policy: its own bundled script and style alone may run (by
// their SHA-256), requests go to the viewer alone, and it is never framed.
extern const char* const kViewerPagePolicy;
}  // namespace ray
