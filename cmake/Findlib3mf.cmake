# Finds lib3mf 1.x (Debian lib3mf-dev: the C interface of Model/COM/NMR_DLLInterfaces.h) and
# defines lib3mf::lib3mf. lib3mf 2.x has a different interface and is not accepted: the header
# checked for below exists only in 1.x. io/mesh_3mf.hpp declares the few C functions it calls
# itself (lib3mf's headers define global Windows-style typedefs and macros), so the target
# carries the library only.
find_path(lib3mf_INCLUDE_DIR Model/COM/NMR_DLLInterfaces.h PATH_SUFFIXES lib3mf)
find_library(lib3mf_LIBRARY NAMES 3MF lib3MF)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(lib3mf REQUIRED_VARS lib3mf_LIBRARY lib3mf_INCLUDE_DIR)
if(lib3mf_FOUND AND NOT TARGET lib3mf::lib3mf)
  add_library(lib3mf::lib3mf UNKNOWN IMPORTED)
  set_target_properties(lib3mf::lib3mf PROPERTIES IMPORTED_LOCATION "${lib3mf_LIBRARY}")
endif()
mark_as_advanced(lib3mf_INCLUDE_DIR lib3mf_LIBRARY)
