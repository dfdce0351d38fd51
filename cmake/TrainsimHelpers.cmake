# Common compile options for every TrainSim target.
add_library(trainsim_options INTERFACE)
target_compile_options(trainsim_options INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual
  # GCC 12 reports false -Wrestrict positives on std::string concatenation at -O2/-O3
  # (GCC bug 105651); the warning carries no signal for this code base.
  $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>
  $<$<BOOL:${TRAINSIM_WERROR}>:-Werror>)
if(TRAINSIM_SANITIZE)
  # GCC's -Wmaybe-uninitialized misfires inside libstdc++'s <regex> and <functional> when the
  # sanitizers' checks are inlined at -O1; the Release build keeps the warning.
  target_compile_options(trainsim_options INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
    $<$<CXX_COMPILER_ID:GNU>:-Wno-maybe-uninitialized>)
  target_link_options(trainsim_options INTERFACE -fsanitize=address,undefined)
endif()

# trainsim_module(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Declares modules/<name> as the static library trainsim_<name>, alias trainsim::<name>, with
# public headers in include/ and private sources in src/.
function(trainsim_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  add_library(trainsim_${name} STATIC ${ARG_SOURCES})
  add_library(trainsim::${name} ALIAS trainsim_${name})
  target_include_directories(trainsim_${name}
    PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
    PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  target_link_libraries(trainsim_${name}
    PUBLIC ${ARG_PUBLIC_DEPS}
    PRIVATE trainsim_options ${ARG_PRIVATE_DEPS})
  set_property(GLOBAL APPEND PROPERTY TRAINSIM_MODULES ${name})
endfunction()

# trainsim_embed_file(<target> <file> <symbol>)
# Compiles <file> into <target> as `extern const std::string_view <symbol>` (namespace
# trainsim::embedded), regenerated whenever the file changes.
function(trainsim_embed_file target file symbol)
  set(out ${CMAKE_CURRENT_BINARY_DIR}/embedded_${symbol}.cpp)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${CMAKE_COMMAND} -DINPUT=${file} -DOUTPUT=${out} -DSYMBOL=${symbol}
            -P ${CMAKE_SOURCE_DIR}/cmake/EmbedFile.cmake
    DEPENDS ${file} ${CMAKE_SOURCE_DIR}/cmake/EmbedFile.cmake
    COMMENT "Embedding ${file}")
  target_sources(${target} PRIVATE ${out})
endfunction()

function(trainsim_print_summary)
  get_property(modules GLOBAL PROPERTY TRAINSIM_MODULES)
  message(STATUS "")
  message(STATUS "TrainSim ${PROJECT_VERSION} (${CMAKE_BUILD_TYPE})")
  message(STATUS "  modules ............ ${modules}")
  message(STATUS "  CLI (trainsim) ..... on")
  message(STATUS "  studio ............. ${TRAINSIM_STUDIO_STATUS}")
  message(STATUS "  tests .............. ${TRAINSIM_BUILD_TESTS}")
  message(STATUS "  benchmarks ......... ${TRAINSIM_BUILD_BENCH}")
  message(STATUS "  asan+ubsan ......... ${TRAINSIM_SANITIZE}")
  message(STATUS "  ccache ............. ${CCACHE_PROGRAM}")
  message(STATUS "")
endfunction()
