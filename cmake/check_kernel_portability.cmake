# The kernel through clang's OpenCL C front end for targets other than PoCL's, as a
# portability check for devices this machine does not have: NVIDIA's (nvptx64-nvidia-nvcl)
# and SPIR (spir64, the portable intermediate most other drivers take), OpenCL C 1.2 as
# ray builds it, every warning an error (-Wdouble-promotion among them: a double in the
# kernel runs at a fraction of float speed on most GPUs). Syntax and semantics only:
# no device code is generated, so no device library is needed.
# Usage: cmake -DCLANG=path -DINPUTS="a|b|c" -DWORK_DIR=dir -P check_kernel_portability.cmake
if(NOT CLANG)
  message("SKIPPED: clang was not found when the build was configured (apt-get install clang)")
  return()
endif()
string(REPLACE "|" ";" INPUTS "${INPUTS}")
set(source "${WORK_DIR}/kernel_portability.cl")
file(WRITE "${source}" "")
foreach(input IN LISTS INPUTS)
  file(READ "${input}" text)
  file(APPEND "${source}" "${text}\n")
endforeach()
# Each variant (cl/device/variant.h): a GPU's (no define), and a CPU device's with one ray a
# work-item and with packets of each width.
foreach(target IN ITEMS nvptx64-nvidia-nvcl spir64)
  foreach(lanes IN ITEMS 0 1 4 8 16)
    set(path_option "")
    set(path "a GPU's")
    if(lanes EQUAL 1)
      set(path_option "-DRAY_CPU_LANES=1")
      set(path "a CPU's, one ray a work-item")
    elseif(lanes GREATER 1)
      set(path_option "-DRAY_CPU_LANES=${lanes}")
      set(path "a CPU's, ${lanes}-ray packets")
    endif()
    # __OPENCL_VERSION__ is the device's to define (PoCL and NVIDIA do); clang alone does not.
    execute_process(
      COMMAND "${CLANG}" -x cl -cl-std=CL1.2 -target ${target} -Xclang -finclude-default-header -fsyntax-only
              -Wall -Wextra -Wdouble-promotion -Wimplicit-float-conversion -Werror
              -D__OPENCL_VERSION__=120 -DRAY_MAX_FRAMES=5 ${path_option} "${source}"
      RESULT_VARIABLE status
      OUTPUT_VARIABLE output
      ERROR_VARIABLE output)
    if(NOT status EQUAL 0)
      message(FATAL_ERROR "the kernel (${path}) does not compile cleanly for ${target}:\n${output}")
    endif()
    message("the kernel (${path}) compiles cleanly for ${target} (OpenCL C 1.2)")
  endforeach()
endforeach()
