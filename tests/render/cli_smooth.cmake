# Smooth surfaces from the command line: `maille render --smooth --lod N` draws them, `maille run
# --format obj --smooth` writes them as OBJ frames (positions, normals, faces), and bad uses are
# usage errors (exit 2).
file(REMOVE_RECURSE ${OUT})
set(scene ${SOURCE}/examples/flag_in_wind.toml)
execute_process(COMMAND ${MAILLE} render ${scene} --smooth --lod 3 --duration 0.1 --width 160
                --height 120 --samples 1 --out ${OUT}/smooth.png
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS ${OUT}/smooth.png)
  message(FATAL_ERROR "maille render --smooth failed (${rc}): ${out} ${err}")
endif()
execute_process(COMMAND ${MAILLE} run ${scene} --steps 40 --every 20 --format obj --smooth --lod 2
                --out ${OUT}/obj RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "maille run --format obj --smooth failed (${rc}): ${out} ${err}")
endif()
# The flag is 30 x 20 points: at lod 2, 59 x 39 smooth vertices and 2 x 58 x 38 triangles.
file(STRINGS ${OUT}/obj/frame_000002.obj v REGEX "^v ")
file(STRINGS ${OUT}/obj/frame_000002.obj vn REGEX "^vn ")
file(STRINGS ${OUT}/obj/frame_000002.obj f REGEX "^f [0-9]+//[0-9]+ ")
list(LENGTH v nv)
list(LENGTH vn nvn)
list(LENGTH f nf)
if(NOT nv EQUAL 2301 OR NOT nvn EQUAL 2301 OR NOT nf EQUAL 4408)
  message(FATAL_ERROR "smooth OBJ: ${nv} v, ${nvn} vn, ${nf} f; expected 2301, 2301, 4408")
endif()
foreach(bad "--smooth" "--format;obj;--smooth;--lod;0" "--format;obj;--smooth;--lod;17")
  execute_process(COMMAND ${MAILLE} run ${scene} --steps 1 ${bad} --out ${OUT}/bad
                  RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "maille run ${bad} should be a usage error (2), got ${rc}")
  endif()
endforeach()
# A scene with no surface (a chain of beads) has nothing to smooth: bad input (1), said so.
execute_process(COMMAND ${MAILLE} run ${SOURCE}/examples/pendulum_chain.toml --steps 1
                --format obj --smooth --out ${OUT}/chain RESULT_VARIABLE rc OUTPUT_QUIET
                ERROR_VARIABLE err)
if(NOT rc EQUAL 1 OR NOT err MATCHES "pendulum_chain.toml: error: .*no surface to smooth")
  message(FATAL_ERROR "smoothing a scene without surface: expected exit 1, got ${rc}: ${err}")
endif()
if(EXISTS ${OUT}/chain)
  message(FATAL_ERROR "a refused --smooth run left its output directory ${OUT}/chain")
endif()
