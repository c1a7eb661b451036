# For trying viewer/CMakeLists.txt before the top-level CMakeLists.txt includes it:
#   cmake -S . -B build-x -DCMAKE_PROJECT_INCLUDE=$PWD/viewer/dev_hook.cmake
# includes it once the top-level directory (and so the geotex target) is complete.
if(NOT DEFINED _geotex_viewer_hooked AND EXISTS ${CMAKE_SOURCE_DIR}/viewer/CMakeLists.txt)
  set(_geotex_viewer_hooked ON)
  cmake_language(DEFER DIRECTORY ${CMAKE_SOURCE_DIR} CALL include ${CMAKE_SOURCE_DIR}/viewer/CMakeLists.txt)
endif()
