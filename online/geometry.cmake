# geometry: cluster generalized cylinders, shells/HSVs (satf/cluster.h) and
# the OpenMesh shim for triangle meshes (satf/mesh.h). OpenMesh stays a
# PRIVATE dependency of satf_mesh; being static, its C++ link needs still
# propagate, so C executables linking satf_geometry get the C++ driver.
find_package(OpenMesh REQUIRED)
add_library(satf_mesh STATIC ${CMAKE_CURRENT_LIST_DIR}/mesh_openmesh.cpp)
target_link_libraries(satf_mesh PUBLIC satf_common
                      PRIVATE OpenMeshCore satf_warnings)
add_library(satf_geometry STATIC
  ${CMAKE_CURRENT_LIST_DIR}/bspline.c
  ${CMAKE_CURRENT_LIST_DIR}/cluster.c
  ${CMAKE_CURRENT_LIST_DIR}/shell.c)
target_link_libraries(satf_geometry PUBLIC satf_mesh satf_common m
                      PRIVATE satf_warnings)
