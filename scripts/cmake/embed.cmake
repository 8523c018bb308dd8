# nurbsbench_embed(<target> <symbol> <file>): compiles <file> into <target> as
#   namespace nurbs::embedded { extern const std::string_view <symbol>; }
# regenerated whenever the file changes, so shaders, kernels and scene data need no loose files
# at run time.
set(NURBSBENCH_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/embed_file.cmake)
# The shared language shim of the single-source kernel headers, which kernels compiled at run time
# (OpenCL C, GL 3.3 GLSL: no #include) get in front of the header.
set(NURBSBENCH_KERNEL_LANGUAGE ${CMAKE_CURRENT_LIST_DIR}/../../strategies/kernel_language/kernel_language.h)
function(nurbsbench_embed target symbol file)
  cmake_parse_arguments(E "" "PREFIX" "" ${ARGN})
  get_filename_component(source ${file} ABSOLUTE)
  set(output ${CMAKE_CURRENT_BINARY_DIR}/embedded/${symbol}.cpp)
  set(prefix_args "")
  if(E_PREFIX)
    get_filename_component(E_PREFIX ${E_PREFIX} ABSOLUTE)
    set(prefix_args -DPREFIX=${E_PREFIX})
  endif()
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DINPUT=${source} ${prefix_args} -DOUTPUT=${output} -DSYMBOL=${symbol}
            -P ${NURBSBENCH_EMBED_SCRIPT}
    DEPENDS ${source} ${E_PREFIX} ${NURBSBENCH_EMBED_SCRIPT}
    COMMENT "Embedding ${file}")
  target_sources(${target} PRIVATE ${output})
endfunction()
# A single-source kernel header for a kernel compiled at run time: kernel_language.h, then it.
function(nurbsbench_embed_kernel_header target symbol file)
  nurbsbench_embed(${target} ${symbol} ${file} PREFIX ${NURBSBENCH_KERNEL_LANGUAGE})
endfunction()
