# ewis_stage(NAME DEPS a b PRIVATE_DEPS c): library ewis_NAME from src/NAME/*.cpp.
# A stage without sources yet is an INTERFACE library, so the stages can land one by one.
function(ewis_stage name)
  cmake_parse_arguments(ARG "" "" "DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${name}/*.cpp)
  if(sources)
    add_library(ewis_${name} STATIC ${sources})
    target_include_directories(ewis_${name} PUBLIC ${PROJECT_SOURCE_DIR}/include)
    target_link_libraries(ewis_${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    # One precompiled header for every stage (Eigen, oneTBB's parallel_for and the common standard headers),
    # built by the first stage and reused by the others: parsing them was 1-3.6 s of each source's 2-18 s.
    get_property(owner GLOBAL PROPERTY EWIS_STAGE_PCH_OWNER)
    if(NOT owner)
      set_property(GLOBAL PROPERTY EWIS_STAGE_PCH_OWNER ewis_${name})
      target_precompile_headers(ewis_${name} PRIVATE <Eigen/Core> <Eigen/Geometry> <tbb/parallel_for.h>
        <algorithm> <array> <cmath> <cstdint> <functional> <limits> <memory> <optional> <string> <vector>)
    else()
      target_precompile_headers(ewis_${name} REUSE_FROM ${owner})
    endif()
  else()
    add_library(ewis_${name} INTERFACE)
    target_include_directories(ewis_${name} INTERFACE ${PROJECT_SOURCE_DIR}/include)
    target_link_libraries(ewis_${name} INTERFACE ${ARG_DEPS} ${ARG_PRIVATE_DEPS})
  endif()
endfunction()
