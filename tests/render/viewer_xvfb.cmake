# maille-viewer under Xvfb: draws N frames, writes the screenshot, exits 0. EXTRA: more flags.
file(REMOVE ${OUT})
execute_process(COMMAND ${XVFB_RUN} -a -s "-screen 0 1024x768x24"
                ${VIEWER} ${SCENE} ${EXTRA} --width 800 --height 600 --frames 20 --screenshot ${OUT}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "maille-viewer failed (${rc}): ${out} ${err}")
endif()
if(NOT EXISTS ${OUT})
  message(FATAL_ERROR "no screenshot at ${OUT}: ${out} ${err}")
endif()
file(READ ${OUT} header LIMIT 24 HEX)
# PNG signature and IHDR: the window's framebuffer, 800x600 (0x320 x 0x258).
if(NOT header MATCHES "^89504e470d0a1a0a0000000d494844520000032000000258$")
  message(FATAL_ERROR "the screenshot is not an 800x600 PNG: ${header}")
endif()
if(DEFINED EXPECT AND NOT out MATCHES "${EXPECT}")
  message(FATAL_ERROR "expected '${EXPECT}' in the viewer's output: ${out} ${err}")
endif()
file(SIZE ${OUT} size)
if(size LESS 20000)
  message(FATAL_ERROR "the screenshot is nearly empty (${size} bytes)")
endif()
