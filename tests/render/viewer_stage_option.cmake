# maille-viewer under Xvfb, switching an obstacle's method live through the Stages panel's path
# (PhysicsThread::set_stage_option): the scene runs rk4, which cannot run facets, so that switch
# is refused with the simulator's reason (shown in the panel, printed at the end) and the viewer
# keeps running; conditional is accepted.
foreach(method facets conditional)
  set(shot ${OUT}/viewer_${method}.png)
  file(REMOVE ${shot})
  execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 1024x768x24"
                  ${VIEWER} ${SCENE} --width 800 --height 600 --frames 30 --screenshot ${shot}
                  --stage-option obstacle:box.method=${method}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "maille-viewer (method ${method}) failed (${rc}): ${out} ${err}")
  endif()
  if(NOT EXISTS ${shot})
    message(FATAL_ERROR "no screenshot at ${shot}: ${out} ${err}")
  endif()
  if(method STREQUAL "facets")
    if(NOT out MATCHES "notice: method = facets refused: stage 'obstacle:box'[^\n]*rk4")
      message(FATAL_ERROR "the refused switch should be reported: ${out} ${err}")
    endif()
  elseif(out MATCHES "notice:")
    message(FATAL_ERROR "the switch to ${method} should be accepted: ${out} ${err}")
  endif()
endforeach()
