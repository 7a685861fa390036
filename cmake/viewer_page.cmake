# The viewer's page (host/viewer/web/), built at build time and embedded like the kernel,
# so that ray view serves nothing from disk. Its libraries (three.js) and the bundler
# (esbuild) come from the npm registry, pinned by host/viewer/web/package-lock.json:
#   1. npm ci installs exactly the locked versions into BUILD/viewer-web/node_modules (never
#      into the source tree), without running any package's install script;
#   2. build.mjs bundles src/main.js and what it imports into one script, writes it into
#      index.html, and writes the Content-Security-Policy that lets that script alone run;
#   3. embed_page.cmake makes both a C++ source (viewer/viewer_page.h).
# Sets RAY_PAGE_CPP, the generated source.
find_program(RAY_NPM npm)
find_program(RAY_NODE NAMES node nodejs)
if(NOT RAY_NPM OR NOT RAY_NODE)
  message(FATAL_ERROR
    "ray's viewer page is bundled at build time with Node.js and npm, which were not found.\n"
    "Install them (Debian: apt-get install nodejs npm, or run scripts/install-deps.sh), or point "
    "CMake at them: -DRAY_NPM=/path/to/npm -DRAY_NODE=/path/to/node")
endif()

set(RAY_WEB_SOURCE ${CMAKE_SOURCE_DIR}/host/viewer/web)
set(RAY_WEB_BUILD ${CMAKE_BINARY_DIR}/viewer-web)
file(GLOB RAY_WEB_MODULES CONFIGURE_DEPENDS ${RAY_WEB_SOURCE}/src/*.js)

# npm ci reads package.json and the lockfile from the folder it installs into: copies of
# them, so the source tree holds no node_modules. npm writes node_modules/.package-lock.json
# last, which stands for the whole install.
set(RAY_WEB_INSTALLED ${RAY_WEB_BUILD}/node_modules/.package-lock.json)
add_custom_command(
  OUTPUT ${RAY_WEB_INSTALLED}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${RAY_WEB_BUILD}
  COMMAND ${CMAKE_COMMAND} -E copy_if_different ${RAY_WEB_SOURCE}/package.json ${RAY_WEB_SOURCE}/package-lock.json
          ${RAY_WEB_BUILD}
  COMMAND ${RAY_NPM} ci --ignore-scripts --no-audit --no-fund --loglevel=error --prefix ${RAY_WEB_BUILD}
  DEPENDS ${RAY_WEB_SOURCE}/package.json ${RAY_WEB_SOURCE}/package-lock.json
  COMMENT "Installing the viewer page's locked npm packages (npm ci)"
  VERBATIM)

set(RAY_PAGE_HTML ${RAY_WEB_BUILD}/index.html)
set(RAY_PAGE_POLICY ${RAY_WEB_BUILD}/content-security-policy.txt)
add_custom_command(
  OUTPUT ${RAY_PAGE_HTML} ${RAY_PAGE_POLICY}
  COMMAND ${RAY_NODE} ${RAY_WEB_SOURCE}/build.mjs ${RAY_WEB_BUILD}/node_modules ${RAY_PAGE_HTML} ${RAY_PAGE_POLICY}
  DEPENDS ${RAY_WEB_INSTALLED} ${RAY_WEB_SOURCE}/build.mjs ${RAY_WEB_SOURCE}/index.html ${RAY_WEB_MODULES}
  COMMENT "Bundling the viewer's page (esbuild)"
  VERBATIM)

set(RAY_PAGE_CPP ${CMAKE_BINARY_DIR}/generated/viewer_page.cpp)
add_custom_command(
  OUTPUT ${RAY_PAGE_CPP}
  COMMAND ${CMAKE_COMMAND} -DOUTPUT=${RAY_PAGE_CPP} -DINPUT=${RAY_PAGE_HTML} -DPOLICY=${RAY_PAGE_POLICY}
          -P ${CMAKE_SOURCE_DIR}/cmake/embed_page.cmake
  DEPENDS ${RAY_PAGE_HTML} ${RAY_PAGE_POLICY} ${CMAKE_SOURCE_DIR}/cmake/embed_page.cmake
  COMMENT "Embedding the viewer's page"
  VERBATIM)
