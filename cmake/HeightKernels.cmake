# Straight-line height-field kernels, generated at build time for these shapes
# (engine/height/height_kernel_shapes.h explains the forms; other shapes use the loop-based kernels):
#   fused:   widths REFRAX_HEIGHT_FUSED_WIDTHS x hidden layers 1..8 x octaves REFRAX_HEIGHT_OCTAVES,
#            forward and backward pass 1
#   layered: widths REFRAX_HEIGHT_LAYERED_WIDTHS (any depth) x octaves REFRAX_HEIGHT_OCTAVES
#   weight-gradient tiles: 1, 16, 32 outputs per block (any layer whose output count they divide),
#            with float atomicAdd and with compare-and-swap adds
# A network of fewer octaves runs on the next listed count's kernels ("padded kernels" in
# engine/height/height_field.h): 6 serves the data-derived sizes 2-6, 8 serves 7-8 (full-size
# presets derive 7: the loop-based forward there took 73% of a training step).
set(REFRAX_HEIGHT_FUSED_WIDTHS 16 32 64 CACHE STRING "widths with fused straight-line height-field kernels")
set(REFRAX_HEIGHT_LAYERED_WIDTHS 128 256 CACHE STRING "widths with layered straight-line height-field kernels")
set(REFRAX_HEIGHT_OCTAVES 6 8 CACHE STRING "encoding octaves with straight-line height-field kernels")
set(REFRAX_HEIGHT_MAX_FUSED_DEPTH 8 CACHE STRING "deepest fused straight-line height-field kernel")

add_executable(refrax_generate_height_kernels ${CMAKE_SOURCE_DIR}/shaders/height/generate_height_kernels.cpp)
target_include_directories(refrax_generate_height_kernels PRIVATE ${CMAKE_SOURCE_DIR})

# Sets out_var to the generated .comp files (in the build tree).
function(refrax_generate_height_kernels out_var)
  set(dir ${CMAKE_BINARY_DIR}/generated/shader_sources)
  file(MAKE_DIRECTORY ${dir})
  set(sources "")
  macro(generate name)
    add_custom_command(
      OUTPUT ${dir}/${name}.comp
      COMMAND refrax_generate_height_kernels ${dir}/${name}.comp ${ARGN}
      DEPENDS refrax_generate_height_kernels
      COMMENT "generate ${name}.comp"
      VERBATIM)
    list(APPEND sources ${dir}/${name}.comp)
  endmacro()
  foreach(octaves ${REFRAX_HEIGHT_OCTAVES})
    foreach(width ${REFRAX_HEIGHT_FUSED_WIDTHS})
      foreach(depth RANGE 1 ${REFRAX_HEIGHT_MAX_FUSED_DEPTH})
        generate(height_fused_w${width}_d${depth}_l${octaves} fused ${width} ${depth} ${octaves})
        generate(height_backprop_w${width}_d${depth}_l${octaves} backprop ${width} ${depth} ${octaves})
      endforeach()
    endforeach()
    foreach(width ${REFRAX_HEIGHT_LAYERED_WIDTHS})
      generate(height_layer_first_w${width}_l${octaves} first ${width} ${octaves})
    endforeach()
  endforeach()
  foreach(width ${REFRAX_HEIGHT_LAYERED_WIDTHS})
    generate(height_layer_hidden_w${width} hidden ${width})
    generate(height_layer_last_w${width} last ${width})
  endforeach()
  foreach(mb 1 16 32)  # kHeightGradBlocks in engine/height/height_kernel_shapes.h
    foreach(add atomic cas)
      generate(height_grad_tile_mb${mb}_${add} grad ${mb} ${add})
    endforeach()
  endforeach()
  set(${out_var} ${sources} PARENT_SCOPE)
endfunction()
