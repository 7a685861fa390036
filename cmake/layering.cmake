# The layering check (scripts/check_layers.py): every target of this folder with its links
# and sources goes to a manifest, build/layers.txt, from which the script finds includes of
# a layer that the including target does not link, cycles, and files of no layer. The
# links in CMakeLists.txt are thus the only statement of the layering.
#
# It runs in the build (target check_layers, part of `all`: an upward include fails the
# build) and in CTest (test layering, which also checks that docs/architecture.md shows
# the current graph; test layering_selftest shows that the checker finds what it should).

set(RAY_LAYER_MANIFEST ${CMAKE_BINARY_DIR}/layers.txt)
get_property(ray_targets DIRECTORY ${CMAKE_SOURCE_DIR} PROPERTY BUILDSYSTEM_TARGETS)
set(manifest "source_dir\t${CMAKE_SOURCE_DIR}\nbinary_dir\t${CMAKE_BINARY_DIR}\n")
get_target_property(ray_include_dirs rayheaders INTERFACE_INCLUDE_DIRECTORIES)
foreach(dir IN LISTS ray_include_dirs)
  string(APPEND manifest "include_dir\t${dir}\n")
endforeach()
set(ray_checked_sources "")
foreach(target IN LISTS ray_targets)
  string(APPEND manifest "target\t${target}\n")
  foreach(kind_property IN ITEMS "link;LINK_LIBRARIES" "interface;INTERFACE_LINK_LIBRARIES")
    list(GET kind_property 0 kind)
    list(GET kind_property 1 property)
    get_target_property(links ${target} ${property})
    if(links)
      foreach(link IN LISTS links)
        string(APPEND manifest "${kind}\t${target}\t${link}\n")
      endforeach()
    endif()
  endforeach()
  get_target_property(sources ${target} SOURCES)
  if(sources)
    foreach(source IN LISTS sources)
      if(source MATCHES "^\\$<")
        continue()  # $<TARGET_OBJECTS:...>: another target's files
      endif()
      cmake_path(ABSOLUTE_PATH source BASE_DIRECTORY ${CMAKE_SOURCE_DIR} NORMALIZE)
      string(APPEND manifest "source\t${target}\t${source}\n")
      cmake_path(IS_PREFIX CMAKE_SOURCE_DIR ${source} in_source_tree)
      cmake_path(IS_PREFIX CMAKE_BINARY_DIR ${source} in_build_tree)
      if(in_source_tree AND NOT in_build_tree)
        list(APPEND ray_checked_sources ${source})
      endif()
    endforeach()
  endif()
endforeach()
# Written only when it changes, so that an unchanged manifest reruns nothing.
file(WRITE ${RAY_LAYER_MANIFEST}.new "${manifest}")
configure_file(${RAY_LAYER_MANIFEST}.new ${RAY_LAYER_MANIFEST} COPYONLY)

find_package(Python3 COMPONENTS Interpreter)
set(RAY_CHECK_LAYERS ${CMAKE_SOURCE_DIR}/scripts/check_layers.py)
if(Python3_FOUND)
  add_custom_command(
    OUTPUT ${CMAKE_BINARY_DIR}/layers.checked
    COMMAND ${Python3_EXECUTABLE} ${RAY_CHECK_LAYERS} ${RAY_LAYER_MANIFEST}
    COMMAND ${CMAKE_COMMAND} -E touch ${CMAKE_BINARY_DIR}/layers.checked
    DEPENDS ${RAY_CHECK_LAYERS} ${RAY_LAYER_MANIFEST} ${ray_checked_sources}
    COMMENT "Checking the layers' includes against their links"
    VERBATIM)
  add_custom_target(check_layers ALL DEPENDS ${CMAKE_BINARY_DIR}/layers.checked)
else()
  message(STATUS "Python 3 not found: the layering check (scripts/check_layers.py) does not run")
endif()

if(RAY_BUILD_TESTS)
  if(Python3_FOUND)
    add_test(NAME layering
      COMMAND ${Python3_EXECUTABLE} ${RAY_CHECK_LAYERS} ${RAY_LAYER_MANIFEST} --docs ${CMAKE_SOURCE_DIR}/docs/architecture.md)
    add_test(NAME layering_selftest COMMAND ${Python3_EXECUTABLE} ${RAY_CHECK_LAYERS} --self-test)
  else()
    add_test(NAME layering COMMAND ${CMAKE_COMMAND} -E echo "SKIPPED: Python 3 not found")
    set_tests_properties(layering PROPERTIES SKIP_REGULAR_EXPRESSION "SKIPPED:")
  endif()
endif()
