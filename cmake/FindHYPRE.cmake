# FindHYPRE: the target HYPRE::HYPRE. Debian's libhypre-dev ships no CMake package
# (headers in /usr/include/hypre, libHYPRE.so); a hypre that does is used as it is.
# Needs MPI::MPI_CXX (find_package(MPI COMPONENTS CXX) first).
find_package(HYPRE CONFIG QUIET)
if(NOT TARGET HYPRE::HYPRE)
  find_path(HYPRE_INCLUDE_DIR HYPRE_struct_ls.h PATH_SUFFIXES hypre)
  find_library(HYPRE_LIBRARY HYPRE)
  include(FindPackageHandleStandardArgs)
  find_package_handle_standard_args(HYPRE
    REQUIRED_VARS HYPRE_LIBRARY HYPRE_INCLUDE_DIR
    REASON_FAILURE_MESSAGE "install libhypre-dev (scripts/install-deps.sh) or set HYPRE_INCLUDE_DIR and HYPRE_LIBRARY")
  if(HYPRE_FOUND)
    add_library(HYPRE::HYPRE UNKNOWN IMPORTED)
    set_target_properties(HYPRE::HYPRE PROPERTIES IMPORTED_LOCATION "${HYPRE_LIBRARY}"
                          INTERFACE_INCLUDE_DIRECTORIES "${HYPRE_INCLUDE_DIR}"
                          INTERFACE_LINK_LIBRARIES MPI::MPI_CXX)
  endif()
else()
  set(HYPRE_FOUND TRUE)
endif()
