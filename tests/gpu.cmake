# gpu part tests. The GL tests run on Mesa's llvmpipe through EGL's
# surfaceless platform, so they need no display and no GPU.
satf_unit_test(test_image SOURCES test_image.c LIBS satf_image)
satf_unit_test(test_gl_headless SOURCES test_gl_headless.c LIBS satf_gl
               LABELS gl)

# The same GL checks through a GLFW window under a virtual X server: the
# test source built with SATF_TEST_WINDOW, reading the default framebuffer.
find_program(SATF_XVFB_RUN xvfb-run)
if(SATF_XVFB_RUN)
  add_executable(test_gl_window test_gl_headless.c)
  target_compile_definitions(test_gl_window PRIVATE SATF_TEST_WINDOW=1)
  target_link_libraries(test_gl_window PRIVATE satf_glfw ${CMOCKA_LIBRARIES}
                        satf_warnings)
  add_test(NAME test_gl_window
           COMMAND ${SATF_XVFB_RUN} -a $<TARGET_FILE:test_gl_window>)
  set_tests_properties(test_gl_window PROPERTIES LABELS "xvfb;gl"
                       ENVIRONMENT "SATF_TEST_TMP=${CMAKE_CURRENT_BINARY_DIR}")
endif()
