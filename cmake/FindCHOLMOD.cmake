# Finds CHOLMOD from SuiteSparse. Debian's SuiteSparse 5.12 ships no CMake
# package configuration, so this module looks for the headers and libraries
# directly and defines the imported target CHOLMOD::CHOLMOD.
#
# CHOLMOD is linked statically, with what the static library needs besides
# (METIS, BLAS and LAPACK for its complex kernels): the executables then give
# its OpenMP calls the serial entry points of
# common/linalg/cholmod_serial_openmp.cpp instead of libgomp's, whose team
# set-up around every supernode cost a third of each factorization.
find_path(CHOLMOD_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_STATIC_LIBRARY NAMES libcholmod.a)
find_library(METIS_LIBRARY metis)
find_library(LAPACK_LIBRARY lapack)
find_library(BLAS_LIBRARY blas)
find_library(SUITESPARSE_CONFIG_LIBRARY suitesparseconfig)
find_library(AMD_LIBRARY amd)
find_library(CAMD_LIBRARY camd)
find_library(COLAMD_LIBRARY colamd)
find_library(CCOLAMD_LIBRARY ccolamd)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(CHOLMOD REQUIRED_VARS
  CHOLMOD_INCLUDE_DIR CHOLMOD_STATIC_LIBRARY SUITESPARSE_CONFIG_LIBRARY METIS_LIBRARY
  LAPACK_LIBRARY BLAS_LIBRARY AMD_LIBRARY CAMD_LIBRARY COLAMD_LIBRARY CCOLAMD_LIBRARY)

if(CHOLMOD_FOUND AND NOT TARGET CHOLMOD::CHOLMOD)
  add_library(CHOLMOD::CHOLMOD UNKNOWN IMPORTED)
  set_target_properties(CHOLMOD::CHOLMOD PROPERTIES
    IMPORTED_LOCATION "${CHOLMOD_STATIC_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${CHOLMOD_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES
      "${AMD_LIBRARY};${CAMD_LIBRARY};${COLAMD_LIBRARY};${CCOLAMD_LIBRARY};${SUITESPARSE_CONFIG_LIBRARY};${METIS_LIBRARY};${LAPACK_LIBRARY};${BLAS_LIBRARY};m")
endif()
mark_as_advanced(CHOLMOD_INCLUDE_DIR CHOLMOD_STATIC_LIBRARY SUITESPARSE_CONFIG_LIBRARY METIS_LIBRARY
  LAPACK_LIBRARY BLAS_LIBRARY AMD_LIBRARY CAMD_LIBRARY COLAMD_LIBRARY CCOLAMD_LIBRARY)
