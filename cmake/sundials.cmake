# SUNDIALS for the kernel, as the interface target thermnet_sundials. Either Debian's
# libsundials-dev as installed (its CMake configuration, shared libraries), or, with
# THERMNET_SUNDIALS_UNPACKED, that package's .deb unpacked into a folder (`dpkg-deb -x`) without
# installing it: its headers and static libraries. The quick start takes the second way
# (scripts/install-deps --quickstart), which spares a newcomer the PETSc, hypre, Open MPI and
# gfortran packages that libsundials-dev depends on and the thermnet executable does not use.
set(THERMNET_SUNDIALS_UNPACKED "" CACHE PATH
    "folder where libsundials-dev's .deb was unpacked (dpkg-deb -x): link its static libraries")

# The SUNDIALS modules the kernel uses.
set(thermnet_sundials_modules cvodes ida kinsol nvecserial sunmatrixdense sunmatrixsparse
                              sunlinsoldense sunlinsolklu sunlinsolspgmr)

add_library(thermnet_sundials INTERFACE)
if(NOT THERMNET_SUNDIALS_UNPACKED)
  find_package(SUNDIALS 6 REQUIRED)
  foreach(module IN LISTS thermnet_sundials_modules)
    target_link_libraries(thermnet_sundials INTERFACE SUNDIALS::${module}_shared)
  endforeach()
  return()
endif()

# The unpacked package: its configuration names shared libraries that only the runtime packages
# install, so the static libraries are imported here. Each package library (cvodes, ida, kinsol)
# carries SUNDIALS's generic code, serial vectors, dense and sparse matrices and the built-in
# linear solvers; KLU comes from libsuitesparse-dev.
set(root "${THERMNET_SUNDIALS_UNPACKED}/usr")
set(libdir "${root}/lib/${CMAKE_LIBRARY_ARCHITECTURE}")
if(NOT EXISTS "${root}/include/cvodes/cvodes.h")
  message(FATAL_ERROR "THERMNET_SUNDIALS_UNPACKED: no SUNDIALS headers under ${root}/include "
                      "(expected libsundials-dev unpacked there with dpkg-deb -x)")
endif()
file(STRINGS "${root}/include/sundials/sundials_config.h" version_line
     REGEX "^#define SUNDIALS_VERSION_MAJOR")
string(REGEX MATCH "[0-9]+" version_major "${version_line}")
if(NOT version_major EQUAL 6)
  message(FATAL_ERROR "THERMNET_SUNDIALS_UNPACKED: SUNDIALS ${version_major} under ${root}; "
                      "thermnet needs SUNDIALS 6")
endif()
find_path(KLU_INCLUDE_DIR klu.h PATH_SUFFIXES suitesparse REQUIRED)
set(static_libraries "")
foreach(module cvodes ida kinsol sunlinsolklu)
  if(NOT EXISTS "${libdir}/libsundials_${module}.a")
    message(FATAL_ERROR "THERMNET_SUNDIALS_UNPACKED: ${libdir}/libsundials_${module}.a is missing")
  endif()
  list(APPEND static_libraries "${libdir}/libsundials_${module}.a")
endforeach()
set(klu_libraries "")
foreach(name klu amd colamd btf suitesparseconfig)
  find_library(SUITESPARSE_${name}_LIBRARY ${name} REQUIRED)
  list(APPEND klu_libraries "${SUITESPARSE_${name}_LIBRARY}")
endforeach()
target_include_directories(thermnet_sundials SYSTEM INTERFACE "${root}/include" "${KLU_INCLUDE_DIR}")
target_link_libraries(thermnet_sundials INTERFACE ${static_libraries} ${klu_libraries} m)
message(STATUS "SUNDIALS ${version_major}: static libraries unpacked in ${THERMNET_SUNDIALS_UNPACKED}")
