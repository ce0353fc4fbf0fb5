# vbl_color: OpenColorIO adapter (C++17 inside, C header color/include/vbl_color.h) + PNG previews.
# Debian 12's OpenColorIOConfig.cmake sits in /usr/share/cmake and computes a wrong prefix, so
# the library is located directly.
find_path(VBL_OCIO_INCLUDE_DIR OpenColorIO/OpenColorIO.h REQUIRED)
find_library(VBL_OCIO_LIBRARY NAMES OpenColorIO REQUIRED)
if(NOT TARGET vbl::ocio)
  add_library(vbl::ocio UNKNOWN IMPORTED)
  set_target_properties(vbl::ocio PROPERTIES IMPORTED_LOCATION ${VBL_OCIO_LIBRARY}
                        INTERFACE_INCLUDE_DIRECTORIES ${VBL_OCIO_INCLUDE_DIR})
endif()

# The shipped config is compiled in (no path to find at run time) and installed for $OCIO users.
set(VBL_COLOR_CONFIG_FILE ${CMAKE_CURRENT_SOURCE_DIR}/config/libvbl.ocio)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${VBL_COLOR_CONFIG_FILE})
file(READ ${VBL_COLOR_CONFIG_FILE} VBL_COLOR_CONFIG_TEXT)
configure_file(${CMAKE_CURRENT_SOURCE_DIR}/src/color_builtin_config.cc.in
               ${CMAKE_CURRENT_BINARY_DIR}/color_builtin_config.cc @ONLY)

file(GLOB VBL_COLOR_C_SOURCES CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/*.c)
add_library(vbl_color STATIC ${VBL_COLOR_SOURCES} ${VBL_COLOR_C_SOURCES} ${CMAKE_CURRENT_BINARY_DIR}/color_builtin_config.cc)
set_target_properties(vbl_color PROPERTIES POSITION_INDEPENDENT_CODE ON LINKER_LANGUAGE CXX)
target_include_directories(vbl_color PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
target_link_libraries(vbl_color PUBLIC vbl PRIVATE vbl::ocio PNG::PNG m)
set(VBL_COLOR_INSTALLED_CONFIG ${CMAKE_INSTALL_FULL_DATADIR}/libvbl/libvbl.ocio)
target_compile_definitions(vbl_color PRIVATE VBL_COLOR_INSTALLED_CONFIG="${VBL_COLOR_INSTALLED_CONFIG}")
install(FILES ${VBL_COLOR_CONFIG_FILE} DESTINATION ${CMAKE_INSTALL_DATADIR}/libvbl)
