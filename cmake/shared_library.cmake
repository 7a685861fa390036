# libray.so: the public API (include/ray/) as a shared library, installed with a CMake
# package (find_package(ray) → ray::ray) and a pkg-config file (ray.pc):
#   cmake --install build --prefix /some/prefix
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

list(TRANSFORM RAY_LIBRARY_LAYERS REPLACE "(.+)" "$<TARGET_OBJECTS:\\1>" OUTPUT_VARIABLE RAY_LIBRARY_OBJECTS)
add_library(libray SHARED ${RAY_LIBRARY_OBJECTS})
set_target_properties(libray PROPERTIES
  OUTPUT_NAME ray EXPORT_NAME ray VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR})
target_include_directories(libray PUBLIC
  $<BUILD_INTERFACE:${CMAKE_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
target_link_libraries(libray PRIVATE ${RAY_DEPENDENCIES})
# Only ray::api is exported (cmake/libray.map); the ray command keeps exporting everything
# for its modules (ENABLE_EXPORTS), from the same objects.
target_link_options(libray PRIVATE "LINKER:--version-script=${CMAKE_SOURCE_DIR}/cmake/libray.map")
set_property(TARGET libray APPEND PROPERTY LINK_DEPENDS ${CMAKE_SOURCE_DIR}/cmake/libray.map)
target_compile_features(libray PUBLIC cxx_std_20)
add_library(ray::ray ALIAS libray)

install(TARGETS libray EXPORT rayTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS ray RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${CMAKE_SOURCE_DIR}/include/ray DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT rayTargets NAMESPACE ray:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ray)

configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/rayConfig.cmake.in
  ${CMAKE_BINARY_DIR}/rayConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ray)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/rayConfigVersion.cmake COMPATIBILITY SameMajorVersion)
install(FILES ${CMAKE_BINARY_DIR}/rayConfig.cmake ${CMAKE_BINARY_DIR}/rayConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ray)

configure_file(${CMAKE_SOURCE_DIR}/cmake/ray.pc.in ${CMAKE_BINARY_DIR}/ray.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/ray.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
