# nurbsbench_spirv(<target> <symbol> <shader> [<included file>...]): compiles the GLSL <shader> to
# SPIR-V with glslangValidator at build time, validates it with spirv-val, and embeds the binary
# into <target> as nurbs::embedded::<symbol> (nurbsbench_embed). Build time rather than run time:
# a shader error fails the build with the compiler's message, spirv-val checks what is shipped,
# and the binary needs no glslang library.
function(nurbsbench_spirv target symbol file)
  get_filename_component(source ${file} ABSOLUTE)
  set(dir ${CMAKE_CURRENT_BINARY_DIR}/spirv)
  set(spv ${dir}/${symbol}.spv)
  set(includes "")
  foreach(f ${ARGN})
    get_filename_component(abs ${f} ABSOLUTE)
    list(APPEND includes ${abs})
  endforeach()
  add_custom_command(
    OUTPUT ${spv}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${dir}
    COMMAND ${NURBSBENCH_GLSLANG} -V --target-env vulkan1.1 -I${CMAKE_CURRENT_SOURCE_DIR}
            -o ${spv} ${source}
    COMMAND ${NURBSBENCH_SPIRV_VAL} --target-env vulkan1.1 ${spv}
    DEPENDS ${source} ${includes} ${NURBSBENCH_KERNEL_LANGUAGE}
    COMMENT "GLSL -> SPIR-V (glslangValidator, spirv-val): ${file}"
    VERBATIM)
  nurbsbench_embed(${target} ${symbol} ${spv})
endfunction()
