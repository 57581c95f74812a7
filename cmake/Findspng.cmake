# Finds libspng (Debian libspng-dev, which ships only a pkg-config file) and defines spng::spng,
# the name upstream's own CMake package uses. io/image.hpp reads and writes PNG through it.
find_path(spng_INCLUDE_DIR spng.h)
find_library(spng_LIBRARY NAMES spng)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(spng REQUIRED_VARS spng_LIBRARY spng_INCLUDE_DIR)
if(spng_FOUND AND NOT TARGET spng::spng)
  add_library(spng::spng UNKNOWN IMPORTED)
  set_target_properties(spng::spng PROPERTIES IMPORTED_LOCATION "${spng_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${spng_INCLUDE_DIR}")
endif()
mark_as_advanced(spng_INCLUDE_DIR spng_LIBRARY)
