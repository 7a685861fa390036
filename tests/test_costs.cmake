# What the long tests cost, in seconds on 2 cores under `ctest -j2` (measured; see
# scripts/test.sh), so that CTest starts the longest first on a fresh clone, before it has
# timings of its own (Testing/Temporary/CTestCostData.txt, which it prefers afterwards).
# Run in the order they are declared, the long script tests came last and ran two at a
# time while the other core had nothing left to do. Tests not listed cost 0: they fill in
# between. Figures within a factor of two are enough; a test renamed here is simply not
# ordered (CTest ignores the name), so keep the names in step with the tests.
#
# Included twice: by tests/CMakeLists.txt after its add_test calls (PROJECT_NAME set: the
# script tests), and by CTest after the discovered Catch2 tests (TEST_INCLUDE_FILES).
set(RAY_TEST_COSTS
  [=[fuzz_smoke]=] 614
  [=[kernel matches host on every course scene]=] 120
  [=[kernel_resources]=] 229
  [=[rusticl]=] 192
  [=[every course scene renders on the OpenCL CPU device or fails clearly, and on two devices alike]=] 141
  [=[soak]=] 114
  [=[kernel_short_stack]=] 94
  [=[both renderers match the course's pending renders that ray has matched]=] 93
  [=[kernel matches host on the course's refraction and area-light scenes]=] 90
  [=[every course scene renders on the reference renderer or fails clearly]=] 60
  [=[multi_device]=] 61
  [=[viewer_hostile_clients]=] 60
  [=[mpi]=] 56
  [=[oclgrind]=] 54
  [=[gpu_bundle]=] 33
  [=[the reference renderer matches the course's renders]=] 30
  [=[viewer_browser]=] 26
  [=[concurrency]=] 25
  [=[the second run of a scene reuses the cached kernel]=] 14
  [=[external_project]=] 13
  [=[API: two Renderers on two threads at once render what they render one at a time]=] 12
  [=[every parse error of every subcommand is a plain sentence naming the option]=] 12
  [=[fault_injection]=] 12
  [=[A hung device is dropped, the frames stay whole, and the engine goes without waiting for it]=] 10
  [=[kernel matches host with stratified sampling and depth of field]=] 10
  [=[installed_library]=] 9
  [=[Limits: huge, truncated and bogus textures leave the surface its colors]=] 9
  [=[kernel matches host on every bundled scene]=] 8
  [=[every course scene loads, or fails with a clear error]=] 6
  [=[kernel matches host with --fresnel]=] 5
  [=[auto, cpu and all take PoCL and never llvmpipe, which is listed with its cap]=] 5
  [=[the reference renderer with --no-bvh renders what it renders with its BVH]=] 5
  [=[API: cancellation, progress, and refused settings and buffers]=] 5
)

list(LENGTH RAY_TEST_COSTS ray_cost_count)
math(EXPR ray_cost_last "${ray_cost_count} - 1")
foreach(i RANGE 0 ${ray_cost_last} 2)
  math(EXPR j "${i} + 1")
  list(GET RAY_TEST_COSTS ${i} ray_cost_name)
  list(GET RAY_TEST_COSTS ${j} ray_cost_seconds)
  if(PROJECT_NAME)  # CMake: only tests that exist take properties
    if(TEST "${ray_cost_name}")
      set_tests_properties("${ray_cost_name}" PROPERTIES COST ${ray_cost_seconds})
    endif()
  else()  # CTest: a name it does not know is ignored
    set_tests_properties("${ray_cost_name}" PROPERTIES COST ${ray_cost_seconds})
  endif()
endforeach()
