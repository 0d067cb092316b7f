# The CUDA backend (src/cuda/*.cu): `tt_render` with TT_DEVICE_GPU and the
# CLI's `--device gpu`. Built when TT_WITH_CUDA is ON and nvcc is found (on
# PATH, through CUDACXX / CMAKE_CUDA_COMPILER, or at /usr/local/cuda/bin/nvcc);
# a GPU is not needed to build it. Without it everything else builds, and
# asking for the GPU reports TT_NO_CUDA_REASON.
#
# Included from the top CMakeLists.txt after the `treetrace` target exists.

set(TT_CUDA_WANTED_ARCHS 70 75 80 90)

function(tt_cuda_disable reason)
  message(STATUS "treetrace: GPU backend not built: ${reason}")
  target_compile_definitions(treetrace_objects PRIVATE TT_NO_CUDA_REASON="${reason}")
endfunction()

if(NOT TT_WITH_CUDA)
  tt_cuda_disable("configured with -DTT_WITH_CUDA=OFF")
  return()
endif()

# nvcc on PATH, else at the toolkit's usual place (often not on PATH);
# CUDACXX or -DCMAKE_CUDA_COMPILER=... choose another. check_language then
# verifies that it compiles, so a broken toolkit only disables the backend.
if(NOT DEFINED CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX})
  find_program(TT_NVCC nvcc PATHS /usr/local/cuda/bin)
  if(TT_NVCC)
    set(ENV{CUDACXX} "${TT_NVCC}")
  endif()
endif()
include(CheckLanguage)
check_language(CUDA)
if(NOT CMAKE_CUDA_COMPILER)
  tt_cuda_disable("nvcc was not found at configure time")
  return()
endif()

# Feldmann's GPU (sm_70) and two newer generations; keep those this nvcc
# can still compile for (CUDA 13 dropped sm_70).
execute_process(COMMAND "${CMAKE_CUDA_COMPILER}" --list-gpu-arch
  OUTPUT_VARIABLE tt_nvcc_archs RESULT_VARIABLE tt_nvcc_rc ERROR_QUIET)
if(NOT tt_nvcc_rc EQUAL 0)
  tt_cuda_disable("${CMAKE_CUDA_COMPILER} --list-gpu-arch failed")
  return()
endif()
set(tt_archs "")
set(tt_dropped "")
foreach(a ${TT_CUDA_WANTED_ARCHS})
  if(tt_nvcc_archs MATCHES "compute_${a}")
    list(APPEND tt_archs ${a})
  else()
    list(APPEND tt_dropped ${a})
  endif()
endforeach()
if(NOT tt_archs)
  tt_cuda_disable("${CMAKE_CUDA_COMPILER} supports none of sm_${TT_CUDA_WANTED_ARCHS}")
  return()
endif()
if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
  set(CMAKE_CUDA_ARCHITECTURES ${tt_archs})
endif()
enable_language(CUDA)
# Programs that link the library stay C programs linked by the C compiler
# (so that -fsanitize links the sanitizer runtime of the compiler that
# built the C code, e.g. clang's); the CUDA runtime comes in explicitly.
set(CMAKE_CUDA_LINKER_PREFERENCE_PROPAGATES 0)
find_package(CUDAToolkit REQUIRED)
string(REPLACE ";" ", " tt_arch_text "${CMAKE_CUDA_ARCHITECTURES}")
if(tt_dropped)
  string(REPLACE ";" ", " tt_dropped_text "${tt_dropped}")
  message(STATUS "treetrace: CUDA ${CMAKE_CUDA_COMPILER_VERSION} (${CMAKE_CUDA_COMPILER}): "
                 "GPU backend for sm_${tt_arch_text}; sm_${tt_dropped_text} left out, "
                 "this nvcc does not support it")
else()
  message(STATUS "treetrace: CUDA ${CMAKE_CUDA_COMPILER_VERSION} (${CMAKE_CUDA_COMPILER}): "
                 "GPU backend for sm_${tt_arch_text}")
endif()

file(GLOB TT_CUDA_SOURCES CONFIGURE_DEPENDS "${CMAKE_CURRENT_SOURCE_DIR}/src/cuda/*.cu")
add_library(treetrace_cuda STATIC ${TT_CUDA_SOURCES})
# The directory's options are for the C compilers (-Wall for gcc/clang,
# -fsanitize): nvcc gets its own. The .cu files are not sanitized; the
# sanitized C code links against them all the same.
set_property(TARGET treetrace_cuda PROPERTY COMPILE_OPTIONS "")
target_compile_options(treetrace_cuda PRIVATE
  # Bit-identical rays and hits on both sides: the shared TT_HD code is
  # ISO C on the CPU, where a * b + c is never fused; without this, nvcc
  # would fuse it and round differently.
  --fmad=false
  -Xcompiler=-Wall,-Wextra)
if(TT_WERROR)
  target_compile_options(treetrace_cuda PRIVATE "SHELL:--Werror all-warnings" -Xcompiler=-Werror)
endif()
set_target_properties(treetrace_cuda PROPERTIES
  CUDA_ARCHITECTURES "${CMAKE_CUDA_ARCHITECTURES}"
  CUDA_STANDARD 17
  CUDA_STANDARD_REQUIRED ON
  CUDA_SEPARABLE_COMPILATION OFF
  # The runtime is linked statically, so the binary runs on machines with a
  # driver but no toolkit; without a driver or GPU it reports that instead.
  CUDA_RUNTIME_LIBRARY Static
  POSITION_INDEPENDENT_CODE ON)
target_include_directories(treetrace_cuda PRIVATE
  "${CMAKE_CURRENT_SOURCE_DIR}/include" "${CMAKE_CURRENT_SOURCE_DIR}/src")
target_compile_definitions(treetrace_cuda PRIVATE TT_CUDA_ARCHS="${tt_arch_text}")
target_link_libraries(treetrace_cuda PUBLIC CUDA::cudart_static)
target_link_libraries(treetrace PRIVATE treetrace_cuda)
target_link_libraries(treetrace_shared PRIVATE treetrace_cuda)
# The libraries were created before CUDA was enabled; they have no CUDA
# sources, but CMake wants the property on every target once the language is on.
set_property(TARGET treetrace treetrace_shared treetrace_objects
  PROPERTY CUDA_ARCHITECTURES "${CMAKE_CUDA_ARCHITECTURES}")
target_compile_definitions(treetrace_objects PUBLIC TT_HAVE_CUDA=1)
target_compile_definitions(treetrace PUBLIC $<BUILD_INTERFACE:TT_HAVE_CUDA=1>)
set(TT_BUILT_WITH_CUDA ON)
