# ray(1) and the bash and zsh completions, written at build time by ray_reference
# (host/main/reference_main.cpp) from the commands' CLI11 parsers and their --help text
# (app/command_reference.h), so that they never drift from `ray --help`. ray_reference
# fails, naming the option, when a parser takes an option that its --help does not list,
# or the reverse. Installed by cmake/Packaging.cmake; checked by tests/reference_pages.py.
add_executable(ray_reference host/main/reference_main.cpp)
target_compile_options(ray_reference PRIVATE ${RAY_WARNINGS})
target_link_libraries(ray_reference PRIVATE ${RAY_LIBRARY_LAYERS} host_viewer)

set(RAY_MANUAL_PAGE ${CMAKE_BINARY_DIR}/ray.1)
set(RAY_MANUAL_PAGE_GZ ${CMAKE_BINARY_DIR}/ray.1.gz)
set(RAY_BASH_COMPLETION ${CMAKE_BINARY_DIR}/completions/ray)
set(RAY_ZSH_COMPLETION ${CMAKE_BINARY_DIR}/completions/_ray)
find_program(RAY_GZIP gzip REQUIRED)
add_custom_command(
  OUTPUT ${RAY_MANUAL_PAGE} ${RAY_MANUAL_PAGE_GZ}
  COMMAND ray_reference man ${RAY_MANUAL_PAGE}
  # Debian's manual pages are compressed; -n: no name or time inside, the same bytes each build.
  COMMAND ${RAY_GZIP} -9nf -k ${RAY_MANUAL_PAGE}
  DEPENDS ray_reference
  COMMENT "Writing ray(1) from ray's command line"
  VERBATIM)
add_custom_command(
  OUTPUT ${RAY_BASH_COMPLETION} ${RAY_ZSH_COMPLETION}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_BINARY_DIR}/completions
  COMMAND ray_reference bash ${RAY_BASH_COMPLETION}
  COMMAND ray_reference zsh ${RAY_ZSH_COMPLETION}
  DEPENDS ray_reference
  COMMENT "Writing ray's bash and zsh completions from its command line"
  VERBATIM)
add_custom_target(ray_reference_pages ALL
  DEPENDS ${RAY_MANUAL_PAGE} ${RAY_MANUAL_PAGE_GZ} ${RAY_BASH_COMPLETION} ${RAY_ZSH_COMPLETION})
