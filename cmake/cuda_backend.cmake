# Decides whether the optional CUDA backend is built (CAPSIM_CUDA = AUTO | ON | OFF |
# EMULATE) and sets CAPSIM_HAVE_CUDA. The CPU build never needs CUDA: the CUDA language is
# enabled only here, and only when the backend is built for a GPU. EMULATE builds the same
# backend with the host compiler, to run on the CPU (cmake/cuda_emulation.cmake).
string(TOUPPER "${CAPSIM_CUDA}" _capsim_cuda)
if(_capsim_cuda MATCHES "^(ON|TRUE|YES|1)$")
  set(_capsim_cuda ON)
elseif(_capsim_cuda MATCHES "^(OFF|FALSE|NO|0)$")
  set(_capsim_cuda OFF)
elseif(NOT _capsim_cuda MATCHES "^(AUTO|EMULATE)$")
  message(FATAL_ERROR "CAPSIM_CUDA must be AUTO, ON, OFF or EMULATE, got '${CAPSIM_CUDA}'")
endif()

set(CAPSIM_HAVE_CUDA OFF)
if(_capsim_cuda STREQUAL "EMULATE")
  include(${CMAKE_CURRENT_LIST_DIR}/cuda_emulation.cmake)
  set(CAPSIM_HAVE_CUDA ON)
elseif(NOT _capsim_cuda STREQUAL "OFF")
  # The toolkit's installers put nvcc in /usr/local/cuda/bin without adding it to PATH.
  if(NOT CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX})
    find_program(CAPSIM_NVCC nvcc PATHS /usr/local/cuda/bin)
    if(CAPSIM_NVCC)
      set(CMAKE_CUDA_COMPILER "${CAPSIM_NVCC}" CACHE FILEPATH "CUDA compiler")
    endif()
  endif()
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    # Ampere (A100) and Hopper (H100/H200): the FP64-capable data-centre GPUs; the code
    # needs double-precision atomicAdd (sm_60 and newer).
    if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
      set(CMAKE_CUDA_ARCHITECTURES 80 90)
    endif()
    enable_language(CUDA)
    find_package(CUDAToolkit REQUIRED)
    set(CAPSIM_HAVE_CUDA ON)
  elseif(_capsim_cuda STREQUAL "ON")
    message(FATAL_ERROR "CAPSIM_CUDA=ON but no CUDA compiler (nvcc) was found: install the "
      "CUDA toolkit, put nvcc on PATH (or set CUDACXX), or configure with -DCAPSIM_CUDA=AUTO")
  endif()
endif()
if(_capsim_cuda STREQUAL "EMULATE")
  message(STATUS "capsim: CUDA backend EMULATED on the host (Thrust "
    "${CAPSIM_THRUST_VERSION} in ${CAPSIM_THRUST_INCLUDE_DIR}, cuFFT by FFTW)")
elseif(CAPSIM_HAVE_CUDA)
  message(STATUS "capsim: CUDA backend ON (nvcc ${CMAKE_CUDA_COMPILER_VERSION}, "
    "architectures ${CMAKE_CUDA_ARCHITECTURES})")
else()
  message(STATUS "capsim: CUDA backend OFF (CAPSIM_CUDA=${CAPSIM_CUDA})")
endif()
