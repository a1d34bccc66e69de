# Generate the .msh files the options files and tests use, from the .geo sources.
# m2d_mesh(<output name> <geo> [PARAM VALUE ...]) -> ${CMAKE_BINARY_DIR}/meshes/<name>.msh
# The .geo sources are copied beside them (the program's -mesh_dir and
# -geo_dir are one directory next to it: about.h).
set(M2D_MESH_DIR ${CMAKE_BINARY_DIR}/meshes)
file(MAKE_DIRECTORY ${M2D_MESH_DIR})
file(GLOB M2D_GEO_FILES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/meshes/*.geo)
foreach(geo ${M2D_GEO_FILES})
  get_filename_component(name ${geo} NAME)
  configure_file(${geo} ${M2D_MESH_DIR}/${name} COPYONLY)
endforeach()
set(M2D_MESHES)
function(m2d_mesh name geo)
  set(args)
  set(params ${ARGN})
  list(LENGTH params n)
  while(n GREATER 1)
    list(POP_FRONT params key value)
    list(APPEND args -setnumber ${key} ${value})
    list(LENGTH params n)
  endwhile()
  set(out ${M2D_MESH_DIR}/${name}.msh)
  add_custom_command(OUTPUT ${out}
    COMMAND ${GMSH_EXECUTABLE} -2 -format msh41 -v 2 ${args} ${CMAKE_SOURCE_DIR}/meshes/${geo} -o ${out}
    DEPENDS ${CMAKE_SOURCE_DIR}/meshes/${geo}
    COMMENT "gmsh ${geo} ${args} -> meshes/${name}.msh" VERBATIM)
  set(M2D_MESHES ${M2D_MESHES} ${out} PARENT_SCOPE)
endfunction()

# single block: levels for the manufactured-solution convergence study
foreach(n 4 8 16 32 64)
  m2d_mesh(block_${n} block.geo n ${n})
endforeach()
m2d_mesh(block block.geo n 4)
# S2: one file holding both bodies, and one file per body
m2d_mesh(patch_uniform patch_uniform.geo)
m2d_mesh(patch_uniform_lower patch_uniform.geo body 1)
m2d_mesh(patch_uniform_upper patch_uniform.geo body 2)
# stack: three blocks, two contact pairs (one file, and one file per block)
m2d_mesh(stack stack.geo)
m2d_mesh(stack_split stack.geo split 1)
foreach(b 1 2 3)
  m2d_mesh(stack_${b} stack.geo body ${b})
endforeach()
# roller: a cylinder between two plates, two Hertz contacts
foreach(l 0 1 2)
  m2d_mesh(roller_${l} roller.geo level ${l})
endforeach()
# S1: the seed report's patch test
m2d_mesh(seed_patch seed_patch.geo)



# S2 interface ratios (upper:lower elements along the interface)
m2d_mesh(patch_3_10 patch_uniform.geo nu 3 nl 10)
m2d_mesh(patch_10_31 patch_uniform.geo nu 10 nl 31)
# S1 refinement study: r x the report's mesh, upper side kept non-matching
m2d_mesh(seed_patch_2 seed_patch.geo nlx 20 nly 20 nux 11 nuy 10)
m2d_mesh(seed_patch_4 seed_patch.geo nlx 40 nly 40 nux 21 nuy 20)
m2d_mesh(seed_patch_8 seed_patch.geo nlx 80 nly 80 nux 41 nuy 40)
m2d_mesh(seed_patch_16 seed_patch.geo nlx 160 nly 160 nux 81 nuy 80)
# S3 Hertz levels 0-4 (level 5, about 1e6 dofs, is made by tools/hertz_mesh.sh for the benchmark)
foreach(l 0 1 2 3 4)
  m2d_mesh(hertz_${l} hertz.geo level ${l})
endforeach()
# S2 with an initial gap of 0.01 between the bodies
m2d_mesh(patch_gap patch_uniform.geo gap 0.01)
# S4 hard cases: interface ratios, inclined interface, matching and sliver
# interfaces, initial penetration
m2d_mesh(patch_2_20 patch_uniform.geo nu 2 nl 20)
m2d_mesh(patch_20_2 patch_uniform.geo nu 20 nl 2)
m2d_mesh(patch_1_30 patch_uniform.geo nu 1 nl 30)
m2d_mesh(patch_30_1 patch_uniform.geo nu 30 nl 1)
m2d_mesh(patch_incl30 patch_uniform.geo angle 30)
m2d_mesh(patch_match patch_uniform.geo nu 10 nl 10)
m2d_mesh(patch_sliver patch_uniform.geo nu 10 nl 10 shift 1e-13)
m2d_mesh(patch_pen patch_uniform.geo gap -0.01)
# Hertz with two curved bodies (-hertz_radius R1:R2)
foreach(l 1 2)
  m2d_mesh(hertz_two_${l} hertz_two.geo level ${l})
endforeach()
# S7 Cattaneo-Mindlin levels 0-3 (graded to the contact)
foreach(l 0 1 2 3)
  m2d_mesh(cattaneo_${l} cattaneo.geo level ${l})
endforeach()
# indenter: a stiff rounded indenter on a rubber block on a base plate, two pairs
foreach(l 0 1 2)
  m2d_mesh(indenter_${l} indenter.geo level ${l})
endforeach()
# the hydrostatic patch test across shaped interfaces (tests/test_kink.py):
# kinks turning by 0-40 degrees, non-matching (7:10 quads along each piece)
# and matching (8:8); a ridge (turn -40, tilted); a circular arc turning by 40
# degrees, matching and non-matching at 2, 4, 8 x the base mesh
foreach(t 0 10 20 40)
  m2d_mesh(kink_${t} kink.geo turn ${t})
  m2d_mesh(kink_${t}_match kink.geo turn ${t} nl 8 nu 8)
endforeach()
m2d_mesh(kink_ridge kink.geo turn -40 tilt 15 xk -0.3 nl 9 nu 6)
# corners the old 45-degree check refused: kinks of 60, 90, 120 degrees (taller
# bodies: H), and a square punch on a foundation with a groove (corner.geo:
# none, away from the punch, under it; tests/test_corner.py)
m2d_mesh(kink_60 kink.geo turn 60)
m2d_mesh(kink_90 kink.geo turn 90 H 2)
m2d_mesh(kink_90_match kink.geo turn 90 H 2 nl 8 nu 8)
m2d_mesh(kink_120 kink.geo turn 120 H 3)
foreach(g 0 1 2)
  m2d_mesh(corner_${g} corner.geo groove ${g})
endforeach()
m2d_mesh(arc_40_match kink.geo shape 1 turn 40 nl 8 nu 8)
foreach(r 2 4 8)
  math(EXPR nl "7 * ${r}")
  math(EXPR nu "10 * ${r}")
  math(EXPR ny "4 * ${r}")
  m2d_mesh(arc_40_x${r} kink.geo shape 1 turn 40 nl ${nl} nu ${nu} ny ${ny})
endforeach()
# thin bodies (issue 33): a cantilever 10 x 0.01, refined through the thickness
# at aspect ratio 1 (nx = 1000 ny), and the issue's 1000 x 4
foreach(ny 1 2 4 8)
  math(EXPR nx "1000 * ${ny}")
  m2d_mesh(beam_${nx}x${ny} beam.geo nx ${nx} ny ${ny})
endforeach()
m2d_mesh(beam_1000x4 beam.geo nx 1000 ny 4)
# two cylinders R1 = 2 on R2 = 1 (contact half-width 0.1 of the smaller radius)
foreach(l 1 2)
  m2d_mesh(cylinders_${l} hertz_two.geo level ${l} R1 2 R2 1)
endforeach()
# columns of 9 and 40 blocks, no two neighbours' meshes matching (many bodies)
foreach(n 9 40)
  m2d_mesh(column_${n} column.geo nblock ${n})
endforeach()
add_custom_target(meshes ALL DEPENDS ${M2D_MESHES})

# the .msh files installed with the scenes (cmake --install): every -mesh an
# options file names, and the levels the scenes' comments offer
set(M2D_SHIPPED_MESHES)
foreach(name block patch_uniform seed_patch stack hertz_0 hertz_1 hertz_2 hertz_3 hertz_4 hertz_two_1 hertz_two_2
             roller_0 roller_1 roller_2 indenter_0 indenter_1 indenter_2 cattaneo_0 cattaneo_1 cattaneo_2 cattaneo_3 kink_40)
  list(APPEND M2D_SHIPPED_MESHES ${M2D_MESH_DIR}/${name}.msh)
endforeach()
file(GLOB scenes CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/options/*.opts)
foreach(scene ${scenes})
  file(STRINGS ${scene} lines REGEX "^-mesh +[^ ]+\\.msh")
  foreach(line ${lines})
    string(REGEX REPLACE "^-mesh +([^ ]+)\\.msh.*" "\\1" name "${line}")
    if(NOT ${M2D_MESH_DIR}/${name}.msh IN_LIST M2D_SHIPPED_MESHES)
      message(FATAL_ERROR "${scene} names ${name}.msh, which meshes/meshes.cmake neither makes for install (M2D_SHIPPED_MESHES)")
    endif()
  endforeach()
endforeach()
