# CAPSIM_CUDA=EMULATE: the CUDA backend built by the host compiler and run on the CPU, so
# that CI without a GPU executes the kernels, launches and device memory handling
# (docs/gpu.md). Included by cuda_backend.cmake, before solver/ is added.
#
# solver/CMakeLists.txt builds the backend exactly as for a GPU; this file supplies what
# nvcc and the toolkit would: CUDA::cudart and CUDA::cufft become the emulated runtime
# (solver/cuda/emulation/, whose cuda_runtime.h and cufft.h shadow the toolkit's) and
# Thrust runs on its OpenMP system. No CUDA toolkit is needed: Debian's libthrust-dev
# provides the headers.

find_path(CAPSIM_THRUST_INCLUDE_DIR thrust/version.h
  DOC "Thrust headers for the emulated CUDA backend (Debian: libthrust-dev)")
if(NOT CAPSIM_THRUST_INCLUDE_DIR)
  message(FATAL_ERROR "CAPSIM_CUDA=EMULATE needs the Thrust headers: install libthrust-dev "
    "(Debian) or set CAPSIM_THRUST_INCLUDE_DIR")
endif()
file(STRINGS "${CAPSIM_THRUST_INCLUDE_DIR}/thrust/version.h" _capsim_thrust_version
  REGEX "^#define THRUST_VERSION [0-9]+")
string(REGEX REPLACE ".* ([0-9]+)$" "\\1" _capsim_thrust_version "${_capsim_thrust_version}")
math(EXPR _major "${_capsim_thrust_version} / 100000")
math(EXPR _minor "${_capsim_thrust_version} / 100 % 1000")
set(CAPSIM_THRUST_VERSION "${_major}.${_minor}")

set(_capsim_emulation ${PROJECT_SOURCE_DIR}/solver/cuda/emulation)
add_library(capsim_cuda_emulation STATIC
  ${_capsim_emulation}/runtime.cpp
  ${_capsim_emulation}/cufft.cpp
)
target_include_directories(capsim_cuda_emulation
  PUBLIC ${_capsim_emulation}
  PRIVATE ${PROJECT_SOURCE_DIR}/solver)
# /usr/include is searched anyway; naming it with -isystem would break libstdc++'s
# #include_next.
if(NOT CAPSIM_THRUST_INCLUDE_DIR STREQUAL "/usr/include")
  target_include_directories(capsim_cuda_emulation SYSTEM PUBLIC ${CAPSIM_THRUST_INCLUDE_DIR})
endif()
target_compile_definitions(capsim_cuda_emulation PUBLIC CAPSIM_CUDA_EMULATED
  THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_OMP)
target_link_libraries(capsim_cuda_emulation PUBLIC OpenMP::OpenMP_CXX PkgConfig::FFTW3)
add_library(CUDA::cudart ALIAS capsim_cuda_emulation)
add_library(CUDA::cufft ALIAS capsim_cuda_emulation)

# The .cu files are C++ here. Their target is made in solver/, after this file runs, so
# the language is set once the whole project has been read.
function(capsim_compile_cu_as_cxx)
  get_target_property(sources capsim_cuda SOURCES)
  get_target_property(dir capsim_cuda SOURCE_DIR)
  list(FILTER sources INCLUDE REGEX "\\.cu$")
  foreach(source IN LISTS sources)
    cmake_path(ABSOLUTE_PATH source BASE_DIRECTORY "${dir}")
    set_source_files_properties(${source} TARGET_DIRECTORY capsim_cuda
      PROPERTIES LANGUAGE CXX)
  endforeach()
  target_compile_options(capsim_cuda PRIVATE ${CAPSIM_FLAGS})
  target_compile_options(capsim_cuda_emulation PRIVATE ${CAPSIM_FLAGS})
  # Under the sanitizers (scripts/test.sh runs the emulated self-test there): Thrust's
  # sequential merge, which the binning's sort reaches, binds a reference to a null
  # execution policy (thrust/detail/reference.h), a report in the library, not in the
  # kernels; that one check is left out of the file that calls it.
  if(CAPSIM_SANITIZE)
    set_source_files_properties(${PROJECT_SOURCE_DIR}/solver/cuda/binning_kernels.cu
      TARGET_DIRECTORY capsim_cuda PROPERTIES COMPILE_OPTIONS -fno-sanitize=null)
  endif()
endfunction()
cmake_language(DEFER DIRECTORY ${PROJECT_SOURCE_DIR} CALL capsim_compile_cu_as_cxx)
