satf_unit_test(test_vdb SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_vdb.c
               LIBS satf_vdb LABELS vdb)
