# geometry: B-splines, cluster frames and points, shells and layer meshes.
satf_unit_test(test_bspline SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_bspline.c
               LIBS satf_geometry LABELS geometry)
satf_unit_test(test_cluster SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_cluster.c
               LIBS satf_geometry LABELS geometry)
satf_unit_test(test_shell_mesh
               SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_shell_mesh.c
               LIBS satf_geometry LABELS geometry)
