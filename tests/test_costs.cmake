# What the long tests cost, in seconds on 2 cores under `ctest -j2` (scripts/test.sh in a
# fresh build folder with a fresh kernel cache), so that CTest starts the longest first on a
# fresh clone, before it has timings of its own (Testing/Temporary/CTestCostData.txt, which
# it prefers afterwards).
# Run in the order they are declared, the long script tests came last and ran two at a
# time while the other core had nothing left to do. Tests not listed cost 0: they fill in
# between. Figures within a factor of two are enough; a test renamed here is simply not
# ordered (CTest ignores the name), so keep the names in step with the tests.
#
# Included twice: by tests/CMakeLists.txt after its add_test calls (PROJECT_NAME set: the
# script tests), and by CTest after the discovered Catch2 tests (TEST_INCLUDE_FILES).
set(RAY_TEST_COSTS
  # 135 s with a 2-job build; 1 job (scripts/fuzz.sh --jobs 1) leaves the other core to CTest;
  # then seven targets, 5 s each by default, a minute each in CI (.ci/run): 1,030 s there
  # on a fresh clone, 2026-12-07 (CTest's longest, run beside the others)
  [=[fuzz_smoke]=] 300
  # soak (105 s) watches the viewer's frames with timing of its own (idle for 0.3 s). Started
  # first, beside the cold kernel builds of a fresh machine, one of its sampled frames differed
  # from a fresh render once (it passed alone, and at the end as before). Cost 1: it starts
  # after the tests above, before every one not listed.
  [=[soak]=] 1
  [=[every course scene renders on the OpenCL CPU device or fails clearly, and on two devices alike]=] 88
  [=[both renderers match the course's pending renders that ray has matched]=] 61
  [=[viewer_hostile_clients]=] 60
  [=[kernel matches host on every course scene]=] 58
  [=[rusticl]=] 57
  [=[cpu_paths]=] 90
  # 31 renders at 1024x768 with the course's switches, and the comparison: 51 s on 2 cores
  [=[course_configs]=] 55
  [=[mpi]=] 54
  [=[multi_device]=] 40
  [=[kernel_resources]=] 30
  [=[every course scene renders on the reference renderer or fails clearly]=] 29
  [=[Undo history of 20,000 spheres and 200 colour edits stays small, and undo and redo give back each document exactly]=] 30
  [=[every course scene that loads saves unedited to its own bytes, and edited to its lines alone]=] 21
  [=[every course scene saves and loads back to a byte-identical 64x48 render]=] 15
  # 199 scenes rendered twice at 64x48 (as the line above); the JSON corpus's two largest
  # scenes (recursive_sphere_10) flatten to millions of instances, twice each
  [=[every course XML scene converts to JSON that renders byte-identical at 64x48, or is refused with the reason]=] 20
  [=[every course JSON scene converts to XML and back to the same JSON]=] 15
  [=[kernel matches host on the course's refraction and area-light scenes]=] 26
  [=[gpu_bundle]=] 18
  [=[concurrency]=] 16
  [=[the reference renderer matches the course's renders]=] 14
  [=[viewer_recovery]=] 23
  [=[viewer_browser_recovery]=] 21
  [=[viewer_browser]=] 13
  # cpack -G DEB and dpkg-shlibdeps over the package's files (34 s alone); nbconvert's kernel
  # and its renders (18 s)
  [=[debian_package]=] 35
  [=[notebook]=] 18
  [=[A hung device is dropped, the frames stay whole, and the engine goes without waiting for it]=] 13
  [=[kernel_short_stack]=] 10
  [=[oclgrind]=] 9
  [=[the second run of a scene reuses the cached kernel]=] 5
  [=[every parse error of every subcommand is a plain sentence naming the option]=] 5
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
