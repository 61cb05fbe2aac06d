# Off-screen snapshots (src/render): the demlab_render library over OSMesa, libpng, libjpeg and
# FreeType, its tests (demlab_render_tests, ctest name "render") and bench_render. With
# DEMLAB_RENDER off, or when one of those libraries is missing, nothing here is built and
# everything else still is; code that renders checks if(TARGET demlab_render), and
# demlab_render carries DEMLAB_HAVE_RENDER=1.
option(DEMLAB_RENDER "Build the off-screen renderer (OSMesa, libpng, libjpeg, FreeType)" ON)

if(NOT DEMLAB_RENDER)
  message(STATUS "demlab: renderer off (DEMLAB_RENDER=OFF); snapshots unavailable")
  return()
endif()

find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  # OSMesa alone: it carries the GL entry points, reached through OSMesaGetProcAddress.
  pkg_check_modules(DEMLAB_OSMESA QUIET IMPORTED_TARGET osmesa)
endif()
find_package(PNG QUIET)
find_package(JPEG QUIET)
find_package(Freetype QUIET)
# Each found-variable's prefix with what to install when it is missing.
set(_missing "")
foreach(_dep "DEMLAB_OSMESA=OSMesa (libosmesa6-dev)" "PNG=libpng (libpng-dev)"
             "JPEG=libjpeg (libjpeg-dev)" "FREETYPE=FreeType (libfreetype-dev)")
  string(REPLACE "=" ";" _dep "${_dep}")
  list(GET _dep 0 _prefix)
  list(GET _dep 1 _package)
  if(NOT ${_prefix}_FOUND)
    list(APPEND _missing "${_package}")
  endif()
endforeach()
if(_missing)
  list(JOIN _missing " and " _missing)
  message(STATUS "demlab: renderer not built: ${_missing} not found; snapshots unavailable")
  return()
endif()

file(GLOB DEMLAB_RENDER_SOURCES CONFIGURE_DEPENDS src/render/*.cpp)
add_library(demlab_render STATIC ${DEMLAB_RENDER_SOURCES})
demlab_precompile(demlab_render)
target_link_libraries(demlab_render PUBLIC demlab_core
                      PRIVATE PkgConfig::DEMLAB_OSMESA PNG::PNG JPEG::JPEG Freetype::Freetype)
target_compile_definitions(demlab_render PUBLIC DEMLAB_HAVE_RENDER=1)

demlab_add_unit_tests(render demlab_render_tests render/ demlab_render PNG::PNG)

add_executable(bench_render ${DEMLAB_PROGRAM_SCOPE} bench/bench_render.cpp)
target_link_libraries(bench_render PRIVATE demlab_render)
