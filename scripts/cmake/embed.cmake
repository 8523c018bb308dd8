# nurbsbench_embed(<target> <symbol> <file>): compiles <file> into <target> as
#   namespace nurbs::embedded { extern const std::string_view <symbol>; }
# regenerated whenever the file changes, so shaders, kernels and scene data need no loose files
# at run time.
set(NURBSBENCH_EMBED_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/embed_file.cmake)
function(nurbsbench_embed target symbol file)
  get_filename_component(source ${file} ABSOLUTE)
  set(output ${CMAKE_CURRENT_BINARY_DIR}/embedded/${symbol}.cpp)
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DINPUT=${source} -DOUTPUT=${output} -DSYMBOL=${symbol}
            -P ${NURBSBENCH_EMBED_SCRIPT}
    DEPENDS ${source} ${NURBSBENCH_EMBED_SCRIPT}
    COMMENT "Embedding ${file}")
  target_sources(${target} PRIVATE ${output})
endfunction()
