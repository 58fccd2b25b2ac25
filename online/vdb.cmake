# vdb: the OpenVDB shim (satf/vdb.h). OpenVDB stays a PRIVATE dependency, so
# consumers see a plain C library; being static, its C++ link needs still
# propagate and CMake links C executables that use it with the C++ driver.
find_package(OpenVDB REQUIRED)
add_library(satf_vdb STATIC ${CMAKE_CURRENT_LIST_DIR}/vdb_openvdb.cpp)
target_link_libraries(satf_vdb PUBLIC satf_common
                      PRIVATE OpenVDB::openvdb satf_warnings)
